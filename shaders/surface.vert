// Shading of the baked surface (Li & Guo's CubeMapping.vert/.frag, made physically consistent):
//   L = B w(mu_o) lobe(mu_o) F_t(mu_o, eta) * exitScale
//       + F_r(mu_o, eta) * L_env(reflect(-w_o, n))
// B: exitance baked per vertex (MODE_SSS; relit here from a relightable bake's transfer with
// RELIGHT_COEFFICIENTS), or albedo * E(n) from the diffuse irradiance cubemap
// (MODE_BRDF: a Lambertian surface, the paper's Figure 3 comparison, so that the two modes differ
// only by light transport). exitScale is 1 / (pi (1 - 2 C_1(eta))) for the normalized exit model
// (the emitted flux equals B; d'Eon 2012) or 1 / pi (Jensen et al. 2001). The paper writes F_r for
// the factor that lets light out; that is the transmittance F_t = 1 - F_r. w(mu_o) per channel is
// the calibrated exit model's angular weight (material/directional_albedo_weight.h: the half-space
// Monte Carlo's shape across albedo, flux-preserving), all 1 for the other models. lobe(mu_o) is
// the exit lobe of optics/exit_lobe.h over the normalized model: (1 + k mu_i) A_0 / (A_0 + k A_1),
// mu_i the cosine inside, A_n the lobe's moments (with exitScale = 1 / (pi A_0) its flux is B),
// k the vertex's slope as the bake's far field measured it (transport/far_field.h), 0 (lobe = 1)
// but for the auto exit model on a bake with a traced far field.
// UNSCATTERED (surface.frag) adds the light that crosses the object in a straight line.
// REFLECT_MIX reproduces the paper's constant mix(base, cube, reflect_factor) instead.
// MODE_IRRADIANCE shows the baked E as a white Lambertian surface (E / pi); MODE_NORMALS shows
// n * 0.5 + 0.5.
//
// As in the paper, everything but the reflection lookup is evaluated per vertex: the Fresnel
// factors and E(n) vary slowly over a triangle, and a reflection vector interpolated linearly is
// the reflection of the linearly interpolated normal (reflect() is linear in n). On a software
// rasterizer this keeps the per-pixel work to one cubemap lookup.
// Vertices are in world space (no model matrix). The outputs are interpolated at the centroid of
// the covered samples: with MSAA a pixel on a silhouette is shaded once, at its centre, which may
// lie outside the triangle, where extrapolated values can turn negative.
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec3 aValue;
layout(location = 3) in vec3 aExitSlope;

uniform mat4 uViewProjection;
uniform vec3 uEye;
uniform float uEta;
uniform float uExitScale;
uniform vec3 uExitWeight[17];  // w(mu) at mu = k / 16
uniform vec2 uLobeMoments;     // A_0, A_1
uniform vec3 uAlbedo;
uniform samplerCube uIrradiance;

centroid out vec3 vBase;       // view-independent radiance: the exit term (or E / pi)
centroid out vec3 vDirection;  // reflected view direction (the normal for MODE_NORMALS)
centroid out float vFresnel;   // F_r(mu_o) weighting the reflection
centroid out vec3 vToEye;      // from the surface to the eye
centroid out vec3 vNormal;     // the vertex normal

#ifdef RELIGHT_COEFFICIENTS
// A relightable bake relit here (bake/relight.h, RelitSplit), for the smooth light's SH
// coefficients uSmoothLight: B = max(sum_k T_k L_k + rest, 0) g b per channel, the transfer T and
// g b per vertex in the storage buffer (renderer.cpp, relightStorage: g b, then T_0, T_1, ...),
// the rest (the compact lights and the bounces, before g) in aValue.
layout(std430, binding = 0) readonly buffer RelightTransfer { float relightData[]; };
uniform vec3 uSmoothLight[RELIGHT_COEFFICIENTS];

vec3 relightEntry(int i) { return vec3(relightData[i], relightData[i + 1], relightData[i + 2]); }

vec3 relitExitance() {
  int base = gl_VertexID * 3 * (RELIGHT_COEFFICIENTS + 1);
  vec3 b = vec3(0.0);
  for (int k = 0; k < RELIGHT_COEFFICIENTS; ++k)
    b += relightEntry(base + 3 * (k + 1)) * uSmoothLight[k];
  return max(b + aValue, vec3(0.0)) * relightEntry(base);
}
#endif

vec3 exitWeight(float mu) {
  float t = clamp(mu, 0.0, 1.0) * 16.0;
  int k = min(int(t), 15);
  return mix(uExitWeight[k], uExitWeight[k + 1], t - float(k));
}

// The exit lobe's radiance over the normalized model's: the lobe over its value at slope 0.
vec3 exitLobe(float mu) {
  float muI = sqrt(max(0.0, 1.0 - (1.0 - mu * mu) / (uEta * uEta)));
  return (vec3(1.0) + aExitSlope * muI) * uLobeMoments.x /
         (vec3(uLobeMoments.x) + aExitSlope * uLobeMoments.y);
}

void main() {
  gl_Position = uViewProjection * vec4(aPosition, 1.0);
  vec3 n = normalize(aNormal);
  vec3 v = normalize(uEye - aPosition);
  // |n.v|: a back face (open meshes, drawn without culling) is shaded as seen from its side;
  // reflect() does not depend on the normal's sign. At silhouettes, where interpolated normals
  // turn slightly away from the eye, this stays continuous at grazing exit.
  float mu = min(abs(dot(n, v)), 1.0);
  vFresnel = fresnelReflectance(mu, uEta);
  vToEye = uEye - aPosition;
  vNormal = n;
  vDirection = reflect(-v, n);
#if defined(MODE_NORMALS)
  vBase = vec3(0.0);
  vDirection = n;
#elif defined(MODE_IRRADIANCE)
  vBase = aValue / PI;
#elif defined(MODE_BRDF)
  vBase = uAlbedo * textureLod(uIrradiance, n, 0.0).rgb * ((1.0 - vFresnel) * uExitScale);
#else
#ifdef RELIGHT_COEFFICIENTS
  vec3 exitance = relitExitance();
#else
  vec3 exitance = aValue;
#endif
  vBase = exitance * exitWeight(mu) * exitLobe(mu) * ((1.0 - vFresnel) * uExitScale);
#endif
}

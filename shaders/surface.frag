// Per pixel: the reflection lookup, added with its Fresnel weight (see surface.vert), and with
// UNSCATTERED the light that crosses the object without scattering (bake/unscattered_light.h):
// from the environment behind, along the view ray, refracted in and out, attenuated over the
// path inside:
//   L_u = F_t^2 e^(-tau) / (1 - F_r^2 e^(-2 tau)) L_env(-w_o),  tau = sigma_t d mu_o / mu_i,
// d the view ray's chord from this surface to the nearest back face behind it (the back faces'
// depth pass), mu_o / mu_i the refracted path's length over the straight one. Exact for a slab
// (parallel faces: the ray leaves along the view ray, F_t and F_r alike at both faces, the series
// of internal reflections summed); elsewhere the faces' tilt against each other is left out.
in vec3 vBase;
in vec3 vDirection;
in float vFresnel;
in vec3 vToEye;
in float vMu;

uniform samplerCube uRadiance;
uniform float uReflectFactor;
#ifdef UNSCATTERED
uniform sampler2D uBackDepth;  // the nearest back face's window depth per pixel
uniform vec2 uDepthFromNdc;    // projection's (P[2][2], P[3][2]): view depth P32 / (z_ndc + P22)
uniform vec3 uSigmaT;          // extinction per mesh unit
uniform float uEta;            // the relative index (surface.vert's)

float viewDepth(float windowDepth) {
  return uDepthFromNdc.y / (2.0 * windowDepth - 1.0 + uDepthFromNdc.x);
}

vec3 unscatteredLight() {
  float back = texelFetch(uBackDepth, ivec2(gl_FragCoord.xy), 0).r;
  if (back >= 1.0) return vec3(0.0);  // no back face behind: nothing crosses
  float front = viewDepth(gl_FragCoord.z);
  float chord = length(vToEye) * max(viewDepth(back) / front - 1.0, 0.0);
  float mu = clamp(vMu, 1e-4, 1.0);
  float muI = sqrt(max(1.0 - (1.0 - mu * mu) / (uEta * uEta), 1e-8));
  vec3 transmittance = exp(-uSigmaT * (chord * mu / muI));
  float t = 1.0 - vFresnel, r = vFresnel;
  return t * t * transmittance / (vec3(1.0) - r * r * transmittance * transmittance) *
         texture(uRadiance, -normalize(vToEye)).rgb;
}
#endif

layout(location = 0) out vec4 fragColor;

void main() {
#if defined(MODE_NORMALS)
  fragColor = vec4(normalize(vDirection) * 0.5 + 0.5, 1.0);
#elif defined(MODE_IRRADIANCE)
  fragColor = encodeOutput(vBase);
#else
  vec3 reflected = texture(uRadiance, vDirection).rgb;
#ifdef REFLECT_MIX
  fragColor = encodeOutput(mix(vBase, reflected, uReflectFactor));
#else
  vec3 radiance = vBase + vFresnel * reflected;
#ifdef UNSCATTERED
  radiance += unscatteredLight();
#endif
  fragColor = encodeOutput(radiance);
#endif
#endif
}

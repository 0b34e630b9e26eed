// Per pixel: the reflection lookup, added with its Fresnel weight (see surface.vert), and with
// UNSCATTERED the light that crosses the object without scattering (transport/unscattered_light.h):
// from the environment behind, refracted in and out, attenuated over its path inside:
//   L_u = F_t^2 e^(-tau) / (1 - F_r^2 e^(-2 tau)) L_env(-w_o),  tau = sigma_t l,
// l the refracted ray's length inside, found by marching it through the back faces' depth (the
// first pass): the ray has left where it lies behind the nearest back face on screen (or off the
// object's image). Exact for a slab (parallel faces: it leaves along the view ray, F_t and F_r
// alike at both faces, the internal reflections' series summed); on curved parts the bend on the
// way out and the exit's own Fresnel factor are left out, and light that would meet the object
// again behind shows the environment.
centroid in vec3 vBase;
centroid in vec3 vDirection;
centroid in float vFresnel;
centroid in vec3 vToEye;
centroid in vec3 vNormal;

uniform samplerCube uRadiance;
uniform float uReflectFactor;
#ifdef UNSCATTERED
uniform sampler2D uBackDepth;  // the nearest back face's window depth per pixel
uniform mat4 uViewProjection;  // surface.vert's
uniform vec2 uViewport;        // pixels
uniform vec3 uEye;             // surface.vert's
uniform float uEta;            // the relative index (surface.vert's)
uniform float uMaxPath;        // the mesh's bounding box diagonal: no path inside is longer
uniform vec3 uSigmaT;          // extinction per mesh unit

const int kMarchSteps = 16, kBisections = 8;
// Past this optical depth in every channel (e^-7 < 0.1 %) the ray counts as absorbed: the march
// stops there (a thick body costs a few steps, not all of them).
const float kOpaqueDepth = 7.0;

// Whether p lies outside the object as the screen sees it: behind the nearest back face of its
// pixel, or where no back face is.
bool leftObject(vec3 p) {
  vec4 clip = uViewProjection * vec4(p, 1.0);
  if (clip.w <= 0.0) return true;
  vec3 ndc = clip.xyz / clip.w;
  if (any(greaterThan(abs(ndc.xy), vec2(1.0)))) return true;
  float back = texelFetch(uBackDepth, ivec2((ndc.xy * 0.5 + 0.5) * uViewport), 0).r;
  return back >= 1.0 || ndc.z * 0.5 + 0.5 >= back;
}

// The refracted ray's length inside from `entry` along r; -1 when it does not leave within
// uMaxPath or has been absorbed before.
float pathInside(vec3 entry, vec3 r) {
  float lo = 0.0, hi = -1.0, step = uMaxPath / float(kMarchSteps);
  float thinnest = min(uSigmaT.r, min(uSigmaT.g, uSigmaT.b));
  for (int i = 1; i <= kMarchSteps && hi < 0.0; ++i) {
    float t = step * float(i);
    if (leftObject(entry + r * t)) hi = t; else lo = t;
    if (hi < 0.0 && thinnest * lo > kOpaqueDepth) return -1.0;
  }
  if (hi < 0.0) return -1.0;
  for (int i = 0; i < kBisections; ++i) {
    float mid = 0.5 * (lo + hi);
    if (leftObject(entry + r * mid)) hi = mid; else lo = mid;
    if (thinnest * lo > kOpaqueDepth) return -1.0;
  }
  return 0.5 * (lo + hi);
}

vec3 unscatteredLight() {
  vec3 toEye = normalize(vToEye);
  vec3 n = normalize(vNormal);
  if (dot(n, toEye) < 0.0) n = -n;
  vec3 r = refract(-toEye, n, 1.0 / uEta);
  float path = pathInside(uEye - vToEye, r);
  if (path < 0.0) return vec3(0.0);
  vec3 transmittance = exp(-uSigmaT * path);
  float t = 1.0 - vFresnel, f = vFresnel;
  return t * t * transmittance / (vec3(1.0) - f * f * transmittance * transmittance) *
         texture(uRadiance, -toEye).rgb;
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

// Shared by every program: exposure, tonemapping, and the Fresnel reflectance. The C++ side
// puts "#version 450 core" and the variant's #defines (MODE_*, TONEMAP_*, FRESNEL_SCHLICK, ...)
// in front. 8-bit output goes into an sRGB framebuffer, which encodes on store (and resolves
// MSAA in linear space), so no shader encodes.
const float PI = 3.14159265358979;

uniform float uExposure;  // 2^EV, applied to radiance before the tonemap

vec3 tonemap(vec3 c) {
#if defined(TONEMAP_REINHARD)
  // Reinhard et al. 2002, simple form per channel.
  return c / (1.0 + c);
#elif defined(TONEMAP_ACES)
  // Narkowicz 2015's fit of the ACES filmic curve.
  return clamp((c * (2.51 * c + 0.03)) / (c * (2.43 * c + 0.59) + 0.14), 0.0, 1.0);
#else
  return c;
#endif
}

vec4 encodeOutput(vec3 radiance) { return vec4(tonemap(radiance * uExposure), 1.0); }

// Reflectance of a smooth dielectric for light arriving at cosI from outside (eta = n_in/n_out);
// mirrors fresnelDielectric and fresnelSchlick of lib/optics/fresnel.h.
float fresnelReflectance(float cosI, float eta) {
#ifdef FRESNEL_SCHLICK
  float r0 = (eta - 1.0) / (eta + 1.0);
  r0 *= r0;
  float m = 1.0 - cosI;
  float m2 = m * m;
  return r0 + (1.0 - r0) * m2 * m2 * m;
#else
  float sin2T = (1.0 - cosI * cosI) / (eta * eta);
  if (sin2T >= 1.0) return 1.0;
  float cosT = sqrt(1.0 - sin2T);
  float rPar = (eta * cosI - cosT) / (eta * cosI + cosT);
  float rPerp = (cosI - eta * cosT) / (cosI + eta * cosT);
  return 0.5 * (rPar * rPar + rPerp * rPerp);
#endif
}

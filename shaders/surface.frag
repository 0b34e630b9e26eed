// Per pixel: the reflection lookup, added with its Fresnel weight (see surface.vert).
in vec3 vBase;
in vec3 vDirection;
in float vFresnel;

uniform samplerCube uRadiance;
uniform float uReflectFactor;

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
  fragColor = encodeOutput(vBase + vFresnel * reflected);
#endif
#endif
}

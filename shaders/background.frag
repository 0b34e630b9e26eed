// The environment seen through each pixel: the view ray from the inverse of the rotation-only
// view-projection, looked up in the radiance cubemap (same orientation as the reflections).
// One level of detail for the whole frame (pixel vs texel angle, set by the renderer) spares the
// per-pixel derivatives.
in vec2 vNdc;

uniform mat4 uInverseViewProjection;  // inverse(projection * mat4(mat3(view)))
uniform samplerCube uRadiance;
uniform float uLod;

layout(location = 0) out vec4 fragColor;

void main() {
  vec4 p = uInverseViewProjection * vec4(vNdc, 1.0, 1.0);
  fragColor = encodeOutput(textureLod(uRadiance, p.xyz / p.w, uLod).rgb);
}

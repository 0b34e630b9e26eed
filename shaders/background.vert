// One triangle that covers the screen, on the far plane (depth 1), drawn after the mesh with
// GL_LEQUAL so that only uncovered pixels run the fragment shader.
out vec2 vNdc;

void main() {
  vNdc = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2) * 2.0 - 1.0;
  gl_Position = vec4(vNdc, 1.0, 1.0);
}

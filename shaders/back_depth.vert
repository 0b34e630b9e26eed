// The back faces' depth pass for the unscattered light (surface.frag, UNSCATTERED): positions
// only (world space, as surface.vert's).
layout(location = 0) in vec3 aPosition;

uniform mat4 uViewProjection;

void main() { gl_Position = uViewProjection * vec4(aPosition, 1.0); }

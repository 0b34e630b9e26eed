// The equirectangular (latitude-longitude) convention, used by every tool:
// u in [0, 1] runs left to right, v in [0, 1] top to bottom; v = 0 looks straight up (+Y).
// The image centre (u, v) = (0.5, 0.5) looks towards -Z; u = 0.75 looks towards +X, u = 0.25
// towards -X, and u = 0 / 1 towards +Z. Seen from inside the sphere, the image is not mirrored:
// a camera at the origin looking down -Z with +Y up sees the image centre, +X to its right.
//   direction(u, v) = (sin(theta) sin(phi), cos(theta), -sin(theta) cos(phi)),
//   phi = 2 pi (u - 0.5), theta = pi v.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace sss {

glm::vec3 equirectDirection(float u, float v);
glm::vec2 equirectCoord(const glm::vec3& direction);  // inverse of equirectDirection

}  // namespace sss

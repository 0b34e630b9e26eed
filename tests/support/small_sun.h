// A test environment: black but for a sun of 1.8 degrees' radius (the texels within it) towards
// `sun`, radiance 1e3: sharp shadows and terminators for the lighting tests.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "envmap/cubemap.h"

namespace sss {

inline Cubemap smallSun(const glm::vec3& sun) {
  Cubemap env(64, glm::vec3(0.0f));
  forEachTexel(64, [&](int f, int x, int y) {
    if (glm::dot(env.direction(f, x, y), sun) > 0.9995f) env.at(f, x, y) = glm::vec3(1e3f);
  });
  return env;
}

}  // namespace sss

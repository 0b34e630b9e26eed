#include "envmap/orientation.h"

#include <cmath>

#include "core/error.h"

namespace sss {

double conventionTurnDeg(EquirectConvention convention) {
  switch (convention) {
    case EquirectConvention::Blender:
    case EquirectConvention::Threejs:
      return -90.0;
    case EquirectConvention::Filament:
      return 180.0;
    case EquirectConvention::Sss:
      break;
  }
  return 0.0;
}

glm::mat3 rotationAboutY(double deg) {
  // Exact for multiples of 90 degrees, so that a quarter turn permutes axes without rounding.
  const double r = std::remainder(deg, 360.0);
  double c = std::cos(r * M_PI / 180.0), s = std::sin(r * M_PI / 180.0);
  if (std::remainder(r, 90.0) == 0.0) {
    c = std::round(c);
    s = std::round(s);
  }
  // Columns: the images of +X, +Y, +Z. x' = c x + s z, z' = -s x + c z.
  return glm::mat3(glm::vec3(static_cast<float>(c), 0.0f, static_cast<float>(-s)),
                   glm::vec3(0.0f, 1.0f, 0.0f),
                   glm::vec3(static_cast<float>(s), 0.0f, static_cast<float>(c)));
}

namespace {
double totalTurnDeg(const EnvironmentOrientation& o, bool equirect) {
  return (equirect ? conventionTurnDeg(o.convention) : 0.0) + o.rotateDeg;
}
}  // namespace

glm::mat3 sourceFromWorld(const EnvironmentOrientation& orientation, bool equirect) {
  return rotationAboutY(-totalTurnDeg(orientation, equirect));
}

bool isIdentity(const EnvironmentOrientation& orientation, bool equirect) {
  return std::remainder(totalTurnDeg(orientation, equirect), 360.0) == 0.0;
}

void checkEnvRotate(double deg) {
  if (!std::isfinite(deg)) fail("", "--env-rotate must be a finite number of degrees");
}

}  // namespace sss

// Luminance of a linear Rec. 709 / sRGB colour (ITU-R BT.709 weights). Computed in the colour's
// own precision, so float and double callers keep their arithmetic.
#pragma once

#include <glm/vec3.hpp>

namespace sss {

template <typename T>
T luminance(const glm::vec<3, T>& c) {
  return T(0.2126) * c.r + T(0.7152) * c.g + T(0.0722) * c.b;
}

}  // namespace sss

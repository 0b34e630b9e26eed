// Component-wise closeness of two vectors, shared by the envmap tests.
#pragma once

#include <gtest/gtest.h>
#include <glm/vec3.hpp>

namespace sss::test {

inline void expectNear(const glm::vec3& a, const glm::vec3& b, float eps) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

}  // namespace sss::test

// The gather's rays per vertex (lib/bake/bake_settings.h): following the tolerance as powers of
// two, and the visibility's cosine set taken alone where that rounding would accept its count.
#include <gtest/gtest.h>

#include "bake/bake_settings.h"

namespace sss {
namespace {

BakeSettings atTolerance(double tolerance) {
  BakeSettings s;
  s.tolerance = tolerance;
  return s;
}

// 64 (0.01 / tolerance)^2, rounded to the power of two within a factor sqrt 2 of it, in [8, 256].
TEST(GatherRays, FollowTheToleranceAsPowersOfTwo) {
  EXPECT_EQ(gatherRaysFor(0.01), 64);
  EXPECT_EQ(gatherRaysFor(0.02), 16);
  EXPECT_EQ(gatherRaysFor(0.0085), 64);  // 88.6 wanted: 64 sqrt 2 = 90.5 holds it
  EXPECT_EQ(gatherRaysFor(0.008), 128);  // 100 wanted
  EXPECT_EQ(gatherRaysFor(0.001), 256);
  EXPECT_EQ(gatherRaysFor(0.5), 8);
}

// The visibility's set alone where its count is within the rounding's band (64 wanted at 1 %:
// from 45.3 up to the rounded 64), else the rounded count; a count the user set is kept.
TEST(GatherRays, TakeTheVisibilitysSetAloneWhereTheRoundingWouldAcceptIt) {
  const BakeSettings s = atTolerance(0.01);
  EXPECT_EQ(gatherRaysWith(s, 56), 56);
  EXPECT_EQ(gatherRaysWith(s, 46), 46);
  EXPECT_EQ(gatherRaysWith(s, 45), 64);  // 45 sqrt 2 = 63.6 < 64: too few
  EXPECT_EQ(gatherRaysWith(s, 0), 64);   // none kept
  EXPECT_EQ(gatherRaysWith(s, 80), 64);  // more than the rounded count: not kept by the bake
  EXPECT_EQ(gatherRaysWith(atTolerance(0.0085), 63), 63);  // 88.6 wanted: 63 sqrt 2 = 89.1
  EXPECT_EQ(gatherRaysWith(atTolerance(0.0085), 62), 64);  // 62 sqrt 2 = 87.7: too few
  EXPECT_EQ(gatherRaysWith(atTolerance(0.008), 71), 71);   // 100 wanted: 71 sqrt 2 = 100.4
  EXPECT_EQ(gatherRaysWith(atTolerance(0.008), 70), 128);  // 70 sqrt 2 = 99: too few
  BakeSettings forced = s;
  forced.interreflectionRays = 32;
  EXPECT_EQ(gatherRaysWith(forced, 56), 32);
}

}  // namespace
}  // namespace sss

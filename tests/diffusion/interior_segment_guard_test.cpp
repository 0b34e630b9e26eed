// The interior-segment guard: no change on convex shapes, no light across a gap of air.
#include <gtest/gtest.h>

#include <vector>

#include "bench/interior_segment_guard.h"
#include "material/diffusion_profile.h"
#include "material/material.h"
#include "material/profile_factory.h"
#include "mesh/primitives.h"
#include "support/joined_meshes.h"

namespace sss {
namespace {

Material marble() {
  return findMaterialPreset("marble");
}

TEST(InteriorSegmentGuard, ChangesNothingOnAConvexSphere) {
  const TriangleMesh sphere = makeIcosphere(3, 6.0f);
  const auto profile = makeProfile("dipole", marble());
  const std::vector<float> areas = vertexAreas(sphere);
  const std::vector<glm::vec3> e(sphere.positions.size(), glm::vec3(1.0f, 2.0f, 3.0f));
  GuardedSumOptions options;
  const auto guarded = diffuseExactGuarded(sphere.positions, sphere.normals, areas, e,
                                           sphere.triangles, *profile, options);
  options.guard = false;
  const auto plain = diffuseExactGuarded(sphere.positions, sphere.normals, areas, e,
                                         sphere.triangles, *profile, options);
  EXPECT_GT(guarded.pairs, sphere.positions.size());
  EXPECT_EQ(guarded.droppedPairs, 0u);
  EXPECT_EQ(guarded.exitance, plain.exitance);
}

// Two spheres 0.4 mm apart (far less than marble's diffusion length, ~8 mm): without the guard
// the lit sphere's light leaks into the dark one; with it the dark one stays black.
TEST(InteriorSegmentGuard, DropsPairsAcrossAGap) {
  const TriangleMesh a = makeIcosphere(3, 5.0f);
  const TriangleMesh two = joinedMeshes(a, a, glm::vec3(10.4f, 0.0f, 0.0f));
  const std::size_t n = a.positions.size();
  std::vector<glm::vec3> e(2 * n, glm::vec3(0.0f));
  std::fill(e.begin(), e.begin() + n, glm::vec3(1.0f));  // only the first sphere is lit
  const std::vector<float> areas = vertexAreas(two);
  const auto profile = makeProfile("dipole", marble());
  GuardedSumOptions options;
  const auto guarded =
      diffuseExactGuarded(two.positions, two.normals, areas, e, two.triangles, *profile, options);
  options.guard = false;
  const auto plain =
      diffuseExactGuarded(two.positions, two.normals, areas, e, two.triangles, *profile, options);
  EXPECT_GT(guarded.droppedPairs, 0u);
  // The vertex of the dark sphere nearest the gap: lit by leakage only.
  std::size_t nearest = n;
  for (std::size_t i = n; i < 2 * n; ++i)
    if (two.positions[i].x < two.positions[nearest].x) nearest = i;
  EXPECT_GT(plain.exitance[nearest].x, 0.05f * plain.exitance[0].x);
  for (std::size_t i = n; i < 2 * n; ++i) ASSERT_EQ(guarded.exitance[i], glm::vec3(0.0f)) << i;
  // The pair test on its own: across the gap no, through a sphere yes.
  const InteriorSegmentGuard guard(two.positions, two.normals, areas, two.triangles);
  std::size_t facing = 0;  // the lit sphere's vertex nearest the gap
  for (std::size_t i = 0; i < n; ++i)
    if (two.positions[i].x > two.positions[facing].x) facing = i;
  EXPECT_FALSE(guard.connected(uint32_t(facing), uint32_t(nearest)));
  EXPECT_TRUE(guard.connected(uint32_t(facing), 0u));
  EXPECT_TRUE(guard.connected(uint32_t(nearest), uint32_t(n)));
  // And the lit sphere equals the lit sphere alone.
  const std::vector<float> aloneAreas = vertexAreas(a);
  const std::vector<glm::vec3> aloneE(n, glm::vec3(1.0f));
  options.guard = true;
  const auto alone = diffuseExactGuarded(a.positions, a.normals, aloneAreas, aloneE, a.triangles,
                                         *profile, options);
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(guarded.exitance[i], alone.exitance[i]) << i;
}

}  // namespace
}  // namespace sss

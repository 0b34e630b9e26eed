// The far field's surface average (lib/transport/surface_average.h): the sum over clusters, used
// where a kernel holds many vertices, against the direct sum; constants kept; the two faces of a
// thin part kept apart in both.
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <vector>

#include "core/random.h"
#include "core/relative_rms.h"
#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"
#include "transport/surface_average.h"

namespace sss {
namespace {

// A smooth field plus per-vertex noise (as the far field's per-batch tallies are), on a sphere of
// 10K vertices with a kernel of 1.2 mm (~330 vertices within 3 sigma): the clusters give the
// direct sum's average to a few parts per thousand.
TEST(SurfaceAverage, ClustersMatchTheDirectSum) {
  const TriangleMesh sphere = makeIcosphere(5, 10.0f);
  const std::vector<float> areas = vertexAreas(sphere);
  std::vector<glm::vec3> values;
  Pcg32 rng(3, 0);
  for (const glm::vec3& p : sphere.positions) {
    const glm::vec3 smooth(2.0f + std::sin(p.x / 3.0f), 2.0f + std::cos(p.y / 4.0f),
                           1.5f + p.z / 10.0f);
    values.push_back(smooth * (0.5f + rng.uniform()));
  }
  const SurfaceAverage direct(sphere, areas, 1.2, 0);
  const SurfaceAverage clusters(sphere, areas, 1.2, 0, true);
  ASSERT_FALSE(direct.clustered());
  ASSERT_TRUE(clusters.clustered());
  const std::vector<glm::vec3> a = clusters(values), b = direct(values);
  EXPECT_LT(relativeRms(a, b, areas), 0.004);
  // The averaging itself is not a no-op: it removes most of the noise.
  EXPECT_GT(relativeRms(values, b, areas), 0.1);
  // A larger kernel over the same mesh picks the clusters by itself.
  EXPECT_TRUE(SurfaceAverage(sphere, areas, 4.0, 0).clustered());
}

// Constants stay constant; on a thin slab (40 x 40 x 1 mm, kernel 2 mm) the top face's values
// do not leak into the bottom face's averages, clustered or not.
TEST(SurfaceAverage, KeepsConstantsAndTheFacesOfAThinPartApart) {
  const TriangleMesh slab = makeSlab(40.0f, 1.0f, 40);
  const std::vector<float> areas = vertexAreas(slab);
  std::vector<glm::vec3> values;
  for (const glm::vec3& n : slab.normals) values.push_back(glm::vec3(n.z > 0.9f ? 1.0f : 0.0f));
  const std::vector<glm::vec3> constant(slab.positions.size(), glm::vec3(0.7f));
  for (bool force : {false, true}) {
    const SurfaceAverage average(slab, areas, 2.0, 0, force);
    const std::vector<glm::vec3> c = average(constant);
    const std::vector<glm::vec3> faces = average(values);
    for (std::size_t i = 0; i < slab.positions.size(); ++i) {
      ASSERT_NEAR(c[i].x, 0.7f, 1e-5f) << i;
      const glm::vec3 p = slab.positions[i];
      if (std::abs(p.x) > 12.0f || std::abs(p.y) > 12.0f) continue;  // kernels off the sides
      if (slab.normals[i].z > 0.999f) {
        ASSERT_NEAR(faces[i].x, 1.0f, 1e-5f) << i;
      } else if (slab.normals[i].z < -0.999f) {
        ASSERT_NEAR(faces[i].x, 0.0f, 1e-5f) << i;
      }
    }
  }
}

}  // namespace
}  // namespace sss

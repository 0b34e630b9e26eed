// Interreflection: the white furnace. A closed, non-absorbing object under uniform radiance 1
// sends radiance 1 in every direction from every vertex, concavities included; without the light
// it sends itself, a pit is dark.
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <vector>

#include "bake/interreflection.h"
#include "bake/visibility.h"
#include "box_with_pit.h"
#include "envmap/cubemap.h"
#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"
#include "optics/fresnel.h"

namespace sss {
namespace {

TEST(Interreflection, WhiteFurnaceSendsRadianceOneFromEveryVertex) {
  const TriangleMesh mesh = boxWithPit();
  const Cubemap white(8, glm::vec3(1.0f));
  const float eta = 1.3f;
  const double full = M_PI * (1.0 - diffuseFresnelReflectance(eta));  // E under a full sky
  VisibilityOptions vis;
  vis.samples = 256;
  const std::vector<glm::vec3> direct = transmittedIrradianceWithVisibility(
      mesh.positions, mesh.normals, mesh.triangles, white, eta, vis);
  InterreflectionOptions options;
  options.rays = 256;
  const InterreflectionGather gather(mesh.positions, mesh.normals, mesh.triangles, white, eta,
                                     options);
  EXPECT_GT(gather.blockedFraction(), 0.02);
  // A non-absorbing object under uniform light returns all it receives where it receives it: the
  // transport of any normalized model maps a uniform E to B = E.
  const auto identity = [](std::span<const glm::vec3> e) {
    return std::vector<glm::vec3>(e.begin(), e.end());
  };
  const BounceResult r = iterateInterreflection(gather, direct, identity, 0, 1e-5);
  EXPECT_GT(r.bounces, 2);
  EXPECT_LT(r.change, 1e-5);
  // Radiance along the normal: the exit model of B plus the reflected sky, F_r(1) * 1.
  const double exitScale = fresnelTransmittance(1.0f, eta) * exitRadianceScale(eta);
  const double reflected = fresnelDielectric(1.0f, eta);
  double pitDirect = 0.0, pitAfter = 0.0;
  int pit = 0;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const double l = r.exitance[v].g * exitScale + reflected;
    ASSERT_NEAR(l, 1.0, 0.06) << "vertex " << v;
    if (direct[v].g / full < 0.8) {  // sees less than ~80 % of the sky
      ++pit;
      pitDirect += direct[v].g / full;
      pitAfter += r.exitance[v].g * exitScale + reflected;
    }
  }
  ASSERT_GT(pit, 10);
  EXPECT_LT(pitDirect / pit, 0.75);        // without interreflection: dark
  EXPECT_NEAR(pitAfter / pit, 1.0, 0.01);  // with it: the furnace's radiance 1
}

TEST(Interreflection, ConvexObjectsSendThemselvesNothing) {
  const TriangleMesh sphere = makeIcosphere(2, 10.0f);
  const Cubemap white(8, glm::vec3(1.0f));
  const InterreflectionGather gather(sphere.positions, sphere.normals, sphere.triangles, white,
                                     1.3f, {});
  EXPECT_EQ(gather.blockedFraction(), 0.0);
  const std::vector<glm::vec3> b(sphere.positions.size(), glm::vec3(1.0f));
  for (const glm::vec3& e : gather.gather(b)) EXPECT_EQ(e, glm::vec3(0.0f));
}

}  // namespace
}  // namespace sss

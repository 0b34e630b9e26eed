// Several materials in one object (lib/bake/material_parts.h): a vertex's shares of the materials
// follow its triangles' areas, and a sphere of two media baked with the border rule matches a
// Monte Carlo of both media (tests/support/two_media_sphere.h) better than the receiver's rule
// or the symmetric kernel alone, within what the bake predicts for the border.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bake/bake.h"
#include "bake/material_parts.h"
#include "material/material.h"
#include "mesh/triangle_mesh.h"
#include "support/tool_test.h"
#include "support/two_media_sphere.h"

namespace sss {
namespace {

TEST(MaterialParts, SharesFollowTheTrianglesAreas) {
  // Two triangles on the edge (0, 1): the first of area 1 (material 0), the second of area 3
  // (material 1, through part 2).
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, -3, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 3, 1}};
  const std::vector<std::uint32_t> trianglePart = {0, 2}, partMaterial = {0, 0, 1};
  const auto shares = vertexMaterialShares(mesh, trianglePart, partMaterial, 2);
  ASSERT_EQ(shares.size(), 2u);
  EXPECT_FLOAT_EQ(shares[0][0], 0.25f);
  EXPECT_FLOAT_EQ(shares[1][0], 0.75f);
  EXPECT_FLOAT_EQ(shares[0][1], 0.25f);
  EXPECT_FLOAT_EQ(shares[0][2], 1.0f);
  EXPECT_FLOAT_EQ(shares[1][3], 1.0f);
  const std::vector<float> areas = {4.0f / 3, 4.0f / 3, 1.0f / 3, 1.0f};
  const std::vector<double> area = areaShares(shares, areas);
  EXPECT_NEAR(area[0], 0.25, 1e-6);
  EXPECT_NEAR(area[1], 0.75, 1e-6);
}

BakeOutput bakeHalves(const std::string& glb, MaterialRule rule) {
  BakeSettings s;
  s.meshPath = glb;
  s.material = findMaterialPreset("skin1");
  s.materialMap = parseMaterialMap("Upper=marble");
  s.materialRule = rule;
  s.run.quiet = true;
  return bake(s, BakeEnvironment{Cubemap(16, glm::vec3(1.0f)), {}});
}

// A 5 mm marble / skin1 sphere under uniform light: marble's light reaches far into the skin1
// half, and its own half loses light into skin1's absorption. The border rule is closer to a
// Monte Carlo of both media than the receiver's rule (which leaves the marble side too bright)
// and than the symmetric kernel alone (which makes skin1's blue too bright next to the marble).
TEST(MaterialParts, TwoMediaSphereMatchesAMonteCarloOfBothMedia) {
  test::ScratchDir dir;
  const std::string glb = dir.path("halves.glb");
  constexpr double kRadiusMm = 5.0;
  test::writeHalvesGlb(glb, kRadiusMm);
  const Material marble = findMaterialPreset("marble"), skin = findMaterialPreset("skin1");
  constexpr int kWalks = 10000;
  const std::vector<test::RingReference> ref =
      test::halvesReference(kRadiusMm, marble, skin, kWalks);
  const BakeOutput border = bakeHalves(glb, MaterialRule::Border);
  const std::vector<glm::dvec3> mixed = test::ringMeans(border.baked);
  const double borderError = test::ringRms(mixed, ref);
  const double receiverError =
      test::ringRms(test::ringMeans(bakeHalves(glb, MaterialRule::Receiver).baked), ref);
  const std::vector<glm::dvec3> symmetric =
      test::ringMeans(bakeHalves(glb, MaterialRule::Symmetric).baked);
  const auto worst = [&](const std::vector<glm::dvec3>& a) {
    double w = 0.0;
    for (std::size_t r = 0; r < ref.size(); ++r)
      for (int c = 0; c < 3; ++c) w = std::max(w, std::abs(a[r][c] / ref[r].radiance[c] - 1.0));
    return w;
  };
  std::printf("relative RMS: border %.4f, receiver %.4f; worst ring: border %.3f, symmetric %.3f\n",
              borderError, receiverError, worst(mixed), worst(symmetric));
  EXPECT_LT(borderError, 0.1);
  EXPECT_GT(receiverError, 1.2 * borderError);
  // Measured: 0.349 against 0.309 (0.39 against 0.32 with the normalized exit model everywhere;
  // skin1's half now leaves through its exit lobe, bake.cpp).
  EXPECT_GT(worst(symmetric), 1.05 * worst(mixed));
  // What the border adds beyond the one-material models' own error (their bakes against their
  // own spheres' references) is within what the JSON predicts, and not far below it.
  const auto oneMaterial = [&](const std::string& preset) {
    BakeSettings s;
    s.meshPath = glb;
    s.material = findMaterialPreset(preset);
    s.run.quiet = true;
    return test::ringMeans(bake(s, BakeEnvironment{Cubemap(16, glm::vec3(1.0f)), {}}).baked);
  };
  std::vector<glm::dvec3> own = oneMaterial("marble");
  const std::vector<glm::dvec3> lower = oneMaterial("skin1");
  std::vector<test::RingReference> ownRef =
      test::halvesReference(kRadiusMm, marble, marble, kWalks);
  const std::vector<test::RingReference> lowerRef =
      test::halvesReference(kRadiusMm, skin, skin, kWalks);
  for (int r = test::kHalvesRings / 2; r <= test::kHalvesRings; ++r) {
    own[r] = r == test::kHalvesRings / 2 ? mixed[r] : lower[r];
    if (r > test::kHalvesRings / 2) ownRef[r] = lowerRef[r];
  }
  const double added = test::ringRms(mixed, ref, own, ownRef);
  const double predicted = border.report.errors.model.materialInterface;
  std::printf("the border adds %.4f, predicted %.4f\n", added, predicted);
  EXPECT_GT(predicted, added);
  EXPECT_LT(predicted, 2.0 * added);
}

}  // namespace
}  // namespace sss

// The model's error estimate (lib/bake/model_error.h) on meshes whose three terms are known in
// closed form: a flat plane under even light (only the exit model's spread), the apex of a
// pyramid (its facets' tilt), a triangle lit at one corner (the light's contrast over the ring).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "bake/model_error.h"
#include "material/material.h"
#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"

namespace sss {
namespace {

TEST(ModelError, FlatEvenlyLitPlaneHasOnlyTheExitModelsSpread) {
  const TriangleMesh plane = makeGridPlane(8, 10.0f);
  const std::size_t n = plane.positions.size();
  const std::vector<glm::vec3> e(n, glm::vec3(2.0f)), red(n, glm::vec3(1.0f, 0.0f, 0.0f));
  const glm::vec3 spread(0.04f, 0.1f, 0.2f);
  const ModelErrorReport r = estimateModelError({plane, red, e, spread});
  EXPECT_NEAR(r.facets, 0.0, 1e-7);
  EXPECT_NEAR(r.lightVariation, 0.0, 1e-7);
  // Weighted by L^2: only the red channel carries radiance.
  EXPECT_NEAR(r.exitModel, kExitModelWeight * 0.04, 1e-7);
  EXPECT_NEAR(r.total, r.exitModel, 1e-12);
  // Grey radiance: the RMS of the three spreads.
  const std::vector<glm::vec3> grey(n, glm::vec3(1.0f));
  const ModelErrorReport g = estimateModelError({plane, grey, e, spread});
  EXPECT_NEAR(g.exitModel, kExitModelWeight * std::sqrt((0.0016 + 0.01 + 0.04) / 3.0), 1e-7);
}

TEST(ModelError, PyramidApexTiltsByItsFacesAngle) {
  // Apex (0, 0, 1) over the square (+-1, +-1, 0): each face tilts 45 degrees from the apex's
  // normal +z, so 1 - cos theta = 1 - 1/sqrt(2). Only the apex carries radiance.
  TriangleMesh m;
  m.positions = {{0, 0, 1}, {1, 1, 0}, {-1, 1, 0}, {-1, -1, 0}, {1, -1, 0}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  m.triangles = {{0, 4, 1}, {0, 1, 2}, {0, 2, 3}, {0, 3, 4}};
  std::vector<glm::vec3> l(5, glm::vec3(0.0f));
  l[0] = glm::vec3(1.0f);
  const std::vector<glm::vec3> e(5, glm::vec3(1.0f));
  const ModelErrorReport r = estimateModelError({m, l, e, glm::vec3(0.0f)});
  EXPECT_NEAR(r.facets, kFacetWeight * (1.0 - 1.0 / std::sqrt(2.0)), 1e-6);
  EXPECT_NEAR(r.exitModel, 0.0, 1e-12);
  EXPECT_NEAR(r.lightVariation, 0.0, 1e-12);
}

TEST(ModelError, LightChangingAcrossARingIsItsContrast) {
  // One triangle lit at a corner: that corner's ring mean is 0 (contrast 1), the other two see
  // (1 + 0) / 2 against their 0 (contrast 1 again); half the light at the corner halves nothing,
  // the contrast being relative.
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  m.triangles = {{0, 1, 2}};
  const std::vector<glm::vec3> l(3, glm::vec3(1.0f));
  for (const float corner : {1.0f, 0.5f}) {
    const std::vector<glm::vec3> e = {glm::vec3(corner), glm::vec3(0.0f), glm::vec3(0.0f)};
    EXPECT_NEAR(estimateModelError({m, l, e, glm::vec3(0.0f)}).lightVariation,
                kLightVariationWeight, 1e-7);
  }
  // Even light: no contrast.
  const std::vector<glm::vec3> even(3, glm::vec3(0.3f));
  EXPECT_NEAR(estimateModelError({m, l, even, glm::vec3(0.0f)}).lightVariation, 0.0, 1e-7);
}

TEST(ModelError, ExitModelSpreadGrowsAsTheAlbedoFalls) {
  // The normalized and calibrated exit models agree near albedo 1 (marble) and part at skin's
  // and ketchup's (README, "Under a sun": 1 %, 4-7 %, 7-12 % apart).
  const glm::vec3 marble = exitModelSpread(findMaterialPreset("marble"));
  const glm::vec3 skin = exitModelSpread(findMaterialPreset("skin1"));
  const glm::vec3 ketchup = exitModelSpread(findMaterialPreset("ketchup"));
  for (int c = 0; c < 3; ++c) {
    EXPECT_LT(marble[c], 0.015f);
    EXPECT_GT(skin[c], marble[c]);
    EXPECT_GT(ketchup[c], 0.05f);
  }
  EXPECT_GT(skin.z, skin.x);  // blue: the lowest albedo of skin1
}

}  // namespace
}  // namespace sss

// What sss-render takes from a baked mesh before drawing (render/baked_shading.h): eta, exit
// scale, the brdf mode's albedo, culling, the attributes each mode needs. No GL.
#include <cmath>

#include <gtest/gtest.h>

#include "material/directional_albedo_weight.h"
#include "material/halfspace_albedo.h"
#include "mesh/primitives.h"
#include "optics/fresnel.h"
#include "render/baked_shading.h"

namespace sss {
namespace {

BakedPlyContents marbleSphere() {
  BakedPlyContents c;
  c.baked.mesh = makeIcosphere(1, 1.0f);
  c.baked.exitance.assign(c.baked.mesh.positions.size(), glm::vec3(0.5f));
  c.baked.sigmaA = glm::dvec3(0.0021, 0.0041, 0.0071);
  c.baked.sigmaSPrime = glm::dvec3(2.19, 2.62, 3.00);
  c.baked.eta = 1.4;
  c.hasExitance = true;
  c.hasMaterial = true;
  return c;
}

TEST(BakedShading, EtaComesFromTheMaterialUnlessAsked) {
  BakedPlyContents c = marbleSphere();
  ShadingRequest request;
  ShadingParameters p = shadingFor(c, request);
  EXPECT_EQ(p.eta, 1.4f);
  EXPECT_FALSE(p.etaIsFallback);
  EXPECT_EQ(p.exitScale, static_cast<float>(exitRadianceScale(1.4f)));
  request.eta = 1.2f;
  request.exitModel = ExitModel::Jensen;
  p = shadingFor(c, request);
  EXPECT_EQ(p.eta, 1.2f);
  EXPECT_EQ(p.exitScale, static_cast<float>(1.0 / M_PI));
  // The calibrated exit model carries the material's angular weights; marble's albedo is near
  // 1, so they are near 1, a little below along the normal.
  request = {};
  EXPECT_EQ(shadingFor(c, request).exitWeight[16].x, 1.0f);  // normalized by default
  request.exitModel = ExitModel::Calibrated;
  p = shadingFor(c, request);
  const DirectionalAlbedoWeight w(c.baked.sigmaSPrime / (c.baked.sigmaA + c.baked.sigmaSPrime),
                                  1.4);
  for (int k = 0; k < kExitWeightNodes; ++k)
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_FLOAT_EQ(p.exitWeight[k][ch], w.at(float(k) / (kExitWeightNodes - 1))[ch]);
  EXPECT_LT(p.exitWeight[16].x, 1.0f);
  EXPECT_GT(p.exitWeight[16].x, 0.97f);
  request.exitModel = ExitModel::Normalized;
  p = shadingFor(c, request);
  EXPECT_EQ(p.exitWeight[16].x, 1.0f);
  // No material recorded: the fallback, said so for the sss mode.
  c.hasMaterial = false;
  p = shadingFor(c, {});
  EXPECT_EQ(p.eta, kFallbackEta);
  EXPECT_TRUE(p.etaIsFallback);
}

// The albedo of the model the bake uses: the Monte Carlo half-space albedo, not the dipole's total.
TEST(BakedShading, BrdfAlbedoIsTheHalfSpaceAlbedo) {
  BakedPlyContents c = marbleSphere();
  ShadingRequest request;
  request.mode = ShadingMode::Brdf;
  ShadingParameters p = shadingFor(c, request);
  const double alpha = 2.62 / (2.62 + 0.0041);
  EXPECT_EQ(p.albedo.g, static_cast<float>(halfSpaceDiffuseAlbedo(alpha, 1.4f)));
  EXPECT_FALSE(p.albedoIsFallback);
  request.albedo = glm::vec3(0.1f, 0.2f, 0.3f);
  EXPECT_EQ(shadingFor(c, request).albedo, glm::vec3(0.1f, 0.2f, 0.3f));
  c.hasMaterial = false;
  request.albedo.reset();
  p = shadingFor(c, request);
  EXPECT_EQ(p.albedo, glm::vec3(kFallbackAlbedo));
  EXPECT_TRUE(p.albedoIsFallback);
  EXPECT_FALSE(p.etaIsFallback);  // said for the sss mode only
}

TEST(BakedShading, AutoCullsOnlyClosedConsistentMeshes) {
  BakedPlyContents c = marbleSphere();
  ShadingRequest request;
  EXPECT_TRUE(shadingFor(c, request).cullBackFaces);
  c.report.boundaryEdges = 4;
  EXPECT_FALSE(shadingFor(c, request).cullBackFaces);
  request.cull = CullMode::Back;
  EXPECT_TRUE(shadingFor(c, request).cullBackFaces);
  c.report.boundaryEdges = 0;
  request.cull = CullMode::None;
  EXPECT_FALSE(shadingFor(c, request).cullBackFaces);
}

TEST(BakedShading, EachModeNamesTheValuesItLacks) {
  BakedPlyContents c = marbleSphere();
  EXPECT_EQ(missingBakedValues(c, ShadingMode::Sss), "");
  EXPECT_EQ(missingBakedValues(c, ShadingMode::Irradiance),
            "irradiance_r, irradiance_g, irradiance_b");
  EXPECT_EQ(missingBakedValues(c, ShadingMode::Brdf), "");
  c.hasExitance = false;
  EXPECT_EQ(missingBakedValues(c, ShadingMode::Sss), "exitance_r, exitance_g, exitance_b");
  const RenderMesh sss = renderMeshFor(marbleSphere().baked, ShadingMode::Sss);
  EXPECT_EQ(sss.values.size(), sss.positions.size());
  EXPECT_EQ(sss.indices.size(), 3 * marbleSphere().baked.mesh.triangles.size());
  EXPECT_TRUE(renderMeshFor(marbleSphere().baked, ShadingMode::Brdf).values.empty());
}

}  // namespace
}  // namespace sss

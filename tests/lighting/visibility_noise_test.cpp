// The visibility noise model behind `--samples auto` (bake.h): the error in B it predicts from the
// pilot must be the error measured against a many-ray reference, and a tighter budget must buy
// more rays.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/geometric.hpp>

#include "bake/bake.h"
#include "core/relative_rms.h"
#include "diffusion/diffusion.h"
#include "floor_and_wall.h"
#include "lighting/visibility.h"
#include "material/diffusion_profile.h"
#include "material/material.h"
#include "material/profile_factory.h"
#include "mesh/triangle_mesh.h"

namespace sss {
namespace {

// A sky gradient plus a small bright blob (a sun): both shadow edges and texel sampling noise.
Cubemap sunAndSky(int size) {
  Cubemap env(size);
  forEachTexel(size, [&](int f, int x, int y) {
    env.at(f, x, y) = glm::vec3(0.4f, 0.6f, 1.0f) * (1.2f + env.direction(f, x, y).y);
  });
  const int c = size / 2;
  for (int y = c; y < c + 2; ++y)
    for (int x = c - 3; x < c - 1; ++x)
      env.at(static_cast<int>(CubeFace::PosY), x, y) = glm::vec3(300.0f, 250.0f, 200.0f);
  return env;
}

// Scaled to 50 mm: with ketchup's ~1 mm mean free path each B averages only a few vertices.
TriangleMesh noisyScene() {
  TriangleMesh mesh = floorAndWall(30);
  for (glm::vec3& p : mesh.positions) p *= 5.0f;
  return mesh;
}

struct Scene {
  TriangleMesh mesh = noisyScene();
  std::vector<float> areas = vertexAreas(mesh);
  Cubemap env = sunAndSky(16);
  std::unique_ptr<DiffusionProfile> profile = makeProfile("dipole", findMaterialPreset("ketchup"));

  std::vector<glm::vec3> exitance(int samples, uint64_t seed, VisibilityNoiseModel* model) const {
    VisibilityOptions options;
    options.samples = samples;
    options.run.seed = seed;
    options.run.threads = 2;
    if (model) {
      options.pilot = VisibilityPilotOptions{};
      options.chooseSamples = [&](const VisibilityPilot& pilot) {
        *model = visibilityNoiseModel(pilot, mesh.positions, areas, *profile);
        return samples;
      };
    }
    const std::vector<glm::vec3> e = transmittedIrradianceWithVisibility(
        mesh.positions, mesh.normals, mesh.triangles, env, 1.3f, options);
    DiffusionOptions diffusion;
    diffusion.method = DiffusionMethod::Gauss;
    diffusion.tolerance = 1e-3;
    diffusion.run.threads = 2;
    diffusion.run.quiet = true;
    return diffuse({mesh.positions, mesh.normals, areas, e}, *profile, diffusion).exitance;
  }
};

TEST(VisibilityNoiseModel, PredictsTheMeasuredErrorOfB) {
  const Scene scene;
  const std::vector<glm::vec3> reference = scene.exitance(1024, 99, nullptr);
  for (int samples : {16, 32}) {
    VisibilityNoiseModel model;
    const double measured = relativeRms(scene.exitance(samples, 1, &model), reference);
    // The reference's own noise adds in quadrature.
    const double predicted = std::hypot(model.errorAt(samples), model.errorAt(1024));
    std::printf("%d rays: predicted %.4g, measured %.4g, rate %.3g, N_eff %.3g\n", samples,
                predicted, measured, model.rate, model.meanEffectiveVertices);
    EXPECT_GT(measured, 0.005) << "the scene must be noisy enough to test anything";
    EXPECT_GT(predicted / measured, 0.5) << samples << " rays: " << predicted << " vs " << measured;
    EXPECT_LT(predicted / measured, 2.0) << samples << " rays: " << predicted << " vs " << measured;
    EXPECT_GE(model.rate, 1.0);
    EXPECT_LE(model.rate, 1.5);
    EXPECT_GT(model.meanEffectiveVertices, 1.0);
  }
}

TEST(VisibilityNoiseModel, TighterBudgetPicksMoreRays) {
  const Scene scene;
  VisibilityNoiseModel model;
  scene.exitance(16, 1, &model);
  // The fewest whole strata of 16 rays that meet the budget.
  EXPECT_EQ(chooseVisibilitySamples(model, model.errorAt(48) * 1.001), 48);
  EXPECT_EQ(chooseVisibilitySamples(model, model.errorAt(48) * 0.999), 64);
  EXPECT_EQ(chooseVisibilitySamples(model, model.errorAt(256) * 1.001), 256);
  EXPECT_EQ(chooseVisibilitySamples(model, 1.0), kMinAutoSamples);
  EXPECT_EQ(chooseVisibilitySamples(model, 0.0), kMaxAutoSamples);
  // A larger cap (a coarse mesh) is used only when the budget needs it.
  EXPECT_EQ(chooseVisibilitySamples(model, model.errorAt(48) * 1.001, 4096), 48);
  EXPECT_EQ(chooseVisibilitySamples(model, model.errorAt(2000) * 1.001, 4096), 2000);
  EXPECT_EQ(chooseVisibilitySamples(model, 0.0, 4096), 4096);
  // The cap follows the mesh: the same total rays, at least 1024 and at most 16384 per vertex.
  EXPECT_EQ(maxAutoSamples(16384), kMaxAutoSamples);
  EXPECT_EQ(maxAutoSamples(100000), kMaxAutoSamples);
  EXPECT_EQ(maxAutoSamples(1839), 9120);  // the sample bunny: 16,777,216 / 1839 = 9123.1
  EXPECT_EQ(maxAutoSamples(100), kMaxAutoSamplesCoarse);
  // More rays, less predicted noise; the pilot's model is the same for any thread count.
  EXPECT_LT(model.errorAt(256), model.errorAt(32));
}

}  // namespace
}  // namespace sss

// Bake stage 3 (lib/bake/light_vertices.h): the transmitted irradiance E per vertex, from the
// irradiance cubemap (mode none) and from visibility rays (mode rays), against the closed form of
// a uniform sky, each other on a convex sphere, and the directional entry's weight under a sun.
#include "bake/light_vertices.h"
#include "support/small_sun.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "envmap/cubemap.h"
#include "material/diffusion_profile.h"
#include "material/directional_albedo_weight.h"
#include "material/material.h"
#include "material/profile_factory.h"
#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"
#include "optics/fresnel.h"
#include "support/box_with_pit.h"

namespace sss {
namespace {

const glm::vec3 kRadiance(0.5f, 1.0f, 2.0f);

struct Scene {
  TriangleMesh mesh = makeIcosphere(2, 10.0f);  // 162 vertices, radius 10 mm
  std::vector<float> areas = vertexAreas(mesh);
  Material material = findMaterialPreset("skin1");
  std::unique_ptr<DiffusionProfile> profile = makeProfile("dipole", material);
};

LightingInput inputFor(const Scene& s, const Cubemap& env, VisibilityMode mode, int samples = 0) {
  return {.meshMm = s.mesh,
          .areasMm2 = s.areas,
          .radiance = env,
          .profile = *s.profile,
          .eta = static_cast<float>(s.material.eta),
          .mode = mode,
          .samples = samples,
          .visibilityBudget = 0.009,  // a 1 % bake's rays alone (ErrorBudget::visibilityBudget)
          .visibilityShare = 0.9,
          .tolerance = 0.01,
          .run = {.seed = 3, .threads = 2, .quiet = true}};
}

// Under a uniform sky of radiance L every normal takes
//   E = integral over the hemisphere of F_t(eta, mu) mu L dw = pi L (1 - 2 C_1(eta)),
// 2 C_1 the diffuse Fresnel reflectance (Li & Guo Eq. 6 without shadows; fresnel.h).
glm::dvec3 uniformSkyIrradiance(float eta) {
  return M_PI * (1.0 - diffuseFresnelReflectance(eta)) * glm::dvec3(kRadiance);
}

// Largest |E_v / E_ref - 1| over vertices and channels.
double maxRelativeDeviation(const std::vector<glm::vec3>& e, const glm::dvec3& reference) {
  double worst = 0.0;
  for (const glm::vec3& v : e)
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(v[c] / reference[c] - 1.0));
  return worst;
}

// Mode none: the irradiance cubemap, looked up at each vertex, gives the closed form at every
// vertex within the cubemap's tolerance (1 %, its relative RMS on the sphere), and reports its
// own error within that tolerance too. It has no per-direction samples: no E_w.
TEST(LightVertices, CubemapUnderAUniformSkyGivesPiLTimesTheDiffuseTransmittance) {
  const Scene s;
  const Cubemap sky(16, kRadiance);
  const VertexLighting lit = lightVertices(inputFor(s, sky, VisibilityMode::None));
  ASSERT_EQ(lit.irradiance.size(), s.mesh.vertexCount());
  const glm::dvec3 reference = uniformSkyIrradiance(static_cast<float>(s.material.eta));
  EXPECT_LT(maxRelativeDeviation(lit.irradiance, reference), 0.01);
  EXPECT_EQ(lit.report.mode, VisibilityMode::None);
  EXPECT_GT(lit.report.cubemap.faceSize, 0);
  EXPECT_LE(lit.report.estimatedError, 0.01);
  EXPECT_TRUE(lit.entryWeighted.empty());
  EXPECT_EQ(lit.report.entry, EntryModel::Diffuse);
  EXPECT_EQ(&lit.transportIrradiance(), &lit.irradiance);
}

// Mode rays on a convex sphere: no ray above a vertex's tangent plane meets the mesh, so the ratio
// estimator (visibility_vertex_estimator.h: E = U Y / X with Y = X when nothing is blocked) returns
// the unoccluded light U exactly, whatever the ray count: the closed form again, the same as mode
// none (within 0.2 %: U's cubemap lookup is good to 0.03 %, visibility_test.cpp; measured 6e-5),
// an occluded fraction of 0, and a pilot whose noise model predicts no noise, so auto takes
// the fewest rays (kMinAutoSamples) and says that they meet the budget.
TEST(LightVertices, RaysOnAConvexSphereAgreeWithTheCubemapAndNeedTheFewestRays) {
  const Scene s;
  const Cubemap sky(16, kRadiance);
  const VertexLighting rays = lightVertices(inputFor(s, sky, VisibilityMode::Rays));
  const VertexLighting cubemap = lightVertices(inputFor(s, sky, VisibilityMode::None));
  const glm::dvec3 reference = uniformSkyIrradiance(static_cast<float>(s.material.eta));
  EXPECT_LT(maxRelativeDeviation(rays.irradiance, reference), 0.01);
  for (std::size_t v = 0; v < s.mesh.vertexCount(); ++v)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(rays.irradiance[v][c] / cubemap.irradiance[v][c], 1.0, 0.002)
          << "vertex " << v << " channel " << c;

  const LightingReport& r = rays.report;
  EXPECT_EQ(r.mode, VisibilityMode::Rays);
  EXPECT_EQ(r.rays.visibility.occludedFraction, 0.0);
  EXPECT_GT(r.rays.visibility.rays, 0u);
  EXPECT_EQ(r.rays.visibility.relativeStdError, 0.0);
  EXPECT_EQ(r.rays.noiseModel.variance, 0.0);
  EXPECT_EQ(r.estimatedError, 0.0);
  EXPECT_EQ(r.rays.irradianceError, 0.0);
  EXPECT_EQ(r.rays.samplesRequested, 0);
  EXPECT_EQ(r.rays.samples, kMinAutoSamples);
  EXPECT_EQ(r.rays.visibility.pilot.replicas, VisibilityPilotOptions{}.replicas);
  EXPECT_EQ(r.rays.samplesReason.rfind("fewest rays", 0), 0u) << r.rays.samplesReason;
  EXPECT_EQ(r.rays.budget, 0.009);  // auto: the visibility budget
  EXPECT_EQ(r.rays.seed, 3u);
  EXPECT_EQ(r.entry, EntryModel::Diffuse);  // no entry weight given
  EXPECT_TRUE(rays.entryWeighted.empty());
}

// Forced rays: the count asked for, reported as forced, and the whole tolerance as their budget
// (they are outside the error split: light_vertices.cpp).
TEST(LightVertices, ForcedSamplesAreReportedAsForced) {
  const Scene s;
  const Cubemap sky(16, kRadiance);
  const VertexLighting lit = lightVertices(inputFor(s, sky, VisibilityMode::Rays, 48));
  EXPECT_EQ(lit.report.rays.samples, 48);
  EXPECT_EQ(lit.report.rays.visibility.samples, 48);
  EXPECT_EQ(lit.report.rays.samplesRequested, 48);
  EXPECT_EQ(lit.report.rays.samplesReason, "forced by the requested sample count");
  EXPECT_EQ(lit.report.rays.budget, 0.01);
  const glm::dvec3 reference = uniformSkyIrradiance(static_cast<float>(s.material.eta));
  EXPECT_LT(maxRelativeDeviation(lit.irradiance, reference), 0.01);
}

// The directional entry weights each direction by w(mu) (directional_albedo_weight.h). At a vertex
// facing a small sun every sample has mu > 0.9995, so E_w / E = w(1) per channel (skin1 takes
// less light at normal incidence than diffuse light: w(1) = 0.96 / 0.94 / 0.93), and on the
// dark side both are 0. Under a uniform sky w averages to 1 over F_t mu: E_w = E (the identity
// directional_albedo_weight.h states), which is what the transport then sums.
TEST(LightVertices, EntryWeightedIrradianceFollowsTheWeightAtNormalIncidence) {
  const Scene s;
  const DirectionalAlbedoWeight weight(s.material);
  const glm::vec3 w1 = weight.at(1.0f);
  for (int c = 0; c < 3; ++c) EXPECT_LT(w1[c], 0.97f) << "channel " << c;

  const glm::vec3 sun = s.mesh.normals[0];
  const Cubemap env = smallSun(sun);
  LightingInput in = inputFor(s, env, VisibilityMode::Rays, 32);
  in.entry = &weight;
  const VertexLighting lit = lightVertices(in);
  ASSERT_EQ(lit.entryWeighted.size(), s.mesh.vertexCount());
  EXPECT_EQ(lit.report.entry, EntryModel::Directional);
  EXPECT_EQ(&lit.transportIrradiance(), &lit.entryWeighted);
  ASSERT_GT(lit.irradiance[0].x, 0.0f);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(lit.entryWeighted[0][c] / lit.irradiance[0][c], w1[c], 0.001) << "channel " << c;
  for (std::size_t v = 0; v < s.mesh.vertexCount(); ++v)
    if (glm::dot(s.mesh.normals[v], sun) < -0.1f) {
      EXPECT_EQ(lit.irradiance[v], glm::vec3(0.0f)) << "vertex " << v;
      EXPECT_EQ(lit.entryWeighted[v], glm::vec3(0.0f)) << "vertex " << v;
    }

  const Cubemap sky(16, kRadiance);
  LightingInput uniform = inputFor(s, sky, VisibilityMode::Rays, 32);
  uniform.entry = &weight;
  const VertexLighting even = lightVertices(uniform);
  for (std::size_t v = 0; v < s.mesh.vertexCount(); ++v)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(even.entryWeighted[v][c] / even.irradiance[v][c], 1.0, 0.002)
          << "vertex " << v << " channel " << c;
}

// On a concave object the rays see its shadows: in boxWithPit's pit (its floor sees about 70 % of
// the sky) E falls below the uniform sky's closed form and rays are occluded; elsewhere none is
// brighter than it. E depends on the seed alone, not on the thread count (Pcg32(seed, vertex) per
// vertex, visibility.h): 1 and 2 threads give the same E bit for bit, another seed another E.
TEST(LightVertices, RaysSeeThePitsShadowAndAreTheSameForAnyThreadCount) {
  Scene s;
  s.mesh = boxWithPit();
  s.areas = vertexAreas(s.mesh);
  const Cubemap sky(16, kRadiance);
  LightingInput one = inputFor(s, sky, VisibilityMode::Rays, 32);
  one.run.threads = 1;
  LightingInput two = one;
  two.run.threads = 2;
  const VertexLighting a = lightVertices(one), b = lightVertices(two);
  EXPECT_EQ(a.irradiance, b.irradiance);
  EXPECT_GT(a.report.rays.visibility.occludedFraction, 0.0);

  const glm::dvec3 reference = uniformSkyIrradiance(static_cast<float>(s.material.eta));
  std::size_t pitFloor = 0;
  for (std::size_t v = 0; v < s.mesh.vertexCount(); ++v) {
    const glm::vec3 p = s.mesh.positions[v];
    for (int c = 0; c < 3; ++c) EXPECT_LT(a.irradiance[v][c], 1.01 * reference[c]);
    if (std::hypot(p.x, p.y) < 2.0f && p.z > 0.0f && p.z < 6.0f) {  // pit floor, 5-6 mm deep
      ++pitFloor;
      for (int c = 0; c < 3; ++c) EXPECT_LT(a.irradiance[v][c], 0.85 * reference[c]);
    }
  }
  EXPECT_GT(pitFloor, 0u);

  LightingInput other = one;
  other.run.seed = 4;
  EXPECT_NE(lightVertices(other).irradiance, a.irradiance);
}

}  // namespace
}  // namespace sss

// The far field (lib/transport/far_field.h) against the forward light tracer: a sun-lit sphere's
// unlit half, the near + far split under uniform light (where B = E P must still hold), auto's
// choice, determinism across thread counts and bad options.
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "bake/bake.h"
#include "bake/bake_settings.h"
#include "bench/study_support.h"
#include "core/error.h"
#include "core/luminance.h"
#include "diffusion/diffusion.h"
#include "envmap/cubemap.h"
#include "lighting/visibility.h"
#include "material/diffusion_profile.h"
#include "material/directional_albedo_weight.h"
#include "material/material.h"
#include "material/profile_factory.h"
#include "mesh/primitives.h"
#include "optics/exit_lobe.h"
#include "optics/fresnel.h"
#include "pathtrace/light_tracer.h"
#include "support/box_with_pit.h"
#include "transport/far_field.h"
#include "transport/finite_object_energy.h"

namespace sss {
namespace {

Cubemap sunEnvironment(const glm::vec3& towardsSun) {
  return study::sunEnvironment(towardsSun, 2.0, 64);  // texels of ~1.4 degrees
}

// E_w per vertex (the directional entry's weighted irradiance) by visibility rays.
std::vector<glm::vec3> entryWeightedIrradiance(const TriangleMesh& mesh, const Cubemap& env,
                                               const Material& m, int samples, int threads) {
  const DirectionalAlbedoWeight weight(m);
  VisibilityOptions vis;
  vis.samples = samples;
  vis.entry = &weight;
  vis.run.threads = threads;
  VisibilityReport visReport;
  transmittedIrradianceWithVisibility(mesh.positions, mesh.normals, mesh.triangles, env,
                                      float(m.eta), vis, &visReport);
  return std::move(visReport.entryWeighted);
}

// The bake's stages on a mesh in mm: E_w by visibility rays, the escape plan with the near share,
// the far field, then B (as lib/bake/bake.cpp runs them at a 1 % tolerance).
struct Baked {
  std::vector<glm::vec3> exitance, farExitance, farSlope;
  FarFieldReport far;
  double nearPartNoise = 0.0;  // calibrateNearPart's
};
Baked bakeWith(const TriangleMesh& mesh, const Cubemap& env, const Material& m, FarFieldMode mode,
               int threads = 0, bool calibrateNearShare = true, uint64_t farSeed = 1) {
  const std::vector<float> areas = vertexAreas(mesh);
  const std::vector<glm::vec3> e = entryWeightedIrradiance(mesh, env, m, 256, threads);
  EnergyOptions energy;
  energy.model = EnergyModel::Escape;
  energy.noiseBudget = 0.006;
  energy.nearWindowMm = farFieldWindowMm(m);
  energy.run.threads = threads;
  EnergyPlan plan = planFiniteObjectEnergy(mesh, areas, m, energy);
  FarFieldOptions o;
  o.mode = mode;
  o.noiseBudget = 0.006 / std::sqrt(2.0);
  o.run.threads = threads;
  o.calibrateNearShare = calibrateNearShare;
  o.run.seed = farSeed;
  const FarField far = traceFarField({mesh, areas, env, m, plan, e, o});
  if (far.traced()) {
    energy.noiseBudget = o.noiseBudget;
    refineNearShare(plan, mesh, areas, m, energy);
  }
  const auto profile = makeProfile("dipole", m);
  DiffusionOptions d;
  d.method = DiffusionMethod::Exact;
  d.run.quiet = true;
  d.run.threads = threads;
  DiffusionResult r = diffuseWithEnergy({mesh.positions, mesh.normals, areas, e}, *profile, d, plan,
                                        m, far.exitance);
  const double nearNoise =
      calibrateNearPart(r.exitance, {mesh, areas, far.exitance, far.nearExitance, far.nearVariance,
                                     far.nearFarCovariance, far.report.smoothingMm, threads});
  return {r.exitance, far.exitance, far.slope, far.report, nearNoise};
}

// Sum of B over the vertices facing away from the sun, area-weighted, all channels.
double unlitSum(const TriangleMesh& sphere, const std::vector<glm::vec3>& b, const glm::vec3& sun) {
  const std::vector<float> areas = vertexAreas(sphere);
  double sum = 0.0;
  for (std::size_t v = 0; v < b.size(); ++v)
    if (glm::dot(glm::normalize(sphere.positions[v]), sun) < 0.0f)
      sum += areas[v] * (b[v].x + b[v].y + b[v].z);
  return sum;
}

// Without the far field, the escape model's geometry-blind kernel puts 1.7x the light on the unlit
// half of a 10 mm skin sphere under a sun. The far field follows the light through it.
TEST(FarField, SunLitSphereUnlitHalfMatchesTheLightTracer) {
  const TriangleMesh sphere = makeIcosphere(3, 10.0f);
  const Material skin = findMaterialPreset("skin1");
  const glm::vec3 sun = glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f));
  const Cubemap env = sunEnvironment(sun);
  const HomogeneousMedium medium = homogeneousMediumOf(skin);
  LightTraceOptions lo;
  lo.paths = 300000;
  lo.run.seed = 99;  // independent of the far field's paths
  const LightTraceResult ref =
      lightTraceSubsurface(sphere.positions, sphere.normals, sphere.triangles,
                           DistantLight::environment(env), medium, lo);
  const double reference = unlitSum(sphere, ref.exitance, sun);

  const Baked withFar = bakeWith(sphere, env, skin, FarFieldMode::Auto);
  ASSERT_TRUE(withFar.far.traced) << withFar.far.reason;
  EXPECT_GT(withFar.far.sensitivity, 0.05);
  // Within its budget, or traced to the work cap and saying so (0.54 % at 2.1M paths).
  if (withFar.far.relativeStdError > 0.006 / std::sqrt(2.0) * 1.05) {
    EXPECT_NE(withFar.far.reason.find("traced to the path cap"), std::string::npos)
        << withFar.far.reason;
  }
  const double ratio = unlitSum(sphere, withFar.exitance, sun) / reference;
  EXPECT_GT(ratio, 0.8);
  EXPECT_LT(ratio, 1.25);
  // What it replaces fails the same check.
  const Baked without = bakeWith(sphere, env, skin, FarFieldMode::Off);
  EXPECT_FALSE(without.far.traced);
  EXPECT_GT(unlitSum(sphere, without.exitance, sun) / reference, 1.5);
}

// The near part of B follows the traced near exits (calibrateNearPart): under a high sun, skin1's
// green and blue light leaves within the near window more often than the escape walks' diffuse
// entry gives (it came straight back). B over the light tracer's, area means over the cap within
// 26 degrees of the sun: 0.99 / 0.99 / 0.99 (R / G / B), with the escape walks' near share as it
// is 1.00 / 0.97 / 0.96. (60-75 degrees from the sun B reads 0.97-0.98 with the calibration and
// 0.99 without: there the uncalibrated near part is too bright and hides the far field's
// averaging, 0.97x; docs/accuracy.md, "Under a sun".)
TEST(FarField, NearPartFollowsTheLightTracerUnderAHighSun) {
  const TriangleMesh sphere = makeIcosphere(3, 10.0f);
  const Material skin = findMaterialPreset("skin1");
  const glm::vec3 sun = glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f));
  const Cubemap env = sunEnvironment(sun);
  LightTraceOptions lo;
  lo.paths = 1000000;
  lo.run.seed = 99;  // independent of the far field's paths
  lo.minScatteringOrder = 1;
  const LightTraceResult ref =
      lightTraceSubsurface(sphere.positions, sphere.normals, sphere.triangles,
                           DistantLight::environment(env), homogeneousMediumOf(skin), lo);
  const std::vector<float> areas = vertexAreas(sphere);
  const auto ratio = [&](const std::vector<glm::vec3>& b, float from, float to) {
    glm::dvec3 sum(0.0), sumRef(0.0);
    for (std::size_t v = 0; v < b.size(); ++v) {
      const float c = glm::dot(glm::normalize(sphere.positions[v]), sun);
      if (c < from || c > to) continue;
      sum += double(areas[v]) * glm::dvec3(b[v]);
      sumRef += double(areas[v]) * glm::dvec3(ref.exitance[v]);
    }
    return sum / sumRef;
  };
  const Baked calibrated = bakeWith(sphere, env, skin, FarFieldMode::On);
  const Baked escapeShare = bakeWith(sphere, env, skin, FarFieldMode::On, 0, false);
  const glm::dvec3 cap = ratio(calibrated.exitance, 0.9f, 1.0f);
  const glm::dvec3 before = ratio(escapeShare.exitance, 0.9f, 1.0f);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(cap[c], 1.0, 0.025) << "channel " << c;
  EXPECT_LT(before.z, 0.975);
  EXPECT_GT(cap.z - before.z, 0.01);
}

// A 20 x 20 x 2 mm ketchup slab lit from behind by a sun 30 degrees off its normal: its red light
// (mean free path 4 mm) leaves the unlit face after a few scatterings, towards grazing angles more
// than diffusion gives. The far field's exit lobe (optics/exit_lobe.h, the slope its own exits
// measured) brings the radiance along the normal there within 8 % of the light tracer's (0.96-0.98
// over two reference seeds), where the normalized exit model for all of B (no lobe) reads
// 1.15-1.17x.
TEST(FarField, ExitLobeGivesTheRadianceLeavingAThinSlab) {
  const TriangleMesh slab = makeSlab(20.0f, 2.0f, 20);
  const Material ketchup = findMaterialPreset("ketchup");
  const glm::vec3 sun(0.5f, 0.0f, -std::sqrt(0.75f));
  const Cubemap env = sunEnvironment(sun);
  LightTraceOptions lo;
  lo.paths = 2000000;
  lo.run.seed = 99;
  lo.minScatteringOrder = 1;  // the unscattered light leaves along the sun, outside the cone
  const LightTraceResult ref =
      lightTraceSubsurface(slab.positions, slab.normals, slab.triangles,
                           DistantLight::environment(env), homogeneousMediumOf(ketchup), lo);
  const Baked baked = bakeWith(slab, env, ketchup, FarFieldMode::On);
  ASSERT_TRUE(baked.far.traced);
  const std::vector<float> areas = vertexAreas(slab);
  const float eta = float(ketchup.eta);
  const ExitLobe lobe(eta);
  const double normalScale = normalExitRadianceScale(eta);
  double reference = 0.0, withLobe = 0.0, normalized = 0.0;
  for (std::size_t v = 0; v < slab.positions.size(); ++v) {
    const glm::vec3 p = slab.positions[v];
    if (slab.normals[v].z < 0.999f || std::abs(p.x) > 5.0f || std::abs(p.y) > 5.0f) continue;
    const double b = baked.exitance[v].r, far = baked.farExitance[v].r;
    EXPECT_LT(baked.farSlope[v].r, -0.2f) << "vertex " << v;  // towards grazing angles
    reference += areas[v] * ref.radiance[v].r;
    withLobe += areas[v] * ((b - far) * normalScale + far * lobe.radiance(baked.farSlope[v].r, 1));
    normalized += areas[v] * b * normalScale;
  }
  EXPECT_NEAR(withLobe / reference, 1.0, 0.08);
  EXPECT_GT(normalized / reference, 1.12);
}

// The far field's averaging bias (the model error's far-field term where it is traced): its
// surface averaging rounds B_far off where it changes fast over the averaging's width, at a sun's
// terminator; under uniform light B_far is flat and only the noise the averaging leaves counts.
TEST(FarField, AveragingBiasIsLargestAtASunsTerminator) {
  const TriangleMesh sphere = makeIcosphere(2, 5.0f);
  const Material marble = findMaterialPreset("marble");
  const Baked sun =
      bakeWith(sphere, sunEnvironment(glm::vec3(0.0f, 0.0f, 1.0f)), marble, FarFieldMode::On);
  const Baked uniform = bakeWith(sphere, Cubemap(16, glm::vec3(1.0f)), marble, FarFieldMode::On);
  ASSERT_TRUE(sun.far.traced && uniform.far.traced);
  EXPECT_GT(sun.far.averagingBias, 0.005) << uniform.far.averagingBias;
  EXPECT_LT(uniform.far.averagingBias, 0.3 * sun.far.averagingBias);
}

// Under uniform light the split is exact in expectation: near (P_near) plus far (traced) must give
// B = E P as the escape model without a far field does, vertex by vertex to the noise.
TEST(FarField, UniformLightKeepsBEqualToEP) {
  const TriangleMesh sphere = makeIcosphere(2, 5.0f);
  const Material marble = findMaterialPreset("marble");
  const Cubemap uniform(16, glm::vec3(1.0f));
  const Baked automatic = bakeWith(sphere, uniform, marble, FarFieldMode::Auto);
  // Nothing for it to move: what auto measures is E's ray noise (0.3 % per vertex) left after its
  // smoothing, below the noise budget it is compared with.
  EXPECT_FALSE(automatic.far.traced) << automatic.far.reason;
  EXPECT_LT(automatic.far.sensitivity, 0.5 * 0.006 / std::sqrt(2.0));
  const Baked forced = bakeWith(sphere, uniform, marble, FarFieldMode::On);
  ASSERT_TRUE(forced.far.traced) << forced.far.reason;
  double sq = 0.0, ref = 0.0;
  glm::dvec3 meanForced(0.0), meanAuto(0.0);
  for (std::size_t v = 0; v < sphere.positions.size(); ++v) {
    const glm::dvec3 f(forced.exitance[v]), a(automatic.exitance[v]);
    sq += glm::dot(f - a, f - a);
    ref += glm::dot(a, a);
    meanForced += f;
    meanAuto += a;
  }
  // The noise budgets (0.42 % each for near and far, 0.6 % for P) allow ~1 % per vertex, and
  // their smoothing correlates neighbours: the means agree to 1.5 % (a budget of half of this
  // one meets 1 %).
  EXPECT_LT(std::sqrt(sq / ref), 0.02);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(meanForced[c] / meanAuto[c], 1.0, 0.015) << c;
}

// A skin1 sphere of `radiusMm` under a sun, its far field traced with seeds 1 and 2 at a budget,
// and B ~ P_near E + B_far (the far field's noise normalization) per vertex.
struct TwoSeeds {
  TriangleMesh sphere;
  std::vector<float> areas;
  FarField a, b;
  std::vector<glm::vec3> exitance;
};

TwoSeeds farFieldOverTwoSeeds(int subdivisions, float radiusMm, double budget) {
  TwoSeeds t;
  t.sphere = makeIcosphere(subdivisions, radiusMm);
  t.areas = vertexAreas(t.sphere);
  const Material skin = findMaterialPreset("skin1");
  const Cubemap env = sunEnvironment(glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f)));
  const std::vector<glm::vec3> e = entryWeightedIrradiance(t.sphere, env, skin, 64, 0);
  EnergyOptions energy;
  energy.model = EnergyModel::Escape;
  energy.nearWindowMm = farFieldWindowMm(skin);
  const EnergyPlan plan = planFiniteObjectEnergy(t.sphere, t.areas, skin, energy);
  FarFieldOptions o;
  o.mode = FarFieldMode::On;
  o.noiseBudget = budget;
  t.a = traceFarField({t.sphere, t.areas, env, skin, plan, e, o});
  o.run.seed = 2;
  t.b = traceFarField({t.sphere, t.areas, env, skin, plan, e, o});
  for (std::size_t v = 0; v < t.areas.size(); ++v)
    t.exitance.push_back(plan.escape.nearProbability[v] * e[v] + t.a.exitance[v]);
  return t;
}

// The noise the far field reports (and the bake adds to its predicted error) holds against the
// spread between two seeds: their difference has twice its variance.
TEST(FarField, ReportedNoiseMatchesTheSpreadOverSeeds) {
  const TwoSeeds t = farFieldOverTwoSeeds(2, 5.0f, 0.01);
  ASSERT_TRUE(t.a.traced() && t.b.traced());
  double diff = 0.0, signal = 0.0;
  for (std::size_t v = 0; v < t.areas.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      const double d = t.a.exitance[v][c] - t.b.exitance[v][c], bv = t.exitance[v][c];
      diff += t.areas[v] * d * d;
      signal += t.areas[v] * bv * bv;
    }
  const double measured = std::sqrt(diff / signal / 2.0);
  const double reported = 0.5 * (t.a.report.relativeStdError + t.b.report.relativeStdError);
  EXPECT_GT(measured / reported, 0.6);
  EXPECT_LT(measured / reported, 1.5);
}

// The exit lobe's noise in the radiance along the normal (FarFieldReport::lobeNoise, part of the
// bake's numerical error), with B held, against the slopes' spread over two seeds: a 10 mm skin1
// sphere at about the bake's budget reads 0.39 % reported against 0.44 % measured. (On the 5 mm
// sphere above, whose lobe kernel spans a third of it, it reads about twice the spread: not
// tested.)
TEST(FarField, ReportedLobeNoiseMatchesTheSpreadOverSeeds) {
  const TwoSeeds t = farFieldOverTwoSeeds(3, 10.0f, 0.0042);
  ASSERT_TRUE(t.a.traced() && t.b.traced());
  const ExitLobe lobe(float(findMaterialPreset("skin1").eta));
  double diff = 0.0, signal = 0.0;
  for (std::size_t v = 0; v < t.areas.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      const double la = lobe.radiance(t.a.slope[v][c], 1.0f);
      const double lb = lobe.radiance(t.b.slope[v][c], 1.0f);
      diff += t.areas[v] * std::pow(t.exitance[v][c] * (la - lb), 2);
      signal += t.areas[v] * std::pow(t.exitance[v][c] * la, 2);
    }
  const double measured = std::sqrt(diff / signal / 2.0);
  const double reported = 0.5 * (t.a.report.lobeNoise + t.b.report.lobeNoise);
  EXPECT_GT(measured / reported, 0.6);
  EXPECT_LT(measured / reported, 1.5);
}

// The noise of B where the far field is traced, its far part's (FarFieldReport::relativeStdError)
// and what the near part's calibration adds to it (calibrateNearPart: the traced near exits'
// variance and their covariance with the far ones, the same paths), against the spread of the
// calibrated B over two of the far field's seeds on a 10 mm skin1 sphere at the bake's budget:
// 0.57 % reported, 0.64 % measured (the far part 0.54 % against 0.45-0.64 % over four seeds).
// Relative to P E + B_far, which counts the far light twice, the noise would read 0.57 % against
// 0.92 %.
TEST(FarField, ReportedNearAndFarNoiseMatchTheSpreadOverSeeds) {
  const TriangleMesh sphere = makeIcosphere(3, 10.0f);
  const Material skin = findMaterialPreset("skin1");
  const Cubemap env = sunEnvironment(glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f)));
  const Baked a = bakeWith(sphere, env, skin, FarFieldMode::On, 0, true, 1);
  const Baked b = bakeWith(sphere, env, skin, FarFieldMode::On, 0, true, 2);
  const std::vector<float> areas = vertexAreas(sphere);
  double diff = 0.0, signal = 0.0;
  for (std::size_t v = 0; v < areas.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      diff += areas[v] * std::pow(a.exitance[v][c] - b.exitance[v][c], 2);
      signal += areas[v] * std::pow(a.exitance[v][c], 2);
    }
  const double measured = std::sqrt(diff / signal / 2.0);
  const double reported = 0.5 * (std::hypot(a.far.relativeStdError, a.nearPartNoise) +
                                 std::hypot(b.far.relativeStdError, b.nearPartNoise));
  EXPECT_GT(a.nearPartNoise, 0.0);
  EXPECT_GT(measured / reported, 0.75);
  EXPECT_LT(measured / reported, 1.33);
}

// The light the object sends itself has no traced far field (that came from the environment):
// with the far field on, the bounces still carry all of P, through the escape model's kernel as
// without it, so that a pit lit mostly by the box's own light keeps its brightness. The near
// share alone would leave the pit's floor 15 % dark (marble's near share is a small part of P).
TEST(FarField, BouncesCarryAllTheLightTheObjectSendsItself) {
  const TriangleMesh box = boxWithPit();
  const Cubemap uniform(16, glm::vec3(1.0f));
  const auto bakePit = [&](FarFieldMode mode) {
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("far_field_pit_" + std::to_string(::getpid()) + ".ply"))
                                 .string();
    study::writeAsciiPly(path, box);
    BakeSettings settings;
    settings.meshPath = path;
    settings.material = findMaterialPreset("marble");
    settings.mmPerUnit = 1.0;
    settings.samples = 64;
    settings.bounces = kAutoBounces;
    settings.tolerance = 0.03;  // a ninth of the default's paths: the effect is 15 %
    settings.farField = mode;
    settings.run.quiet = true;
    BakeOutput out = bake(settings, BakeEnvironment{uniform, {}});
    std::filesystem::remove(path);
    return out;
  };
  const BakeOutput off = bakePit(FarFieldMode::Off), on = bakePit(FarFieldMode::On);
  ASSERT_TRUE(on.report.farField.traced) << on.report.farField.reason;
  ASSERT_GE(on.report.interreflection.bounces, 2);
  double pitOff = 0.0, pitOn = 0.0;
  int pit = 0;
  for (std::size_t v = 0; v < box.positions.size(); ++v) {
    if (std::hypot(box.positions[v].x, box.positions[v].y) > 3.0f || box.normals[v].z < 0.5f)
      continue;  // the pit's floor
    ++pit;
    pitOff += luminance(glm::dvec3(off.baked.exitance[v]));
    pitOn += luminance(glm::dvec3(on.baked.exitance[v]));
  }
  ASSERT_GT(pit, 5);
  EXPECT_NEAR(pitOn / pitOff, 1.0, 0.04);
}

TEST(FarField, SameResultForAnyThreadCount) {
  const TriangleMesh sphere = makeIcosphere(2, 4.0f);
  const Material skin = findMaterialPreset("skin1");
  const Cubemap env = sunEnvironment(glm::vec3(0.0f, 0.0f, 1.0f));
  const Baked one = bakeWith(sphere, env, skin, FarFieldMode::On, 1);
  const Baked two = bakeWith(sphere, env, skin, FarFieldMode::On, 2);
  ASSERT_TRUE(one.far.traced);
  EXPECT_EQ(one.far.paths, two.far.paths);
  EXPECT_EQ(one.exitance, two.exitance);  // the near part's calibration included
  EXPECT_EQ(one.farSlope, two.farSlope);
  EXPECT_EQ(one.far.lobeNoise, two.far.lobeNoise);
}

TEST(FarField, OffAndHalfSpaceTraceNothingAndBadOptionsThrow) {
  const TriangleMesh sphere = makeIcosphere(1, 4.0f);
  const std::vector<float> areas = vertexAreas(sphere);
  const Material skin = findMaterialPreset("skin1");
  const Cubemap env = sunEnvironment(glm::vec3(0.0f, 0.0f, 1.0f));
  const std::vector<glm::vec3> e(sphere.positions.size(), glm::vec3(1.0f));
  EnergyPlan halfSpace;  // model HalfSpace
  FarFieldOptions o;
  o.mode = FarFieldMode::On;
  const FarField none = traceFarField({sphere, areas, env, skin, halfSpace, e, o});
  EXPECT_FALSE(none.traced());
  EXPECT_TRUE(none.exitance.empty());
  o.noiseBudget = 0.0;
  EXPECT_THROW(traceFarField({sphere, areas, env, skin, halfSpace, e, o}), Error);
  o.noiseBudget = 0.01;
  o.maxPaths = o.pilotPaths - 1;
  EXPECT_THROW(traceFarField({sphere, areas, env, skin, halfSpace, e, o}), Error);
}

}  // namespace
}  // namespace sss

// The visibility rays' pilot (lib/lighting/visibility_pilot.h): its evenly strided vertices, its
// option checks, the variance its replicas measure against a many-replica reference of the same
// estimator, and determinism across thread counts.
#include "lighting/visibility_pilot.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/bounds.h"
#include "core/error.h"
#include "core/random.h"
#include "envmap/cubemap.h"
#include "envmap/environment_sampler.h"
#include "lighting/facet_light.h"
#include "lighting/unoccluded_intake.h"
#include "lighting/visibility_vertex_estimator.h"
#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"
#include "optics/fresnel.h"
#include "raytrace/triangle_scene.h"

namespace sss {
namespace {

constexpr float kEta = 1.3f;
const glm::vec3 kRadiance(0.5f, 1.0f, 2.0f);

// pilotVertices: stride s = ceil(n / max), vertices s/2, s/2 + s, ... below n: ascending, evenly
// strided, half a stride in, at most max of them (all when n <= max).
TEST(PilotVertices, EvenlyStridedHalfAStrideInAtMostMax) {
  EXPECT_EQ(pilotVertices(1000, 100).size(), 100u);
  EXPECT_EQ(pilotVertices(1000, 100).front(), 5u);
  EXPECT_EQ(pilotVertices(1000, 100).back(), 995u);
  EXPECT_EQ(pilotVertices(5, 1024), (std::vector<uint32_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(pilotVertices(10, 5), (std::vector<uint32_t>{1, 3, 5, 7, 9}));
  // With an uneven stride fewer than max come out: ceil(10 / 4) = 3, so 1, 4, 7.
  EXPECT_EQ(pilotVertices(10, 4), (std::vector<uint32_t>{1, 4, 7}));
  EXPECT_TRUE(pilotVertices(0, 16).empty());
  EXPECT_EQ(pilotVertices(7, 0), (std::vector<uint32_t>{3}));  // max 0 counts as 1
  for (std::size_t n : {1u, 2u, 17u, 100u, 1023u, 1024u, 1025u, 5000u})
    for (std::size_t max : {1u, 3u, 64u, 1024u}) {
      const std::vector<uint32_t> v = pilotVertices(n, max);
      const std::size_t stride = (n + max - 1) / max;
      ASSERT_FALSE(v.empty());
      EXPECT_LE(v.size(), std::min(n, max)) << n << " " << max;
      if (n <= max) {
        EXPECT_EQ(v.size(), n) << n << " " << max;
      }
      EXPECT_EQ(v.front(), stride / 2) << n << " " << max;
      EXPECT_LT(v.back(), n);
      EXPECT_GE(v.back() + stride, n) << n << " " << max;  // none left out at the end
      for (std::size_t k = 1; k < v.size(); ++k) EXPECT_EQ(v[k] - v[k - 1], stride);
    }
}

// Bad options throw before any estimator is made.
TEST(VisibilityPilot, ThrowsOnBadOptions) {
  const auto never = []() -> VertexEstimator {
    ADD_FAILURE() << "an estimator was made";
    throw Error("unreachable");
  };
  const auto run = [&](int replicas, int coarse, int fine) {
    VisibilityPilotOptions o;
    o.replicas = replicas;
    o.coarseRays = coarse;
    o.fineRays = fine;
    return runVisibilityPilot(100, o, 1, 1, never);
  };
  EXPECT_THROW(run(1, 8, 32), Error);  // replicas < 2
  EXPECT_THROW(run(0, 8, 32), Error);  // no pilot is not a pilot to run
  EXPECT_THROW(run(4, 1, 32), Error);  // rays < 2
  EXPECT_THROW(run(4, 8, 8), Error);   // coarse = fine
  EXPECT_THROW(run(4, 32, 8), Error);  // coarse > fine
}

// Everything a VertexEstimator holds by reference, for one mesh under a uniform sky.
struct EstimatorScene {
  TriangleMesh mesh;
  Cubemap sky{16, kRadiance};
  EnvironmentSampler sampler{sky};
  VertexFacets facets;
  TriangleScene scene;
  float extent;
  std::optional<UnoccludedIntake> unoccluded;  // the ratio estimator's control, or none

  EstimatorScene(TriangleMesh m, bool ratio)
      : mesh(std::move(m)),
        facets(lightFacets(mesh.positions, mesh.normals, mesh.triangles)),
        scene(mesh.positions, mesh.triangles, TriangleSceneOptions::surfaceRays(1)),
        extent(boundsOf(mesh.positions).longestSide()) {
    if (ratio) unoccluded.emplace(sky, kEta, nullptr, 1);
  }
  VertexEstimator make() const {
    return VertexEstimator(mesh.positions, mesh.normals, facets, sampler, scene, kEta, extent,
                           nullptr, unoccluded ? &*unoccluded : nullptr);
  }
};

// Mean, variance and the variance's standard error per channel of `count` independent m-ray
// estimates at vertex v (the standard error from the fourth central moment:
// Var(s^2) ~ (mu_4 - sigma^4) / count).
struct Moments {
  glm::dvec3 mean{0.0}, variance{0.0}, varianceStdError{0.0};
};
Moments referenceMoments(const EstimatorScene& s, std::size_t v, int rays, int count) {
  VertexEstimator estimator = s.make();
  std::vector<glm::dvec3> values(static_cast<std::size_t>(count));
  Moments m;
  for (int k = 0; k < count; ++k) {
    Pcg32 rng(777, static_cast<uint64_t>(k));
    values[k] = glm::dvec3(estimator.estimate(v, rays, rng).irradiance);
    m.mean += values[k] / double(count);
  }
  glm::dvec3 m2(0.0), m4(0.0);
  for (const glm::dvec3& x : values) {
    const glm::dvec3 d2 = (x - m.mean) * (x - m.mean);
    m2 += d2;
    m4 += d2 * d2 / double(count);
  }
  m.variance = m2 / double(count - 1);
  for (int c = 0; c < 3; ++c)
    m.varianceStdError[c] = std::sqrt(std::max(0.0, m4[c] - m.variance[c] * m.variance[c]) / count);
  return m;
}

// On a flat plate under a uniform sky every vertex's estimate has the same distribution (one
// facet, +Z; nothing above it to hit), so the pilot's per-vertex variances are 1024 draws of an
// unbiased variance estimate (4 replicas) of one variance. The plain sum of the samples
// (no ratio to the unoccluded light) has a variance that is not 0; the reference is that variance
// from 20000 independent estimates of the same estimator. Their means must agree within 4 of
// their combined standard errors (the spread of the pilot's 1024 values over sqrt(1024), and the
// reference's own): about 2.5 % of the variance, so a pilot off by 10 % fails. The fine replicas'
// mean is the closed form pi L (1 - 2 C_1) within its noise.
TEST(VisibilityPilot, ReplicasMeasureTheEstimatorsVarianceAtBothLevels) {
  const EstimatorScene s(makeGridPlane(31, 10.0f), false);  // 1024 vertices
  const VisibilityPilotOptions options;                     // 4 replicas of 8 and 32 rays
  const VisibilityPilot pilot =
      runVisibilityPilot(s.mesh.vertexCount(), options, 11, 2, [&] { return s.make(); });
  ASSERT_EQ(pilot.vertices.size(), 1024u);
  EXPECT_EQ(pilot.replicas, 4);
  EXPECT_EQ(pilot.coarseRays, 8);
  EXPECT_EQ(pilot.fineRays, 32);

  const double m = static_cast<double>(pilot.vertices.size());
  for (const bool fine : {false, true}) {
    const std::vector<glm::vec3>& variance = fine ? pilot.fineVariance : pilot.coarseVariance;
    const Moments ref = referenceMoments(s, 0, fine ? 32 : 8, 20000);
    for (int c = 0; c < 3; ++c) {
      double sum = 0.0, sumSq = 0.0;
      for (const glm::vec3& v : variance) {
        sum += v[c];
        sumSq += double(v[c]) * v[c];
      }
      const double mean = sum / m;
      const double spread = std::sqrt((sumSq - sum * mean) / (m - 1.0));
      const double stdError = std::hypot(spread / std::sqrt(m), ref.varianceStdError[c]);
      ASSERT_GT(ref.variance[c], 0.0);
      EXPECT_NEAR(mean, ref.variance[c], 4.0 * stdError)
          << (fine ? "fine" : "coarse") << " channel " << c;
      EXPECT_LT(stdError, 0.025 * ref.variance[c]);  // a test that can tell 10 % apart
    }
  }
  // More rays, less variance (the pilot's two levels give the rate, visibility_noise_model.h).
  double coarse = 0.0, fineSum = 0.0;
  for (std::size_t k = 0; k < pilot.vertices.size(); ++k) {
    coarse += pilot.coarseVariance[k].y;
    fineSum += pilot.fineVariance[k].y;
  }
  EXPECT_LT(fineSum, 0.5 * coarse);

  const double closed = M_PI * (1.0 - diffuseFresnelReflectance(kEta));
  glm::dvec3 meanE(0.0);
  for (const glm::vec3& e : pilot.irradiance) meanE += glm::dvec3(e) / m;
  const Moments fineRef = referenceMoments(s, 0, 32, 2000);
  for (int c = 0; c < 3; ++c) {
    const double sigma = std::sqrt(fineRef.variance[c] / 4.0 / m);  // the mean of 4 x 1024
    EXPECT_NEAR(meanE[c], closed * kRadiance[c], 4.0 * sigma + 2e-3 * closed * kRadiance[c])
        << "channel " << c;
  }
  EXPECT_GT(pilot.rays, 0u);
  EXPECT_LE(pilot.rays, uint64_t(1024) * 4 * (8 + 32));
}

// On a convex sphere nothing is in the way, and the ratio estimator returns the unoccluded light
// at any ray count (visibility_vertex_estimator.h: Y = X): every replica is the same, so the
// measured variance is exactly 0 at both levels.
TEST(VisibilityPilot, RatioEstimatorOnAConvexSphereHasNoVariance) {
  const EstimatorScene s(makeIcosphere(3, 10.0f), true);
  VisibilityPilotOptions options;
  options.maxVertices = 128;
  const VisibilityPilot pilot =
      runVisibilityPilot(s.mesh.vertexCount(), options, 11, 2, [&] { return s.make(); });
  ASSERT_EQ(pilot.vertices.size(), 107u);  // stride ceil(642 / 128) = 6: 3, 9, ..., 639
  for (std::size_t k = 0; k < pilot.vertices.size(); ++k) {
    EXPECT_EQ(pilot.coarseVariance[k], glm::vec3(0.0f)) << "vertex " << pilot.vertices[k];
    EXPECT_EQ(pilot.fineVariance[k], glm::vec3(0.0f)) << "vertex " << pilot.vertices[k];
    EXPECT_GT(pilot.irradiance[k].x, 0.0f);
  }
}

// Each vertex's replicas draw from Pcg32(seed + offset, vertex) (visibility_pilot.cpp): the pilot
// is the same, bit for bit, for 1 and 2 threads, and another seed gives another.
TEST(VisibilityPilot, SameSeedGivesTheSamePilotForAnyThreadCount) {
  const EstimatorScene s(makeGridPlane(15, 10.0f), false);  // 256 vertices
  VisibilityPilotOptions options;
  options.maxVertices = 64;
  const auto make = [&] { return s.make(); };
  const VisibilityPilot one = runVisibilityPilot(s.mesh.vertexCount(), options, 11, 1, make);
  const VisibilityPilot two = runVisibilityPilot(s.mesh.vertexCount(), options, 11, 2, make);
  EXPECT_EQ(one.vertices, two.vertices);
  EXPECT_EQ(one.irradiance, two.irradiance);
  EXPECT_EQ(one.coarseVariance, two.coarseVariance);
  EXPECT_EQ(one.fineVariance, two.fineVariance);
  EXPECT_EQ(one.rays, two.rays);
  const VisibilityPilot other = runVisibilityPilot(s.mesh.vertexCount(), options, 12, 2, make);
  EXPECT_NE(other.fineVariance, one.fineVariance);
}

}  // namespace
}  // namespace sss

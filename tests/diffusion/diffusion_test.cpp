// The diffusion sums of Li & Guo Eq. 7 (lib/diffusion/diffusion.h) against analytic cases (a plane
// under uniform light), refinement (a sphere at four subdivision levels), the O(N^2) reference, and
// thread counts.
#include "diffusion/diffusion.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <limits>
#include <memory>
#include <vector>

#include "core/error.h"
#include "core/relative_rms.h"
#include "material/diffusion_profile.h"
#include "material/dipole_profile.h"
#include "material/gaussian_sum_fit.h"
#include "material/material.h"
#include "material/profile_factory.h"
#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"

namespace sss {
namespace {

struct Scene {
  TriangleMesh mesh;
  std::vector<float> areas;
  std::vector<glm::vec3> irradiance;
  DiffusionInput input() const { return {mesh.positions, mesh.normals, areas, irradiance}; }
};

Scene uniformScene(TriangleMesh mesh) {
  Scene s{std::move(mesh), {}, {}};
  s.areas = vertexAreas(s.mesh);
  s.irradiance.assign(s.mesh.vertexCount(), glm::vec3(1));
  return s;
}

// Smooth light from one side plus an ambient floor; with `step`, blue is a hard shadow edge.
Scene litScene(TriangleMesh mesh, bool step) {
  Scene s = uniformScene(std::move(mesh));
  const glm::vec3 light = glm::normalize(glm::vec3(1, 2, 0.5));
  for (std::size_t i = 0; i < s.irradiance.size(); ++i) {
    const float c = std::max(0.0f, glm::dot(s.mesh.normals[i], light));
    s.irradiance[i] =
        glm::vec3(c * c * c + 0.05f, 0.5f * c + 0.02f, step ? (c > 0.5f ? 1.0f : 0.0f) : c + 0.1f);
  }
  return s;
}

DiffusionResult run(const Scene& s, const DiffusionProfile& profile, DiffusionMethod method,
                    int threads = 0, double tolerance = 0.01) {
  DiffusionOptions options;
  options.method = method, options.run.threads = threads, options.run.quiet = true;
  options.tolerance = tolerance;
  return diffuse(s.input(), profile, options);
}

// Dense enough for the O(N^2) reference on a 50 mm plane: diffuse mean free path ~1.8 mm.
Material denseMaterial() {
  Material m;
  m.name = "dense";
  m.sigmaA = glm::dvec3(0.05, 0.08, 0.12);
  m.sigmaSPrime = glm::dvec3(2.0, 2.5, 3.0);
  m.eta = 1.3;
  return m;
}

// Interior vertices (farther than `margin` from the border) of a grid plane of side `size`.
void expectPlaneInteriorMatchesTotal(const Scene& s, const std::vector<glm::vec3>& b,
                                     const glm::dvec3& total, float size, float margin,
                                     double tolerance, const char* what) {
  std::size_t checked = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    const glm::vec3 p = s.mesh.positions[i];
    if (std::max(std::abs(p.x), std::abs(p.y)) > 0.5f * size - margin) continue;
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(b[i][c] / total[c], 1.0, tolerance)
          << what << " vertex " << i << " channel " << c;
    ++checked;
  }
  EXPECT_GT(checked, 10u) << what;
}

TEST(Diffusion, PlaneUnderUniformLightGivesTotalReflectanceExact) {
  const Scene s = uniformScene(makeGridPlane(50, 50));  // 1 mm spacing
  const DipoleProfile profile(denseMaterial());
  const DiffusionResult r = run(s, profile, DiffusionMethod::Exact);
  expectPlaneInteriorMatchesTotal(s, r.exitance, profile.totalReflectance(), 50, 20, 0.01, "exact");
}

TEST(Diffusion, PlaneUnderUniformLightGivesTotalReflectanceGaussian) {
  // skin1: 99% of the red energy within 13.7 mm; interior = 30 mm from the border.
  const Scene s = uniformScene(makeGridPlane(100, 100));
  const DipoleProfile profile(findMaterialPreset("skin1"));
  for (DiffusionMethod m : {DiffusionMethod::Gauss, DiffusionMethod::Hierarchical,
                            DiffusionMethod::Incremental, DiffusionMethod::Auto}) {
    const DiffusionResult r = run(s, profile, m);
    expectPlaneInteriorMatchesTotal(s, r.exitance, profile.totalReflectance(), 100, 30, 0.01,
                                    kDiffusionMethodNames.name(m));
  }
}

TEST(Diffusion, CoarsePlaneStaysCloseToTotalReflectance) {
  // 4 mm spacing, 8x skin1's blue transport mean free path: sampling the narrowest Gaussians at
  // points would multiply B by ~1/(2 pi v) A, over 100 here; the disc terms keep it within 5%.
  const Scene s = uniformScene(makeGridPlane(30, 120));
  const DipoleProfile profile(findMaterialPreset("skin1"));
  for (DiffusionMethod m : {DiffusionMethod::Exact, DiffusionMethod::Gauss,
                            DiffusionMethod::Hierarchical, DiffusionMethod::Incremental}) {
    const DiffusionResult r = run(s, profile, m);
    expectPlaneInteriorMatchesTotal(s, r.exitance, profile.totalReflectance(), 120, 40, 0.05,
                                    kDiffusionMethodNames.name(m));
  }
}

TEST(Diffusion, SphereConvergesUnderRefinement) {
  // 20 mm marble sphere at 162, 642, 2562, 10242 vertices; icosphere subdivision keeps the
  // coarser vertices first, so levels compare on shared vertices.
  const DipoleProfile profile(findMaterialPreset("marble"));
  std::vector<std::vector<glm::vec3>> b;
  for (int level = 2; level <= 5; ++level) {
    const Scene s = litScene(makeIcosphere(level, 10), false);
    b.push_back(run(s, profile, DiffusionMethod::Auto).exitance);
  }
  for (const auto& v : b[0])
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(v[c]));
  // On the coarser level's vertices, shared with the finest.
  const auto finest = [&](std::size_t level) { return std::span(b[3]).first(b[level].size()); };
  EXPECT_LT(relativeRms(b[2], finest(2)), 0.01);
  EXPECT_LT(relativeRms(b[0], finest(0)), 0.10);
}

TEST(Diffusion, FastMethodsMatchExactWithinTolerance) {
  // Marble on a 20 mm sphere: the kernel spans the whole object; blue has a hard shadow edge.
  const Scene s = litScene(makeIcosphere(4, 10), true);
  const DipoleProfile profile(findMaterialPreset("marble"));
  const DiffusionResult exact = run(s, profile, DiffusionMethod::Exact);
  for (DiffusionMethod m : {DiffusionMethod::Gauss, DiffusionMethod::Hierarchical,
                            DiffusionMethod::Incremental, DiffusionMethod::Auto}) {
    const DiffusionResult r = run(s, profile, m);
    EXPECT_LT(relativeRms(r.exitance, exact.exitance), 0.01) << kDiffusionMethodNames.name(m);
    if (m != DiffusionMethod::Auto) {
      EXPECT_EQ(r.report.method, m);
    }
    EXPECT_GT(r.report.gaussians, 0);
    EXPECT_EQ(r.report.cutoffs.size(), std::size_t(r.report.gaussians));
  }
}

// The Gaussian mixture the fast methods sum (octree_gaussian_sum.h), pair by pair with no cutoff:
// each other vertex j a disc of variance c_j = A_j / 4 pi blurring every Gaussian,
// E_j A_j sum_k w_k G(v_k + c_j, r), and the vertex's own disc integrated.
std::vector<glm::vec3> mixtureSummedPairByPair(const Scene& s, const GaussianSum& sum) {
  const std::size_t n = s.mesh.vertexCount();
  std::vector<glm::vec3> b(n);
  for (std::size_t i = 0; i < n; ++i) {
    glm::dvec3 total(0.0);
    for (std::size_t k = 0; k < sum.size(); ++k) {
      const double v = sum.variances[k];
      total += sum.weights[k] * -std::expm1(-s.areas[i] / M_PI / (2.0 * v)) *
               glm::dvec3(s.irradiance[i]);
      for (std::size_t j = 0; j < n; ++j) {
        if (j == i) continue;
        const double spread = v + s.areas[j] / (4.0 * M_PI);
        const double r2 = glm::dot(glm::dvec3(s.mesh.positions[i] - s.mesh.positions[j]),
                                   glm::dvec3(s.mesh.positions[i] - s.mesh.positions[j]));
        total += sum.weights[k] * glm::dvec3(s.irradiance[j]) * double(s.areas[j]) *
                 std::exp(-r2 / (2.0 * spread)) / (2.0 * M_PI * spread);
      }
    }
    b[i] = glm::vec3(total);
  }
  return b;
}

// The octree sums drop each Gaussian beyond its cutoff, a quarter of the tolerance at most
// (octree_gaussian_sum.h; measured here: gauss 1 % of the tolerance, hierarchical 3-7 % with
// its clusters). On a mesh whose vertex discs are wider than marble's narrow Gaussians (a 10 mm
// sphere, 1.4 mm between vertices: c = 0.16 mm^2 against v = 0.023-0.22 mm^2) a cutoff that
// ignored the disc drops their terms between neighbours: gauss 10-23 % of the tolerance.
TEST(Diffusion, GaussianSumsMatchTheirMixtureSummedPairByPair) {
  const Scene s = litScene(makeIcosphere(3, 10), true);
  const DipoleProfile profile(findMaterialPreset("marble"));
  for (const double tolerance : {0.01, 0.003}) {
    const GaussianSumFit fit =
        fitGaussians(profile, 0.5 * tolerance, DiffusionOptions{}.maxGaussians);
    const std::vector<glm::vec3> reference = mixtureSummedPairByPair(s, fit.sum);
    const DiffusionResult gauss = run(s, profile, DiffusionMethod::Gauss, 0, tolerance);
    EXPECT_LT(relativeRms(gauss.exitance, reference), 0.05 * tolerance) << tolerance;
    const DiffusionResult hier = run(s, profile, DiffusionMethod::Hierarchical, 0, tolerance);
    EXPECT_LT(relativeRms(hier.exitance, reference), hier.report.estimatedError) << tolerance;
  }
}

// A mesh cache keeps the octree between calls and gives the same sums, bit for bit; another
// mesh, or the same arrays changed, builds a new one.
TEST(Diffusion, AMeshCacheGivesTheSameSumsAndFollowsTheMesh) {
  const Scene a = litScene(makeIcosphere(3, 10), true);
  Scene b = litScene(makeIcosphere(3, 12), false);
  const DipoleProfile profile(findMaterialPreset("marble"));
  DiffusionMeshCache cache;
  DiffusionOptions cached;
  cached.method = DiffusionMethod::Hierarchical, cached.run.quiet = true;
  cached.meshCache = &cache;
  DiffusionOptions plain = cached;
  plain.meshCache = nullptr;
  const auto same = [&](const Scene& s) {
    const DiffusionResult with = diffuse(s.input(), profile, cached);
    const DiffusionResult without = diffuse(s.input(), profile, plain);
    ASSERT_EQ(with.exitance.size(), without.exitance.size());
    EXPECT_EQ(0, std::memcmp(with.exitance.data(), without.exitance.data(),
                             with.exitance.size() * sizeof(glm::vec3)));
  };
  same(a);
  same(a);  // kept
  same(b);  // another mesh
  for (glm::vec3& p : b.mesh.positions) p *= 1.5f;
  for (float& area : b.areas) area *= 2.25f;
  same(b);  // the same arrays, changed
  same(a);
}

// The cache's Gaussian fits: the fit fitGaussians gives, for each profile and tolerance asked,
// however the calls interleave (two materials of one name's model, two tolerances).
TEST(Diffusion, AMeshCacheKeepsTheFitOfEachProfileAndTolerance) {
  const DipoleProfile marble(findMaterialPreset("marble")), skin(findMaterialPreset("skin1"));
  const auto expectSame = [](const GaussianSumFit& kept, const GaussianSumFit& fresh) {
    EXPECT_EQ(kept.sum.variances, fresh.sum.variances);
    ASSERT_EQ(kept.sum.weights.size(), fresh.sum.weights.size());
    for (std::size_t k = 0; k < kept.sum.weights.size(); ++k)
      EXPECT_EQ(kept.sum.weights[k], fresh.sum.weights[k]);
    EXPECT_EQ(kept.error, fresh.error);
  };
  DiffusionMeshCache cache;
  for (int round = 0; round < 2; ++round)  // fitted, then kept
    for (const DipoleProfile* profile : {&marble, &skin})
      for (const double tolerance : {0.005, 0.015}) {
        SCOPED_TRACE(std::to_string(round) + " " + std::to_string(tolerance));
        expectSame(cache.fit(*profile, tolerance, 16), fitGaussians(*profile, tolerance, 16));
      }
  // The two materials' fits differ (the cache does not hand one the other's).
  EXPECT_NE(cache.fit(marble, 0.005, 16).sum.variances, cache.fit(skin, 0.005, 16).sum.variances);
}

TEST(Diffusion, WideKernelHierarchicalMatchesGauss) {
  // Skim milk (diffuse mean free path 18 mm) on an 80 mm sphere: gauss sums thousands of points
  // per vertex, the clusters stand in for most of them. (Far points take only the wide Gaussians
  // in either method, octree_gaussian_sum.h; measured: 2.4x fewer terms.)
  const Scene s = litScene(makeIcosphere(4, 40), true);
  const DipoleProfile profile(findMaterialPreset("skimmilk"));
  const DiffusionResult gauss = run(s, profile, DiffusionMethod::Gauss);
  const DiffusionResult hier = run(s, profile, DiffusionMethod::Hierarchical);
  EXPECT_LT(relativeRms(hier.exitance, gauss.exitance), 0.005);
  EXPECT_LT(hier.report.interactions, gauss.report.interactions / 2);
}

// Sources without light are skipped (the bounces' light on convex parts, a compact light's unlit
// side): light on half a sphere sums as the same light with a faint rest that no sum skips, to
// float rounding, with fewer terms.
TEST(Diffusion, SourcesWithoutLightAreSkippedWithoutChangingTheSum) {
  Scene dark = uniformScene(makeIcosphere(4, 40));
  const glm::vec3 light = glm::normalize(glm::vec3(1, 2, 0.5));
  for (std::size_t i = 0; i < dark.irradiance.size(); ++i) {
    const float c = glm::dot(dark.mesh.normals[i], light);
    dark.irradiance[i] = c > 0.0f ? glm::vec3(c, 0.5f * c, c * c) : glm::vec3(0.0f);
  }
  Scene faint = dark;
  for (glm::vec3& e : faint.irradiance)
    if (e == glm::vec3(0.0f)) e = glm::vec3(1e-30f);
  const DipoleProfile profile(findMaterialPreset("skimmilk"));
  for (const DiffusionMethod method : {DiffusionMethod::Hierarchical, DiffusionMethod::Gauss}) {
    const DiffusionResult skipped = run(dark, profile, method);
    const DiffusionResult all = run(faint, profile, method);
    EXPECT_LT(relativeRms(skipped.exitance, all.exitance), 1e-5);
    EXPECT_LT(skipped.report.interactions, 0.8 * all.report.interactions);
  }
}

TEST(Diffusion, OtherProfilesMatchExact) {
  // Their fits reach about 0.7% (not the 0.5% asked) with 16 Gaussians, one of them a spike of
  // variance ~1e-7 mm^2 for Burley's 1/r peak: hence 2% here.
  const Scene s = litScene(makeIcosphere(4, 10), true);
  for (const char* kind : {"burley", "beam"}) {
    const auto profile = makeProfile(kind, findMaterialPreset("skin1"));
    const DiffusionResult exact = run(s, *profile, DiffusionMethod::Exact);
    for (DiffusionMethod m : {DiffusionMethod::Gauss, DiffusionMethod::Hierarchical}) {
      const DiffusionResult r = run(s, *profile, m);
      EXPECT_LT(relativeRms(r.exitance, exact.exitance), 0.02)
          << kind << " " << kDiffusionMethodNames.name(m);
    }
  }
}

// Reciprocity (swap source and receiver): the exitance at vertex a from unit power entering at
// vertex b equals the exitance at b from unit power entering at a, R_d depending only on the
// distance. What breaks it is the discretization, and only near the source: the Gaussian methods
// spread each source over a disc of its own area (diffusion.h, "Stability"), so a pair whose
// areas differ (a is a valence-5 vertex of the icosphere, smaller than its neighbours) differs by
// the blur of the larger disc; the exact sum integrates discs only one edge around the receiver.
// Measured (ratio b->a / a->b): exact 1.03 at one edge, 1 to 1e-7 beyond; gauss and hierarchical
// 1.03-1.04 at one edge, 1.007-1.010 at 5 mm, 1.001-1.002 at 15 mm.
TEST(Diffusion, TransportIsReciprocal) {
  Scene s = uniformScene(makeIcosphere(3, 10));
  const DipoleProfile profile(findMaterialPreset("marble"));
  const auto closestTo = [&](const glm::vec3& p) {
    std::size_t best = 0;
    for (std::size_t v = 1; v < s.mesh.positions.size(); ++v)
      if (glm::distance(s.mesh.positions[v], p) < glm::distance(s.mesh.positions[best], p))
        best = v;
    return best;
  };
  const std::size_t a = 0;
  const glm::vec3 pa = s.mesh.positions[a];
  // Points on the sphere at chord distances d from a: rotate a about an axis perpendicular to it.
  const glm::vec3 axis = glm::normalize(glm::cross(pa, glm::vec3(0.3f, 0.4f, 0.5f)));
  const auto atChord = [&](float d) {
    const float angle = 2.0f * std::asin(d / 20.0f);
    return closestTo(pa * std::cos(angle) + glm::cross(axis, pa) * std::sin(angle));
  };
  const auto response = [&](std::size_t source, std::size_t receiver, DiffusionMethod method) {
    s.irradiance.assign(s.mesh.vertexCount(), glm::vec3(0.0f));
    s.irradiance[source] = glm::vec3(1.0f / s.areas[source]);  // unit power entering
    return run(s, profile, method).exitance[receiver];
  };
  struct Pair {
    float mm;
    double exact, fast;  // tolerances on the ratio
  };
  for (const Pair pair :
       {Pair{1.5f, 0.05, 0.05}, Pair{5.0f, 1e-5, 0.015}, Pair{15.0f, 1e-5, 0.004}}) {
    const std::size_t b = atChord(pair.mm);
    ASSERT_NE(a, b);
    for (const DiffusionMethod m :
         {DiffusionMethod::Exact, DiffusionMethod::Gauss, DiffusionMethod::Hierarchical}) {
      const glm::vec3 ab = response(a, b, m), ba = response(b, a, m);
      for (int c = 0; c < 3; ++c) {
        ASSERT_GT(ab[c], 0.0f);
        EXPECT_NEAR(ba[c] / ab[c], 1.0, m == DiffusionMethod::Exact ? pair.exact : pair.fast)
            << kDiffusionMethodNames.name(m) << " at " << pair.mm << " mm, channel " << c;
      }
    }
  }
}

TEST(Diffusion, SameResultForOneAndTwoThreads) {
  const Scene s = litScene(makeIcosphere(3, 10), true);
  const DipoleProfile profile(findMaterialPreset("marble"));
  for (DiffusionMethod m : {DiffusionMethod::Exact, DiffusionMethod::Gauss,
                            DiffusionMethod::Hierarchical, DiffusionMethod::Incremental}) {
    const DiffusionResult one = run(s, profile, m, 1), two = run(s, profile, m, 2);
    ASSERT_EQ(one.exitance.size(), two.exitance.size());
    EXPECT_EQ(0, std::memcmp(one.exitance.data(), two.exitance.data(),
                             one.exitance.size() * sizeof(glm::vec3)))
        << kDiffusionMethodNames.name(m);
  }
}

TEST(Diffusion, AutoExplainsItsChoice) {
  const DipoleProfile profile(findMaterialPreset("marble"));
  const DiffusionResult small =
      run(litScene(makeIcosphere(2, 10), false), profile, DiffusionMethod::Auto);
  EXPECT_EQ(small.report.method, DiffusionMethod::Exact);
  EXPECT_NE(small.report.reason.find("exact"), std::string::npos);
  const DiffusionResult large =
      run(litScene(makeIcosphere(5, 40), false), profile, DiffusionMethod::Auto);
  EXPECT_EQ(large.report.method, DiffusionMethod::Hierarchical) << large.report.reason;
  EXPECT_GT(large.report.estimatedError, 0.0);
  EXPECT_LE(large.report.estimatedError, 0.01);
}

TEST(Diffusion, RejectsBadInput) {
  const DipoleProfile profile(findMaterialPreset("marble"));
  Scene s = litScene(makeIcosphere(1, 10), false);
  s.areas.pop_back();
  EXPECT_THROW(run(s, profile, DiffusionMethod::Gauss), Error);
  s = litScene(makeIcosphere(1, 10), false);
  s.mesh.positions[3].y = std::numeric_limits<float>::quiet_NaN();
  try {
    run(s, profile, DiffusionMethod::Gauss);
    FAIL() << "NaN position accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("1 non-finite positions"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("vertex 3"), std::string::npos) << e.what();
  }
  s = litScene(makeIcosphere(1, 10), false);
  s.areas[0] = -1;
  EXPECT_THROW(run(s, profile, DiffusionMethod::Exact), Error);
  s = litScene(makeIcosphere(1, 10), false);
  EXPECT_THROW(run(s, profile, DiffusionMethod::Gauss, 0, 0.0), Error);
  try {
    kDiffusionMethodNames.parse("fast");
    FAIL() << "unknown method accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("hierarchical"), std::string::npos);
  }
  EXPECT_EQ(kDiffusionMethodNames.parse("incremental"), DiffusionMethod::Incremental);
}

TEST(Diffusion, EmptyInputGivesEmptyOutput) {
  const DipoleProfile profile(findMaterialPreset("marble"));
  const DiffusionResult r = diffuse({}, profile);
  EXPECT_TRUE(r.exitance.empty());
}

}  // namespace
}  // namespace sss

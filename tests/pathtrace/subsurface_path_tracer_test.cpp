// The Monte Carlo reference against analytic transport: Chandrasekhar's half-space albedo,
// energy conservation, no scattering, determinism.
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "envmap/cubemap.h"
#include "material/material.h"
#include "mesh/primitives.h"
#include "optics/fresnel.h"
#include "pathtrace/subsurface_path_tracer.h"

namespace sss {
namespace {

// The array overload on a whole mesh: a medium given by its coefficients, not a Material.
PathTraceResult traceMedium(const TriangleMesh& mesh, const Cubemap& radiance,
                            const HomogeneousMedium& medium, const PathTraceOptions& options) {
  return pathTraceSubsurface(mesh.positions, mesh.normals, mesh.triangles, radiance, medium,
                             options);
}

// Gauss-Legendre nodes and weights on [0, 1] (Newton on P_n).
void gaussLegendre01(int n, std::vector<double>& x, std::vector<double>& w) {
  x.resize(n);
  w.resize(n);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-15) break;
    }
    x[i] = 0.5 * (1.0 - z);
    w[i] = 1.0 / ((1.0 - z * z) * dp * dp);  // 2 / ((1 - z^2) P'^2), halved for [0, 1]
  }
}

// Chandrasekhar's H-function for isotropic scattering with albedo a, by iterating
// 1/H(mu) = sqrt(1 - a) + (a/2) int_0^1 mu' H(mu') / (mu + mu') dmu' (Chandrasekhar 1960,
// Radiative Transfer, eq. V.(35) form). Returns its moments H0 = int H and H1 = int mu H.
struct HMoments {
  double h0, h1;
};
HMoments chandrasekharH(double a) {
  std::vector<double> x, w;
  gaussLegendre01(96, x, w);
  std::vector<double> h(x.size(), 1.0), next(x.size());
  for (int it = 0; it < 2000; ++it) {
    double change = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      double integral = 0.0;
      for (std::size_t j = 0; j < x.size(); ++j) integral += w[j] * x[j] * h[j] / (x[i] + x[j]);
      next[i] = 1.0 / (std::sqrt(1.0 - a) + 0.5 * a * integral);
      change = std::max(change, std::abs(next[i] - h[i]));
    }
    h.swap(next);
    if (change < 1e-13) break;
  }
  HMoments m{0.0, 0.0};
  for (std::size_t i = 0; i < x.size(); ++i) {
    m.h0 += w[i] * h[i];
    m.h1 += w[i] * x[i] * h[i];
  }
  return m;
}

std::size_t findVertex(const TriangleMesh& mesh, const glm::vec3& p) {
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    if (glm::length(mesh.positions[i] - p) < 1e-4f) return i;
  ADD_FAILURE() << "no vertex at the expected position";
  return 0;
}

TEST(Chandrasekhar, HFunctionMomentIdentity) {
  // Exact identity H0 = (2/a)(1 - sqrt(1 - a)) checks the iteration the albedo test relies on.
  for (double a : {0.5, 0.9, 0.99}) {
    EXPECT_NEAR(chandrasekharH(a).h0, 2.0 / a * (1.0 - std::sqrt(1.0 - a)), 1e-9) << a;
  }
}

// Index-matched, isotropically scattering half-space (a thick box much wider than the diffusion
// length) under uniform radiance 1: B = pi * (1 - 2 sqrt(1 - a) H1(a)) at the top centre. The
// three channels carry a = 0.5, 0.9, 0.99 with different sigma_t, so one run also checks the
// spectral MIS between channels.
TEST(PathTracer, HalfSpaceAlbedoMatchesChandrasekhar) {
  const TriangleMesh box = makeBox(glm::vec3(200.0f, 200.0f, 100.0f), 2);
  const std::size_t top = findVertex(box, glm::vec3(0.0f, 0.0f, 50.0f));
  ASSERT_NEAR(box.normals[top].z, 1.0f, 1e-6f);
  const glm::dvec3 a(0.5, 0.9, 0.99), sigmaT(2.0, 1.0, 0.5);
  HomogeneousMedium medium;
  medium.sigmaS = a * sigmaT;
  medium.sigmaA = sigmaT - medium.sigmaS;
  medium.eta = 1.0;
  PathTraceOptions options;
  options.samples = 60000;
  options.vertices = {static_cast<uint32_t>(top)};
  options.estimateRadiance = false;
  options.minScatteringOrder = 0;  // the whole albedo: with eta = 1 nothing reflects specularly
  options.run.quiet = true;
  const Cubemap uniform(8, glm::vec3(1.0f));
  const PathTraceResult r = traceMedium(box, uniform, medium, options);
  ASSERT_EQ(r.exitance.size(), 1u);
  for (int c = 0; c < 3; ++c) {
    const double exact = M_PI * (1.0 - 2.0 * std::sqrt(1.0 - a[c]) * chandrasekharH(a[c]).h1);
    const double se = r.exitanceStdErr[0][c];
    EXPECT_LT(se, 0.01 * exact) << "too few walks for a meaningful test, channel " << c;
    EXPECT_NEAR(r.exitance[0][c], exact, 3.5 * se)
        << "channel " << c << " a = " << a[c] << " (standard error " << se << ")";
  }
  EXPECT_EQ(r.escapedWalks, 0u);
  EXPECT_EQ(r.truncatedWalks, 0u);
}

// No absorption, index-matched, convex: every walk leaves and sees the uniform sky, so with equal
// sigma_t in all channels every walk returns exactly pi (exitance) or 1 (radiance). Dense
// enough (radius 200 mean free paths) that light crossing without scattering is negligible
// (~1e-5): the faceted 1-ring's cut-off directions (~2% here) must be redrawn, not lost.
TEST(PathTracer, ConservesEnergyWithoutAbsorption) {
  const TriangleMesh sphere = makeIcosphere(2, 5.0f);
  HomogeneousMedium medium;
  medium.sigmaS = glm::dvec3(40.0);
  medium.eta = 1.0;
  PathTraceOptions options;
  options.samples = 16;
  options.run.quiet = true;
  const Cubemap uniform(8, glm::vec3(1.0f));
  const PathTraceResult r = traceMedium(sphere, uniform, medium, options);
  double sum = 0.0;
  for (std::size_t i = 0; i < sphere.positions.size(); ++i) {
    sum += r.exitance[i].x;
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(r.radiance[i][c], 1.0, 1e-5) << "vertex " << i;
  }
  EXPECT_NEAR(sum / double(sphere.positions.size()), M_PI, 2e-3);
  EXPECT_GT(r.redrawnDirections, r.walks / 200);
  EXPECT_EQ(r.escapedWalks, 0u);
}

// With eta = 1.3 the light that enters is (1 - 2 C_1) of pi L, and all of it leaves again
// (Fresnel reflections inside included); channels with different sigma_t go through the MIS.
TEST(PathTracer, ConservesEnergyThroughFresnelBoundary) {
  const TriangleMesh sphere = makeIcosphere(2, 5.0f);
  HomogeneousMedium medium;
  medium.sigmaS = glm::dvec3(0.5, 1.0, 2.0);
  medium.eta = 1.3;
  PathTraceOptions options;
  options.samples = 400;
  options.vertices = {0, 7, 40, 100};
  options.minScatteringOrder = 0;
  options.run.quiet = true;
  const Cubemap uniform(8, glm::vec3(1.0f));
  const PathTraceResult r = traceMedium(sphere, uniform, medium, options);
  const double entered = M_PI * (1.0 - diffuseFresnelReflectance(1.3f));
  for (std::size_t k = 0; k < options.vertices.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      const double se = r.exitanceStdErr[k][c];
      EXPECT_GT(se, 0.0);
      EXPECT_NEAR(r.exitance[k][c], entered, 4.0 * se + 1e-4) << "vertex " << k << " ch " << c;
      // Along the normal the walk starts with weight F_t(1) and always comes back with L = 1.
      EXPECT_NEAR(r.radiance[k][c], fresnelTransmittance(1.0f, 1.3f),
                  4.0 * r.radianceStdErr[k][c] + 1e-4);
    }
  }
}

TEST(PathTracer, NoScatteringGivesNoSubsurfaceExitance) {
  const TriangleMesh sphere = makeIcosphere(2, 5.0f);
  HomogeneousMedium medium;
  medium.sigmaA = glm::dvec3(0.1, 0.5, 1.0);
  medium.eta = 1.3;
  PathTraceOptions options;
  options.samples = 32;
  options.run.quiet = true;
  const Cubemap uniform(8, glm::vec3(1.0f));
  const PathTraceResult r = traceMedium(sphere, uniform, medium, options);
  for (std::size_t i = 0; i < sphere.positions.size(); ++i) {
    ASSERT_EQ(r.exitance[i], glm::vec3(0.0f));
    ASSERT_EQ(r.radiance[i], glm::vec3(0.0f));
  }
  // The same medium counting unscattered transmission (order 0) is not zero: the test above can
  // fail.
  options.minScatteringOrder = 0;
  options.vertices = {0};
  const PathTraceResult direct = traceMedium(sphere, uniform, medium, options);
  EXPECT_GT(direct.exitance[0].x, 0.1f);
}

TEST(PathTracer, SameResultForAnyThreadCountAndVertexSubset) {
  const TriangleMesh sphere = makeIcosphere(2, 4.0f);
  HomogeneousMedium medium;
  medium.sigmaA = glm::dvec3(0.02, 0.05, 0.1);
  medium.sigmaS = glm::dvec3(1.0, 1.2, 1.5);
  medium.eta = 1.3;
  medium.g = 0.3;
  PathTraceOptions options;
  options.samples = 8;
  options.run.seed = 42;
  options.run.quiet = true;
  const Cubemap uniform(8, glm::vec3(0.5f, 1.0f, 2.0f));
  options.run.threads = 1;
  const PathTraceResult one = traceMedium(sphere, uniform, medium, options);
  options.run.threads = 2;
  const PathTraceResult two = traceMedium(sphere, uniform, medium, options);
  EXPECT_EQ(one.exitance, two.exitance);
  EXPECT_EQ(one.radiance, two.radiance);
  EXPECT_EQ(one.exitanceStdErr, two.exitanceStdErr);
  options.vertices = {5, 3};
  const PathTraceResult subset = traceMedium(sphere, uniform, medium, options);
  EXPECT_EQ(subset.exitance[0], one.exitance[5]);
  EXPECT_EQ(subset.radiance[1], one.radiance[3]);
}

// Henyey-Greenstein: by the similarity relation a forward-scattering medium (g = 0.8,
// sigma_s = sigma_s' / (1 - g)) reflects about what the isotropic one with sigma_s' does; the
// relation is approximate (a few percent at high albedo), a wrong phase sampling is not (with
// isotropic sampling and 5x sigma_s the albedo would jump to ~0.99).
TEST(PathTracer, HenyeyGreensteinFollowsTheSimilarityRelation) {
  const TriangleMesh box = makeBox(glm::vec3(200.0f, 200.0f, 100.0f), 2);
  const std::size_t top = findVertex(box, glm::vec3(0.0f, 0.0f, 50.0f));
  const double g = 0.8, albedoPrime = 0.95;
  HomogeneousMedium isotropic;
  isotropic.sigmaS = glm::dvec3(albedoPrime);
  isotropic.sigmaA = glm::dvec3(1.0 - albedoPrime);
  HomogeneousMedium forward = isotropic;
  forward.sigmaS = isotropic.sigmaS / (1.0 - g);
  forward.g = g;
  PathTraceOptions options;
  options.samples = 20000;
  options.vertices = {static_cast<uint32_t>(top)};
  options.estimateRadiance = false;
  options.run.quiet = true;
  const Cubemap uniform(8, glm::vec3(1.0f));
  const PathTraceResult iso = traceMedium(box, uniform, isotropic, options);
  const PathTraceResult hg = traceMedium(box, uniform, forward, options);
  EXPECT_NEAR(hg.exitance[0].x / iso.exitance[0].x, 1.0, 0.08);
  EXPECT_GT(hg.meanScatteringEvents, 3.0 * iso.meanScatteringEvents);
}

// Walks in a large sphere without absorption take thousands of steps: the pilot says so before
// the run.
TEST(PathTracer, WarnsWhenWalksAreLong) {
  const TriangleMesh sphere = makeIcosphere(2, 100.0f);  // 4000 mean free paths across
  HomogeneousMedium medium;
  medium.sigmaS = glm::dvec3(20.0);
  PathTraceOptions options;
  options.samples = 1;
  options.vertices = {0};
  options.run.quiet = true;
  const Cubemap uniform(4, glm::vec3(1.0f));
  const PathTraceResult r = traceMedium(sphere, uniform, medium, options);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("walks long"), std::string::npos) << r.warnings[0];
  medium.sigmaA = glm::dvec3(5.0);  // albedo 0.8: short walks, no warning
  const PathTraceResult shortWalks = traceMedium(sphere, uniform, medium, options);
  EXPECT_TRUE(shortWalks.warnings.empty());
}

// The Material overload: sigma_s = sigma_s' / (1 - g) with the material's g, and a viewer far
// along a vertex normal sees that vertex as the Normal mode does.
TEST(PathTracer, MaterialOverloadAndViewerDirection) {
  const TriangleMesh sphere = makeIcosphere(2, 6.0f);
  Material material = findMaterialPreset("skin1");
  material.g = 0.5;
  HomogeneousMedium medium;
  medium.sigmaA = material.sigmaA;
  medium.sigmaS = material.sigmaSPrime / 0.5;
  medium.eta = material.eta;
  medium.g = 0.5;
  PathTraceOptions options;
  options.samples = 16;
  options.vertices = {3};
  options.run.quiet = true;
  const Cubemap env(8, glm::vec3(1.0f, 0.5f, 0.25f));
  const PathTraceResult a = pathTraceSubsurface(sphere, env, material, options);
  const PathTraceResult b = traceMedium(sphere, env, medium, options);
  EXPECT_EQ(a.exitance, b.exitance);
  EXPECT_EQ(a.radiance, b.radiance);
  EXPECT_GT(a.radiance[0].x, 0.0f);
  options.radianceDirection = RadianceDirection::TowardsPoint;
  options.viewPoint = sphere.positions[3] + 1e4f * sphere.normals[3];
  const PathTraceResult viewed = pathTraceSubsurface(sphere, env, material, options);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(viewed.radiance[0][c], a.radiance[0][c], 1e-3f * a.radiance[0][c]);
  options.viewPoint = -options.viewPoint;  // behind the vertex: it faces away
  EXPECT_EQ(pathTraceSubsurface(sphere, env, material, options).radiance[0], glm::vec3(0.0f));
}

TEST(PathTracer, RejectsBadInput) {
  const TriangleMesh sphere = makeIcosphere(1, 1.0f);
  const Cubemap uniform(4, glm::vec3(1.0f));
  HomogeneousMedium medium;
  PathTraceOptions options;
  options.run.quiet = true;
  auto run = [&] { traceMedium(sphere, uniform, medium, options); };
  EXPECT_THROW(run(), Error);  // no extinction
  medium.sigmaS = glm::dvec3(1.0);
  medium.g = 1.0;
  EXPECT_THROW(run(), Error);
  medium.g = 0.0;
  medium.sigmaA = glm::dvec3(-1.0);
  EXPECT_THROW(run(), Error);
  medium.sigmaA = glm::dvec3(0.0);
  options.vertices = {100000};
  EXPECT_THROW(run(), Error);
}

}  // namespace
}  // namespace sss

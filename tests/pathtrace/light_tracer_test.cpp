// The forward light tracer against independent references: the backward tracer under uniform
// light, the closed form of a slab's unscattered light, a plane-parallel (1D) Monte Carlo of a
// slab under a collimated beam, energy conservation, light that leaves and enters again, and
// determinism across thread counts.
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <vector>

#include "core/error.h"
#include "envmap/cubemap.h"
#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"
#include "optics/fresnel.h"
#include "pathtrace/light_tracer.h"
#include "pathtrace/subsurface_path_tracer.h"
#include "support/box_with_pit.h"
#include "support/joined_meshes.h"
#include "support/plane_parallel_slab.h"

namespace sss {
namespace {

LightTraceResult lightTrace(const TriangleMesh& mesh, const DistantLight& light,
                            const HomogeneousMedium& medium, const LightTraceOptions& options) {
  return lightTraceSubsurface(mesh.positions, mesh.normals, mesh.triangles, light, medium, options);
}

HomogeneousMedium makeMedium(glm::dvec3 sigmaS, glm::dvec3 sigmaA, double eta) {
  HomogeneousMedium m;
  m.sigmaS = sigmaS;
  m.sigmaA = sigmaA;
  m.eta = eta;
  return m;
}

// Area-weighted mean of B over the vertices of a slab face (normal z sign) within |x|, |y| <
// half; its standard error from the per-vertex ones (independent enough across vertices for a
// tolerance).
struct FaceMean {
  glm::dvec3 mean{0.0}, stdErr{0.0};
};
FaceMean centralFaceMean(const TriangleMesh& slab, const LightTraceResult& r, float zSign,
                         float half) {
  const std::vector<float> areas = vertexAreas(slab);
  FaceMean f;
  double area = 0.0;
  glm::dvec3 var(0.0);
  for (std::size_t v = 0; v < slab.positions.size(); ++v) {
    const glm::vec3 p = slab.positions[v];
    if (slab.normals[v].z * zSign < 0.999f || std::abs(p.x) > half || std::abs(p.y) > half)
      continue;
    f.mean += double(areas[v]) * glm::dvec3(r.exitance[v]);
    var += double(areas[v]) * double(areas[v]) * glm::dvec3(r.exitanceStdErr[v]) *
           glm::dvec3(r.exitanceStdErr[v]);
    area += areas[v];
  }
  f.mean /= area;
  f.stdErr = glm::sqrt(var) / area;
  return f;
}

TEST(LightTracer, MatchesBackwardTracerUnderUniformLight) {
  const TriangleMesh sphere = makeIcosphere(2, 3.0f);
  const HomogeneousMedium medium = makeMedium({1.0, 2.0, 3.0}, {0.1, 0.05, 0.2}, 1.3);
  const Cubemap uniform(4, glm::vec3(1.0f));
  LightTraceOptions lo;
  lo.paths = 200000;
  const LightTraceResult fwd = lightTrace(sphere, DistantLight::environment(uniform), medium, lo);

  PathTraceOptions po;
  po.samples = 1500;
  po.minScatteringOrder = 0;  // the light tracer counts every order
  po.run.quiet = true;
  // Entering over each vertex's facets: the faceted surface the light tracer sees. Entering at
  // the vertex through its smooth normal (the apex of a cone of facets, where light escapes more
  // easily) measures 1.4 %, 0.6 % and 4.6 % more than the facets' hat-weighted mean on this
  // 162-vertex sphere of 0.3-0.9 mm mean free paths.
  po.entry = WalkEntry::OneRing;
  for (uint32_t v = 0; v < sphere.positions.size(); v += 14) po.vertices.push_back(v);
  const PathTraceResult bwd =
      pathTraceSubsurface(sphere.positions, sphere.normals, sphere.triangles, uniform, medium, po);
  // Per vertex and channel: differences within combined standard errors (chi-square per degree
  // of freedom near 1, no outlier), for both B and the radiance along the normal.
  double chiB = 0.0, chiL = 0.0, maxZ = 0.0;
  int dof = 0;
  for (std::size_t k = 0; k < po.vertices.size(); ++k) {
    const uint32_t v = po.vertices[k];
    for (int c = 0; c < 3; ++c) {
      const double zB = (fwd.exitance[v][c] - bwd.exitance[k][c]) /
                        std::hypot(fwd.exitanceStdErr[v][c], bwd.exitanceStdErr[k][c]);
      const double zL = (fwd.radiance[v][c] - bwd.radiance[k][c]) /
                        std::hypot(fwd.radianceStdErr[v][c], bwd.radianceStdErr[k][c]);
      chiB += zB * zB;
      chiL += zL * zL;
      maxZ = std::max({maxZ, std::abs(zB), std::abs(zL)});
      ++dof;
    }
  }
  EXPECT_LT(chiB / dof, 2.0);
  EXPECT_LT(chiL / dof, 2.0);
  EXPECT_LT(maxZ, 4.5);
  // The sphere-wide means (uniform light: B is the same everywhere) agree to the mean's noise.
  // Radiance: the cone tally's bias is below this test's noise (~1 %).
  auto mean = [](const std::vector<glm::vec3>& values) {
    glm::dvec3 m(0.0);
    for (const glm::vec3& x : values) m += glm::dvec3(x);
    return m / double(values.size());
  };
  const glm::dvec3 ratioB = mean(fwd.exitance) / mean(bwd.exitance);
  const glm::dvec3 ratioL = mean(fwd.radiance) / mean(bwd.radiance);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(ratioB[c], 1.0, 0.015) << c;
    EXPECT_NEAR(ratioL[c], 1.0, 0.03) << c;
  }
}

// The unscattered light crossing a slab is the closed form, a collimated beam at incidence theta
// (inside theta_t) with the Fresnel reflectance R at both faces (the same inside and out) and the
// internal reflections' geometric series:
//   T = (1 - R)^2 e^-tau / (1 - R^2 e^-2tau),   B_lit = (1 - R)^2 R e^-2tau / (1 - R^2 e^-2tau),
// tau = sigma_t d / cos theta_t, relative to the irradiance on the lit face. Traced with sigma_s =
// 0 (all the light), or with scattering and only its unscattered part.
void expectSlabUnscatteredClosedForm(const HomogeneousMedium& medium, bool unscatteredOnly) {
  const float d = 1.0f;
  const TriangleMesh slab = makeSlab(40.0f, d, 20);
  const double theta = 30.0 * M_PI / 180.0;
  const glm::vec3 towards(float(std::sin(theta)), 0.0f, float(std::cos(theta)));
  LightTraceOptions lo;
  lo.paths = 300000;
  lo.unscatteredOnly = unscatteredOnly;
  const LightTraceResult r =
      lightTrace(slab, DistantLight::disc(towards, 0.0, glm::vec3(1.0f)), medium, lo);
  const double e = std::cos(theta);
  const double R = fresnelDielectric(float(std::cos(theta)), float(medium.eta));
  const double cosT =
      std::sqrt(1.0 - std::sin(theta) * std::sin(theta) / (medium.eta * medium.eta));
  const FaceMean bottom = centralFaceMean(slab, r, -1.0f, 10.0f);
  const FaceMean top = centralFaceMean(slab, r, 1.0f, 10.0f);
  for (int c = 0; c < 3; ++c) {
    const double a = std::exp(-(medium.sigmaA[c] + medium.sigmaS[c]) * d / cosT);
    const double series = 1.0 / (1.0 - R * R * a * a);
    const double t = (1 - R) * (1 - R) * a * series, lit = (1 - R) * (1 - R) * R * a * a * series;
    EXPECT_NEAR(bottom.mean[c] / e, t, 4.0 * bottom.stdErr[c] / e + 1e-3 * t) << c;
    EXPECT_NEAR(top.mean[c] / e, lit, 4.0 * top.stdErr[c] / e + 1e-3 * lit) << c;
    EXPECT_LT(bottom.stdErr[c] / bottom.mean[c], 0.01);
  }
}

TEST(LightTracer, SlabUnscatteredLightMatchesClosedForm) {
  expectSlabUnscatteredClosedForm(makeMedium({0.0, 0.0, 0.0}, {0.2, 0.7, 2.0}, 1.5), false);
}

TEST(LightTracer, UnscatteredOnlyMatchesTheClosedFormInAScatteringSlab) {
  expectSlabUnscatteredClosedForm(makeMedium({0.5, 1.0, 2.0}, {0.1, 0.2, 0.4}, 1.4), true);
}

// All the light = the unscattered part (traced alone) + the light scattered at least once, per
// vertex within the standard errors, exitance and radiance along the normal, on a sphere under a
// small sun where the unscattered light is a large, focused share of the far side.
TEST(LightTracer, UnscatteredAndScatteredLightAddUpToAllOfIt) {
  const TriangleMesh sphere = makeIcosphere(2, 2.0f);
  const HomogeneousMedium medium = makeMedium({0.2, 0.5, 1.0}, {0.05, 0.2, 0.3}, 1.3);
  const DistantLight sun =
      DistantLight::disc(glm::vec3(0.3f, 0.4f, 0.866f), 2.0 * M_PI / 180.0, glm::vec3(1.0f));
  LightTraceOptions lo;
  lo.paths = 400000;
  const LightTraceResult all = lightTrace(sphere, sun, medium, lo);
  lo.minScatteringOrder = 1;
  lo.run.seed = 2;
  const LightTraceResult scattered = lightTrace(sphere, sun, medium, lo);
  lo.minScatteringOrder = 0;
  lo.unscatteredOnly = true;
  lo.run.seed = 3;
  const LightTraceResult unscattered = lightTrace(sphere, sun, medium, lo);
  double chiB = 0.0, chiL = 0.0, unscatteredL = 0.0, totalL = 0.0;
  int dof = 0;
  for (std::size_t v = 0; v < sphere.positions.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      auto z2 = [&](const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& ae,
                    const std::vector<glm::vec3>& b, const std::vector<glm::vec3>& be,
                    const std::vector<glm::vec3>& u, const std::vector<glm::vec3>& ue) {
        const double var = ae[v][c] * ae[v][c] + be[v][c] * be[v][c] + ue[v][c] * ue[v][c];
        const double diff = a[v][c] - b[v][c] - u[v][c];
        return var > 0.0 ? diff * diff / var : 0.0;
      };
      chiB += z2(all.exitance, all.exitanceStdErr, scattered.exitance, scattered.exitanceStdErr,
                 unscattered.exitance, unscattered.exitanceStdErr);
      chiL += z2(all.radiance, all.radianceStdErr, scattered.radiance, scattered.radianceStdErr,
                 unscattered.radiance, unscattered.radianceStdErr);
      unscatteredL += unscattered.radiance[v][c];
      totalL += all.radiance[v][c];
      ++dof;
    }
  EXPECT_LT(chiB / dof, 1.5);
  EXPECT_LT(chiL / dof, 1.5);
  EXPECT_GT(chiB / dof, 0.5);             // the standard errors are not inflated either
  EXPECT_GT(unscatteredL / totalL, 0.1);  // the part tested is not negligible
}

// A scattering slab under a collimated beam: the central part of a wide 3D slab against the
// plane-parallel Monte Carlo (tests/support/plane_parallel_slab.h), transmitted and diffusely
// reflected fractions.
TEST(LightTracer, ScatteringSlabMatchesPlaneParallelMonteCarlo) {
  const float d = 1.0f;
  const TriangleMesh slab = makeSlab(40.0f, d, 20);
  const glm::dvec3 sigmaS(2.0, 4.0, 1.0), sigmaA(0.2, 0.05, 0.5);
  const double eta = 1.4, theta = 20.0 * M_PI / 180.0;
  const glm::vec3 towards(float(std::sin(theta)), 0.0f, float(std::cos(theta)));
  LightTraceOptions lo;
  lo.paths = 200000;
  const LightTraceResult r = lightTrace(slab, DistantLight::disc(towards, 0.0, glm::vec3(1.0f)),
                                        makeMedium(sigmaS, sigmaA, eta), lo);
  const double e = std::cos(theta);
  const FaceMean bottom = centralFaceMean(slab, r, -1.0f, 10.0f);
  const FaceMean top = centralFaceMean(slab, r, 1.0f, 10.0f);
  for (int c = 0; c < 3; ++c) {
    const test::SlabFractions ref =
        test::planeParallelSlab(d, sigmaS[c], sigmaA[c], eta, 0.0, std::cos(theta), 200000, 7);
    EXPECT_NEAR(bottom.mean[c] / e, ref.transmitted,
                4.0 * bottom.stdErr[c] / e + 0.01 * ref.transmitted)
        << c;
    EXPECT_NEAR(top.mean[c] / e, ref.reflected, 4.0 * top.stdErr[c] / e + 0.01 * ref.reflected)
        << c;
  }
}

// Without absorption every bit of power that enters leaves (spectral MIS makes the per-path
// weights vary across channels, not their mean); the vertex tallies sum to the exits exactly.
TEST(LightTracer, ConservesEnergyWithoutAbsorption) {
  const TriangleMesh sphere = makeIcosphere(2, 3.0f);
  const HomogeneousMedium medium = makeMedium({1.0, 2.0, 4.0}, {0.0, 0.0, 0.0}, 1.3);
  LightTraceOptions lo;
  lo.paths = 40000;
  const LightTraceResult r =
      lightTrace(sphere, DistantLight::disc({0.3f, 0.5f, 0.8f}, 0.05, glm::vec3(1.0f)), medium, lo);
  const std::vector<float> areas = vertexAreas(sphere);
  for (int c = 0; c < 3; ++c) {
    double tallied = 0.0;
    for (std::size_t v = 0; v < areas.size(); ++v) tallied += areas[v] * r.exitance[v][c];
    EXPECT_NEAR(tallied / r.exitedPower[c], 1.0, 1e-4) << c;
    EXPECT_NEAR(r.exitedPower[c] / r.enteredPower[c], 1.0, 0.01) << c;
    EXPECT_NEAR(r.escapedPower[c] / r.hitPower[c], 1.0, 0.01) << c;
    // The sphere intercepts pi r^2 of the beam's irradiance 1.
    EXPECT_NEAR(r.hitPower[c] / (M_PI * 9.0), 1.0, 0.02) << c;
  }
  EXPECT_EQ(r.lostWalks, 0u);
  EXPECT_EQ(r.truncatedPaths, 0u);
}

// The radiance along a vertex normal is that of the faceted surface seen down the normal. On an
// icosahedron every facet tilts 37.4 degrees from its vertices' normals. A non-absorbing object
// under uniform radiance 1 (the white furnace) sends radiance 1 - F_r(mu) out of each facet in
// every direction at cosine mu to the facet's normal (the refracted part; the tracer does not
// tally the specular reflection), so the tally over the cone about n_k is
//   L = int_cone (n_f . w) (1 - F_r(n_f . w)) dw / int_cone (n_f . w) dw,
// about 0.98, where an estimator per vertex area instead of projected area would give 0.79 of it.
TEST(LightTracer, RadianceOfAFacetedSurfaceIsPerProjectedArea) {
  const TriangleMesh icosahedron = makeIcosphere(0, 3.0f);
  const HomogeneousMedium medium = makeMedium({1.0, 1.0, 1.0}, {0.0, 0.0, 0.0}, 1.3);
  LightTraceOptions lo;
  lo.paths = 400000;
  const LightTraceResult r =
      lightTrace(icosahedron, DistantLight::environment(Cubemap(4, glm::vec3(1.0f))), medium, lo);
  // The expected value by quadrature over the 15-degree cone about n_k (any vertex: all alike).
  const glm::vec3 nk = icosahedron.normals[icosahedron.triangles[0].x];
  const glm::vec3 nf =
      glm::normalize(glm::cross(icosahedron.positions[icosahedron.triangles[0].y] -
                                    icosahedron.positions[icosahedron.triangles[0].x],
                                icosahedron.positions[icosahedron.triangles[0].z] -
                                    icosahedron.positions[icosahedron.triangles[0].x]));
  const glm::vec3 t = glm::normalize(
      glm::cross(nk, std::abs(nk.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
  const glm::vec3 b = glm::cross(nk, t);
  double num = 0.0, den = 0.0;
  const int n = 400;
  const double cone = 15.0 * M_PI / 180.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double theta = cone * (i + 0.5) / n, phi = 2.0 * M_PI * (j + 0.5) / n;
      const glm::vec3 w =
          float(std::cos(theta)) * nk +
          float(std::sin(theta)) * (float(std::cos(phi)) * t + float(std::sin(phi)) * b);
      const double mu = glm::dot(nf, w), dw = std::sin(theta);  // the grid's constant steps cancel
      num += mu * fresnelTransmittance(float(mu), 1.3f) * dw;
      den += mu * dw;
    }
  const double expected = num / den;
  EXPECT_GT(expected, 0.97);
  double mean = 0.0, var = 0.0;
  for (std::size_t v = 0; v < icosahedron.positions.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      mean += r.radiance[v][c];
      var += double(r.radianceStdErr[v][c]) * r.radianceStdErr[v][c];
    }
  const double count = 3.0 * double(icosahedron.positions.size());
  const double stdErr = std::sqrt(var) / count;
  mean /= count;
  EXPECT_LT(stdErr, 0.006);
  EXPECT_NEAR(mean, expected, 4.0 * stdErr + 0.005);  // + the cone tally's own 0.5 %
}

// Two spheres in a line with the beam: the far one lies wholly in the near one's shadow, so all
// its light has left the near one and entered it again. Without absorption all of it leaves.
TEST(LightTracer, FollowsLightThatEntersTheObjectAgain) {
  TriangleMesh near = makeIcosphere(2, 3.0f);
  const std::size_t n = near.positions.size();
  const TriangleMesh second = near;
  for (glm::vec3& p : near.positions) p.x += 4.0f;
  const TriangleMesh pair = joinedMeshes(near, second, glm::vec3(-4.0f, 0.0f, 0.0f));
  const HomogeneousMedium medium = makeMedium({0.5, 0.5, 0.5}, {0.0, 0.0, 0.0}, 1.3);
  LightTraceOptions lo;
  lo.paths = 40000;
  const LightTraceResult r =
      lightTrace(pair, DistantLight::disc({1.0f, 0.0f, 0.0f}, 0.0, glm::vec3(1.0f)), medium, lo);
  const std::vector<float> areas = vertexAreas(pair);
  double nearPower = 0.0, farPower = 0.0;
  for (std::size_t v = 0; v < pair.positions.size(); ++v)
    (v < n ? nearPower : farPower) += areas[v] * r.exitance[v].x;
  EXPECT_GT(r.reentries, 300u);
  EXPECT_GT(farPower, 0.05 * nearPower);  // ~0.095 measured
  EXPECT_NEAR(r.escapedPower.x / r.hitPower.x, 1.0, 0.01);
  EXPECT_NEAR(r.exitedPower.x / r.enteredPower.x, 1.0, 0.01);
}

// The standard errors the studies subtract as the reference's noise (relative RMS with the noise
// removed) must be the spread a run with another seed shows: over 24 seeds, the variance of each
// vertex's radiance against the mean of its squared standard errors, summed over vertices and
// channels. The box with a pit under a small sun: light that leaves and enters again, and a
// directional source, where batch means could hide a heavy tail. (32 batches per run; a variance
// off by their k / (k - 1) would already miss the 3 %.)
TEST(LightTracer, ReportedStandardErrorsMatchTheSpreadOverSeeds) {
  const TriangleMesh pit = boxWithPit();
  const HomogeneousMedium medium = makeMedium({1.0, 2.0, 3.0}, {0.02, 0.05, 0.1}, 1.4);
  const DistantLight sun =
      DistantLight::disc(glm::normalize(glm::vec3(0.5f, 0.0f, 0.866f)), 0.02, glm::vec3(1.0f));
  LightTraceOptions lo;
  lo.paths = 40000;
  constexpr int kSeeds = 24;
  const std::size_t n = pit.positions.size();
  std::vector<glm::dvec3> sum(n, glm::dvec3(0.0)), sum2(n, glm::dvec3(0.0)),
      reported(n, glm::dvec3(0.0));
  for (int s = 0; s < kSeeds; ++s) {
    lo.run.seed = 100 + s;
    const LightTraceResult r = lightTrace(pit, sun, medium, lo);
    for (std::size_t v = 0; v < n; ++v) {
      const glm::dvec3 l(r.radiance[v]), se(r.radianceStdErr[v]);
      sum[v] += l;
      sum2[v] += l * l;
      reported[v] += se * se / double(kSeeds);
    }
  }
  double spread = 0.0, claimed = 0.0;
  for (std::size_t v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c) {
      const double mean = sum[v][c] / kSeeds;
      spread += (sum2[v][c] / kSeeds - mean * mean) * kSeeds / (kSeeds - 1.0);
      claimed += reported[v][c];
    }
  EXPECT_NEAR(spread / claimed, 1.0, 0.03);
}

TEST(LightTracer, SameResultForAnyThreadCount) {
  const TriangleMesh sphere = makeIcosphere(1, 3.0f);
  const HomogeneousMedium medium = makeMedium({1.0, 2.0, 3.0}, {0.1, 0.05, 0.2}, 1.3);
  LightTraceOptions lo;
  lo.paths = 4000;
  lo.batches = 8;
  const DistantLight light = DistantLight::disc({0.0f, 0.0f, 1.0f}, 0.1, glm::vec3(1.0f));
  lo.run.threads = 1;
  const LightTraceResult one = lightTrace(sphere, light, medium, lo);
  lo.run.threads = 3;
  const LightTraceResult three = lightTrace(sphere, light, medium, lo);
  EXPECT_EQ(one.exitance, three.exitance);
  EXPECT_EQ(one.radiance, three.radiance);
  EXPECT_EQ(one.exitanceStdErr, three.exitanceStdErr);
}

// The far field's options (lib/transport/far_field.h): rounds of paths add up to one run; a window
// far below any exit distance leaves the tallies as they are, one far above every distance empties
// them; stopping at the first exit drops only light that entered again.
TEST(LightTracer, RoundsWindowsAndFirstExits) {
  const TriangleMesh sphere = makeIcosphere(1, 3.0f);
  const HomogeneousMedium medium = makeMedium({1.0, 2.0, 3.0}, {0.1, 0.05, 0.2}, 1.3);
  const DistantLight light = DistantLight::disc({0.0f, 0.0f, 1.0f}, 0.1, glm::vec3(1.0f));
  LightTraceOptions lo;
  lo.paths = 4000;
  lo.batches = 8;
  const LightTraceResult all = lightTrace(sphere, light, medium, lo);
  lo.paths = 2000;
  const LightTraceResult first = lightTrace(sphere, light, medium, lo);
  lo.firstPath = 2000;
  const LightTraceResult second = lightTrace(sphere, light, medium, lo);
  for (std::size_t v = 0; v < sphere.positions.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      const float both = 0.5f * (first.exitance[v][c] + second.exitance[v][c]);
      EXPECT_NEAR(all.exitance[v][c], both, 1e-5f * (all.exitance[v][c] + 1e-6f));
    }
  lo.paths = 4000;
  lo.firstPath = 0;
  lo.nearWindowMm = glm::dvec3(1e-9);
  EXPECT_EQ(lightTrace(sphere, light, medium, lo).exitance, all.exitance);
  lo.nearWindowMm = glm::dvec3(1e6);
  for (const glm::vec3& b : lightTrace(sphere, light, medium, lo).exitance)
    EXPECT_LT(b.x + b.y + b.z, 1e-9f);
  lo.nearWindowMm = glm::dvec3(0.0);
  lo.stopAtFirstExit = true;
  const LightTraceResult once = lightTrace(sphere, light, medium, lo);
  EXPECT_EQ(once.exitance, all.exitance);  // convex: nothing enters again
  lo.nearWindowMm = glm::dvec3(-1.0);
  EXPECT_THROW(lightTrace(sphere, light, medium, lo), Error);
}

TEST(LightTracer, RejectsBadInput) {
  const TriangleMesh sphere = makeIcosphere(1, 3.0f);
  const HomogeneousMedium medium = makeMedium({1.0, 1.0, 1.0}, {0.1, 0.1, 0.1}, 1.3);
  const DistantLight light = DistantLight::disc({0.0f, 0.0f, 1.0f}, 0.0, glm::vec3(1.0f));
  LightTraceOptions lo;
  lo.batches = 1;
  EXPECT_ANY_THROW(lightTrace(sphere, light, medium, lo));
  lo = {};
  lo.coneHalfAngleDeg = 0.0;
  EXPECT_ANY_THROW(lightTrace(sphere, light, medium, lo));
  EXPECT_ANY_THROW(lightTrace(TriangleMesh{}, light, medium, {}));
  EXPECT_ANY_THROW(DistantLight::disc(glm::vec3(0.0f), 0.0, glm::vec3(1.0f)));
  EXPECT_ANY_THROW(DistantLight::environment(Cubemap(4, glm::vec3(0.0f))));
}

}  // namespace
}  // namespace sss

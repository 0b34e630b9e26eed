// The exit lobe (optics/exit_lobe.h): its closed forms against quadrature and Monte Carlo, and its
// prediction of the radiance along the normal from the mean internal cosine of traced exits,
// against the light tracer's own cone tally of the same exits, where the normalized exit model
// (the lobe of slope 0) fails: a thin slab lit from behind; and why the far field's lobe is fitted
// to all exits: a low-albedo face under a high sun.
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/random.h"
#include "material/material.h"
#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"
#include "optics/exit_lobe.h"
#include "optics/fresnel.h"
#include "pathtrace/light_tracer.h"
#include "pathtrace/subsurface_path_tracer.h"
#include "transport/finite_object_energy.h"

namespace sss {
namespace {

struct RegionMeans {
  glm::dvec3 exitance{0.0}, cosine{0.0}, radiance{0.0};
};

// Area-weighted means over the vertices `inRegion` selects.
template <class Select>
RegionMeans regionMeans(const TriangleMesh& mesh, const LightTraceResult& r, Select inRegion) {
  const std::vector<float> areas = vertexAreas(mesh);
  RegionMeans m;
  double area = 0.0;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    if (!inRegion(mesh.positions[v], mesh.normals[v])) continue;
    const double a = areas[v];
    m.exitance += a * glm::dvec3(r.exitance[v]);
    m.cosine += a * glm::dvec3(r.exitCosine[v]);
    m.radiance += a * glm::dvec3(r.radiance[v]);
    area += a;
  }
  m.exitance /= area;
  m.cosine /= area;
  m.radiance /= area;
  return m;
}

// The lobe's cosine-weighted mean radiance over a cone of half-angle `coneDeg` about the normal
// (what the light tracer's radiance tally measures), by the midpoint rule.
double coneMeanRadiance(const ExitLobe& lobe, double slope, double coneDeg) {
  const double lo = std::cos(coneDeg * M_PI / 180.0);
  constexpr int n = 200;
  double sum = 0.0, weight = 0.0;
  for (int i = 0; i < n; ++i) {
    const double mu = lo + (1.0 - lo) * (i + 0.5) / n;
    sum += lobe.radiance(slope, float(mu)) * mu;
    weight += mu;
  }
  return sum / weight;
}

// The radiance over the tracer's cone that the lobe (slope from the region's mean internal
// cosine) and the normalized exit model (slope 0) predict from the region's B, over the traced
// radiance.
struct Predictions {
  glm::dvec3 lobe{0.0}, normalized{0.0};
};
Predictions predictions(const RegionMeans& m, float eta, double coneDeg) {
  const ExitLobe lobe(eta);
  Predictions p;
  for (int c = 0; c < 3; ++c) {
    const double k = lobe.slopeFor(m.cosine[c] / m.exitance[c]);
    p.lobe[c] = m.exitance[c] * coneMeanRadiance(lobe, k, coneDeg) / m.radiance[c];
    p.normalized[c] = m.exitance[c] * coneMeanRadiance(lobe, 0.0, coneDeg) / m.radiance[c];
  }
  return p;
}

constexpr float kEta = 1.3f;

TEST(ExitLobe, SlopeZeroIsTheNormalizedExitModel) {
  const ExitLobe lobe(kEta);
  EXPECT_NEAR(lobe.moment(0), 1.0 - diffuseFresnelReflectance(kEta), 1e-6);
  for (float mu : {0.05f, 0.3f, 0.7f, 1.0f})
    EXPECT_NEAR(lobe.radiance(0.0, mu), fresnelTransmittance(mu, kEta) * exitRadianceScale(kEta),
                1e-6);
}

TEST(ExitLobe, EmitsTheExitanceForEverySlope) {
  const ExitLobe lobe(kEta);
  for (double k : {-1.0, -0.5, 0.0, 1.0, 5.0, 100.0}) {
    // Flux = 2 pi int L(mu) mu dmu, by the midpoint rule (a different quadrature from the
    // moments' Simpson rule).
    double flux = 0.0;
    constexpr int n = 20000;
    for (int i = 0; i < n; ++i) {
      const float mu = (float(i) + 0.5f) / n;
      flux += lobe.radiance(k, mu) * mu / n;
    }
    EXPECT_NEAR(2.0 * M_PI * flux, 1.0, 1e-4) << "slope " << k;
  }
}

TEST(ExitLobe, SlopeForInvertsTheMeanCosineAndClamps) {
  const ExitLobe lobe(kEta);
  for (double k : {-0.9, -0.3, 0.0, 0.4, 2.0, 30.0})
    EXPECT_NEAR(lobe.slopeFor(lobe.meanCosine(k)), k, 1e-6 * (1.0 + std::abs(k)));
  EXPECT_EQ(lobe.slopeFor(0.1), ExitLobe::kMinSlope);
  EXPECT_EQ(lobe.slopeFor(1.0), ExitLobe::kMaxSlope);
  EXPECT_EQ(lobe.slopeFor(std::nan("")), ExitLobe::kMinSlope);
  // The derivative against a central difference.
  for (double k : {-0.5, 0.0, 2.0}) {
    const double m = lobe.meanCosine(k), h = 1e-6;
    const double numeric = (lobe.slopeFor(m + h) - lobe.slopeFor(m - h)) / (2.0 * h);
    EXPECT_NEAR(lobe.slopeDerivative(m), numeric, 1e-4 * numeric) << "slope " << k;
  }
}

TEST(ExitLobe, SlopeForNormalRatioGivesThatRadianceAlongTheNormal) {
  const ExitLobe lobe(kEta);
  for (double ratio : {0.85, 0.93, 1.0, 1.05}) {
    const double k = lobe.slopeForNormalRatio(ratio);
    EXPECT_NEAR(lobe.radiance(k, 1.0f) / lobe.radiance(0.0, 1.0f), ratio, 1e-9) << ratio;
  }
  EXPECT_EQ(lobe.slopeForNormalRatio(1.0), 0.0);
  EXPECT_EQ(lobe.slopeForNormalRatio(0.0), ExitLobe::kMinSlope);
  EXPECT_EQ(lobe.slopeForNormalRatio(100.0), ExitLobe::kMaxSlope);
}

// A slope well above its noise stays, one at its noise halves, one below it fades to 0.
TEST(ExitLobe, ShrinksASlopeByItsNoise) {
  const ExitLobe lobe(kEta);
  const double k = -0.6, m = lobe.meanCosine(k), dk = lobe.slopeDerivative(m);
  EXPECT_NEAR(lobe.shrunkSlopeFor(m, 0.0), k, 1e-9);
  // var m such that the slope's standard deviation is |k|: weight k^2 / (k^2 + k^2) = 1/2.
  EXPECT_NEAR(lobe.shrunkSlopeFor(m, k * k / (dk * dk)), 0.5 * k, 1e-9);
  EXPECT_NEAR(lobe.shrunkSlopeFor(m, 100.0 * k * k / (dk * dk)), k / 101.0, 1e-9);
  EXPECT_NEAR(lobe.shrunkSlopeFor(lobe.meanCosine(0.0), 1e-4), 0.0, 1e-12);
}

// The mean internal cosine of the light that leaves, by Monte Carlo: directions inside drawn with
// density proportional to (1 + k mu_i) mu_i (the flux towards the boundary of that radiance),
// each crossing with probability F_t (total internal reflection beyond the critical angle).
TEST(ExitLobe, MeanCosineMatchesMonteCarlo) {
  const ExitLobe lobe(kEta);
  for (double k : {-0.8, 0.0, 1.5}) {
    Pcg32 rng(7, uint64_t(k * 100 + 1000));
    double sum = 0.0, count = 0.0;
    const double peak = (1.0 + std::max(k, 0.0));
    for (int i = 0; i < 400000; ++i) {
      const double mu = std::sqrt(rng.uniformDouble());         // pdf 2 mu
      if (rng.uniformDouble() * peak > 1.0 + k * mu) continue;  // times (1 + k mu)
      const float cosOut = std::sqrt(std::max(0.0, 1.0 - kEta * kEta * (1.0 - mu * mu)));
      if (cosOut <= 0.0f || rng.uniformDouble() >= fresnelTransmittance(cosOut, kEta)) continue;
      sum += mu;
      count += 1.0;
    }
    EXPECT_NEAR(sum / count, lobe.meanCosine(k), 1.5e-3) << "slope " << k;
  }
}

// A 20 x 20 x 2 mm ketchup slab lit from behind by a collimated sun 30 degrees off its normal:
// red light (mean free path 4 mm) leaves the unlit face after a few scatterings, more of it at
// grazing angles than diffusion gives. The normalized exit model puts 1.19x the traced radiance
// along the normal there (1.15x on the lit face); the lobe from the same exits' mean cosine 0.97x
// (0.94x).
TEST(ExitLobe, PredictsTheRadianceLeavingAThinSlab) {
  const Material ketchup = findMaterialPreset("ketchup");
  const TriangleMesh slab = makeSlab(20.0f, 2.0f, 20);
  const DistantLight sun =
      DistantLight::disc({std::sin(0.5236f), 0.0f, -std::cos(0.5236f)}, 0.0, glm::vec3(1.0f));
  LightTraceOptions o;
  o.paths = 2000000;
  o.tallyExitCosine = true;
  o.minScatteringOrder = 1;  // what crosses unscattered leaves collimated: no exit lobe's
  o.stopAtFirstExit = true;
  const LightTraceResult r = lightTraceSubsurface(slab.positions, slab.normals, slab.triangles, sun,
                                                  homogeneousMediumOf(ketchup), o);
  for (float side : {1.0f, -1.0f}) {
    const Predictions p = predictions(regionMeans(slab, r,
                                                  [side](glm::vec3 x, glm::vec3 n) {
                                                    return n.z * side > 0.999f &&
                                                           std::abs(x.x) < 5 && std::abs(x.y) < 5;
                                                  }),
                                      float(ketchup.eta), o.coneHalfAngleDeg);
    EXPECT_NEAR(p.lobe.r, 1.0, 0.08) << "face " << side;
    EXPECT_GT(p.normalized.r, 1.12) << "face " << side;
  }
}

// A 10 mm marble sphere under a collimated sun: on its unlit half the light has diffused across
// it and flows outwards, so it leaves more along the normal than an isotropic interior gives; the
// normalized exit model reads 0.92-0.96x the traced radiance there (over a 30-degree cone), the
// lobe 0.98-1.02x.
TEST(ExitLobe, PredictsTheRadianceOnTheUnlitHalfOfASphere) {
  const Material marble = findMaterialPreset("marble");
  const TriangleMesh sphere = makeIcosphere(3, 10.0f);
  LightTraceOptions o;
  o.paths = 400000;
  o.tallyExitCosine = true;
  o.stopAtFirstExit = true;
  o.coneHalfAngleDeg = 30.0;  // more exits than the default 15 (the lobe is compared over it)
  const LightTraceResult r = lightTraceSubsurface(
      sphere.positions, sphere.normals, sphere.triangles,
      DistantLight::disc({0, 0, 1}, 0.0, glm::vec3(1.0f)), homogeneousMediumOf(marble), o);
  const Predictions p =
      predictions(regionMeans(sphere, r, [](glm::vec3, glm::vec3 n) { return n.z < -0.3f; }),
                  float(marble.eta), o.coneHalfAngleDeg);
  EXPECT_NEAR(p.lobe.r, 1.0, 0.04) << "normalized " << p.normalized.r;
  // Both read the same B and traced radiance, so their gap is the measured slope's, not noise
  // (0.92-0.96 for the normalized model over seeds 1-3, the lobe 0.98-1.02).
  EXPECT_LT(p.normalized.r, p.lobe.r - 0.04);
}

// A 10 mm thick skin1 slab under a sun along its normal, the middle of its lit face (a half-space
// to the light): the far field's window (transport/far_field.h) splits the exits by angle as well
// as by distance. Light that leaves within a fraction of a mean free path of where it entered went
// nearly straight back, so the near exits crowd the normal and the far ones avoid it. The lobe of
// all exits puts 0.97-1.02x the traced radiance along the normal (seeds 1-4, all channels); B_far
// through the lobe of the far exits and B - B_far through the normalized model 0.96-0.98x,
// 0.93-0.94x and 0.88-0.93x (R / G / B).
TEST(ExitLobe, OneLobeForAllExitsFollowsALowAlbedoFaceUnderAHighSun) {
  const Material skin = findMaterialPreset("skin1");
  const TriangleMesh slab = makeSlab(40.0f, 10.0f, 20);
  const DistantLight sun = DistantLight::disc({0, 0, 1}, 0.0, glm::vec3(1.0f));
  LightTraceOptions o;
  o.paths = 600000;
  o.tallyExitCosine = true;
  o.minScatteringOrder = 1;
  o.stopAtFirstExit = true;
  const auto trace = [&] {
    return lightTraceSubsurface(slab.positions, slab.normals, slab.triangles, sun,
                                homogeneousMediumOf(skin), o);
  };
  const LightTraceResult all = trace();
  o.nearWindowMm = farFieldWindowMm(skin);
  o.tallyRadiance = false;
  const LightTraceResult far = trace();
  o.exitCosineOfAllExits = true;
  const LightTraceResult farWithAllCosines = trace();
  // The same paths: the all-exit tallies beside the windowed B are the unwindowed run's (up to
  // the float sums' order).
  const auto same = [](const std::vector<glm::vec3>& x, const std::vector<glm::vec3>& y) {
    double worst = 0.0;
    for (std::size_t v = 0; v < x.size(); ++v)
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, double(std::abs(x[v][c] - y[v][c])) / std::abs(y[v][c]));
    return x.size() == y.size() && worst < 1e-5;
  };
  ASSERT_TRUE(same(farWithAllCosines.cosineExitance, all.exitance));
  ASSERT_TRUE(same(farWithAllCosines.exitCosine, all.exitCosine));
  ASSERT_TRUE(same(farWithAllCosines.exitance, far.exitance));

  const auto litMiddle = [](glm::vec3 x, glm::vec3 n) {
    return n.z > 0.999f && std::abs(x.x) < 10 && std::abs(x.y) < 10;
  };
  const RegionMeans a = regionMeans(slab, all, litMiddle), f = regionMeans(slab, far, litMiddle);
  const ExitLobe lobe(float(skin.eta));
  for (int c = 0; c < 3; ++c) {
    const double cone = o.coneHalfAngleDeg;
    const double allLobe =
        a.exitance[c] * coneMeanRadiance(lobe, lobe.slopeFor(a.cosine[c] / a.exitance[c]), cone);
    const double split =
        (a.exitance[c] - f.exitance[c]) * coneMeanRadiance(lobe, 0.0, cone) +
        f.exitance[c] * coneMeanRadiance(lobe, lobe.slopeFor(f.cosine[c] / f.exitance[c]), cone);
    EXPECT_NEAR(allLobe / a.radiance[c], 1.0, 0.04) << "channel " << c;
    if (c > 0) {
      EXPECT_LT(split / a.radiance[c], 0.96) << "channel " << c;
    }
  }
}

}  // namespace
}  // namespace sss

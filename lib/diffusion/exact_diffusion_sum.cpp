#include "diffusion/exact_diffusion_sum.h"

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "core/parallel.h"
#include "core/progress.h"
#include "material/diffusion_profile.h"

namespace sss {

namespace {

// Sources closer than kNearDiscs disc radii are averaged over their disc.
constexpr double kNearDiscs = 4;
constexpr int kDiscRings = 4, kDiscAngles = 8;

// Mean of R_d(|x_o - y|) over y in the disc of radius rho around x_i in the plane normal to n_i:
// equal-area polar midpoint rule (kDiscRings x kDiscAngles cells).
glm::dvec3 discAverage(const DiffusionProfile& profile, const glm::dvec3& xi, const glm::dvec3& ni,
                       double rho, const glm::dvec3& xo) {
  const glm::dvec3 a = std::abs(ni.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 t = glm::normalize(glm::cross(ni, a)), b = glm::cross(ni, t);
  glm::dvec3 sum(0);
  for (int ring = 0; ring < kDiscRings; ++ring) {
    const double radius = rho * std::sqrt((ring + 0.5) / kDiscRings);
    for (int k = 0; k < kDiscAngles; ++k) {
      const double phi = 2 * std::numbers::pi * (k + 0.5 * (ring & 1) + 0.25) / kDiscAngles;
      const glm::dvec3 y = xi + radius * (std::cos(phi) * t + std::sin(phi) * b);
      sum += profile.evaluate(glm::length(y - xo));
    }
  }
  return sum / static_cast<double>(kDiscRings * kDiscAngles);
}

// Vertex o's B (and rho) from every vertex of the input.
void sumAtVertex(const DiffusionInput& in, const DiffusionProfile& profile, std::size_t o,
                 glm::dvec3& sum, glm::dvec3& weights) {
  const std::size_t n = in.positions.size();
  const double rho = std::sqrt(in.areas[o] / std::numbers::pi);
  const glm::dvec3 self = profile.integrateDisc(rho);
  sum = self * glm::dvec3(in.irradiance[o]), weights = self;
  const glm::dvec3 xo(in.positions[o]);
  for (std::size_t i = 0; i < n; ++i) {
    if (i == o) continue;
    const glm::dvec3 xi(in.positions[i]);
    const double r = glm::length(xi - xo);
    const double rhoI = std::sqrt(in.areas[i] / std::numbers::pi);
    const glm::dvec3 rd = r < kNearDiscs * rhoI
                              ? discAverage(profile, xi, glm::dvec3(in.normals[i]), rhoI, xo)
                              : profile.evaluate(r);
    sum += rd * glm::dvec3(in.irradiance[i]) * static_cast<double>(in.areas[i]);
    weights += rd * static_cast<double>(in.areas[i]);
  }
}

}  // namespace

DiffusionResult exactDiffusionSum(const DiffusionInput& input, const DiffusionProfile& profile,
                                  const DiffusionOptions& options) {
  const std::size_t n = input.positions.size();
  DiffusionResult out;
  out.exitance.resize(n);
  if (options.weightSums) out.weightSums.resize(n);
  Progress progress("diffusion (exact)", n, options.run.quiet);
  parallelFor(n, options.run.threads, 32, [&](std::size_t b, std::size_t e) {
    for (std::size_t o = b; o < e; ++o) {
      glm::dvec3 sum, weights;
      sumAtVertex(input, profile, o, sum, weights);
      out.exitance[o] = glm::vec3(sum);
      if (options.weightSums) out.weightSums[o] = glm::vec3(weights);
    }
    progress.advance(e - b);
  });
  progress.finish();
  out.report.interactions = n * n;
  return out;
}

}  // namespace sss

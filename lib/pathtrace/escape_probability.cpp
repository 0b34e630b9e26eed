#include "pathtrace/escape_probability.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/random.h"
#include "core/timer.h"
#include "material/material.h"
#include "mesh/triangle_mesh.h"
#include "optics/fresnel.h"
#include "pathtrace/one_ring_sampler.h"
#include "pathtrace/walk_sampling.h"
#include "raytrace/triangle_scene.h"

namespace sss {
namespace {

// A walk whose absorption weight exp(-sigma_a l) falls below e^-30 scores 0 (bias < 1e-13).
constexpr double kNegligibleOpticalDepth = 30.0;
constexpr int kMaxEvents = 1 << 20;  // safety cap: such walks score 0 (counted as lost)

struct WalkOutcome {
  double weight = 0.0;
  uint64_t events = 0;
  bool lost = false;  // left through a hole, or hit the cap
};

class EscapeWalker {
 public:
  EscapeWalker(const TriangleScene& scene, const std::vector<glm::uvec3>& triangles,
               const Material& m)
      : scene_(scene),
        triangles_(triangles),
        sigmaA_(m.sigmaA),
        sigmaS_(m.sigmaS()),
        g_(m.g),
        eta_(static_cast<float>(m.eta)) {}

  // One walk for channel c entering at point x of triangle `start` (unit face normal n).
  WalkOutcome walk(const glm::vec3& x, const glm::vec3& n, uint32_t start, int c,
                   Pcg32& rng) const {
    glm::vec3 wo = sampleCosineHemisphere(n, rng);
    while (rng.uniformDouble() >= fresnelTransmittance(glm::dot(wo, n), eta_))
      wo = sampleCosineHemisphere(n, rng);
    const glm::vec3 inward = refractDirection(-wo, -n, 1.0f / eta_);
    return walkInside(x - scene_.epsilon() * n, inward, start, c, rng);
  }

 private:
  WalkOutcome walkInside(glm::vec3 p, glm::vec3 d, uint32_t start, int c, Pcg32& rng) const {
    WalkOutcome out;
    const float eps = scene_.epsilon();
    const double sigmaS = sigmaS_[c], sigmaA = sigmaA_[c];
    double length = 0.0, forced = 1.0;
    uint64_t boundaryHits = 0;
    for (;;) {
      if (out.events >= static_cast<uint64_t>(kMaxEvents)) {
        out.lost = true;
        return out;
      }
      const SceneHit hit = scene_.intersect(p, d);
      if (!hit.hit) {
        out.lost = true;
        return out;
      }
      double t;
      if (out.events == 0) {
        if (boundaryHits == 0 && hit.triangle == start) {  // grazing: out through the entry face
          out.lost = true;
          return out;
        }
        // Forced scattering until the first event: on this segment the walk either scatters
        // (probability p_s = 1 - exp(-sigma_s t_hit)) or reaches the far side and reflects back
        // inside (F_r); it carries their sum q and picks one in proportion. Light that crosses
        // and leaves unscattered is not diffusion's: no zero scores from the first flights.
        const double scatterProbability = -std::expm1(-sigmaS * double(hit.t));
        if (!(scatterProbability > 0.0)) return out;  // no scattering (and no endless bouncing)
        glm::vec3 normal = hit.faceNormal;
        float cosI = glm::dot(d, normal);
        if (cosI < 0.0f) {
          normal = -normal;
          cosI = -cosI;
        }
        const double q =
            scatterProbability + (1.0 - scatterProbability) * fresnelDielectric(cosI, 1.0f / eta_);
        forced *= q;
        if (rng.uniformDouble() * q >= scatterProbability) {
          ++boundaryHits;
          length += hit.t;
          const glm::vec3 hitPoint = p + hit.t * d;
          d = glm::normalize(d - 2.0f * cosI * normal);
          p = hitPoint - eps * normal;
          continue;
        }
        t = -std::log1p(-rng.uniformDouble() * scatterProbability) / sigmaS;
      } else {
        t = sigmaS > 0.0 ? -std::log(1.0 - rng.uniformDouble()) / sigmaS
                         : std::numeric_limits<double>::infinity();
      }
      if (t < hit.t) {
        length += t;
        if (sigmaA * length > kNegligibleOpticalDepth) return out;
        p += static_cast<float>(t) * d;
        d = sampleHenyeyGreenstein(d, g_, rng);
        ++out.events;
        continue;
      }
      ++boundaryHits;
      length += hit.t;
      const glm::vec3 hitPoint = p + hit.t * d;
      glm::vec3 normal = hit.faceNormal;
      float cosI = glm::dot(d, normal);
      if (cosI < 0.0f) {  // a back face (open or inconsistent mesh): cross it anyway
        normal = -normal;
        cosI = -cosI;
      }
      if (rng.uniformDouble() < fresnelDielectric(cosI, 1.0f / eta_)) {
        d = glm::normalize(d - 2.0f * cosI * normal);
        p = hitPoint - eps * normal;
        continue;
      }
      out.weight = forced * std::exp(-sigmaA * length);
      return out;
    }
  }

  const TriangleScene& scene_;
  const std::vector<glm::uvec3>& triangles_;
  glm::dvec3 sigmaA_, sigmaS_;
  double g_;
  float eta_;
};

}  // namespace

EscapeResult estimateEscapeProbability(const TriangleMesh& meshMm, std::span<const float> areas,
                                       const Material& material, const EscapeOptions& options) {
  const Stopwatch clock;
  const std::size_t n = meshMm.positions.size();
  if (n == 0 || meshMm.triangles.empty()) fail("", "escape probability: empty mesh");
  if (areas.size() != n) fail("", "escape probability: one area per vertex needed");
  validateMaterial(material);
  if (!(std::abs(material.g) < 1.0)) fail("", "escape probability: |g| must be below 1");
  if (options.walks < 1) fail("", "escape probability: walks must be at least 1");

  const TriangleScene scene(meshMm.positions, meshMm.triangles);
  const EscapeWalker walker(scene, meshMm.triangles, material);
  const std::size_t probes = std::min(n, std::max<std::size_t>(options.maxProbes, 1));
  auto probeVertex = [&](std::size_t k) { return static_cast<uint32_t>(k * n / probes); };

  const OneRingSampler entries(meshMm.positions, meshMm.triangles);

  // Walks at the probes: mean and variance of the mean per channel.
  std::vector<glm::dvec3> probeMean(probes), probeVariance(probes);
  std::atomic<uint64_t> totalEvents{0}, totalLost{0};
  Progress progress("escape walks", probes, options.quiet);
  parallelFor(probes, options.threads, 8, [&](std::size_t begin, std::size_t end) {
    uint64_t events = 0, lost = 0;
    for (std::size_t k = begin; k < end; ++k) {
      const uint32_t v = probeVertex(k);
      Pcg32 rng(options.seed, v);
      for (int c = 0; c < 3; ++c) {
        double sum = 0.0, sumSq = 0.0;
        for (int s = 0; s < options.walks && entries.hasSurface(v); ++s) {
          const SurfacePoint entry = entries.sample(v, rng);
          const WalkOutcome o = walker.walk(entry.position, entry.normal, entry.triangle, c, rng);
          sum += o.weight;
          sumSq += o.weight * o.weight;
          events += o.events;
          lost += o.lost;
        }
        const double w = options.walks, mean = sum / w;
        probeMean[k][c] = mean;
        probeVariance[k][c] =
            options.walks > 1 ? std::max(0.0, sumSq / w - mean * mean) / (w - 1.0) : mean * mean;
      }
    }
    totalEvents += events;
    totalLost += lost;
    progress.advance(end - begin);
  });
  progress.finish();

  // Smoothing over the surface.
  double totalArea = 0.0;
  for (float a : areas) totalArea += a;
  const double spacing = std::sqrt(totalArea / double(probes));
  // One width for all channels: P varies with the object's shape, which the longest diffusion
  // length sees.
  const glm::dvec3 sigmaTr = material.sigmaTr();
  const double shortestTr = std::min({sigmaTr.x, sigmaTr.y, sigmaTr.z});
  const double length =
      shortestTr > 0.0 ? options.smoothing / shortestTr : double(scene.diagonal());
  const glm::dvec3 sigma(std::max(length, 2.0 * spacing));
  const double reach2 = 9.0 * std::max({sigma.x, sigma.y, sigma.z}) *
                        std::max({sigma.x, sigma.y, sigma.z});  // 3 sigma
  EscapeResult result;
  result.probability.assign(n, glm::vec3(0.0f));
  std::vector<glm::dvec3> variance(n);
  parallelFor(n, options.threads, 64, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const glm::vec3 x = meshMm.positions[i];
      glm::dvec3 num(0.0), den(0.0), var(0.0);
      std::size_t nearest = 0;
      float nearestD2 = std::numeric_limits<float>::infinity();
      for (std::size_t k = 0; k < probes; ++k) {
        const uint32_t v = probeVertex(k);
        const glm::vec3 dx = meshMm.positions[v] - x;
        const float d2 = glm::dot(dx, dx);
        if (d2 < nearestD2) {
          nearestD2 = d2;
          nearest = k;
        }
        if (d2 > reach2) continue;
        for (int c = 0; c < 3; ++c) {
          const double w = std::exp(-0.5 * d2 / (sigma[c] * sigma[c])) * areas[v];
          num[c] += w * probeMean[k][c];
          den[c] += w;
          var[c] += w * w * probeVariance[k][c];
        }
      }
      for (int c = 0; c < 3; ++c) {
        if (den[c] > 0.0) {
          result.probability[i][c] = static_cast<float>(std::min(1.0, num[c] / den[c]));
          variance[i][c] = var[c] / (den[c] * den[c]);
        } else {  // no probe within reach (a far-away component): the nearest one
          result.probability[i][c] = static_cast<float>(std::min(1.0, probeMean[nearest][c]));
          variance[i][c] = probeVariance[nearest][c];
        }
      }
    }
  });

  double errorSq = 0.0, valueSq = 0.0;
  glm::dvec3 weighted(0.0);
  for (std::size_t i = 0; i < n; ++i) {
    weighted += glm::dvec3(result.probability[i]) * double(areas[i]);
    for (int c = 0; c < 3; ++c) {
      errorSq += variance[i][c];
      valueSq += double(result.probability[i][c]) * result.probability[i][c];
    }
  }
  result.mean = totalArea > 0.0 ? weighted / totalArea : glm::dvec3(0.0);
  result.relativeStdError = valueSq > 0.0 ? std::sqrt(errorSq / valueSq) : 0.0;
  result.probes = probes;
  result.walks = uint64_t(probes) * 3u * uint64_t(options.walks);
  result.lostWalks = totalLost;
  result.meanScatteringEvents = double(totalEvents) / double(std::max<uint64_t>(result.walks, 1));
  result.smoothingSigmaMm = sigma;
  result.seconds = clock.seconds();
  return result;
}

}  // namespace sss

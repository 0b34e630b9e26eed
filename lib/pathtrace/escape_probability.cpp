#include "pathtrace/escape_probability.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/parallel.h"
#include "core/random.h"
#include "core/timer.h"
#include "material/material.h"
#include "mesh/triangle_mesh.h"
#include "optics/fresnel.h"
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
      if (out.events == 0 && boundaryHits == 0) {
        if (hit.triangle == start) {  // grazing: back out through the entry triangle
          out.lost = true;
          return out;
        }
        // Forced first scattering: the flight is drawn inside [0, t_hit) and the walk carries
        // the probability 1 - exp(-sigma_s t_hit) that it scatters there (light that crosses
        // unscattered is not diffusion's): no zero scores from the first flight.
        const double scatterProbability = -std::expm1(-sigmaS * double(hit.t));
        if (!(scatterProbability > 0.0)) return out;
        forced = scatterProbability;
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
  if (meshMm.normals.size() != n || areas.size() != n)
    fail("", "escape probability: one normal and one area per vertex needed");
  validateMaterial(material);
  if (!(std::abs(material.g) < 1.0)) fail("", "escape probability: |g| must be below 1");
  if (options.walks < 1) fail("", "escape probability: walks must be at least 1");

  const TriangleScene scene(meshMm.positions, meshMm.triangles);
  const EscapeWalker walker(scene, meshMm.triangles, material);
  const std::size_t probes = std::min(n, std::max<std::size_t>(options.maxProbes, 1));
  auto probeVertex = [&](std::size_t k) { return static_cast<uint32_t>(k * n / probes); };

  // The triangles around each probe vertex (CSR), with their areas, where its walks enter.
  std::vector<uint32_t> firstTriangle(n + 1, 0), vertexTriangles(3 * meshMm.triangles.size());
  for (const glm::uvec3& t : meshMm.triangles)
    for (int k = 0; k < 3; ++k) ++firstTriangle[t[k] + 1];
  for (std::size_t v = 0; v < n; ++v) firstTriangle[v + 1] += firstTriangle[v];
  {
    std::vector<uint32_t> fill(firstTriangle.begin(), firstTriangle.end() - 1);
    for (uint32_t f = 0; f < meshMm.triangles.size(); ++f)
      for (int k = 0; k < 3; ++k) vertexTriangles[fill[meshMm.triangles[f][k]]++] = f;
  }
  std::vector<float> triangleArea(meshMm.triangles.size());
  std::vector<glm::vec3> triangleNormal(meshMm.triangles.size());
  for (std::size_t f = 0; f < meshMm.triangles.size(); ++f) {
    const glm::uvec3 t = meshMm.triangles[f];
    const glm::vec3 c = glm::cross(meshMm.positions[t.y] - meshMm.positions[t.x],
                                   meshMm.positions[t.z] - meshMm.positions[t.x]);
    const float twice = glm::length(c);
    triangleArea[f] = 0.5f * twice;
    triangleNormal[f] = twice > 0.0f ? c / twice : glm::vec3(0.0f);
  }

  // Walks at the probes: mean and variance of the mean per channel.
  std::vector<glm::dvec3> probeMean(probes), probeVariance(probes);
  std::atomic<uint64_t> totalEvents{0}, totalLost{0};
  parallelFor(probes, options.threads, 8, [&](std::size_t begin, std::size_t end) {
    uint64_t events = 0, lost = 0;
    for (std::size_t k = begin; k < end; ++k) {
      const uint32_t v = probeVertex(k);
      Pcg32 rng(options.seed, v);
      const uint32_t begin = firstTriangle[v], end = firstTriangle[v + 1];
      float ringArea = 0.0f;
      for (uint32_t j = begin; j < end; ++j) ringArea += triangleArea[vertexTriangles[j]];
      for (int c = 0; c < 3; ++c) {
        double sum = 0.0, sumSq = 0.0;
        for (int s = 0; s < options.walks && ringArea > 0.0f; ++s) {
          // A point of the vertex's triangles (area-weighted, uniform inside), entering through
          // the face: the faceted surface the vertex stands for, not its cone-shaped apex.
          float pick = static_cast<float>(rng.uniformDouble()) * ringArea;
          uint32_t f = vertexTriangles[end - 1];
          for (uint32_t j = begin; j < end; ++j) {
            pick -= triangleArea[vertexTriangles[j]];
            if (pick < 0.0f) {
              f = vertexTriangles[j];
              break;
            }
          }
          double u = rng.uniformDouble(), w = rng.uniformDouble();
          if (u + w > 1.0) {
            u = 1.0 - u;
            w = 1.0 - w;
          }
          const glm::uvec3 t = meshMm.triangles[f];
          const glm::vec3 x =
              meshMm.positions[t.x] +
              static_cast<float>(u) * (meshMm.positions[t.y] - meshMm.positions[t.x]) +
              static_cast<float>(w) * (meshMm.positions[t.z] - meshMm.positions[t.x]);
          const WalkOutcome o = walker.walk(x, triangleNormal[f], f, c, rng);
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
  });

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

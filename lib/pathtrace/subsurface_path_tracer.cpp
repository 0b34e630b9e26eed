#include "pathtrace/subsurface_path_tracer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/format.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/random.h"
#include "core/timer.h"
#include "core/tool.h"
#include "material/material.h"
#include "mesh/triangle_mesh.h"
#include "optics/fresnel.h"
#include "pathtrace/medium_walk.h"
#include "pathtrace/one_ring_sampler.h"
#include "pathtrace/walk_sampling.h"
#include "raytrace/triangle_scene.h"

namespace sss {
namespace {

// Walks longer than this (mean scattering events, from a pilot run) earn a warning.
constexpr double kLongWalkEvents = 500.0;
constexpr int kPilotWalks = 256;
// Outside directions cut off by the faceted 1-ring are redrawn at most this often per sample.
constexpr int kMaxRedraws = 16;

// The backward walk: the shared medium walk, then the environment along the refracted exit
// direction where the mesh does not occlude it.
struct Walker {
  const TriangleScene& scene;
  const Cubemap& environment;
  MediumWalker medium;
  bool occlusion;
  int minOrder;

  // One walk from a point inside along d, started at mesh vertex `start`; returns the
  // MIS-weighted radiance it brings back per unit starting weight.
  glm::dvec3 walk(glm::vec3 p, glm::vec3 d, uint32_t start, Pcg32& rng,
                  MediumWalkStats& stats) const {
    const MediumExit exit = medium.walkToExit(p, d, start, rng, stats);
    if (!exit.exited || static_cast<int>(stats.events) < minOrder) return glm::dvec3(0.0);
    const glm::vec3 origin = exit.point + scene.epsilon() * exit.normal;
    if (occlusion && scene.occluded(origin, exit.direction)) return glm::dvec3(0.0);
    return exit.weight * glm::dvec3(environment.sample(exit.direction));
  }
};

struct Accumulator {
  glm::dvec3 sum{0.0}, sumSq{0.0};
  void add(const glm::dvec3& x) {
    sum += x;
    sumSq += x * x;
  }
  void result(int n, glm::vec3& mean, glm::vec3& stdErr) const {
    const glm::dvec3 m = sum / double(n);
    const glm::dvec3 var =
        n > 1 ? glm::max(glm::dvec3(0.0), (sumSq / double(n) - m * m) * (double(n) / (n - 1)))
              : glm::dvec3(0.0);
    mean = glm::vec3(m);
    stdErr = glm::vec3(glm::sqrt(var / double(n)));
  }
};

// Walk counts of one run: summed per thread, then over the threads.
struct WalkCounts {
  uint64_t events = 0, hits = 0, walks = 0, truncated = 0, escaped = 0, redrawn = 0;
};

struct AtomicWalkCounts {
  std::atomic<uint64_t> events{0}, hits{0}, walks{0}, truncated{0}, escaped{0}, redrawn{0};
  void add(const WalkCounts& c) {
    events += c.events;
    hits += c.hits;
    walks += c.walks;
    truncated += c.truncated;
    escaped += c.escaped;
    redrawn += c.redrawn;
  }
};

void addWarning(PathTraceResult& result, const std::string& message) {
  result.warnings.push_back(message);
  warn(message);
}

void validateInputs(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
                    const std::vector<glm::uvec3>& triangles, const Cubemap& environment,
                    const HomogeneousMedium& medium, const PathTraceOptions& options) {
  if (positions.empty() || triangles.empty()) fail("", "path tracer: empty mesh");
  if (normals.size() != positions.size()) fail("", "path tracer: one normal per vertex needed");
  if (environment.empty()) fail("", "path tracer: empty environment");
  if (options.samples < 1) fail("", "path tracer: samples must be at least 1");
  validateHomogeneousMedium(medium);
}

// The walks of one run over the listed vertices (all of them when the list is empty).
class VertexTracer {
 public:
  VertexTracer(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
               const std::vector<glm::uvec3>& triangles, const Cubemap& environment,
               const HomogeneousMedium& medium, const PathTraceOptions& options)
      : positions_(positions),
        normals_(normals),
        medium_(medium),
        options_(options),
        sigmaT_(medium.sigmaA + medium.sigmaS),
        scene_(positions, triangles),
        walker_{scene_, environment,
                MediumWalker(scene_, triangles, medium.sigmaS, sigmaT_,
                             static_cast<float>(medium.eta), medium.g, options.maxScatteringEvents),
                options.occlusion, options.minScatteringOrder},
        eta_(static_cast<float>(medium.eta)),
        eps_(scene_.epsilon()),
        oneRing_(positions, triangles) {
    for (uint32_t v : options.vertices)
      if (v >= positions.size()) fail("", "path tracer: vertex index out of range");
  }

  std::size_t count() const {
    return options_.vertices.empty() ? positions_.size() : options_.vertices.size();
  }
  std::size_t vertexAt(std::size_t k) const {
    return options_.vertices.empty() ? k : options_.vertices[k];
  }

  // The pilot run's expected walk length (events per walk); warns when walks are long.
  void warnOfLongWalks(PathTraceResult& result) const;
  // Every estimate of the k-th listed vertex into result[k]; its walks are added to counts.
  void traceVertex(std::size_t k, PathTraceResult& result, WalkCounts& counts) const;

 private:
  // One walk entering at x through a boundary of normal n (start: the vertex whose own triangles
  // count as "blocked", or none).
  glm::dvec3 walkFrom(const glm::vec3& x, uint32_t start, const glm::vec3& n, const glm::vec3& wo,
                      Pcg32& rng, MediumWalkStats& stats) const {
    const float mu = glm::dot(wo, n);
    if (!(mu > 0.0f)) return glm::dvec3(0.0);  // a facet turned away from a fixed direction
    const glm::vec3 inward = refractDirection(-wo, -n, 1.0f / eta_);
    return double(fresnelTransmittance(mu, eta_)) *
           walker_.walk(x - eps_ * n, inward, start, rng, stats);
  }

  // One sample of vertex i into acc: for the exitance (fixedWo null), outside directions whose
  // inward ray leaves again through the vertex's own triangles before scattering (grazing
  // directions the faceted 1-ring cuts off the smooth surface's hemisphere) are redrawn; see the
  // header.
  void sampleVertex(std::size_t i, const glm::vec3& normal, const glm::vec3* fixedWo, double weight,
                    Pcg32& rng, Accumulator& acc, WalkCounts& counts) const {
    glm::dvec3 value(0.0);
    for (int attempt = 0; attempt < kMaxRedraws; ++attempt) {
      MediumWalkStats stats;
      if (options_.entry == WalkEntry::OneRing && oneRing_.hasSurface(uint32_t(i))) {
        const SurfacePoint entry = oneRing_.sample(uint32_t(i), rng);
        const glm::vec3 wo = fixedWo ? *fixedWo : sampleCosineHemispherePolar(entry.normal, rng);
        value = walkFrom(entry.position, kNoStartVertex, entry.normal, wo, rng, stats);
      } else {
        const glm::vec3 wo = fixedWo ? *fixedWo : sampleCosineHemispherePolar(normal, rng);
        value = walkFrom(positions_[i], uint32_t(i), normal, wo, rng, stats);
      }
      counts.events += stats.events;
      counts.hits += stats.boundaryHits;
      counts.truncated += stats.truncated;
      counts.escaped += stats.escaped;
      ++counts.walks;
      if (!stats.blocked || fixedWo) break;
      ++counts.redrawn;
    }
    acc.add(weight * value);
  }

  const std::vector<glm::vec3>& positions_;
  const std::vector<glm::vec3>& normals_;
  const HomogeneousMedium& medium_;
  const PathTraceOptions& options_;
  const glm::dvec3 sigmaT_;
  const TriangleScene scene_;
  const Walker walker_;
  const float eta_;
  const float eps_;
  const OneRingSampler oneRing_;
};

// Walk length. Exit times of walks started at a boundary are heavy-tailed (P(T > t) ~ t^-1/2) up
// to the absorption time 1 / (1 - albedo) or the time to diffuse across the object, so a short
// pilot run sees only the bulk: the expected length is the larger of the pilot's mean and the
// model min(3 sqrt(1 / (1 - albedo)), size sigma_t / 2), calibrated on half-spaces and on spheres
// without absorption.
void VertexTracer::warnOfLongWalks(PathTraceResult& result) const {
  const std::size_t n = count();
  const std::size_t probes = std::min<std::size_t>(n, 32);
  uint64_t events = 0, walks = 0;
  const Stopwatch pilotClock;
  for (std::size_t k = 0; k < probes; ++k) {
    const std::size_t i = vertexAt(k * n / probes);
    Pcg32 rng(options_.run.seed ^ 0x9E3779B97F4A7C15ULL, i);
    const glm::vec3 normal = glm::normalize(normals_[i]);
    for (std::size_t s = 0; s < kPilotWalks / probes; ++s, ++walks) {
      MediumWalkStats stats;
      walkFrom(positions_[i], uint32_t(i), normal, sampleCosineHemispherePolar(normal, rng), rng,
               stats);
      events += stats.events;
    }
  }
  const double secondsPerEvent = pilotClock.seconds() / double(std::max<uint64_t>(events, 1));
  double expected = double(events) / double(walks);
  for (int c = 0; c < 3; ++c) {
    if (!(sigmaT_[c] > 0.0)) continue;
    const double absorption = medium_.sigmaS[c] < sigmaT_[c]
                                  ? sigmaT_[c] / (sigmaT_[c] - medium_.sigmaS[c])
                                  : std::numeric_limits<double>::infinity();
    const double across = 0.5 * double(scene_.diagonal()) * sigmaT_[c];
    expected = std::max(expected, std::min(3.0 * std::sqrt(absorption), across));
  }
  const int estimates = int(options_.estimateExitance) + int(options_.estimateRadiance);
  const double predicted =
      secondsPerEvent * expected * double(n) * options_.samples * estimates /
      (options_.run.threads <= 0 ? defaultThreadCount() : options_.run.threads);
  if (expected > kLongWalkEvents) {
    addWarning(result, "the albedo makes walks long: about " + format("%.0f", expected) +
                           " scattering events per walk; expect roughly " +
                           format("%.0f", predicted) +
                           " s (fewer walks, or a diffusion method, are faster)");
  }
}

void VertexTracer::traceVertex(std::size_t k, PathTraceResult& result, WalkCounts& counts) const {
  const std::size_t i = vertexAt(k);
  Pcg32 rng(options_.run.seed, i);
  const glm::vec3 normal = glm::normalize(normals_[i]);
  const uint64_t escapedBefore = counts.escaped, walksBefore = counts.walks;
  if (options_.estimateExitance) {
    Accumulator acc;
    for (int s = 0; s < options_.samples; ++s)
      sampleVertex(i, normal, nullptr, M_PI, rng, acc, counts);
    acc.result(options_.samples, result.exitance[k], result.exitanceStdErr[k]);
  }
  if (options_.estimateRadiance) {
    const glm::vec3 wo = options_.radianceDirection == RadianceDirection::Normal
                             ? normal
                             : glm::normalize(options_.viewPoint - positions_[i]);
    if (glm::dot(wo, normal) > 0.0f) {
      Accumulator acc;
      for (int s = 0; s < options_.samples; ++s)
        sampleVertex(i, normal, &wo, 1.0, rng, acc, counts);
      acc.result(options_.samples, result.radiance[k], result.radianceStdErr[k]);
    }
  }
  result.escapedFraction[k] = float(double(counts.escaped - escapedBefore) /
                                    double(std::max<uint64_t>(counts.walks - walksBefore, 1)));
}

// The result arrays for n vertices, zero where estimated, empty where not.
void allocateResult(std::size_t n, const PathTraceOptions& options, PathTraceResult& result) {
  result.escapedFraction.assign(n, 0.0f);
  if (options.estimateExitance) {
    result.exitance.assign(n, glm::vec3(0.0f));
    result.exitanceStdErr.assign(n, glm::vec3(0.0f));
  }
  if (options.estimateRadiance) {
    result.radiance.assign(n, glm::vec3(0.0f));
    result.radianceStdErr.assign(n, glm::vec3(0.0f));
  }
}

// The run's totals and the warnings they call for.
void summarizeWalks(const AtomicWalkCounts& total, const PathTraceOptions& options,
                    PathTraceResult& result) {
  result.walks = total.walks;
  result.truncatedWalks = total.truncated;
  result.escapedWalks = total.escaped;
  result.redrawnDirections = total.redrawn;
  result.meanScatteringEvents = result.walks ? double(total.events) / double(result.walks) : 0.0;
  result.meanBoundaryHits = result.walks ? double(total.hits) / double(result.walks) : 0.0;
  if (result.truncatedWalks > 0)
    addWarning(result, std::to_string(result.truncatedWalks) + " of " +
                           std::to_string(result.walks) + " walks reached the cap of " +
                           std::to_string(options.maxScatteringEvents) +
                           " interactions and were dropped (biased low)");
  if (result.escapedWalks * 1000 > result.walks)
    addWarning(result, std::to_string(result.escapedWalks) + " of " + std::to_string(result.walks) +
                           " walks left through holes in the mesh: is it closed?");
}

}  // namespace

void validateHomogeneousMedium(const HomogeneousMedium& medium) {
  if (!(std::abs(medium.g) < 1.0)) fail("", "path tracer: |g| must be below 1");
  const glm::dvec3 sigmaT = medium.sigmaA + medium.sigmaS;
  for (int c = 0; c < 3; ++c) {
    if (!(medium.sigmaA[c] >= 0.0) || !(medium.sigmaS[c] >= 0.0) || !std::isfinite(sigmaT[c]))
      fail("", "path tracer: coefficients must be finite and non-negative");
  }
  if (!(std::max({sigmaT.x, sigmaT.y, sigmaT.z}) > 0.0))
    fail("", "path tracer: the medium has no extinction");
  if (!(medium.eta >= 1.0)) fail("", "path tracer: eta must be at least 1");
}

PathTraceResult pathTraceSubsurface(const std::vector<glm::vec3>& positions,
                                    const std::vector<glm::vec3>& normals,
                                    const std::vector<glm::uvec3>& triangles,
                                    const Cubemap& environment, const HomogeneousMedium& medium,
                                    const PathTraceOptions& options) {
  const Stopwatch clock;
  validateInputs(positions, normals, triangles, environment, medium, options);
  const VertexTracer tracer(positions, normals, triangles, environment, medium, options);
  PathTraceResult result;
  tracer.warnOfLongWalks(result);

  const std::size_t n = tracer.count();
  allocateResult(n, options, result);
  AtomicWalkCounts total;
  Progress progress("pathtrace", n, options.run.quiet);
  parallelFor(n, options.run.threads, 4, [&](std::size_t begin, std::size_t end) {
    WalkCounts counts;
    for (std::size_t k = begin; k < end; ++k) {
      tracer.traceVertex(k, result, counts);
      progress.advance();
    }
    total.add(counts);
  });
  progress.finish();
  summarizeWalks(total, options, result);
  result.seconds = clock.seconds();
  return result;
}

PathTraceResult pathTraceSubsurface(const TriangleMesh& meshMm, const Cubemap& radiance,
                                    const Material& material, const PathTraceOptions& options) {
  validateMaterial(material);
  return pathTraceSubsurface(meshMm.positions, meshMm.normals, meshMm.triangles, radiance,
                             homogeneousMediumOf(material), options);
}

HomogeneousMedium homogeneousMediumOf(const Material& material) {
  HomogeneousMedium medium;
  medium.sigmaA = material.sigmaA;
  medium.sigmaS = material.sigmaS();
  medium.eta = material.eta;
  medium.g = material.g;
  return medium;
}

}  // namespace sss

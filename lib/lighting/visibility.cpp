// transmittedIrradianceWithVisibility(): input checks, the Embree scene, the optional pilot, the
// full pass over the vertices and the report. The per-vertex estimator:
// visibility_vertex_estimator.cpp; the pilot: visibility_pilot.cpp; the environment's importance
// sampling: lib/envmap/environment_sampler.cpp.
#include "lighting/visibility.h"

#include <atomic>
#include <cmath>
#include <optional>

#include "core/bounds.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/random.h"
#include "core/relative_rms.h"
#include "core/timer.h"
#include "envmap/environment_sampler.h"
#include "lighting/facet_light.h"
#include "lighting/unoccluded_intake.h"
#include "lighting/visibility_pilot.h"
#include "lighting/visibility_vertex_estimator.h"
#include "raytrace/triangle_scene.h"

namespace sss {

namespace {

// Vertices per chunk of the full pass (parallelFor's grain: fixed, so results do not depend on
// the thread count).
constexpr std::size_t kVisibilityGrain = 256;

void validateInput(std::size_t vertexCount, std::span<const glm::vec3> normals,
                   std::span<const glm::uvec3> triangles, const VisibilityOptions& options) {
  if (normals.size() != vertexCount) fail("", "visibility: one normal per vertex required");
  if (!options.chooseSamples && options.samples < 2)
    fail("", "visibility rays per vertex must be at least 2");
  if (triangles.empty()) fail("", "visibility: the mesh has no triangles");
  for (const glm::uvec3& t : triangles) {
    if (t.x >= vertexCount || t.y >= vertexCount || t.z >= vertexCount) {
      fail("", "visibility: triangle index out of range");
    }
  }
}

struct FullPass {
  std::vector<glm::vec3> irradiance, entryWeighted;
  // When kept: per chunk of kVisibilityGrain vertices its hits, and per vertex their count.
  std::vector<std::vector<CosineHit>> cosineHits;
  std::vector<uint32_t> cosineHitCounts;
  std::vector<float> relativeVariance;  // < 0: unlit vertex
  uint64_t rays = 0, occluded = 0;
  double seconds = 0.0;
};

// Every vertex's estimate with `samples` rays, seeded per vertex (Pcg32(seed, vertex)).
FullPass traceAllVertices(std::size_t vertexCount, int samples, const VisibilityOptions& options,
                          const std::function<VertexEstimator()>& makeEstimator) {
  FullPass pass;
  pass.irradiance.assign(vertexCount, glm::vec3(0.0f));
  if (options.entry) pass.entryWeighted.assign(vertexCount, glm::vec3(0.0f));
  pass.relativeVariance.assign(vertexCount, -1.0f);
  const bool keep =
      options.keepCosineHitsUpTo > 0 && cosineSamplesOf(samples) <= options.keepCosineHitsUpTo;
  if (keep) {
    pass.cosineHits.resize((vertexCount + kVisibilityGrain - 1) / kVisibilityGrain);
    pass.cosineHitCounts.assign(vertexCount, 0);
  }
  std::atomic<uint64_t> totalRays{0}, totalOccluded{0};
  Progress progress("visibility", vertexCount, options.run.quiet);
  Stopwatch traceClock;
  parallelFor(vertexCount, options.run.threads, kVisibilityGrain,
              [&](std::size_t begin, std::size_t end) {
                VertexEstimator estimator = makeEstimator();
                estimator.keepCosineHits(keep);
                uint64_t rays = 0, occluded = 0;
                for (std::size_t v = begin; v < end; ++v) {
                  Pcg32 rng(options.run.seed, v);
                  const VertexEstimate e = estimator.estimate(v, samples, rng);
                  pass.irradiance[v] = e.irradiance;
                  if (options.entry) pass.entryWeighted[v] = e.entryWeighted;
                  pass.relativeVariance[v] = e.relativeVariance;
                  if (keep) {
                    const std::vector<CosineHit>& hits = estimator.cosineHits();
                    std::vector<CosineHit>& chunk = pass.cosineHits[begin / kVisibilityGrain];
                    chunk.insert(chunk.end(), hits.begin(), hits.end());
                    pass.cosineHitCounts[v] = static_cast<uint32_t>(hits.size());
                  }
                  rays += e.rays;
                  occluded += e.occluded;
                }
                totalRays += rays;
                totalOccluded += occluded;
                progress.advance(end - begin);
              });
  progress.finish();
  pass.seconds = traceClock.seconds();
  pass.rays = totalRays;
  pass.occluded = totalOccluded;
  return pass;
}

// The kept cosine hits, one array with offsets (each chunk freed once copied).
CosineHits flatten(FullPass& pass, int samples) {
  CosineHits out;
  if (pass.cosineHitCounts.empty()) return out;
  out.perVertex = cosineSamplesOf(samples);
  out.offsets.assign(pass.cosineHitCounts.size() + 1, 0);
  for (std::size_t v = 0; v < pass.cosineHitCounts.size(); ++v)
    out.offsets[v + 1] = out.offsets[v] + pass.cosineHitCounts[v];
  out.hits.reserve(out.offsets.back());
  for (auto& chunk : pass.cosineHits) {
    out.hits.insert(out.hits.end(), chunk.begin(), chunk.end());
    std::vector<CosineHit>().swap(chunk);
  }
  return out;
}

// Root mean square of the lit vertices' relative variances.
double rmsRelativeStdError(const std::vector<float>& relativeVariance) {
  MeanSquare lit;
  for (float r : relativeVariance)
    if (r >= 0.0f) lit.add(r);
  return lit.rms();
}

}  // namespace

std::vector<glm::vec3> transmittedIrradianceWithVisibility(std::span<const glm::vec3> positions,
                                                           std::span<const glm::vec3> normals,
                                                           std::span<const glm::uvec3> triangles,
                                                           const Cubemap& radiance, float eta,
                                                           const VisibilityOptions& options,
                                                           VisibilityReport* report) {
  const std::size_t vertexCount = positions.size();
  validateInput(vertexCount, normals, triangles, options);
  const EnvironmentSampler sampler(radiance);

  Stopwatch buildClock;
  std::optional<TriangleScene> own;
  const TriangleScene& scene = givenOrBuilt(options.scene, own, positions, triangles,
                                            TriangleSceneOptions::surfaceRays(options.run.threads));
  const double buildSeconds = buildClock.seconds();

  const float extent = boundsOf(positions).longestSide();
  const VertexFacets facets = lightFacets(positions, normals, triangles);
  Stopwatch unoccludedClock;
  std::optional<UnoccludedIntake> unoccluded;
  if (options.ratioToUnoccluded)
    unoccluded.emplace(radiance, eta, options.entry, options.run.threads);
  const double unoccludedSeconds = unoccludedClock.seconds();
  const UnoccludedIntake* control = unoccluded ? &*unoccluded : nullptr;
  const auto makeEstimator = [&]() {
    return VertexEstimator(positions, normals, facets, sampler, scene, eta, extent, options.entry,
                           control);
  };

  VisibilityPilot pilot;
  if (options.pilot.replicas > 0) {
    pilot = runVisibilityPilot(vertexCount, options.pilot, options.run.seed, options.run.threads,
                               makeEstimator);
  }
  const int samples = options.chooseSamples ? options.chooseSamples(pilot) : options.samples;
  if (samples < 2) fail("", "visibility rays per vertex must be at least 2");

  FullPass pass = traceAllVertices(vertexCount, samples, options, makeEstimator);
  if (report) {
    report->buildSeconds = buildSeconds;
    report->traceSeconds = pass.seconds;
    report->unoccludedSeconds = unoccludedSeconds;
    report->rays = pass.rays;
    report->occludedFraction =
        pass.rays > 0 ? static_cast<double>(pass.occluded) / static_cast<double>(pass.rays) : 0.0;
    report->relativeStdError = rmsRelativeStdError(pass.relativeVariance);
    report->samples = samples;
    report->pilot = std::move(pilot);
    report->entryWeighted = std::move(pass.entryWeighted);
    report->cosineHits = flatten(pass, samples);
  }
  return std::move(pass.irradiance);
}

}  // namespace sss

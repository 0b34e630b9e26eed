#include "lighting/visibility_pilot.h"

#include <algorithm>
#include <atomic>
#include <vector>

#include "core/error.h"
#include "core/parallel.h"
#include "core/random.h"
#include "core/timer.h"

namespace sss {

namespace {

// Pilot replicas draw their rotations from their own stream family, apart from the full pass.
constexpr uint64_t kPilotSeedOffset = 0x9E3779B97F4A7C15ull;

}  // namespace

std::vector<uint32_t> pilotVertices(std::size_t vertexCount, std::size_t maxVertices) {
  std::vector<uint32_t> vertices;
  const std::size_t wanted = std::max<std::size_t>(maxVertices, 1);
  const std::size_t stride = (vertexCount + wanted - 1) / wanted;
  for (std::size_t v = stride / 2; v < vertexCount; v += stride) {
    vertices.push_back(static_cast<uint32_t>(v));
  }
  return vertices;
}

namespace {

// Replicas of one vertex's estimate: their mean, and per channel the variance of one replica.
class ReplicaLevels {
 public:
  ReplicaLevels(VertexEstimator estimator, int replicas)
      : estimator_(std::move(estimator)), values_(static_cast<std::size_t>(replicas)) {}

  // Mean and variance (per channel) of `replicas` estimates with `count` rays each.
  glm::vec3 level(uint32_t v, int count, Pcg32& rng, glm::vec3& variance) {
    glm::dvec3 mean(0.0);
    for (glm::dvec3& value : values_) {
      const VertexEstimate e = estimator_.estimate(v, count, rng);
      value = glm::dvec3(e.irradiance);
      mean += value;
      rays_ += e.rays;
    }
    mean /= static_cast<double>(values_.size());
    glm::dvec3 sum(0.0);
    for (const glm::dvec3& value : values_) sum += (value - mean) * (value - mean);
    variance = glm::vec3(sum / static_cast<double>(values_.size() - 1));
    return glm::vec3(mean);
  }
  uint64_t rays() const { return rays_; }

 private:
  VertexEstimator estimator_;
  std::vector<glm::dvec3> values_;
  uint64_t rays_ = 0;
};

}  // namespace

VisibilityPilot runVisibilityPilot(std::size_t vertexCount, const VisibilityPilotOptions& options,
                                   uint64_t seed, int threads,
                                   const std::function<VertexEstimator()>& makeEstimator) {
  if (options.coarseRays < 2 || options.fineRays <= options.coarseRays || options.replicas < 2) {
    fail("", "visibility pilot: at least 2 replicas of 2 rays, coarse < fine");
  }
  Stopwatch clock;
  VisibilityPilot pilot;
  pilot.replicas = options.replicas;
  pilot.coarseRays = options.coarseRays;
  pilot.fineRays = options.fineRays;
  pilot.vertices = pilotVertices(vertexCount, options.maxVertices);
  const std::size_t m = pilot.vertices.size();
  pilot.irradiance.assign(m, glm::vec3(0.0f));
  pilot.coarseVariance.assign(m, glm::vec3(0.0f));
  pilot.fineVariance.assign(m, glm::vec3(0.0f));
  std::atomic<uint64_t> totalRays{0};
  parallelFor(m, threads, 16, [&](std::size_t begin, std::size_t end) {
    ReplicaLevels replicas(makeEstimator(), options.replicas);
    for (std::size_t k = begin; k < end; ++k) {
      const uint32_t v = pilot.vertices[k];
      Pcg32 rng(seed + kPilotSeedOffset, v);
      replicas.level(v, options.coarseRays, rng, pilot.coarseVariance[k]);
      pilot.irradiance[k] = replicas.level(v, options.fineRays, rng, pilot.fineVariance[k]);
    }
    totalRays += replicas.rays();
  });
  pilot.rays = totalRays;
  pilot.seconds = clock.seconds();
  return pilot;
}

}  // namespace sss

#include "bench/interior_segment_guard.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/parallel.h"
#include "core/timer.h"
#include "material/diffusion_profile.h"
#include "raytrace/triangle_scene.h"

namespace sss {

InteriorSegmentGuard::InteriorSegmentGuard(std::span<const glm::vec3> positions,
                                           std::span<const glm::vec3> normals,
                                           std::span<const float> areas,
                                           std::span<const glm::uvec3> triangles)
    : scene_(std::make_unique<TriangleScene>(positions, triangles)) {
  if (normals.size() != positions.size() || areas.size() != positions.size())
    fail("", "interior-segment guard: per-vertex arrays differ in length");
  // A tenth of the vertex's disc radius: inside the medium, well within the triangles around it.
  inner_.resize(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const float rho = std::sqrt(std::max(areas[i], 0.0f) / float(M_PI));
    inner_[i] = positions[i] - std::max(0.1f * rho, 4.0f * scene_->epsilon()) * normals[i];
  }
}

InteriorSegmentGuard::~InteriorSegmentGuard() = default;

bool InteriorSegmentGuard::connected(uint32_t a, uint32_t b) const {
  const glm::vec3 seg = inner_[b] - inner_[a];
  const float len = glm::length(seg);
  return !(len > 0.0f && scene_->occluded(inner_[a], seg / len, 0.0f, len));
}

GuardedSumResult diffuseExactGuarded(std::span<const glm::vec3> positions,
                                     std::span<const glm::vec3> normals,
                                     std::span<const float> areas,
                                     std::span<const glm::vec3> irradiance,
                                     std::span<const glm::uvec3> triangles,
                                     const DiffusionProfile& profile,
                                     const GuardedSumOptions& options) {
  const Stopwatch clock;
  const std::size_t n = positions.size();
  if (normals.size() != n || areas.size() != n || irradiance.size() != n)
    fail("", "guarded diffusion: per-vertex arrays differ in length");
  const double radius = profile.radiusContaining(options.energyFraction);
  const InteriorSegmentGuard guard(positions, normals, areas, triangles);
  GuardedSumResult result;
  result.exitance.assign(n, glm::vec3(0.0f));
  std::atomic<uint64_t> pairs{0}, dropped{0};
  const double r2max = radius * radius;
  parallelFor(n, options.threads, 16, [&](std::size_t begin, std::size_t end) {
    uint64_t localPairs = 0, localDropped = 0;
    for (std::size_t o = begin; o < end; ++o) {
      // Self term: the profile integrated over the vertex's own disc.
      const double rho = std::sqrt(std::max(double(areas[o]), 0.0) / M_PI);
      glm::dvec3 b = profile.integrateDisc(rho) * glm::dvec3(irradiance[o]);
      for (std::size_t i = 0; i < n; ++i) {
        if (i == o) continue;
        const glm::vec3 d = positions[i] - positions[o];
        const double r2 = double(glm::dot(d, d));
        if (r2 > r2max) continue;
        ++localPairs;
        if (options.guard && !guard.connected(uint32_t(o), uint32_t(i))) {
          ++localDropped;
          continue;
        }
        b += profile.evaluate(std::sqrt(r2)) * double(areas[i]) * glm::dvec3(irradiance[i]);
      }
      result.exitance[o] = glm::vec3(b);
    }
    pairs += localPairs;
    dropped += localDropped;
  });
  result.pairs = pairs;
  result.droppedPairs = dropped;
  result.seconds = clock.seconds();
  return result;
}

}  // namespace sss

// The interior-segment guard for the diffusion sum B(x_o) = sum_i R_d(|x_i - x_o|) E_i A_i
// (Li & Guo Eq. 7). Study-only (accuracy_study's guard rows; the bake does not use it): the
// library sss_bench_guard of tests/bench, tested by interior_segment_guard_test.cpp.
//
// A diffusion profile assumes light travels from x_i to x_o through the medium; on concave or
// disconnected geometry (a dragon's claws, the gap between a leg and the body) the Euclidean
// distance is short while the straight segment leaves the object, so the sum leaks light across
// air. The guard keeps a pair only if the segment between the two points, each moved inward along
// its normal by a small fraction of the local spacing, crosses no triangle (one Embree occlusion
// ray per pair within the profile's support). Convex parts and thin slabs (the segment runs
// through the interior) are unchanged; pairs across a gap are dropped.
//
// The sum here is the exact O(N^2) one (every pair inside the radius holding 99.9% of the
// profile's energy), with the self term integrated over the vertex's disc of area A_i, so that the
// guard's effect and cost are measured against the same sum without it (guard = false).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace sss {

class DiffusionProfile;  // material/diffusion_profile.h
class TriangleScene;     // raytrace/triangle_scene.h

// The pair test on its own, for any diffusion sum that wants it (one Embree occlusion ray per
// call; thread-safe). Endpoints: each vertex moved inward along its normal by a tenth of the
// radius of its disc of area A_i.
class InteriorSegmentGuard {
 public:
  InteriorSegmentGuard(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                       std::span<const float> areas, std::span<const glm::uvec3> triangles);
  ~InteriorSegmentGuard();
  InteriorSegmentGuard(const InteriorSegmentGuard&) = delete;
  InteriorSegmentGuard& operator=(const InteriorSegmentGuard&) = delete;

  // True when the straight segment between vertices a and b stays inside the object.
  bool connected(uint32_t a, uint32_t b) const;

 private:
  std::unique_ptr<TriangleScene> scene_;
  std::vector<glm::vec3> inner_;
};

struct GuardedSumOptions {
  bool guard = true;
  double energyFraction = 0.999;  // support radius: the disc holding this much of R_d's energy
  int threads = 0;                // <= 0: all cores
};

struct GuardedSumResult {
  std::vector<glm::vec3> exitance;  // B per vertex
  uint64_t pairs = 0;               // pairs inside the support radius (excluding self)
  uint64_t droppedPairs = 0;        // of those, segments that leave the object
  double seconds = 0.0;
};

// positions in mm, unit outward normals, areas in mm^2, E the transmitted irradiance; the
// triangles are the boundary the segments are tested against. Deterministic for any thread count.
GuardedSumResult diffuseExactGuarded(std::span<const glm::vec3> positions,
                                     std::span<const glm::vec3> normals,
                                     std::span<const float> areas,
                                     std::span<const glm::vec3> irradiance,
                                     std::span<const glm::uvec3> triangles,
                                     const DiffusionProfile& profile,
                                     const GuardedSumOptions& options = {});

}  // namespace sss

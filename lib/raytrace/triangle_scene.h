// An Embree 3 BVH over one triangle mesh, shared by the visibility pass of the bake (streams of
// occlusion rays per vertex), the Monte Carlo walks of lib/pathtrace (nearest hit with its face
// normal, single occlusion rays) and the interior-segment guard study (tests/bench). Embree stays
// out of this header.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace sss {

struct SceneHit {
  float t = 0.0f;              // distance along the (unit) direction; only valid when hit
  glm::vec3 faceNormal{0.0f};  // unit, by the triangle's winding (outward for a CCW-out mesh)
  uint32_t triangle = 0;       // index of the triangle hit
  bool hit = false;
};

// Offset (and tNear) of a ray leaving the surface at p, along the normal: 2e-5 of p's largest
// coordinate magnitude, or of the mesh's extent if larger, so that float rounding never makes the
// ray hit the triangles around its own start. One rule for the bake's visibility and
// interreflection rays, so that both call the same directions blocked.
inline float surfaceRayOffset(const glm::vec3& p, float extent) {
  return 2e-5f * std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), extent});
}

// One ray of a stream: blocked if the mesh meets it within (tNear, tFar); for intersect, the
// nearest hit there.
struct OcclusionRay {
  glm::vec3 origin{0.0f};
  glm::vec3 direction{0.0f};
  float tNear = 0.0f;
  float tFar = std::numeric_limits<float>::infinity();
};

struct TriangleSceneOptions {
  enum class BuildQuality { Medium, High };
  // High: spatial-split SAH, the better tree for many rays per build; Medium: binned SAH, faster
  // to build.
  BuildQuality quality = BuildQuality::High;
  // Robust (watertight) traversal: no ray slips between triangles through an edge or a vertex.
  bool robust = true;
  // Embree device threads for the build; <= 0: all cores.
  int threads = 0;

  // For the bake's rays from its vertices (visibility, the interreflection gather): medium
  // quality, as the high-quality build (spatial splits) costs more time than it saves on the
  // bake's millions of rays (tests/bench/results/bake); not robust, as the rays leave from an
  // offset origin (surfaceRayOffset) and the cheaper traversal is the one those measurements used.
  // One setting for both, so that they call the same directions blocked.
  static TriangleSceneOptions surfaceRays(int threads) {
    TriangleSceneOptions options;
    options.quality = BuildQuality::Medium;
    options.robust = false;
    options.threads = threads;
    return options;
  }
};

class TriangleScene {
 public:
  // Throws Error on an empty mesh or if Embree cannot build the scene. Triangle indices must be
  // in range (the caller checks).
  TriangleScene(std::span<const glm::vec3> positions, std::span<const glm::uvec3> triangles,
                const TriangleSceneOptions& options = {});
  ~TriangleScene();
  TriangleScene(const TriangleScene&) = delete;
  TriangleScene& operator=(const TriangleScene&) = delete;

  // Thread-safe queries; direction must be unit length.
  SceneHit intersect(const glm::vec3& origin, const glm::vec3& direction, float tNear = 0.0f,
                     float tFar = 1e30f) const;
  bool occluded(const glm::vec3& origin, const glm::vec3& direction, float tNear = 0.0f,
                float tFar = 1e30f) const;
  // Occlusion of a batch of incoherent rays as one Embree stream (rtcOccluded1M), cheaper than
  // one query per ray; blocked[k] = 1 if rays[k] is occluded, else 0. Thread-safe.
  void occluded(std::span<const OcclusionRay> rays, std::vector<char>& blocked) const;
  // The nearest hits of a batch of incoherent rays as one stream (rtcIntersect1M); hits[k] for
  // rays[k]. Thread-safe.
  void intersect(std::span<const OcclusionRay> rays, std::vector<SceneHit>& hits) const;

  // A length for ray offsets: 4e-6 of the larger of the bounding box diagonal and the largest
  // coordinate magnitude (~70 float spacings there).
  float epsilon() const { return epsilon_; }
  // The unit normal SceneHit::faceNormal gives for a triangle.
  const glm::vec3& faceNormal(uint32_t triangle) const { return faceNormals_[triangle]; }
  float diagonal() const { return diagonal_; }
  std::size_t triangleCount() const { return faceNormals_.size(); }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<glm::vec3> faceNormals_;
  float epsilon_ = 0.0f;
  float diagonal_ = 0.0f;
};

// Throws Error unless `scene` holds as many triangles as `triangles` (a scene a caller built over
// the mesh a stage traces).
void requireSceneOfMesh(const TriangleScene& scene, std::span<const glm::uvec3> triangles);

// The scene a caller built over this mesh (`given`, with the same options: one BVH for every stage
// that traces the mesh; requireSceneOfMesh), else one built here into `own`.
const TriangleScene& givenOrBuilt(const TriangleScene* given, std::optional<TriangleScene>& own,
                                  std::span<const glm::vec3> positions,
                                  std::span<const glm::uvec3> triangles,
                                  const TriangleSceneOptions& options);

}  // namespace sss

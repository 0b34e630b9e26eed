#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "raytrace/triangle_scene.h"

namespace sss {

// The cosine technique's rays that met the mesh, kept for the interreflection gather
// (transport/interreflection.h), which needs rays from the facets' cosine lobes that meet the
// object, and so can take these instead of tracing its own: one ray set, both uses. Per vertex,
// of `perVertex` cosine samples (Hammersley, stratified), those whose facets take light in, as
// the gather samples them; the visibility's estimate is unchanged.
struct CosineHit {
  glm::vec3 direction{0.0f};
  glm::vec3 weight{0.0f};  // the facets' intake with the entry's weight, over the cosine pdf
  float t = 0.0f;          // the nearest hit (SceneHit) without its face normal
  uint32_t triangle = 0;
  uint32_t sample = 0;  // its index in the vertex's stratified set (the gather's ray index)
};
// The visibility's cosine samples among `samples` per vertex: half, rounded down (the
// environment's technique takes the other half, rounded up).
inline int cosineSamplesOf(int samples) {
  return samples - (samples + 1) / 2;
}

struct CosineHits {
  int perVertex = 0;              // cosine samples per vertex; 0: none kept
  std::vector<uint32_t> offsets;  // vertex v's hits: [offsets[v], offsets[v + 1])
  std::vector<CosineHit> hits;
};

}  // namespace sss

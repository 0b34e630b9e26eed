// Uniform points on the triangles around a vertex (area-weighted), with their face normals: where
// walks enter for "the surface a vertex stands for" (its one third of each adjacent triangle,
// Li & Guo's M(x_i)) rather than at the vertex itself, which on a coarse convex mesh is the apex
// of a cone of facets (light leaves it too easily) and on a concave one the bottom of a pit.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "core/random.h"

namespace sss {

struct SurfacePoint {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};  // the triangle's unit normal (by its winding)
  uint32_t triangle = 0;
};

class OneRingSampler {
 public:
  OneRingSampler(std::span<const glm::vec3> positions, std::span<const glm::uvec3> triangles)
      : positions_(positions), triangles_(triangles), first_(positions.size() + 1, 0) {
    for (const glm::uvec3& t : triangles)
      for (int k = 0; k < 3; ++k) ++first_[t[k] + 1];
    for (std::size_t v = 0; v < positions.size(); ++v) first_[v + 1] += first_[v];
    ring_.resize(3 * triangles.size());
    std::vector<uint32_t> fill(first_.begin(), first_.end() - 1);
    for (uint32_t f = 0; f < triangles.size(); ++f)
      for (int k = 0; k < 3; ++k) ring_[fill[triangles[f][k]]++] = f;
    area_.resize(triangles.size());
    normal_.resize(triangles.size());
    for (std::size_t f = 0; f < triangles.size(); ++f) {
      const glm::uvec3 t = triangles[f];
      const glm::vec3 c =
          glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x]);
      const float twice = glm::length(c);
      area_[f] = 0.5f * twice;
      normal_[f] = twice > 0.0f ? c / twice : glm::vec3(0.0f);
    }
  }

  // False for a vertex without triangles of positive area.
  bool hasSurface(uint32_t v) const { return ringArea(v) > 0.0f; }

  // Three uniform numbers per point: the triangle, then two barycentrics.
  SurfacePoint sample(uint32_t v, Pcg32& rng) const {
    float pick = static_cast<float>(rng.uniformDouble()) * ringArea(v);
    uint32_t f = ring_[first_[v + 1] - 1];
    for (uint32_t j = first_[v]; j < first_[v + 1]; ++j) {
      pick -= area_[ring_[j]];
      if (pick < 0.0f) {
        f = ring_[j];
        break;
      }
    }
    double u = rng.uniformDouble(), w = rng.uniformDouble();
    if (u + w > 1.0) {
      u = 1.0 - u;
      w = 1.0 - w;
    }
    const glm::uvec3 t = triangles_[f];
    const glm::vec3 a = positions_[t.x];
    return {a + static_cast<float>(u) * (positions_[t.y] - a) +
                static_cast<float>(w) * (positions_[t.z] - a),
            normal_[f], f};
  }

 private:
  float ringArea(uint32_t v) const {
    float sum = 0.0f;
    for (uint32_t j = first_[v]; j < first_[v + 1]; ++j) sum += area_[ring_[j]];
    return sum;
  }

  std::span<const glm::vec3> positions_;
  std::span<const glm::uvec3> triangles_;
  std::vector<uint32_t> first_, ring_;  // CSR: the triangles of vertex v are ring_[first_[v]..)
  std::vector<float> area_;
  std::vector<glm::vec3> normal_;
};

}  // namespace sss

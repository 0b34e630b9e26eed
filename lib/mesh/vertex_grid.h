// Vertices sorted by grid cell, for the neighbours of a point within a radius: the diffusion
// noise model's pilot sums (bake/visibility_noise_model.cpp) and the far field's smoothing
// (bake/surface_average.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <tuple>
#include <vector>

#include <glm/vec3.hpp>

namespace sss {

// Cell side = the radius, so that a point's neighbours within it are in the 27 cells around it,
// found by binary search.
class VertexGrid {
  struct Cell {
    int64_t x, y, z;
    uint32_t v;
    auto key() const { return std::tie(x, y, z); }
  };

 public:
  VertexGrid(std::span<const glm::vec3> positions, double cellSide)
      : side_(cellSide), cells_(positions.size()) {
    for (std::size_t i = 0; i < positions.size(); ++i) {
      const glm::dvec3 c = cellOf(positions[i]);
      cells_[i] = {static_cast<int64_t>(c.x), static_cast<int64_t>(c.y), static_cast<int64_t>(c.z),
                   static_cast<uint32_t>(i)};
    }
    std::sort(cells_.begin(), cells_.end(), [](const Cell& a, const Cell& b) {
      return a.key() < b.key() || (a.key() == b.key() && a.v < b.v);
    });
  }
  // Calls visit(vertex) for every vertex in the 27 cells around p, cell by cell.
  template <typename Visit>
  void forEachNear(const glm::vec3& p, Visit&& visit) const {
    const glm::dvec3 c = cellOf(p);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const Cell query{static_cast<int64_t>(c.x) + dx, static_cast<int64_t>(c.y) + dy,
                           static_cast<int64_t>(c.z) + dz, 0};
          auto it =
              std::lower_bound(cells_.begin(), cells_.end(), query,
                               [](const Cell& a, const Cell& b) { return a.key() < b.key(); });
          for (; it != cells_.end() && it->key() == query.key(); ++it) visit(it->v);
        }
      }
    }
  }

 private:
  glm::dvec3 cellOf(const glm::vec3& p) const {
    return glm::dvec3(std::floor(p.x / side_), std::floor(p.y / side_), std::floor(p.z / side_));
  }
  double side_;
  std::vector<Cell> cells_;
};

}  // namespace sss

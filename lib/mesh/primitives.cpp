#include "mesh/primitives.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

#include <glm/geometric.hpp>

#include "core/error.h"

namespace sss {

TriangleMesh makeIcosphere(int subdivisions, float radius) {
  if (subdivisions < 0 || subdivisions > 10) fail("", "icosphere subdivisions must be 0..10");
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<glm::vec3> unit = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                 {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                 {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (glm::vec3& p : unit) p = glm::normalize(p);
  std::vector<glm::uvec3> tris = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                  {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                  {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                  {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<unsigned, unsigned>, unsigned> midpoints;
    auto midpoint = [&](unsigned a, unsigned b) {
      const auto key = std::minmax(a, b);
      auto [it, inserted] = midpoints.try_emplace(key, static_cast<unsigned>(unit.size()));
      if (inserted) unit.push_back(glm::normalize(unit[a] + unit[b]));
      return it->second;
    };
    std::vector<glm::uvec3> finer;
    finer.reserve(tris.size() * 4);
    for (const glm::uvec3& tri : tris) {
      const unsigned ab = midpoint(tri.x, tri.y), bc = midpoint(tri.y, tri.z),
                     ca = midpoint(tri.z, tri.x);
      finer.push_back({tri.x, ab, ca});
      finer.push_back({tri.y, bc, ab});
      finer.push_back({tri.z, ca, bc});
      finer.push_back({ab, bc, ca});
    }
    tris = std::move(finer);
  }
  TriangleMesh mesh;
  mesh.normals = unit;
  mesh.positions.reserve(unit.size());
  for (const glm::vec3& n : unit) mesh.positions.push_back(n * radius);
  mesh.triangles = std::move(tris);
  return mesh;
}

TriangleMesh makeGridPlane(int n, float size) {
  if (n < 1) fail("", "grid plane needs n >= 1");
  TriangleMesh mesh;
  const unsigned row = static_cast<unsigned>(n) + 1;
  for (unsigned j = 0; j < row; ++j) {
    for (unsigned i = 0; i < row; ++i) {
      mesh.positions.push_back({size * (float(i) / n - 0.5f), size * (float(j) / n - 0.5f), 0});
      mesh.normals.push_back({0, 0, 1});
    }
  }
  for (unsigned j = 0; j + 1 < row; ++j) {
    for (unsigned i = 0; i + 1 < row; ++i) {
      const unsigned a = j * row + i, b = a + 1, c = a + row + 1, d = a + row;
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  }
  return mesh;
}

namespace {

// Closed box surface on the integer lattice [0, cells]^3 (points with a coordinate on a face),
// so that the faces' shared edge vertices weld exactly.
TriangleMesh makeLatticeBox(const glm::vec3& size, const glm::ivec3& cells) {
  for (int a = 0; a < 3; ++a) {
    if (cells[a] < 1) fail("", "box needs at least one cell per axis");
    if (!(size[a] > 0.0f)) fail("", "box sizes must be positive");
  }
  TriangleMesh mesh;
  std::map<std::array<int, 3>, unsigned> index;
  auto vertex = [&](std::array<int, 3> p) {
    auto [it, inserted] = index.try_emplace(p, static_cast<unsigned>(mesh.positions.size()));
    if (inserted) {
      glm::vec3 x;
      for (int a = 0; a < 3; ++a) x[a] = size[a] * (float(p[a]) / cells[a] - 0.5f);
      mesh.positions.push_back(x);
    }
    return it->second;
  };
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;  // e_u x e_v = e_a
    for (int side = 0; side < 2; ++side) {
      for (int j = 0; j < cells[v]; ++j) {
        for (int i = 0; i < cells[u]; ++i) {
          std::array<unsigned, 4> quad;
          const int corners[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
          for (int k = 0; k < 4; ++k) {
            std::array<int, 3> p;
            p[a] = side * cells[a];
            p[u] = corners[k][0];
            p[v] = corners[k][1];
            quad[k] = vertex(p);
          }
          if (side == 1) {
            mesh.triangles.push_back({quad[0], quad[1], quad[2]});
            mesh.triangles.push_back({quad[0], quad[2], quad[3]});
          } else {  // the -a face looks the other way
            mesh.triangles.push_back({quad[0], quad[2], quad[1]});
            mesh.triangles.push_back({quad[0], quad[3], quad[2]});
          }
        }
      }
    }
  }
  mesh.normals = computeVertexNormals(mesh);
  return mesh;
}

}  // namespace

TriangleMesh makeBox(const glm::vec3& size, int subdivisions) {
  return makeLatticeBox(size, glm::ivec3(subdivisions));
}

TriangleMesh makeSlab(float width, float thickness, int n) {
  if (n < 1 || !(width > 0.0f) || !(thickness > 0.0f)) fail("", "slab needs n >= 1 and sizes > 0");
  const int rows = std::max(1, static_cast<int>(std::lround(thickness / (width / n))));
  return makeLatticeBox({width, width, thickness}, {n, n, rows});
}

}  // namespace sss

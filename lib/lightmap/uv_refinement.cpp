#include "lightmap/uv_refinement.h"

#include <cmath>
#include <queue>
#include <string>
#include <unordered_map>
#include <utility>

#include <glm/geometric.hpp>

#include "core/error.h"

namespace sss {
namespace {

using EdgeKey = std::uint64_t;

EdgeKey edgeKey(std::uint32_t a, std::uint32_t b) {
  return a < b ? (EdgeKey(a) << 32) | b : (EdgeKey(b) << 32) | a;
}

// Texture coordinates a lightmap can hold: finite and in [0, 1] (a repeat or an offset would put
// two places of the surface on one texel).
void checkTexcoords(const std::string& path, std::span<const glm::vec2> uv) {
  constexpr float kSlack = 1e-5f;
  for (std::size_t i = 0; i < uv.size(); ++i) {
    const glm::vec2 t = uv[i];
    if (!(std::isfinite(t.x) && std::isfinite(t.y) && t.x >= -kSlack && t.x <= 1.0f + kSlack &&
          t.y >= -kSlack && t.y <= 1.0f + kSlack)) {
      fail(path, "TEXCOORD_0 of triangle " + std::to_string(i / 3) + " is (" + std::to_string(t.x) +
                     ", " + std::to_string(t.y) +
                     "), outside [0, 1]: a lightmap needs every texture coordinate in the map");
    }
  }
}

// The triangles, their corners' texture coordinates and the edges between them, split one edge
// at a time.
class Refiner {
 public:
  Refiner(UvRefinement& out, double texels) : out_(out), texels_(texels) {
    for (std::uint32_t t = 0; t < out_.triangles.size(); ++t) {
      for (int i = 0; i < 3; ++i) edges_[key(t, i)].push_back(t);
    }
    for (const auto& [k, tris] : edges_) push(k);
  }

  // Splits the longest edge while it is longer than maxTexels.
  void run(double maxTexels, std::size_t maxVertices, const std::string& path) {
    while (!queue_.empty() && queue_.top().first > maxTexels) {
      const EdgeKey k = queue_.top().second;
      queue_.pop();
      if (!edges_.contains(k)) continue;  // split already, through a longer duplicate entry
      if (out_.vertexCount() >= maxVertices) {
        fail(path, "refining the mesh to the texture's texels needs more than " +
                       std::to_string(maxVertices) + " vertices: use a smaller --texture");
      }
      split(k);
    }
  }

 private:
  EdgeKey key(std::uint32_t t, int i) const {
    const glm::uvec3& tri = out_.triangles[t];
    return edgeKey(tri[i], tri[(i + 1) % 3]);
  }
  // Corner i's edge (to corner i + 1) of triangle t, in texels.
  double texelLength(std::uint32_t t, int i) const {
    const glm::vec2* uv = &out_.cornerTexcoords[3 * t];
    return glm::length(glm::dvec2(uv[(i + 1) % 3] - uv[i])) * texels_;
  }
  int cornerOf(std::uint32_t t, EdgeKey k) const {
    for (int i = 0; i < 3; ++i) {
      if (key(t, i) == k) return i;
    }
    return -1;
  }
  void push(EdgeKey k) {
    double length = 0.0;
    for (std::uint32_t t : edges_[k]) length = std::max(length, texelLength(t, cornerOf(t, k)));
    queue_.emplace(length, k);
  }

  // Edge k's midpoint m becomes a vertex; each triangle (p, q, c) on it becomes (p, m, c) and
  // (m, q, c), in the same corner slots, so the winding is kept.
  void split(EdgeKey k) {
    const std::vector<std::uint32_t> sharing = std::move(edges_[k]);
    edges_.erase(k);
    const auto m = static_cast<std::uint32_t>(out_.vertexCount());
    out_.newVertexParents.push_back({std::uint32_t(k >> 32), std::uint32_t(k & 0xffffffffu)});
    std::vector<EdgeKey> touched;
    for (const std::uint32_t t : sharing) {
      const int i = cornerOf(t, k);
      const int j = (i + 1) % 3;
      const glm::uvec3 tri = out_.triangles[t];
      const glm::vec2 mid =
          0.5f * (out_.cornerTexcoords[3 * t + i] + out_.cornerTexcoords[3 * t + j]);
      const auto t2 = static_cast<std::uint32_t>(out_.triangles.size());
      glm::uvec3 second = tri;
      second[i] = m;
      out_.triangles.push_back(second);
      for (int c = 0; c < 3; ++c) out_.cornerTexcoords.push_back(out_.cornerTexcoords[3 * t + c]);
      out_.cornerTexcoords[3 * t2 + i] = mid;
      out_.parentTriangle.push_back(out_.parentTriangle[t]);
      out_.triangles[t][j] = m;
      out_.cornerTexcoords[3 * t + j] = mid;
      // (q, c) moves to the second triangle; (p, m), (m, q) and (m, c) are new.
      std::vector<std::uint32_t>& qc = edges_[edgeKey(tri[j], tri[(i + 2) % 3])];
      for (std::uint32_t& s : qc) s = s == t ? t2 : s;
      edges_[edgeKey(tri[i], m)].push_back(t);
      edges_[edgeKey(m, tri[j])].push_back(t2);
      edges_[edgeKey(m, tri[(i + 2) % 3])].push_back(t);
      edges_[edgeKey(m, tri[(i + 2) % 3])].push_back(t2);
      touched.push_back(edgeKey(m, tri[(i + 2) % 3]));
    }
    touched.push_back(edgeKey(std::uint32_t(k >> 32), m));
    touched.push_back(edgeKey(m, std::uint32_t(k & 0xffffffffu)));
    for (const EdgeKey e : touched) push(e);
  }

  UvRefinement& out_;
  double texels_;
  std::unordered_map<EdgeKey, std::vector<std::uint32_t>> edges_;
  // Longest first; equal lengths by key, so the order (and the result) is the same every run.
  std::priority_queue<std::pair<double, EdgeKey>> queue_;
};

}  // namespace

UvRefinement refineToTexels(const std::string& path, std::size_t vertexCount,
                            std::span<const glm::uvec3> triangles,
                            std::span<const glm::vec2> cornerTexcoords, int textureSize,
                            double maxEdgeTexels, std::size_t maxVertices) {
  if (cornerTexcoords.size() != 3 * triangles.size()) {
    fail(path, "has no TEXCOORD_0 for every triangle: a lightmap needs texture coordinates");
  }
  checkTexcoords(path, cornerTexcoords);
  UvRefinement out;
  out.originalVertices = vertexCount;
  out.triangles.assign(triangles.begin(), triangles.end());
  out.cornerTexcoords.assign(cornerTexcoords.begin(), cornerTexcoords.end());
  out.originalCornerTexcoords = out.cornerTexcoords;
  out.parentTriangle.resize(triangles.size());
  for (std::uint32_t t = 0; t < triangles.size(); ++t) out.parentTriangle[t] = t;
  Refiner refiner(out, textureSize);
  refiner.run(maxEdgeTexels, maxVertices, path);
  return out;
}

TriangleMesh refinedMesh(const UvRefinement& refinement, const TriangleMesh& original) {
  TriangleMesh mesh;
  mesh.positions = refinedValues<glm::vec3>(refinement, original.positions);
  mesh.normals = refinedValues<glm::vec3>(refinement, original.normals);
  for (std::size_t v = original.normals.size(); v < mesh.normals.size(); ++v) {
    const float length = glm::length(mesh.normals[v]);
    // Opposite normals at an edge's ends (a fold of zero thickness): keep the first end's.
    mesh.normals[v] =
        length > 1e-6f ? mesh.normals[v] / length
                       : mesh.normals[refinement.newVertexParents[v - original.normals.size()][0]];
  }
  mesh.triangles = refinement.triangles;
  return mesh;
}

}  // namespace sss

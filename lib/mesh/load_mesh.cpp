#include "mesh/load_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <sstream>

#include <glm/geometric.hpp>

#include "core/bounds.h"
#include "core/error.h"
#include "core/file_extension.h"
#include "mesh/gltf_reader.h"
#include "mesh/openmesh_reader.h"
#include "mesh/ply_format.h"

namespace sss {

namespace {

// Union-find with path halving; deterministic.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), std::size_t{0});
  }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

std::string plural(std::size_t n, const std::string& word) {
  if (n == 1) return "1 " + word;
  const std::size_t at = word.rfind("vertex");
  if (at != std::string::npos && at + 6 == word.size()) {
    return std::to_string(n) + " " + word.substr(0, at) + "vertices";
  }
  return std::to_string(n) + " " + word + "s";
}

// Edge statistics, non-manifold vertices and components of an indexed triangle list.
void analyzeTopology(const TriangleMesh& mesh, MeshReport& r) {
  const std::size_t nt = mesh.triangles.size();
  struct HalfEdge {
    unsigned lo, hi;
    bool forward;  // lo -> hi in its triangle
    unsigned tri;
  };
  std::vector<HalfEdge> edges;
  edges.reserve(3 * nt);
  for (unsigned t = 0; t < nt; ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const unsigned a = tri[k], b = tri[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), a < b, t});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.tri < y.tri;
  });
  // Corner 3t+k is triangle t at its k-th vertex; corners around a vertex that share an edge
  // belong to one fan.
  DisjointSets fans(3 * nt);
  DisjointSets components(mesh.positions.size());
  auto cornerOf = [&](unsigned t, unsigned v) {
    const glm::uvec3& tri = mesh.triangles[t];
    return 3 * std::size_t{t} + (tri.x == v ? 0 : tri.y == v ? 1 : 2);
  };
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    const std::size_t n = j - i;
    if (n == 1) ++r.boundaryEdges;
    if (n == 2 && edges[i].forward == edges[i + 1].forward) ++r.misorientedEdges;
    if (n > 2) ++r.nonManifoldEdges;
    components.unite(edges[i].lo, edges[i].hi);
    for (std::size_t k = i + 1; k < j; ++k) {
      fans.unite(cornerOf(edges[i].tri, edges[i].lo), cornerOf(edges[k].tri, edges[i].lo));
      fans.unite(cornerOf(edges[i].tri, edges[i].hi), cornerOf(edges[k].tri, edges[i].hi));
    }
    i = j;
  }
  std::vector<unsigned> fanCount(mesh.positions.size(), 0);
  for (std::size_t c = 0; c < 3 * nt; ++c) {
    if (fans.find(c) == c) ++fanCount[mesh.triangles[c / 3][c % 3]];
  }
  for (unsigned f : fanCount) r.nonManifoldVertices += f > 1;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) r.components += components.find(v) == v;
}

// Errors that stop the cleanup: too many vertices, a normal count that differs, NaN/Inf
// coordinates, no faces, a face list that does not add up.
void checkRawMesh(const std::string& path, const RawMesh& raw) {
  const std::size_t nv = raw.positions.size();
  if (nv > 0xffffffffu) fail(path, "too many vertices");
  if (!raw.normals.empty() && raw.normals.size() != nv) fail(path, "normal count differs");
  for (std::size_t i = 0; i < nv; ++i) {
    const glm::vec3& p = raw.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      std::ostringstream s;
      s << "vertex " << i << " has a non-finite coordinate (" << p.x << ", " << p.y << ", " << p.z
        << ")";
      fail(path, s.str());
    }
  }
  if (raw.faceSizes.empty()) fail(path, "no faces (a point cloud is not a surface)");
  if (std::accumulate(raw.faceSizes.begin(), raw.faceSizes.end(), std::size_t{0}) !=
      raw.faceCorners.size()) {
    fail(path, "face corner count mismatch");
  }
}

std::string number(double x, int precision = 6) {
  std::ostringstream s;
  s.precision(precision);
  s << x;
  return s.str();
}

// The largest coordinate magnitude and the vertex that has it.
std::pair<double, std::size_t> farthestCoordinate(const TriangleMesh& mesh) {
  double maxAbs = 0.0;
  std::size_t vertex = 0;
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3& p = mesh.positions[i];
    const double a = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    if (a > maxAbs) maxAbs = a, vertex = i;
  }
  return {maxAbs, vertex};
}

// The median edge length of an even stride sample of at most 2^16 triangles, in double.
double medianEdgeLength(const TriangleMesh& mesh) {
  const std::size_t nt = mesh.triangles.size();
  const std::size_t stride = std::max<std::size_t>(1, (nt + 65535) / 65536);
  std::vector<double> lengths;
  lengths.reserve(3 * ((nt + stride - 1) / stride));
  for (std::size_t t = 0; t < nt; t += stride) {
    const glm::uvec3& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      lengths.push_back(glm::length(glm::dvec3(mesh.positions[tri[k]]) -
                                    glm::dvec3(mesh.positions[tri[(k + 1) % 3]])));
    }
  }
  if (lengths.empty()) return 0.0;
  const auto middle = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
  std::nth_element(lengths.begin(), middle, lengths.end());
  return *middle;
}

// Triangulates (fans) and drops degenerate triangles; an out-of-range index is an error.
// faceOf (optional) receives each triangle's face.
std::vector<glm::uvec3> triangulate(const std::string& path, const RawMesh& raw, MeshReport& r,
                                    std::vector<unsigned>* faceOf) {
  const std::size_t nv = raw.positions.size();
  std::vector<glm::uvec3> tris;
  tris.reserve(raw.faceSizes.size());
  std::size_t at = 0;
  for (std::size_t f = 0; f < raw.faceSizes.size(); ++f) {
    const unsigned size = raw.faceSizes[f];
    const unsigned* c = raw.faceCorners.data() + at;
    at += size;
    for (unsigned k = 0; k < size; ++k) {
      if (c[k] >= nv) {
        fail(path, "face " + std::to_string(f) + " refers to vertex " + std::to_string(c[k]) +
                       " but there are only " + plural(nv, "vertex"));
      }
    }
    if (size < 3) {
      ++r.droppedDegenerate;
      continue;
    }
    if (size > 3) ++r.triangulatedPolygons;
    for (unsigned k = 1; k + 1 < size; ++k) {
      const glm::uvec3 t(c[0], c[k], c[k + 1]);
      const glm::dvec3 a(raw.positions[t.x]);
      const glm::dvec3 n =
          glm::cross(glm::dvec3(raw.positions[t.y]) - a, glm::dvec3(raw.positions[t.z]) - a);
      if (t.x == t.y || t.y == t.z || t.z == t.x || n == glm::dvec3(0.0)) {
        ++r.droppedDegenerate;
      } else {
        tris.push_back(t);
        if (faceOf) faceOf->push_back(static_cast<unsigned>(f));
      }
    }
  }
  return tris;
}

// Duplicates: the same vertex set as an earlier triangle (either winding); the first stays.
// faceOf (optional) follows the triangles.
void dropDuplicateTriangles(std::vector<glm::uvec3>& tris, MeshReport& r,
                            std::vector<unsigned>* faceOf) {
  std::vector<std::pair<std::array<unsigned, 3>, std::size_t>> keys(tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t) {
    std::array<unsigned, 3> k = {tris[t].x, tris[t].y, tris[t].z};
    std::sort(k.begin(), k.end());
    keys[t] = {k, t};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<char> duplicate(tris.size(), 0);
  for (std::size_t i = 1; i < keys.size(); ++i) {
    if (keys[i].first == keys[i - 1].first) duplicate[keys[i].second] = 1;
  }
  std::size_t kept = 0;
  for (std::size_t t = 0; t < tris.size(); ++t) {
    if (duplicate[t]) continue;
    if (faceOf) (*faceOf)[kept] = (*faceOf)[t];
    tris[kept++] = tris[t];
  }
  r.droppedDuplicate = tris.size() - kept;
  tris.resize(kept);
  if (faceOf) faceOf->resize(kept);
}

// Removes unreferenced vertices, keeping the order of the rest: mesh gets the positions and
// (file) normals of the vertices its triangles use, renumbered. Returns each output vertex's
// index in raw.
std::vector<unsigned> keepReferencedVertices(const RawMesh& raw, TriangleMesh& mesh,
                                             MeshReport& r) {
  const std::size_t nv = raw.positions.size();
  std::vector<glm::uvec3>& tris = mesh.triangles;
  std::vector<unsigned> newIndex(nv, 0xffffffffu);
  for (const glm::uvec3& t : tris) newIndex[t.x] = newIndex[t.y] = newIndex[t.z] = 0;
  std::vector<unsigned> origin;
  origin.reserve(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    if (newIndex[i] == 0) {
      newIndex[i] = static_cast<unsigned>(origin.size());
      origin.push_back(static_cast<unsigned>(i));
    }
  }
  r.droppedUnreferenced = nv - origin.size();
  const bool hadNormals = !raw.normals.empty();
  mesh.positions.resize(origin.size());
  if (hadNormals) mesh.normals.resize(origin.size());
  for (std::size_t i = 0; i < origin.size(); ++i) {
    mesh.positions[i] = raw.positions[origin[i]];
    if (hadNormals) mesh.normals[i] = raw.normals[origin[i]];
  }
  for (glm::uvec3& t : tris) t = glm::uvec3(newIndex[t.x], newIndex[t.y], newIndex[t.z]);
  return origin;
}

// Normals: keep usable file normals (renormalized only when clearly not unit, so that our own
// files read back bit-exactly), compute the others; file normals against the winding on the whole
// are negated.
void settleNormals(TriangleMesh& mesh, bool hadNormals, MeshReport& r) {
  const std::vector<glm::vec3> computed = computeVertexNormals(mesh);
  if (!hadNormals) {
    mesh.normals = computed;
    r.normalsComputed = true;
    return;
  }
  std::size_t replaced = 0;
  double agreement = 0.0;
  for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
    glm::vec3& n = mesh.normals[i];
    const float len = glm::length(n);
    if (!std::isfinite(len) || len < 1e-20f) {
      n = computed[i];
      ++replaced;
      continue;
    }
    if (std::abs(len - 1.0f) > 1e-4f) n /= len;
    agreement += glm::dot(glm::dvec3(n), glm::dvec3(computed[i]));
  }
  if (agreement < 0.0) {
    for (glm::vec3& n : mesh.normals) n = -n;
    r.normalsNegated = true;
  }
  if (replaced == mesh.normals.size()) r.normalsComputed = true;
  if (replaced > 0 && replaced < mesh.normals.size()) {
    r.warnings.push_back(plural(replaced, "vertex normal") +
                         " zero or not finite: computed from the faces");
  }
}

// One warning line per repair or topology problem the report counts.
void addCleanupWarnings(MeshReport& r) {
  if (r.droppedDegenerate) {
    r.warnings.push_back("dropped " + plural(r.droppedDegenerate, "degenerate face") +
                         " (repeated vertex, fewer than 3 corners or zero area)");
  }
  if (r.droppedDuplicate) {
    r.warnings.push_back("dropped " + plural(r.droppedDuplicate, "duplicate face"));
  }
  if (r.droppedUnreferenced) {
    r.warnings.push_back("removed " + plural(r.droppedUnreferenced, "unreferenced vertex"));
  }
  if (r.nonManifoldEdges) {
    r.warnings.push_back(plural(r.nonManifoldEdges, "non-manifold edge") +
                         " (shared by more than two faces)");
  }
  if (r.misorientedEdges) {
    r.warnings.push_back(plural(r.misorientedEdges, "edge") +
                         " between faces of opposite orientation (inconsistent winding)");
  }
  if (r.nonManifoldVertices) {
    r.warnings.push_back(plural(r.nonManifoldVertices, "non-manifold vertex") +
                         " (separate fans of faces meeting at one vertex)");
  }
  if (r.normalsComputed) r.warnings.push_back("no vertex normals: computed (area-weighted)");
  if (r.orientationFlipped) {
    r.warnings.push_back("closed mesh was inside out (negative volume): faces flipped");
  }
  if (r.normalsNegated) {
    r.warnings.push_back("vertex normals pointed against the face winding: negated");
  }
}

}  // namespace

void checkCoordinateRange(const std::string& path, const TriangleMesh& mesh, double maxCoordinate,
                          const std::string& unit) {
  const auto [maxAbs, vertex] = farthestCoordinate(mesh);
  if (maxAbs <= maxCoordinate) return;
  const std::string u = unit.empty() ? "" : " " + unit;
  const glm::vec3& p = mesh.positions[vertex];
  fail(path, "vertex " + std::to_string(vertex) + " (" + number(p.x) + ", " + number(p.y) + ", " +
                 number(p.z) + ") has a coordinate of " + number(maxAbs) + u +
                 ", beyond the limit of " + number(maxCoordinate, 10) + u + " for float geometry");
}

void checkFloatPrecision(const std::string& path, const TriangleMesh& mesh) {
  const auto [maxAbs, vertex] = farthestCoordinate(mesh);
  const Bounds3 bounds = boundsOf(mesh.positions);
  const double reach = std::max(maxAbs, glm::length(glm::dvec3(bounds.hi) - glm::dvec3(bounds.lo)));
  const double edge = medianEdgeLength(mesh);
  if (!(reach > kMaxReachInEdges * edge)) return;
  const glm::vec3& p = mesh.positions[vertex];
  fail(path, "the mesh reaches " + number(reach) + " (vertex " + std::to_string(vertex) + " at (" +
                 number(p.x) + ", " + number(p.y) + ", " + number(p.z) + ")), " +
                 number(reach / edge, 3) + " times its median edge length " + number(edge, 3) +
                 ": float ray tracing resolves at most " + number(kMaxReachInEdges) +
                 " (2^16); a stray vertex, or a mesh far from its origin?");
}

TriangleMesh cleanMesh(const std::string& path, RawMesh raw, MeshReport* report,
                       std::vector<unsigned>* vertexOrigin, std::vector<unsigned>* faceOrigin) {
  MeshReport local;
  MeshReport& r = report ? *report : local;
  r.fileVertices = raw.positions.size();
  r.fileFaces = raw.faceSizes.size();
  checkRawMesh(path, raw);

  TriangleMesh mesh;
  if (faceOrigin) faceOrigin->clear();
  mesh.triangles = triangulate(path, raw, r, faceOrigin);
  dropDuplicateTriangles(mesh.triangles, r, faceOrigin);
  if (mesh.triangles.empty()) {
    fail(path, "all " + plural(r.fileFaces, "face") + " are degenerate or duplicate");
  }
  std::vector<unsigned> origin = keepReferencedVertices(raw, mesh, r);
  const bool hadNormals = !raw.normals.empty();
  raw = RawMesh();
  checkCoordinateRange(path, mesh, kMaxCoordinate);
  checkFloatPrecision(path, mesh);

  analyzeTopology(mesh, r);
  const bool closed = r.boundaryEdges == 0 && r.nonManifoldEdges == 0 && r.misorientedEdges == 0;
  if (closed && signedVolume(mesh) < 0.0) {
    for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
    r.orientationFlipped = true;
  }
  settleNormals(mesh, hadNormals, r);
  addCleanupWarnings(r);
  if (vertexOrigin) *vertexOrigin = std::move(origin);
  return mesh;
}

namespace {

// A glTF scene through the cleanup, its parts' data following the triangles: each triangle's
// part, and its corners' texture coordinates found by the raw vertex each corner came from (the
// cleanup may have turned a triangle).
TriangleMesh loadGltf(const std::string& path, MeshReport& r, MeshParts* parts) {
  GltfMesh g = readGltf(path);
  r.format = lowerExtension(path);
  r.warnings = std::move(g.warnings);
  const std::vector<unsigned> rawCorners = g.raw.faceCorners;
  std::vector<unsigned> vertexOrigin, faceOrigin;
  TriangleMesh mesh = cleanMesh(path, std::move(g.raw), &r, &vertexOrigin, &faceOrigin);
  if (!parts) return mesh;
  parts->mmPerUnit = 1000.0;  // glTF 2.0, section 3.3.1: metres
  parts->weldedVertices = g.weldedVertices;
  parts->parts = std::move(g.parts);
  parts->surfaces = std::move(g.surfaces);
  parts->trianglePart.resize(mesh.triangles.size());
  if (!g.cornerTexcoords.empty()) parts->cornerTexcoords.resize(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const unsigned face = faceOrigin[t];
    parts->trianglePart[t] = g.facePart[face];
    if (g.cornerTexcoords.empty()) continue;
    for (int k = 0; k < 3; ++k) {
      const unsigned rawVertex = vertexOrigin[mesh.triangles[t][k]];
      int j = 0;
      while (j < 2 && rawCorners[3 * face + j] != rawVertex) ++j;
      parts->cornerTexcoords[3 * t + k] = g.cornerTexcoords[3 * face + j];
    }
  }
  return mesh;
}

}  // namespace

TriangleMesh loadMesh(const std::string& path, MeshReport* report, MeshParts* parts) {
  MeshReport local;
  MeshReport& r = report ? *report : local;
  r = MeshReport();
  if (parts) *parts = MeshParts();
  const std::string ext = lowerExtension(path);
  RawMesh raw;
  if (ext == "gltf" || ext == "glb") {
    return loadGltf(path, r, parts);
  } else if (ext == "ply") {
    ply::PlyMesh ply = ply::readPly(path);
    raw = ply::takeMesh(ply, r);
  } else if (ext == "obj" || ext == "off" || ext == "stl" || ext == "om") {
    r.format = ext;
    raw = readWithOpenMesh(path, ext);
  } else {
    fail(path,
         "unknown mesh format '" + ext + "' (expected .ply, .obj, .off, .stl, .om, .gltf or .glb)");
  }
  return cleanMesh(path, std::move(raw), &r);
}

}  // namespace sss

#include "mesh/gltf_reader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "core/error.h"
#include "core/file_extension.h"
#include "core/memory.h"
#include "mesh/gltf_document.h"
#include "mesh/gltf_materials.h"

namespace sss {
namespace {

using gltf::Document;

constexpr std::uint64_t kNone = std::numeric_limits<std::uint64_t>::max();

// `n` finite numbers from the member `key` of a node (`fallback` when absent).
template <std::size_t N>
std::array<double, N> numbers(const Document& doc, const gltf::Json& node, const char* key,
                              const std::string& where, std::array<double, N> fallback) {
  const auto it = node.find(key);
  if (it == node.end()) return fallback;
  if (!it->is_array() || it->size() != N) {
    doc.fail(where + ": \"" + key + "\" is not " + std::to_string(N) + " numbers");
  }
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) {
    if (!(*it)[i].is_number()) doc.fail(where + ": \"" + key + "\" holds a non-number");
    out[i] = (*it)[i].get<double>();
    if (!std::isfinite(out[i])) doc.fail(where + ": \"" + key + "\" is not finite");
  }
  return out;
}

// Section 3.5.3: the node's matrix (column-major), or T * R * S.
glm::dmat4 localTransform(const Document& doc, const gltf::Json& node, std::uint64_t i) {
  const std::string where = "node " + std::to_string(i);
  if (node.contains("matrix")) {
    if (node.contains("translation") || node.contains("rotation") || node.contains("scale")) {
      doc.fail(where + " has both a matrix and translation, rotation or scale");
    }
    const auto m = numbers<16>(doc, node, "matrix", where, {});
    glm::dmat4 out;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) out[c][r] = m[4 * c + r];
    return out;
  }
  const auto t = numbers<3>(doc, node, "translation", where, {0, 0, 0});
  auto q = numbers<4>(doc, node, "rotation", where, {0, 0, 0, 1});
  const auto s = numbers<3>(doc, node, "scale", where, {1, 1, 1});
  const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(len > 0.0) || !std::isfinite(len)) doc.fail(where + ": the rotation is not a quaternion");
  const double x = q[0] / len, y = q[1] / len, z = q[2] / len, w = q[3] / len;
  // The rotation matrix of the unit quaternion (x, y, z, w), columns scaled by s.
  const glm::dmat3 rotation(1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w),
                            2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                            2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y));
  glm::dmat4 out(1.0);
  for (int c = 0; c < 3; ++c) out[c] = glm::dvec4(rotation[c] * s[c], 0.0);
  out[3] = glm::dvec4(t[0], t[1], t[2], 1.0);
  return out;
}

// Each node's parent (kNone for a root); a node with two parents, a child that does not exist or
// a cycle is an error (section 3.5.2: the nodes form disjoint strict trees).
std::vector<std::uint64_t> parentsOf(const Document& doc, const gltf::Json& nodes) {
  std::vector<std::uint64_t> parent(nodes.size(), kNone);
  for (std::uint64_t i = 0; i < nodes.size(); ++i) {
    const gltf::Json& node = doc.element("nodes", i);
    for (const gltf::Json& c : doc.array(node, "children")) {
      if (!c.is_number_unsigned() || c.get<std::uint64_t>() >= nodes.size()) {
        doc.fail("node " + std::to_string(i) + " has a child that does not exist");
      }
      const std::uint64_t child = c.get<std::uint64_t>();
      if (parent[child] != kNone || child == i) {
        doc.fail("node " + std::to_string(child) + " has two parents or is its own child");
      }
      parent[child] = i;
    }
  }
  // Up from each node until a root or a node already done: meeting the walk's own path is a cycle.
  std::vector<char> state(nodes.size(), 0);  // 0 new, 1 on the current path, 2 done
  std::vector<std::uint64_t> path;
  for (std::uint64_t i = 0; i < nodes.size(); ++i) {
    path.clear();
    std::uint64_t j = i;
    while (j != kNone && state[j] == 0) state[j] = 1, path.push_back(j), j = parent[j];
    if (j != kNone && state[j] == 1) {
      doc.fail("the node graph has a cycle through node " + std::to_string(j));
    }
    for (std::uint64_t k : path) state[k] = 2;
  }
  return parent;
}

struct Instance {
  std::uint64_t node = 0, mesh = 0;
  glm::dmat4 world{1.0};
};

// The nodes of the default scene (or scene 0) that place a mesh, with their world transforms,
// in depth-first order (without recursion: a deep chain of nodes cannot exhaust the stack).
std::vector<Instance> sceneInstances(const Document& doc, std::vector<std::string>& warnings) {
  const gltf::Json& json = doc.json();
  const gltf::Json& nodes = doc.array(json, "nodes");
  const std::vector<std::uint64_t> parent = parentsOf(doc, nodes);
  if (doc.array(json, "scenes").empty()) doc.fail("no scene (\"scenes\" is empty or absent)");
  const gltf::Json& scene = doc.element("scenes", doc.index(json, "scene", 0));
  std::vector<std::pair<std::uint64_t, glm::dmat4>> stack;
  const gltf::Json& roots = doc.array(scene, "nodes");
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) {
    if (!it->is_number_unsigned() || it->get<std::uint64_t>() >= nodes.size()) {
      doc.fail("the scene lists a node that does not exist");
    }
    if (parent[it->get<std::uint64_t>()] != kNone) doc.fail("the scene lists a node with a parent");
    stack.emplace_back(it->get<std::uint64_t>(), glm::dmat4(1.0));
  }
  std::vector<char> visited(nodes.size(), 0);
  std::vector<Instance> out;
  while (!stack.empty()) {
    const auto [i, parentWorld] = stack.back();
    stack.pop_back();
    if (visited[i]) doc.fail("the scene lists node " + std::to_string(i) + " twice");
    visited[i] = 1;
    const gltf::Json& node = doc.element("nodes", i);
    const glm::dmat4 world = parentWorld * localTransform(doc, node, i);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(world[c][r])) {
          doc.fail("node " + std::to_string(i) + "'s world transform is not finite");
        }
    if (node.contains("mesh")) {
      out.push_back({i, doc.index(node, "mesh"), world});
      if (node.contains("skin")) {
        warnings.push_back("node " + std::to_string(i) + ": skin ignored (the bind pose is read)");
      }
    }
    const gltf::Json& children = doc.array(node, "children");
    for (auto it = children.rbegin(); it != children.rend(); ++it) {
      stack.emplace_back(it->get<std::uint64_t>(), world);
    }
  }
  return out;
}

std::string meshWhere(std::uint64_t mesh, std::uint64_t primitive) {
  return "mesh " + std::to_string(mesh) + " primitive " + std::to_string(primitive);
}

// What the scene will allocate, from the accessors' counts, against the memory available: a
// small file can place a large mesh many times.
void checkSceneSize(const Document& doc, const std::vector<Instance>& instances) {
  std::uint64_t vertices = 0, corners = 0;
  for (const Instance& instance : instances) {
    const gltf::Json& mesh = doc.element("meshes", instance.mesh);
    for (const gltf::Json& primitive : doc.array(mesh, "primitives")) {
      if (!primitive.is_object() || !primitive.contains("attributes")) continue;  // reported later
      const gltf::Json& attributes = primitive.at("attributes");
      if (!attributes.is_object() || !attributes.contains("POSITION")) continue;
      const std::uint64_t n = doc.accessorCount(doc.index(attributes, "POSITION"));
      vertices += n;
      corners +=
          primitive.contains("indices") ? doc.accessorCount(doc.index(primitive, "indices")) : n;
    }
  }
  if (vertices >= std::numeric_limits<std::uint32_t>::max() ||
      corners >= 3ull * std::numeric_limits<std::uint32_t>::max()) {
    doc.fail("the scene places " + std::to_string(vertices) + " vertices and " +
             std::to_string(corners) + " corners, beyond 32-bit indices");
  }
  // Per vertex: the positions and normals placed, the weld's keys, order and sums, the welded
  // copies (about 130 bytes); per corner: the indices, texture coordinates, face lists and the
  // cleanup's triangles (about 40 bytes).
  checkMemoryNeed(doc.path(), "reading " + std::to_string(vertices) + " vertices",
                  vertices * 160 + corners * 48);
}

// Accumulates the primitives' vertices and triangles.
struct SceneBuilder {
  std::vector<glm::vec3> positions, normals;
  std::vector<char> hasNormal;
  std::vector<unsigned> corners;
  std::vector<glm::vec2> cornerTexcoords;
  std::vector<std::uint32_t> facePart;
  std::vector<MeshPart> parts;
};

// The triangles of a primitive's corner list by its mode (section 3.7.2.1), wound as the file
// says: each a (first, second, third) of indices into `indices`.
std::vector<std::array<std::uint32_t, 3>> triangleCorners(const Document& doc, std::uint64_t mode,
                                                          std::size_t n, const std::string& where) {
  std::vector<std::array<std::uint32_t, 3>> tris;
  const auto u = [](std::size_t i) { return static_cast<std::uint32_t>(i); };
  if (mode == 4) {
    if (n % 3 != 0) doc.fail(where + ": " + std::to_string(n) + " corners, not a multiple of 3");
    for (std::size_t i = 0; i + 2 < n; i += 3) tris.push_back({u(i), u(i + 1), u(i + 2)});
  } else if (mode == 5) {  // strip: every other triangle turned so that all wind alike
    for (std::size_t i = 0; i + 2 < n; ++i) {
      if (i % 2 == 0)
        tris.push_back({u(i), u(i + 1), u(i + 2)});
      else
        tris.push_back({u(i + 1), u(i), u(i + 2)});
    }
  } else if (mode == 6) {  // fan around the first corner
    for (std::size_t i = 1; i + 1 < n; ++i) tris.push_back({u(i), u(i + 1), 0});
  } else {
    static const char* kModes[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
    doc.fail(where + " has mode " + (mode < 4 ? std::string(kModes[mode]) + " (" : "(") +
             std::to_string(mode) + "): only triangles, strips and fans (4, 5, 6) are surfaces");
  }
  return tris;
}

std::string materialKey(const Document& doc, const gltf::Json& primitive) {
  if (!primitive.contains("material")) return "";
  const std::uint64_t m = doc.index(primitive, "material");
  const std::string name = doc.string(doc.element("materials", m), "name");
  return name.empty() ? "#" + std::to_string(m) : name;
}

// The primitive's attribute `name` as `components` floats per vertex (empty when absent), one
// element per position.
std::vector<float> attribute(const Document& doc, const gltf::Json& attributes, const char* name,
                             int components, const std::vector<int>& types, bool normalized,
                             std::size_t vertices, const std::string& where) {
  if (!attributes.contains(name)) return {};
  std::vector<float> values = doc.readFloats(doc.index(attributes, name), components, types,
                                             normalized, std::string(name) + " of " + where);
  if (values.size() != vertices * static_cast<std::size_t>(components)) {
    doc.fail(where + ": " + name + " has " + std::to_string(values.size() / components) +
             " elements, POSITION " + std::to_string(vertices));
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      doc.fail(where + ": " + name + " element " + std::to_string(i / components) +
               " is not finite");
    }
  }
  return values;
}

// Appends the primitive's vertices, transformed by `world`, to the builder.
void addVertices(const Document& doc, SceneBuilder& b, const std::vector<float>& p,
                 const std::vector<float>& n, const glm::dmat4& world, const std::string& where) {
  const glm::dmat3 linear(world);
  const double det = glm::determinant(linear);
  const glm::dmat3 normalMatrix =
      std::abs(det) > 0.0 ? glm::transpose(glm::inverse(linear)) : glm::dmat3(0.0);
  const bool keepNormals = normalMatrix == glm::dmat3(1.0);  // as the file has them, bit for bit
  for (std::size_t i = 0; i < p.size() / 3; ++i) {
    const glm::dvec4 q = world * glm::dvec4(p[3 * i], p[3 * i + 1], p[3 * i + 2], 1.0);
    const glm::vec3 v(q);
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
      doc.fail(where + ": vertex " + std::to_string(i) + " is beyond float range once placed");
    }
    b.positions.push_back(v);
    glm::vec3 normal(0.0f);
    if (!n.empty()) {
      const glm::vec3 fileNormal(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
      const glm::dvec3 m = normalMatrix * glm::dvec3(fileNormal);
      const double length = glm::length(m);
      normal = keepNormals ? fileNormal : length > 0.0 ? glm::vec3(m / length) : glm::vec3(0.0f);
    }
    b.normals.push_back(normal);
    b.hasNormal.push_back(!n.empty());
  }
}

// One primitive placed by one node: its vertices, triangles (wound back where the node mirrors),
// texture coordinates per corner and its part.
void addPrimitive(const Document& doc, SceneBuilder& b, const Instance& instance,
                  std::uint64_t index, const gltf::Json& primitive) {
  const std::string where = meshWhere(instance.mesh, index);
  if (!primitive.is_object()) doc.fail(where + " is not an object");
  const auto attributes = primitive.find("attributes");
  if (attributes == primitive.end() || !attributes->is_object()) {
    doc.fail(where + " has no attributes");
  }
  if (!attributes->contains("POSITION")) doc.fail(where + " has no POSITION");
  const std::vector<float> p = doc.readFloats(doc.index(*attributes, "POSITION"), 3, {gltf::kFloat},
                                              false, "POSITION of " + where);
  const std::size_t nv = p.size() / 3;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!std::isfinite(p[i])) {
      doc.fail(where + ": POSITION element " + std::to_string(i / 3) + " is not finite");
    }
  }
  const std::vector<float> n =
      attribute(doc, *attributes, "NORMAL", 3, {gltf::kFloat}, false, nv, where);
  const std::vector<float> uv =
      attribute(doc, *attributes, "TEXCOORD_0", 2,
                {gltf::kFloat, gltf::kUnsignedByte, gltf::kUnsignedShort}, true, nv, where);
  std::vector<std::uint32_t> indices;
  if (primitive.contains("indices")) {
    indices = doc.readIndices(doc.index(primitive, "indices"), "indices of " + where);
  } else {
    indices.resize(nv);
    std::iota(indices.begin(), indices.end(), 0u);
  }
  for (std::size_t k = 0; k < indices.size(); ++k) {
    if (indices[k] >= nv) {
      doc.fail(where + ": index " + std::to_string(k) + " is " + std::to_string(indices[k]) +
               ", but there are " + std::to_string(nv) + " vertices");
    }
  }
  const auto tris = triangleCorners(doc, doc.index(primitive, "mode", 4), indices.size(), where);
  const bool mirrored = glm::determinant(glm::dmat3(instance.world)) < 0.0;
  const auto base = static_cast<unsigned>(b.positions.size());
  addVertices(doc, b, p, n, instance.world, where);
  const auto part = static_cast<std::uint32_t>(b.parts.size());
  for (std::array<std::uint32_t, 3> t : tris) {
    if (mirrored) std::swap(t[1], t[2]);
    for (std::uint32_t c : t) {
      const std::uint32_t v = indices[c];
      b.corners.push_back(base + v);
      b.cornerTexcoords.push_back(uv.empty() ? glm::vec2(0.0f)
                                             : glm::vec2(uv[2 * v], uv[2 * v + 1]));
    }
    b.facePart.push_back(part);
  }
  MeshPart info;
  const gltf::Json& node = doc.element("nodes", instance.node);
  const gltf::Json& mesh = doc.element("meshes", instance.mesh);
  info.node = doc.string(node, "name");
  info.nodeIndex = instance.node;
  info.mesh = doc.string(mesh, "name");
  info.meshIndex = instance.mesh;
  info.primitive = index;
  info.material = materialKey(doc, primitive);
  if (primitive.contains("material"))
    info.materialIndex = static_cast<std::int64_t>(doc.index(primitive, "material"));
  info.transform = instance.world;
  info.hasTexcoords = !uv.empty();
  info.triangles = tris.size();
  b.parts.push_back(std::move(info));
}

// A position's key for welding: its bits, with -0 as +0.
std::array<std::uint32_t, 3> positionKey(const glm::vec3& p) {
  std::array<std::uint32_t, 3> key;
  for (int k = 0; k < 3; ++k) {
    const float v = p[k] + 0.0f;
    std::memcpy(&key[k], &v, 4);
  }
  return key;
}

// Welds vertices at identical positions into `raw` (first occurrences keep their order); a
// welded vertex's normal is its copies' when they agree, else their normalized sum (zero, for the
// cleanup to compute, when they cancel or none has one).
std::size_t weld(const SceneBuilder& b, RawMesh& raw) {
  const std::size_t n = b.positions.size();
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::vector<std::array<std::uint32_t, 3>> keys(n);
  for (std::size_t i = 0; i < n; ++i) keys[i] = positionKey(b.positions[i]);
  std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) {
    return keys[x] != keys[y] ? keys[x] < keys[y] : x < y;
  });
  std::vector<std::uint32_t> first(n);  // each vertex's first copy
  for (std::size_t k = 0; k < n; ++k) {
    const bool same = k > 0 && keys[order[k]] == keys[order[k - 1]];
    first[order[k]] = same ? first[order[k - 1]] : order[k];
  }
  std::vector<std::uint32_t> welded(n);
  const bool anyNormal = std::find(b.hasNormal.begin(), b.hasNormal.end(), 1) != b.hasNormal.end();
  std::vector<glm::dvec3> sum;
  std::vector<char> agree;
  for (std::size_t i = 0; i < n; ++i) {
    if (first[i] == i) {
      welded[i] = static_cast<std::uint32_t>(raw.positions.size());
      raw.positions.push_back(b.positions[i]);
      raw.normals.push_back(b.hasNormal[i] ? b.normals[i] : glm::vec3(0.0f));
      sum.push_back(glm::dvec3(raw.normals.back()));
      agree.push_back(1);
      continue;
    }
    const std::uint32_t w = welded[i] = welded[first[i]];
    if (!b.hasNormal[i]) continue;
    if (std::memcmp(&raw.normals[w], &b.normals[i], sizeof(glm::vec3)) != 0) agree[w] = 0;
    sum[w] += glm::dvec3(b.normals[i]);
  }
  for (std::size_t w = 0; w < raw.normals.size(); ++w) {
    if (agree[w]) continue;
    const double length = glm::length(sum[w]);
    raw.normals[w] = length > 1e-6 ? glm::vec3(sum[w] / length) : glm::vec3(0.0f);
  }
  if (!anyNormal) raw.normals.clear();
  raw.faceCorners.resize(b.corners.size());
  for (std::size_t c = 0; c < b.corners.size(); ++c) raw.faceCorners[c] = welded[b.corners[c]];
  raw.faceSizes.assign(b.corners.size() / 3, 3);
  return n - raw.positions.size();
}

GltfMesh readDocument(const Document& doc) {
  GltfMesh out;
  const std::vector<Instance> instances = sceneInstances(doc, out.warnings);
  if (instances.empty()) doc.fail("the scene places no mesh");
  checkSceneSize(doc, instances);
  SceneBuilder b;
  bool morphs = false;
  for (const Instance& instance : instances) {
    const gltf::Json& primitives = doc.array(doc.element("meshes", instance.mesh), "primitives");
    if (primitives.empty())
      doc.fail("mesh " + std::to_string(instance.mesh) + " has no primitives");
    for (std::uint64_t k = 0; k < primitives.size(); ++k) {
      morphs = morphs || (primitives[k].is_object() && primitives[k].contains("targets"));
      addPrimitive(doc, b, instance, k, primitives[k]);
    }
  }
  if (morphs) out.warnings.push_back("morph targets ignored (the base shape is read)");
  out.weldedVertices = weld(b, out.raw);
  out.facePart = std::move(b.facePart);
  const bool anyTexcoords =
      std::any_of(b.parts.begin(), b.parts.end(), [](const MeshPart& p) { return p.hasTexcoords; });
  if (anyTexcoords) out.cornerTexcoords = std::move(b.cornerTexcoords);
  out.parts = std::move(b.parts);
  out.surfaces = readSurfaceMaterials(doc);
  return out;
}

}  // namespace

GltfMesh readGltf(const std::string& path) {
  try {
    const Document doc(path, lowerExtension(path) == "glb");
    return readDocument(doc);
  } catch (const gltf::Json::exception& e) {
    fail(path, std::string("glTF JSON: ") + e.what());
  }
}

}  // namespace sss

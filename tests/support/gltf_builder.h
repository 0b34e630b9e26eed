// Hand-built glTF 2.0 assets for the reader's tests: a binary buffer with its bufferViews and
// accessors, the JSON around it (nodes, meshes, materials, scenes set by the test), written as a
// .glb, a .gltf with a base64 data: URI or a .gltf with an external .bin (glTF 2.0 specification,
// sections 3.6 and 4.4). Every accessor is exactly as the test asks: lying ones included.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

namespace sss::test {

class GltfBuilder {
 public:
  using Json = nlohmann::json;
  Json doc = {{"asset", {{"version", "2.0"}}}};
  std::string bin;

  // Appends `bytes` as a bufferView (4-byte aligned); byteStride when stride > 0.
  int view(const std::string& bytes, int stride = 0) {
    bin.resize((bin.size() + 3) / 4 * 4, '\0');
    Json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}};
    if (stride > 0) v["byteStride"] = stride;
    bin += bytes;
    doc["bufferViews"].push_back(v);
    return static_cast<int>(doc["bufferViews"].size()) - 1;
  }
  int accessor(int bufferView, int componentType, std::size_t count, const std::string& type,
               std::size_t byteOffset = 0, bool normalized = false) {
    Json a = {{"componentType", componentType}, {"count", count}, {"type", type}};
    if (bufferView >= 0) a["bufferView"] = bufferView;
    if (byteOffset > 0) a["byteOffset"] = byteOffset;
    if (normalized) a["normalized"] = true;
    doc["accessors"].push_back(a);
    return static_cast<int>(doc["accessors"].size()) - 1;
  }
  template <class T>
  static std::string bytesOf(const std::vector<T>& values) {
    std::string s(values.size() * sizeof(T), '\0');
    if (!values.empty()) std::memcpy(s.data(), values.data(), s.size());
    return s;
  }
  // POSITION with the bounds section 3.7.2.1 requires.
  int positions(const std::vector<glm::vec3>& p) {
    const int a = accessor(view(bytesOf(p)), 5126, p.size(), "VEC3");
    glm::vec3 lo = p.empty() ? glm::vec3(0.0f) : p[0], hi = lo;
    for (const glm::vec3& v : p)
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], v[k]), hi[k] = std::max(hi[k], v[k]);
    doc["accessors"][a]["min"] = {lo.x, lo.y, lo.z};
    doc["accessors"][a]["max"] = {hi.x, hi.y, hi.z};
    return a;
  }
  int texcoords(const std::vector<glm::vec2>& uv) {
    return accessor(view(bytesOf(uv)), 5126, uv.size(), "VEC2");
  }
  // Indices as `componentType` (5121, 5123 or 5125).
  int indices(const std::vector<unsigned>& idx, int componentType = 5125) {
    std::string bytes;
    for (unsigned i : idx) {
      const int size = componentType == 5121 ? 1 : componentType == 5123 ? 2 : 4;
      bytes.append(reinterpret_cast<const char*>(&i), size);
    }
    return accessor(view(bytes), componentType, idx.size(), "SCALAR");
  }
  // A mesh of one primitive per entry: (attributes, indices or -1, material or -1, mode).
  struct Primitive {
    Json attributes;
    int indices = -1;
    int material = -1;
    int mode = -1;
  };
  int mesh(const std::vector<Primitive>& primitives, const std::string& name = "") {
    Json m = {{"primitives", Json::array()}};
    if (!name.empty()) m["name"] = name;
    for (const Primitive& p : primitives) {
      Json j = {{"attributes", p.attributes}};
      if (p.indices >= 0) j["indices"] = p.indices;
      if (p.material >= 0) j["material"] = p.material;
      if (p.mode >= 0) j["mode"] = p.mode;
      m["primitives"].push_back(j);
    }
    doc["meshes"].push_back(m);
    return static_cast<int>(doc["meshes"].size()) - 1;
  }
  int node(Json node) {
    doc["nodes"].push_back(std::move(node));
    return static_cast<int>(doc["nodes"].size()) - 1;
  }
  int material(const std::string& name) {
    doc["materials"].push_back(name.empty() ? Json::object() : Json{{"name", name}});
    return static_cast<int>(doc["materials"].size()) - 1;
  }
  void scene(const std::vector<int>& roots) {
    doc["scenes"] = Json::array({{{"nodes", roots}}});
    doc["scene"] = 0;
  }

  // The GLB's bytes: buffer 0 is the BIN chunk.
  std::string glb() const {
    Json d = doc;
    d["buffers"] = Json::array({{{"byteLength", bin.size()}}});
    std::string json = d.dump();
    json.resize((json.size() + 3) / 4 * 4, ' ');
    std::string chunk = bin;
    chunk.resize((chunk.size() + 3) / 4 * 4, '\0');
    std::string out;
    const auto u32 = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    u32(0x46546C67);
    u32(2);
    u32(static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + chunk.size()));
    u32(static_cast<std::uint32_t>(json.size()));
    u32(0x4E4F534A);
    out += json;
    u32(static_cast<std::uint32_t>(chunk.size()));
    u32(0x004E4942);
    out += chunk;
    return out;
  }
  // The .gltf text with buffer 0 as `uri` (a file name, or "" for a base64 data: URI).
  std::string gltf(const std::string& uri = "") const {
    Json d = doc;
    d["buffers"] = Json::array(
        {{{"byteLength", bin.size()},
          {"uri", uri.empty() ? "data:application/octet-stream;base64," + base64(bin) : uri}}});
    return d.dump(1);
  }

  static std::string base64(const std::string& data) {
    static const char* kAlphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < data.size(); i += 3) {
      const std::uint32_t v =
          std::uint8_t(data[i]) << 16 | std::uint8_t(data[i + 1]) << 8 | std::uint8_t(data[i + 2]);
      for (int k = 3; k >= 0; --k) out += kAlphabet[(v >> (6 * k)) & 63];
    }
    if (i + 1 == data.size()) {
      const std::uint32_t v = std::uint8_t(data[i]) << 16;
      out += {kAlphabet[v >> 18], kAlphabet[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == data.size()) {
      const std::uint32_t v = std::uint8_t(data[i]) << 16 | std::uint8_t(data[i + 1]) << 8;
      out += {kAlphabet[v >> 18], kAlphabet[(v >> 12) & 63], kAlphabet[(v >> 6) & 63], '='};
    }
    return out;
  }
};

// A unit tetrahedron, wound outwards (positive signed volume): 4 vertices, 4 triangles.
inline std::vector<glm::vec3> tetrahedronPositions() {
  return {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
}
inline std::vector<unsigned> tetrahedronIndices() {
  return {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
}

}  // namespace sss::test

#include "mesh/lightmapped_glb.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "core/atomic_output.h"
#include "core/error.h"
#include "mesh/glb_builder.h"

namespace sss {
namespace {

using Json = GlbBinary::Json;

constexpr int kTriangles = 4;
constexpr int kLinear = 9729, kLinearMipmapLinear = 9987, kClampToEdge = 33071;

// The triangles of one node: its parts' (one primitive each) over the welded mesh.
struct NodeParts {
  std::uint64_t nodeIndex = 0;
  std::vector<std::size_t> parts;  // indices into MeshParts::parts
};

std::vector<NodeParts> groupByNode(const MeshParts& parts) {
  std::vector<NodeParts> nodes;
  for (std::size_t p = 0; p < parts.parts.size(); ++p) {
    auto it = std::find_if(nodes.begin(), nodes.end(), [&](const NodeParts& n) {
      return n.nodeIndex == parts.parts[p].nodeIndex;
    });
    if (it == nodes.end()) it = nodes.insert(nodes.end(), {parts.parts[p].nodeIndex, {}});
    it->parts.push_back(p);
  }
  return nodes;
}

// One primitive's vertices in its node's frame: a vertex per distinct (welded vertex, texture
// coordinate) among the part's triangle corners.
struct PrimitiveData {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> texcoords;
  std::vector<glm::uvec3> triangles;
};

PrimitiveData primitiveData(const LightmappedAsset& a, std::uint32_t part,
                            const glm::dmat4& transform) {
  const glm::dmat4 toLocal = glm::inverse(transform);
  const glm::dmat3 normalToLocal = glm::transpose(glm::dmat3(transform));
  const bool mirrored = glm::determinant(glm::dmat3(transform)) < 0.0;
  const bool allParts = a.parts.trianglePart.empty();
  PrimitiveData out;
  std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>, std::uint32_t> index;
  for (std::size_t t = 0; t < a.mesh.triangles.size(); ++t) {
    if (!allParts && a.parts.trianglePart[t] != part) continue;
    glm::uvec3 corners;
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t v = a.mesh.triangles[t][c];
      const glm::vec2 uv = a.parts.cornerTexcoords[3 * t + c];
      std::uint32_t u32, v32;
      std::memcpy(&u32, &uv.x, 4);
      std::memcpy(&v32, &uv.y, 4);
      const auto [it, added] =
          index.try_emplace({v, u32, v32}, static_cast<std::uint32_t>(out.positions.size()));
      if (added) {
        out.positions.push_back(
            glm::vec3(toLocal * glm::dvec4(glm::dvec3(a.mesh.positions[v]), 1)));
        out.normals.push_back(
            glm::vec3(glm::normalize(normalToLocal * glm::dvec3(a.mesh.normals[v]))));
        out.texcoords.push_back(uv);
      }
      corners[c] = it->second;
    }
    // A mirroring node reverses the winding again where it is drawn (glTF 2.0, 3.7.2.1).
    if (mirrored) std::swap(corners[1], corners[2]);
    out.triangles.push_back(corners);
  }
  return out;
}

Json nodeMatrix(const glm::dmat4& m) {
  Json out = Json::array();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out.push_back(m[c][r]);
  return out;
}

// sigma_tr = sqrt(3 sigma_a (sigma_a + sigma_s')) per mm: the diffuse light's attenuation
// (Jensen et al. 2001, the dipole's effective transport coefficient), as attenuationColor over
// attenuationDistance: the colour left after the shortest channel's 1 / sigma_tr.
Json volumeExtension(const LightmappedAsset& a, double thicknessLocal) {
  const glm::dvec3 sa = a.sigmaAPerMm, sigmaTr = glm::sqrt(3.0 * sa * (sa + a.sigmaSPrimePerMm));
  const double largest = std::max({sigmaTr.x, sigmaTr.y, sigmaTr.z});
  Json volume = {{"thicknessFactor", thicknessLocal}};
  if (largest > 0.0) {
    const double distanceMm = 1.0 / largest;
    const glm::dvec3 colour = glm::exp(-sigmaTr * distanceMm);
    volume["attenuationDistance"] = distanceMm / 1000.0;
    volume["attenuationColor"] = {colour.x, colour.y, colour.z};
  }
  return volume;
}

Json materialJson(const LightmappedAsset& a, double thicknessLocal) {
  const std::string name = a.materialName.empty() ? "baked" : a.materialName;
  return {{"name", name + " (baked translucency: emission, coat)"},
          {"pbrMetallicRoughness",
           {{"baseColorFactor", {0.0, 0.0, 0.0, 1.0}},
            {"metallicFactor", 0.0},
            {"roughnessFactor", 0.0}}},
          {"emissiveTexture", {{"index", 0}}},
          {"emissiveFactor", {1.0, 1.0, 1.0}},
          {"extensions",
           {{"KHR_materials_emissive_strength", {{"emissiveStrength", a.emissiveStrength}}},
            {"KHR_materials_clearcoat",
             {{"clearcoatFactor", a.coatWeight}, {"clearcoatRoughnessFactor", 0.0}}},
            {"KHR_materials_specular", {{"specularFactor", 0.0}}},
            {"KHR_materials_ior", {{"ior", a.eta}}},
            {"KHR_materials_transmission", {{"transmissionFactor", 0.0}}},
            {"KHR_materials_volume", volumeExtension(a, thicknessLocal)}}}};
}

// The scene: a node per source node (its world transform, scaled to metres), a mesh per node.
// Returns the number of nodes.
std::size_t addScene(const LightmappedAsset& a, GlbBinary& bin, Json& doc) {
  const double metresPerUnit = a.mmPerUnit / 1000.0;
  const glm::dmat4 toMetres = glm::dmat4(glm::dmat3(metresPerUnit));
  std::vector<NodeParts> nodes = groupByNode(a.parts);
  if (nodes.empty()) nodes.push_back({0, {0}});
  Json nodeList = Json::array(), meshList = Json::array(), roots = Json::array();
  for (const NodeParts& node : nodes) {
    const MeshPart* first = a.parts.parts.empty() ? nullptr : &a.parts.parts[node.parts[0]];
    const glm::dmat4 transform = first ? first->transform : glm::dmat4(1.0);
    Json primitives = Json::array();
    for (const std::size_t part : node.parts) {
      const PrimitiveData data = primitiveData(a, static_cast<std::uint32_t>(part), transform);
      if (data.triangles.empty()) continue;  // every triangle of the part was cleaned away
      primitives.push_back({{"attributes",
                             {{"POSITION", bin.addVec3(data.positions, true)},
                              {"NORMAL", bin.addVec3(data.normals, false)},
                              {"TEXCOORD_0", bin.addVec2(data.texcoords)}}},
                            {"indices", bin.addIndices(data.triangles)},
                            {"material", 0},
                            {"mode", kTriangles}});
    }
    if (primitives.empty()) continue;
    Json mesh = {{"primitives", primitives}};
    if (first && !first->mesh.empty()) mesh = {{"name", first->mesh}, {"primitives", primitives}};
    meshList.push_back(mesh);
    Json n = Json::object();
    if (first && !first->node.empty()) n["name"] = first->node;
    n["mesh"] = meshList.size() - 1;
    const glm::dmat4 world = toMetres * transform;
    if (world != glm::dmat4(1.0)) n["matrix"] = nodeMatrix(world);
    roots.push_back(nodeList.size());
    nodeList.push_back(n);
  }
  doc["scene"] = 0;
  doc["scenes"] = Json::array({{{"nodes", roots}}});
  doc["nodes"] = nodeList;
  doc["meshes"] = meshList;
  return nodeList.size();
}

// The node transforms' mean linear scale (metres per local unit), for the thickness.
double meanScale(const LightmappedAsset& a) {
  double sum = 0.0;
  for (const MeshPart& p : a.parts.parts)
    sum += std::cbrt(std::abs(glm::determinant(glm::dmat3(p.transform))));
  const double local = a.parts.parts.empty() ? 1.0 : sum / double(a.parts.parts.size());
  return local * a.mmPerUnit / 1000.0;
}

}  // namespace

void writeLightmappedGlb(const std::string& path, const LightmappedAsset& a) {
  if (a.parts.cornerTexcoords.size() != 3 * a.mesh.triangles.size()) {
    fail(path, "the lightmapped asset has no texture coordinate per triangle corner");
  }
  if (a.emissivePng.empty() || !(a.emissiveStrength > 0.0) || !std::isfinite(a.emissiveStrength)) {
    fail(path, "the lightmap is empty or not finite");
  }
  if (!(a.coatWeight >= 0.0 && a.coatWeight <= 1.0))
    fail(path, "the coat's weight is not in [0, 1]");
  GlbBinary bin;
  Json doc;
  try {
    doc["asset"] = {{"version", "2.0"},
                    {"generator", "sss-tools"},
                    {"extras", {{"sss", Json::parse(a.extrasJson.empty() ? "{}" : a.extrasJson)}}}};
    doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_clearcoat",
                             "KHR_materials_specular",          "KHR_materials_ior",
                             "KHR_materials_transmission",      "KHR_materials_volume"};
    if (addScene(a, bin, doc) == 0) fail(path, "no triangle to write");
    // Json::array: a braced list of one JSON value may be taken for a copy of it (compilers
    // differ), not an array holding it.
    doc["materials"] = Json::array({materialJson(a, a.thicknessM / meanScale(a))});
    doc["textures"] = Json::array({{{"sampler", 0}, {"source", 0}}});
    const int imageView = bin.addView(a.emissivePng.data(), a.emissivePng.size());
    doc["images"] = Json::array({{{"bufferView", imageView}, {"mimeType", "image/png"}}});
    doc["samplers"] = Json::array({{{"magFilter", kLinear},
                                    {"minFilter", kLinearMipmapLinear},
                                    {"wrapS", kClampToEdge},
                                    {"wrapT", kClampToEdge}}});
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("cannot encode the glTF JSON: ") + e.what());
  }
  writeFileAtomically(path, encodeGlb(path, std::move(doc), bin));
}

}  // namespace sss

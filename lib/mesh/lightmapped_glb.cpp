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
#include "core/format.h"
#include "mesh/glb_builder.h"

namespace sss {
namespace {

using Json = GlbBinary::Json;

constexpr int kTriangles = 4;
constexpr int kLinear = kGltfLinear, kLinearMipmapLinear = kGltfLinearMipmapLinear,
              kClampToEdge = kGltfClampToEdge;

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

// TANGENT for a normal map (glTF 2.0, 3.7.2.1: unit XYZ, W the sign that makes cross(N, T) W
// the bitangent): per vertex, the derivative of position along u, and along -v for the
// bitangent (the normal map's +Y is up in the image, where v grows downwards), summed over its
// triangles (Lengyel, "Computing Tangent Space Basis Vectors for an Arbitrary Mesh", 2001) and
// made orthogonal to the normal.
std::vector<glm::vec4> tangentsOf(const PrimitiveData& d) {
  std::vector<glm::dvec3> alongU(d.positions.size(), glm::dvec3(0.0)), up = alongU;
  for (const glm::uvec3& t : d.triangles) {
    const glm::dvec3 e1 = glm::dvec3(d.positions[t[1]] - d.positions[t[0]]);
    const glm::dvec3 e2 = glm::dvec3(d.positions[t[2]] - d.positions[t[0]]);
    const glm::dvec2 s1 = glm::dvec2(d.texcoords[t[1]] - d.texcoords[t[0]]);
    const glm::dvec2 s2 = glm::dvec2(d.texcoords[t[2]] - d.texcoords[t[0]]);
    const double det = s1.x * s2.y - s2.x * s1.y;
    if (std::abs(det) < 1e-20) continue;  // no texture-space area
    const glm::dvec3 dpdu = (e1 * s2.y - e2 * s1.y) / det;
    const glm::dvec3 dpdv = (e2 * s1.x - e1 * s2.x) / det;
    for (int c = 0; c < 3; ++c) {
      alongU[t[c]] += dpdu;
      up[t[c]] -= dpdv;
    }
  }
  std::vector<glm::vec4> out(d.positions.size());
  for (std::size_t v = 0; v < out.size(); ++v) {
    const glm::dvec3 n = glm::dvec3(d.normals[v]);
    glm::dvec3 t = alongU[v] - n * glm::dot(n, alongU[v]);
    if (glm::length(t) < 1e-12) {  // no texture-space derivative: any unit vector across n
      t = glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0));
    }
    t = glm::normalize(t);
    out[v] = glm::vec4(glm::vec3(t), glm::dot(glm::cross(n, t), up[v]) < 0.0 ? -1.0f : 1.0f);
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
Json volumeExtension(const LightmappedAsset::Medium& medium, double thicknessLocal) {
  const glm::dvec3 sa = medium.sigmaAPerMm;
  const glm::dvec3 sigmaTr = glm::sqrt(3.0 * sa * (sa + medium.sigmaSPrimePerMm));
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

// The written file's textures, samplers and images: texture, sampler and image 0 are the
// lightmap's; each kept source texture follows, its image and sampler written once.
class TextureTable {
 public:
  TextureTable(const LightmappedAsset& a, GlbBinary& bin) : asset_(a), bin_(bin) {
    samplers_.push_back({{"magFilter", kLinear},
                         {"minFilter", kLinearMipmapLinear},
                         {"wrapS", kClampToEdge},
                         {"wrapT", kClampToEdge}});
    const int view = bin.addView(a.emissivePng.data(), a.emissivePng.size());
    images_.push_back({{"bufferView", view}, {"mimeType", "image/png"}});
    textures_.push_back({{"sampler", 0}, {"source", 0}});
  }

  // A textureInfo for `t` (with `scaleKey`: its scale or strength, when not 1).
  Json info(const SurfaceTexture& t, const char* scaleKey = nullptr) {
    Json out = {{"index", texture(t)}};
    if (scaleKey && t.scale != 1.0) out[scaleKey] = t.scale;
    return out;
  }

  void write(Json& doc) const {
    doc["textures"] = textures_;
    doc["images"] = images_;
    doc["samplers"] = samplers_;
  }

 private:
  std::size_t texture(const SurfaceTexture& t) {
    Json sampler = {{"wrapS", t.wrapS}, {"wrapT", t.wrapT}};
    if (t.magFilter) sampler["magFilter"] = t.magFilter;
    if (t.minFilter) sampler["minFilter"] = t.minFilter;
    const Json tex = {{"sampler", indexOf(samplers_, sampler)}, {"source", image(t.image)}};
    return indexOf(textures_, tex);
  }

  std::size_t image(std::uint32_t i) {
    const auto it = imageIndex_.find(i);
    if (it != imageIndex_.end()) return it->second;
    const SurfaceImage& source = asset_.parts.surfaces.images.at(i);
    const int view = bin_.addView(source.bytes.data(), source.bytes.size());
    images_.push_back({{"bufferView", view}, {"mimeType", source.mimeType}});
    return imageIndex_[i] = images_.size() - 1;
  }

  static std::size_t indexOf(Json& list, const Json& value) {
    for (std::size_t k = 0; k < list.size(); ++k)
      if (list[k] == value) return k;
    list.push_back(value);
    return list.size() - 1;
  }

  const LightmappedAsset& asset_;
  GlbBinary& bin_;
  Json textures_ = Json::array(), samplers_ = Json::array(), images_ = Json::array();
  std::map<std::uint32_t, std::size_t> imageIndex_;
};

// The baked material on a source material's surface (surface_material.h): its roughness on the
// coat (the only layer that reflects) and the base, its normal map on both, its occlusion, and
// its alpha (with the base colour texture where alpha is drawn: the colour factor stays black).
void keepSurface(const SurfaceMaterial& s, TextureTable& textures, Json& m) {
  Json& pbr = m["pbrMetallicRoughness"];
  Json& coat = m["extensions"]["KHR_materials_clearcoat"];
  pbr["baseColorFactor"] = {0.0, 0.0, 0.0, s.alpha};
  pbr["roughnessFactor"] = s.roughness;
  coat["clearcoatRoughnessFactor"] = s.roughness;
  if (s.baseColor && s.alphaMode != "OPAQUE") pbr["baseColorTexture"] = textures.info(*s.baseColor);
  // Roughness is G in both textures (glTF 2.0 3.9.2; KHR_materials_clearcoat).
  if (s.roughnessMap) {
    pbr["metallicRoughnessTexture"] = textures.info(*s.roughnessMap);
    coat["clearcoatRoughnessTexture"] = textures.info(*s.roughnessMap);
  }
  if (s.normal) {
    m["normalTexture"] = textures.info(*s.normal, "scale");
    coat["clearcoatNormalTexture"] = textures.info(*s.normal, "scale");
  }
  if (s.occlusion) m["occlusionTexture"] = textures.info(*s.occlusion, "strength");
  if (s.alphaMode != "OPAQUE") m["alphaMode"] = s.alphaMode;
  if (s.alphaMode == "MASK") m["alphaCutoff"] = s.alphaCutoff;
  if (s.doubleSided) {
    // A double-sided surface bounds no volume (KHR_materials_volume), and the factor-0
    // transmission is there only for the volume.
    m["doubleSided"] = true;
    m["extensions"].erase("KHR_materials_volume");
    m["extensions"].erase("KHR_materials_transmission");
  }
}

// The material of the parts whose source material is `surface` (null: none).
Json materialJson(const LightmappedAsset& a, const LightmappedAsset::Medium& medium,
                  double thicknessLocal, const SurfaceMaterial* surface, TextureTable& textures) {
  const std::string name = surface && !surface->name.empty() ? surface->name
                           : medium.name.empty()             ? "baked"
                                                             : medium.name;
  Json m = {{"name", name + " (baked translucency: emission, coat)"},
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
              {"KHR_materials_volume", volumeExtension(medium, thicknessLocal)}}}};
  if (surface) keepSurface(*surface, textures, m);
  return m;
}

// The written materials: one per source material the parts use (in order of first use), one for
// the parts without; each part's index among them.
struct MaterialSlots {
  std::vector<std::int64_t> source;  // per written material: its source material, -1: none
  std::vector<std::size_t> ofPart;
};

MaterialSlots materialSlots(const LightmappedAsset& a) {
  MaterialSlots slots;
  const std::size_t sources = a.parts.surfaces.materials.size();
  for (const MeshPart& p : a.parts.parts) {
    const std::int64_t m =
        p.materialIndex >= 0 && std::size_t(p.materialIndex) < sources ? p.materialIndex : -1;
    const auto it = std::find(slots.source.begin(), slots.source.end(), m);
    slots.ofPart.push_back(std::size_t(it - slots.source.begin()));
    if (it == slots.source.end()) slots.source.push_back(m);
  }
  if (slots.source.empty()) slots.source.push_back(-1);
  return slots;
}

// The medium of the parts a written material draws: the asset's, or (partMedia) its first
// part's; the parts of one source material have one medium (the material map is keyed by it).
LightmappedAsset::Medium mediumOfSlot(const LightmappedAsset& a, const MaterialSlots& slots,
                                      std::size_t slot) {
  for (std::size_t p = 0; p < a.partMedia.size() && p < slots.ofPart.size(); ++p)
    if (slots.ofPart[p] == slot) return a.partMedia[p];
  return a.medium;
}

// The scene: a node per source node (its world transform, scaled to metres), a mesh per node.
// Returns the number of nodes.
std::size_t addScene(const LightmappedAsset& a, const MaterialSlots& slots, GlbBinary& bin,
                     Json& doc) {
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
      const std::size_t material = a.parts.parts.empty() ? 0 : slots.ofPart[part];
      Json attributes = {{"POSITION", bin.addVec3(data.positions, true)},
                         {"NORMAL", bin.addVec3(data.normals, false)},
                         {"TEXCOORD_0", bin.addVec2(data.texcoords)}};
      const std::int64_t source = slots.source[material];
      if (source >= 0 && a.parts.surfaces.materials[source].normal)
        attributes["TANGENT"] = bin.addVec4(tangentsOf(data));
      primitives.push_back({{"attributes", attributes},
                            {"indices", bin.addIndices(data.triangles)},
                            {"material", material},
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
    doc["extensionsUsed"] = Json::array();  // filled below, after the materials
    const MaterialSlots slots = materialSlots(a);
    if (addScene(a, slots, bin, doc) == 0) fail(path, "no triangle to write");
    TextureTable textures(a, bin);
    const double thicknessLocal = a.thicknessM / meanScale(a);
    Json materials = Json::array();
    for (std::size_t slot = 0; slot < slots.source.size(); ++slot) {
      const std::int64_t m = slots.source[slot];
      const SurfaceMaterial* surface = m >= 0 ? &a.parts.surfaces.materials[m] : nullptr;
      materials.push_back(
          materialJson(a, mediumOfSlot(a, slots, slot), thicknessLocal, surface, textures));
    }
    for (const Json& m : materials)
      for (const auto& [name, value] : m["extensions"].items())
        if (std::find(doc["extensionsUsed"].begin(), doc["extensionsUsed"].end(), name) ==
            doc["extensionsUsed"].end())
          doc["extensionsUsed"].push_back(name);
    doc["materials"] = materials;
    textures.write(doc);
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("cannot encode the glTF JSON: ") + e.what());
  }
  writeFileAtomically(path, encodeGlb(path, std::move(doc), bin));
}

std::vector<std::string> droppedSurfaceNotes(const LightmappedAsset& a) {
  std::vector<std::string> notes;
  for (const std::int64_t m : materialSlots(a).source) {
    if (m < 0) continue;
    const SurfaceMaterial& s = a.parts.surfaces.materials[m];
    const std::string name = s.name.empty() ? format("#%.0f", double(m)) : s.name;
    for (const std::string& d : s.dropped)
      notes.push_back("material '" + name + "': " + d + " not kept");
  }
  return notes;
}

}  // namespace sss

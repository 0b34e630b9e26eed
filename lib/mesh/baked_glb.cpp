#include "mesh/baked_glb.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/tool.h"
#include "mesh/glb_builder.h"
#include "mesh/glb_chunks.h"
#include "mesh/gltf_document.h"
#include "mesh/quantized_transfer.h"
#include "optics/exit_lobe.h"
#include "optics/fresnel.h"

namespace sss {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the GLB reader copies little-endian bytes");

using Json = nlohmann::ordered_json;

// 2: a relightable bake's transfer quantized (quantized_transfer.h), float scales and an attribute
// per coefficient; 3: from order 4, its bands from 4 in 8 bits with _TRANSFER_SCALE_HIGH; 4: the
// scales as exponents and the steps packed four to an attribute (addRelightAttributes). Other
// bakes are written as 1, relightable bakes as 4.
constexpr int kGlbFormatVersion = 4;
constexpr int kHighBandsGlbVersion = 3;
using gltf::kByte, gltf::kFloat, gltf::kShort, gltf::kUnsignedByte, gltf::kUnsignedInt,
    gltf::kUnsignedShort;
constexpr int kTriangles = 4;

// ---------------------------------------------------------------- writing

// COLOR_0 and how it was made (extras.sss.color).
struct DisplayColors {
  std::vector<glm::vec3> colors;
  Json description;
};

// exposure * the radiance sss-render draws along the normal under its default exit model: B F_t(1,
// eta) / (pi (1 - 2 C_1(eta))) (shaders/surface.vert, normalized), with a traced far field B
// through the exit lobe its exits measured instead (optics/exit_lobe.h; slope 0 is the same).
DisplayColors displayColors(const std::string& path, const BakedMesh& baked) {
  const float eta = static_cast<float>(baked.eta);
  const double radiancePerExitance = normalExitRadianceScale(eta);
  const double exposure = previewScaleFor(baked);
  const double scale = exposure * radiancePerExitance;
  const ExitLobe lobe(eta);
  DisplayColors out;
  std::size_t clamped = 0;
  float peak = 0.0f;
  out.colors.reserve(baked.exitance.size());
  for (std::size_t i = 0; i < baked.exitance.size(); ++i) {
    glm::dvec3 radiance = radiancePerExitance * glm::dvec3(baked.exitance[i]);
    if (!baked.exitSlope.empty())
      radiance = glm::dvec3(baked.exitance[i]) * lobe.normalRadiance(baked.exitSlope[i]);
    const glm::vec3 c = glm::vec3(exposure * radiance);
    const float high = std::max({c.x, c.y, c.z});
    peak = std::max(peak, high);
    clamped += high > 1.0f;
    out.colors.push_back(glm::clamp(c, 0.0f, 1.0f));
  }
  if (clamped > 0) {
    warn(path + ": COLOR_0 clamped to 1 at " + std::to_string(clamped) + " of " +
         std::to_string(baked.exitance.size()) + " vertices (up to " + std::to_string(peak) +
         " under the exposure " + std::to_string(exposure) + "); _EXITANCE holds them unclamped");
  }
  out.description = {{"exposure", exposure},
                     {"exit_model", baked.exitSlope.empty() ? "normalized" : "auto"},
                     {"radiance_per_exitance", radiancePerExitance},
                     {"scale", scale},
                     {"clamped_vertices", clamped}};
  return out;
}

Json sssExtras(const BakedMesh& baked, const Json& color, const std::string& reportJson) {
  const int format = baked.relightOrder < 0 ? 1 : kGlbFormatVersion;
  Json sss = {{"format", format}, {"position_unit", "m"}, {"mm_per_unit", baked.mmPerUnit}};
  if (!baked.materialName.empty()) {
    const glm::dvec3 &a = baked.sigmaA, &s = baked.sigmaSPrime;
    sss["material"] = {{"name", baked.materialName},
                       {"sigma_a_per_mm", {a.x, a.y, a.z}},
                       {"sigma_s_prime_per_mm", {s.x, s.y, s.z}},
                       {"eta", baked.eta}};
  }
  if (!color.is_null()) sss["color"] = color;
  if (baked.relightOrder >= 0)
    sss["relight"] = {{"order", baked.relightOrder}, {"transport", baked.relightTransport}};
  sss["checked"] = baked.meshChecked;
  sss["unscattered"] = baked.unscatteredTraced;
  sss["comments"] = baked.extraComments;
  if (!reportJson.empty()) sss["report"] = Json::parse(reportJson);
  return sss;
}

// The steps of coefficients [first, last) (quantized_transfer.h) as one list per vertex, entry
// i = 3 (k - first) + c, four entries to a normalized VEC4 attribute: entry i is component i % 4
// of <prefix><i / 4>, the last attribute padded with zeros. Packed, not one VEC3 per coefficient:
// a vertex attribute's elements are 4-byte aligned, which would pad every VEC3.
std::size_t packedTransferAttributes(std::size_t first, std::size_t last) {
  return (3 * (last - first) + 3) / 4;
}

void addPackedTransfer(GlbBinary& bin, const QuantizedTransfer& transfer, std::size_t count,
                       std::size_t first, std::size_t last, const std::string& prefix,
                       int componentType, Json& attributes) {
  const std::size_t n = transfer.values.size() / count, entries = 3 * (last - first);
  for (std::size_t j = 0; j < packedTransferAttributes(first, last); ++j) {
    std::vector<int16_t> components(4 * n, 0);
    for (std::size_t v = 0; v < n; ++v)
      for (std::size_t i = 4 * j; i < std::min(4 * j + 4, entries); ++i)
        components[4 * v + i % 4] = transfer.values[v * count + first + i / 3][i % 3];
    attributes[prefix + std::to_string(j)] = bin.addIntegerVec4(components, componentType, true);
  }
}

// Scales as their exponents (scaleExponent): a BYTE VEC4 (r, g, b, 0) per vertex, 4 bytes where
// a float VEC3 takes 12.
int addScaleExponents(GlbBinary& bin, const std::vector<glm::vec3>& scales, float normalizer) {
  std::vector<int16_t> exponents(scales.size() * 4, 0);
  for (std::size_t v = 0; v < scales.size(); ++v)
    for (int c = 0; c < 3; ++c)
      exponents[4 * v + c] = int16_t(scaleExponent(scales[v][c], normalizer));
  return bin.addIntegerVec4(exponents, kByte, false);
}

// The bounces' gather rays that met the front of a surface (BakedMesh::gatherFrontHits): four
// 16-bit words to an UNSIGNED_SHORT VEC4 _GATHER_HITS_<j>.
void addFrontHits(GlbBinary& bin, const BakedMesh& baked, Json& attributes) {
  const std::size_t words = baked.gatherFrontHitWords(), n = baked.mesh.positions.size();
  for (std::size_t j = 0; j < words / 4; ++j) {
    std::vector<int16_t> components(4 * n);
    for (std::size_t v = 0; v < n; ++v)
      for (std::size_t c = 0; c < 4; ++c)
        components[4 * v + c] =
            std::bit_cast<int16_t>(baked.gatherFrontHits[v * words + 4 * j + c]);
    attributes["_GATHER_HITS_" + std::to_string(j)] =
        bin.addIntegerVec4(components, kUnsignedShort, false);
  }
}

// A relightable bake's per-vertex values as custom attributes: the steps of bands 0-3 as
// normalized SHORT _TRANSFER_LOW_<j> (addPackedTransfer) with their scales' exponents
// _TRANSFER_EXPONENT and, at orders 4-8, those of bands 4 and up as normalized BYTE
// _TRANSFER_HIGH_<j> with _TRANSFER_EXPONENT_HIGH; _RADIANCE_GAIN, _EXITANCE_PER_RADIANCE and,
// with the escape model, _ESCAPE_PROBABILITY, and with bounces _GATHER_HITS_<j> (addFrontHits).
// The order and the transport key go to extras.sss.relight.
void addRelightAttributes(const std::string& path, GlbBinary& bin, const BakedMesh& baked,
                          Json& attributes) {
  const std::size_t count = baked.relightCount();
  const std::size_t low = std::min(count, kShortTransferCoefficients);
  const QuantizedTransfer transfer = quantizeTransfer(path, baked.relightTransfer, count);
  attributes["_TRANSFER_EXPONENT"] = addScaleExponents(bin, transfer.scale, kTransferNormalizer);
  addPackedTransfer(bin, transfer, count, 0, low, "_TRANSFER_LOW_", kShort, attributes);
  if (!transfer.scaleHigh.empty()) {
    attributes["_TRANSFER_EXPONENT_HIGH"] =
        addScaleExponents(bin, transfer.scaleHigh, kHighTransferNormalizer);
    addPackedTransfer(bin, transfer, count, low, count, "_TRANSFER_HIGH_", kByte, attributes);
  }
  attributes["_RADIANCE_GAIN"] = bin.addVec3(baked.radianceGain, false);
  attributes["_EXITANCE_PER_RADIANCE"] = bin.addVec3(baked.exitancePerRadiance, false);
  if (!baked.escapeProbability.empty())
    attributes["_ESCAPE_PROBABILITY"] = bin.addVec3(baked.escapeProbability, false);
  addFrontHits(bin, baked, attributes);
}

// The glTF JSON for the primitive whose attributes `bin` holds.
Json gltfDocument(const std::string& path, const BakedMesh& baked, GlbBinary& bin,
                  const DisplayColors& colors, const std::string& reportJson) {
  const double metresPerUnit = baked.mmPerUnit / 1000.0;
  std::vector<glm::vec3> metres;
  metres.reserve(baked.mesh.positions.size());
  for (const glm::vec3& p : baked.mesh.positions)
    metres.push_back(glm::vec3(glm::dvec3(p) * metresPerUnit));
  Json attributes = {{"POSITION", bin.addVec3(metres, true)},
                     {"NORMAL", bin.addVec3(baked.mesh.normals, false)}};
  if (!baked.exitance.empty()) attributes["COLOR_0"] = bin.addVec3(colors.colors, false);
  if (!baked.irradiance.empty()) attributes["_IRRADIANCE"] = bin.addVec3(baked.irradiance, false);
  if (!baked.exitance.empty()) attributes["_EXITANCE"] = bin.addVec3(baked.exitance, false);
  if (baked.relightOrder >= 0) addRelightAttributes(path, bin, baked, attributes);
  if (!baked.farExitance.empty())
    attributes["_FAR_EXITANCE"] = bin.addVec3(baked.farExitance, false);
  if (!baked.exitSlope.empty()) attributes["_EXIT_SLOPE"] = bin.addVec3(baked.exitSlope, false);
  const int indices = bin.addIndices(baked.mesh.triangles);
  const std::string name = baked.materialName.empty() ? "baked" : baked.materialName;
  return {{"asset",
           {{"version", "2.0"},
            {"generator", "sss-tools"},
            {"extras", {{"sss", sssExtras(baked, colors.description, reportJson)}}}}},
          {"extensionsUsed", {"KHR_materials_unlit"}},
          {"scene", 0},
          {"scenes", {{{"nodes", {0}}}}},
          {"nodes", {{{"mesh", 0}, {"name", name}}}},
          {"meshes",
           {{{"name", name},
             {"primitives",
              {{{"attributes", attributes},
                {"indices", indices},
                {"material", 0},
                {"mode", kTriangles}}}}}}},
          {"materials",
           {{{"name", name + " (baked radiance, vertex colour)"},
             {"pbrMetallicRoughness",
              {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}},
               {"metallicFactor", 0.0},
               {"roughnessFactor", 1.0}}},
             {"extensions", {{"KHR_materials_unlit", Json::object()}}}}}}};
}

}  // namespace

void writeBakedGlb(const std::string& path, const BakedMesh& baked, const std::string& reportJson) {
  checkBakedMesh(path, baked);
  DisplayColors colors;
  if (!baked.exitance.empty()) colors = displayColors(path, baked);
  GlbBinary bin;
  Json document;
  try {
    document = gltfDocument(path, baked, bin, colors, reportJson);
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("cannot encode the glTF JSON: ") + e.what());
  }
  writeFileAtomically(path, encodeGlb(path, std::move(document), bin));
}

// ---------------------------------------------------------------- reading

namespace {

// A non-negative integer member (required unless `fallback` is given).
std::uint64_t index(const std::string& path, const Json& object, const char* key,
                    std::optional<std::uint64_t> fallback = std::nullopt) {
  const auto it = object.find(key);
  if (it == object.end()) {
    if (fallback) return *fallback;
    fail(path, std::string("glTF: missing \"") + key + "\"");
  }
  if (!it->is_number_unsigned()) fail(path, std::string("glTF: \"") + key + "\" is not an index");
  return it->get<std::uint64_t>();
}

const Json& element(const std::string& path, const Json& document, const char* array,
                    std::uint64_t i) {
  const auto it = document.find(array);
  if (it == document.end() || !it->is_array() || i >= it->size()) {
    fail(path, std::string("glTF: ") + array + "[" + std::to_string(i) + "] does not exist");
  }
  const Json& e = (*it)[i];
  if (!e.is_object()) fail(path, std::string("glTF: ") + array + " holds a non-object");
  return e;
}

// Where an accessor's elements lie in the BIN chunk, checked against its bufferView and buffer.
struct AccessorSpan {
  const char* data = nullptr;
  std::uint64_t count = 0, stride = 0, componentType = 0;
};

// The components of an accessor element of `type` ("SCALAR", "VEC3" or "VEC4").
std::size_t componentsOf(const char* type) {
  const std::string t = type;
  return t == "VEC4" ? 4 : t == "VEC3" ? 3 : 1;
}

AccessorSpan accessorSpan(const std::string& path, const Json& document, const std::string& bin,
                          std::uint64_t accessorIndex, const char* type, const char* what) {
  const Json& accessor = element(path, document, "accessors", accessorIndex);
  const std::string where = std::string("glTF: the ") + what + " accessor";
  if (accessor.contains("sparse")) fail(path, where + " is sparse (not supported)");
  if (accessor.value("type", "") != type) fail(path, where + " is not " + type);
  AccessorSpan span;
  span.componentType = index(path, accessor, "componentType");
  const std::uint64_t componentSize = span.componentType == kFloat           ? 4
                                      : span.componentType == kUnsignedInt   ? 4
                                      : span.componentType == kUnsignedShort ? 2
                                      : span.componentType == kShort         ? 2
                                      : span.componentType == kUnsignedByte  ? 1
                                      : span.componentType == kByte          ? 1
                                                                             : 0;
  if (componentSize == 0) fail(path, where + " has an unsupported componentType");
  const std::uint64_t elementSize = componentSize * componentsOf(type);
  span.count = index(path, accessor, "count");
  if (span.count == 0) fail(path, where + " is empty");
  const Json& view = element(path, document, "bufferViews", index(path, accessor, "bufferView"));
  if (index(path, view, "buffer") != 0) fail(path, where + " is not in the GLB's buffer");
  const std::uint64_t viewOffset = index(path, view, "byteOffset", 0);
  const std::uint64_t viewLength = index(path, view, "byteLength");
  span.stride = index(path, view, "byteStride", elementSize);
  const std::uint64_t offset = index(path, accessor, "byteOffset", 0);
  if (span.stride < elementSize || span.stride > 252) fail(path, where + ": bad byteStride");
  // Overflow-free: every term is below 2^32 except the product, bounded by the division.
  if (viewOffset > bin.size() || viewLength > bin.size() - viewOffset || offset > viewLength ||
      elementSize > viewLength - offset ||
      span.count - 1 > (viewLength - offset - elementSize) / span.stride) {
    fail(path, where + " (" + std::to_string(span.count) + " elements) overruns its buffer");
  }
  span.data = bin.data() + viewOffset + offset;
  return span;
}

std::vector<glm::vec3> readVec3(const std::string& path, const Json& document,
                                const std::string& bin, std::uint64_t accessor, const char* what) {
  const AccessorSpan span = accessorSpan(path, document, bin, accessor, "VEC3", what);
  if (span.componentType != kFloat) fail(path, std::string("glTF: ") + what + " is not float");
  std::vector<glm::vec3> values(span.count);
  for (std::uint64_t i = 0; i < span.count; ++i)
    std::memcpy(&values[i], span.data + i * span.stride, 12);
  return values;
}

// The integers of a BYTE, SHORT or UNSIGNED_SHORT (its 16 bits) accessor of `type` VEC3 or
// VEC4, `normalized` or not, its elements' components in a row: what addIntegerVec4 writes.
std::vector<int16_t> readIntegers(const std::string& path, const Json& document,
                                  const std::string& bin, std::uint64_t accessor,
                                  const std::string& what, const char* type, int componentType,
                                  bool normalized) {
  const AccessorSpan span = accessorSpan(path, document, bin, accessor, type, what.c_str());
  const Json& a = element(path, document, "accessors", accessor);
  const Json normalizedFlag = a.value("normalized", Json(false));
  const bool byte = componentType == kByte;
  if (span.componentType != std::uint64_t(componentType) || normalizedFlag != Json(normalized))
    fail(path, "glTF: " + what + " is not " + (normalized ? "normalized " : "") +
                   (byte                      ? "BYTE"
                    : componentType == kShort ? "SHORT"
                                              : "UNSIGNED_SHORT"));
  const std::size_t components = componentsOf(type);
  std::vector<int16_t> values(span.count * components);
  for (std::uint64_t i = 0; i < span.count; ++i) {
    const char* p = span.data + i * span.stride;
    for (std::size_t c = 0; c < components; ++c) {
      if (byte) {
        values[i * components + c] = static_cast<int8_t>(p[c]);
      } else {
        std::memcpy(&values[i * components + c], p + 2 * c, 2);
      }
    }
  }
  return values;
}

std::vector<unsigned> readIndices(const std::string& path, const Json& document,
                                  const std::string& bin, std::uint64_t accessor) {
  const AccessorSpan span = accessorSpan(path, document, bin, accessor, "SCALAR", "indices");
  if (span.componentType == kFloat) fail(path, "glTF: the indices are float");
  std::vector<unsigned> indices(span.count);
  for (std::uint64_t i = 0; i < span.count; ++i) {
    const char* p = span.data + i * span.stride;
    if (span.componentType == kUnsignedInt) {
      indices[i] = readU32(p);
    } else if (span.componentType == kUnsignedShort) {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      indices[i] = v;
    } else {
      indices[i] = static_cast<unsigned char>(*p);
    }
  }
  return indices;
}

glm::dvec3 readTriple(const std::string& path, const Json& material, const char* key) {
  const Json& t = material.at(key);
  if (!t.is_array() || t.size() != 3) fail(path, std::string("glTF extras: bad ") + key);
  return {t[0].get<double>(), t[1].get<double>(), t[2].get<double>()};
}

// extras.sss into contents (the material, exposure, flags, comments).
void readSssExtras(const std::string& path, const Json& sss, BakedPlyContents& contents) {
  BakedMesh& baked = contents.baked;
  if (!sss.is_object()) fail(path, "glTF extras: \"sss\" is not an object");
  if (sss.value("format", 0) > kGlbFormatVersion) {
    fail(path, "baked GLB format " + sss["format"].dump() + " is newer than this program reads");
  }
  if (const auto m = sss.find("material"); m != sss.end()) {
    baked.materialName = m->at("name").get<std::string>();
    baked.sigmaA = readTriple(path, *m, "sigma_a_per_mm");
    baked.sigmaSPrime = readTriple(path, *m, "sigma_s_prime_per_mm");
    baked.eta = m->at("eta").get<double>();
    contents.hasMaterial = true;
  }
  if (const auto c = sss.find("color"); c != sss.end()) {
    baked.previewScale = c->at("exposure").get<double>();
  }
  if (const auto r = sss.find("relight"); r != sss.end()) {
    const int order = r->at("order").get<int>();
    if (order < 0 || order > kMaxStoredRelightOrder) fail(path, "glTF extras: bad relight order");
    baked.relightOrder = order;
    baked.relightTransport = r->at("transport").get<std::string>();
    contents.hasRelight = true;
  }
  baked.meshChecked = sss.value("checked", false);
  baked.unscatteredTraced = sss.value("unscattered", false);
  if (const auto c = sss.find("comments"); c != sss.end()) {
    baked.extraComments = c->get<std::vector<std::string>>();
  }
}

// Where a relightable bake's attributes are: the file, its JSON and BIN chunk, the primitive's
// attributes, and the vertex and coefficient counts.
struct RelightAttributeSource {
  const std::string& path;
  const Json& document;
  const std::string& bin;
  const Json& attributes;
  std::size_t vertices = 0, count = 0;

  std::uint64_t accessor(const std::string& name) const {
    if (!attributes.contains(name)) fail(path, "glTF: a relightable bake without " + name);
    return index(path, attributes, name.c_str());
  }
  std::vector<glm::vec3> vec3(const std::string& name) const {
    std::vector<glm::vec3> values = readVec3(path, document, bin, accessor(name), name.c_str());
    if (values.size() != vertices) fail(path, "glTF: the attributes have different counts");
    return values;
  }
  std::vector<int16_t> integers(const std::string& name, const char* type, int componentType,
                                bool normalized = true) const {
    std::vector<int16_t> values =
        readIntegers(path, document, bin, accessor(name), name, type, componentType, normalized);
    if (values.size() != vertices * componentsOf(type))
      fail(path, "glTF: the attributes have different counts");
    return values;
  }
  // _GATHER_HITS_0, _1, ... (addFrontHits) at [vertex * words + w]; empty where there are none.
  std::vector<uint16_t> frontHits() const {
    std::vector<std::vector<int16_t>> groups;
    for (std::string name = "_GATHER_HITS_0"; attributes.contains(name);
         name = "_GATHER_HITS_" + std::to_string(groups.size()))
      groups.push_back(integers(name, "VEC4", kUnsignedShort, false));
    const std::size_t words = 4 * groups.size();
    std::vector<uint16_t> hits(vertices * words);
    for (std::size_t j = 0; j < groups.size(); ++j)
      for (std::size_t v = 0; v < vertices; ++v)
        for (std::size_t c = 0; c < 4; ++c)
          hits[v * words + 4 * j + c] = std::bit_cast<uint16_t>(groups[j][4 * v + c]);
    return hits;
  }
  void checkStep(const std::string& name, int16_t q, int limit) const {
    if (q < -limit || q > limit)
      fail(path, "glTF: " + name + " has a step count beyond " + std::to_string(limit));
  }
};

// Formats 2 and 3: a normalized VEC3 _TRANSFER_<k> per coefficient (BYTE from k = 16 with
// `high`).
void readTransferPerCoefficient(const RelightAttributeSource& in, bool high,
                                QuantizedTransfer& transfer) {
  for (std::size_t k = 0; k < in.count; ++k) {
    const std::string name = "_TRANSFER_" + std::to_string(k);
    const bool byte = high && k >= kShortTransferCoefficients;
    const std::vector<int16_t> steps = in.integers(name, "VEC3", byte ? kByte : kShort);
    for (std::size_t v = 0; v < in.vertices; ++v) {
      for (int c = 0; c < 3; ++c) {
        in.checkStep(name, steps[3 * v + c], transferStepLimit(k, high));
        transfer.values[v * in.count + k][c] = steps[3 * v + c];
      }
    }
  }
}

// Format 4: scales as exponents (addScaleExponents); the fourth component must be zero.
std::vector<glm::vec3> readScaleExponents(const RelightAttributeSource& in, const std::string& name,
                                          float normalizer) {
  const std::vector<int16_t> exponents = in.integers(name, "VEC4", kByte, false);
  std::vector<glm::vec3> scales(in.vertices);
  for (std::size_t v = 0; v < in.vertices; ++v) {
    if (exponents[4 * v + 3] != 0)
      fail(in.path, "glTF: " + name + " has a non-zero fourth component");
    for (int c = 0; c < 3; ++c)
      scales[v][c] = scaleOfExponent(in.path, exponents[4 * v + c], normalizer);
  }
  return scales;
}

// Format 4: coefficients [first, last) packed in <prefix><j> (addPackedTransfer); the padding
// must be zero.
void readPackedTransfer(const RelightAttributeSource& in, std::size_t first, std::size_t last,
                        const std::string& prefix, bool byte, QuantizedTransfer& transfer) {
  const std::size_t entries = 3 * (last - first);
  const int limit = transferStepLimit(first, byte);
  for (std::size_t j = 0; j < packedTransferAttributes(first, last); ++j) {
    const std::string name = prefix + std::to_string(j);
    const std::vector<int16_t> steps = in.integers(name, "VEC4", byte ? kByte : kShort);
    for (std::size_t v = 0; v < in.vertices; ++v) {
      for (std::size_t i = 4 * j; i < 4 * j + 4; ++i) {
        const int16_t q = steps[4 * v + i % 4];
        if (i >= entries) {
          if (q != 0) fail(in.path, "glTF: " + name + " has a non-zero padding component");
          continue;
        }
        in.checkStep(name, q, limit);
        transfer.values[v * in.count + first + i / 3][i % 3] = q;
      }
    }
  }
}

// Whether the file holds a high bands' scale, `present`, where it must: from format 3 at orders
// above 3.
void checkHighScale(const RelightAttributeSource& in, bool present, int format, int order,
                    const char* name) {
  if (present != (format >= kHighBandsGlbVersion && hasHighBands(in.count)))
    fail(in.path, present
                      ? std::string("glTF: ") + name + " in a format " + std::to_string(format) +
                            " bake of order " + std::to_string(order)
                      : std::string("glTF: a relightable bake of order above 3 without ") + name);
}

// Formats 2 and 3: float scales and one normalized VEC3 per coefficient.
std::vector<glm::vec3> readQuantizedVec3Transfer(const RelightAttributeSource& in, int format,
                                                 int order) {
  QuantizedTransfer transfer;
  transfer.scale = in.vec3("_TRANSFER_SCALE");
  checkTransferScales(in.path, transfer.scale);
  const bool high = in.attributes.contains("_TRANSFER_SCALE_HIGH");
  checkHighScale(in, high, format, order, "_TRANSFER_SCALE_HIGH");
  if (high) {
    transfer.scaleHigh = in.vec3("_TRANSFER_SCALE_HIGH");
    checkTransferScales(in.path, transfer.scaleHigh);
  }
  transfer.values.resize(in.vertices * in.count);
  readTransferPerCoefficient(in, high, transfer);
  return dequantizeTransfer(transfer, in.count);
}

// Format 4: exponents and packed steps (addRelightAttributes).
std::vector<glm::vec3> readPackedTransferAttributes(const RelightAttributeSource& in, int format,
                                                    int order) {
  QuantizedTransfer transfer;
  transfer.scale = readScaleExponents(in, "_TRANSFER_EXPONENT", kTransferNormalizer);
  const bool high = in.attributes.contains("_TRANSFER_EXPONENT_HIGH");
  checkHighScale(in, high, format, order, "_TRANSFER_EXPONENT_HIGH");
  const std::size_t low = std::min(in.count, kShortTransferCoefficients);
  transfer.values.resize(in.vertices * in.count);
  readPackedTransfer(in, 0, low, "_TRANSFER_LOW_", false, transfer);
  if (high) {
    transfer.scaleHigh = readScaleExponents(in, "_TRANSFER_EXPONENT_HIGH", kHighTransferNormalizer);
    readPackedTransfer(in, low, in.count, "_TRANSFER_HIGH_", true, transfer);
  }
  return dequantizeTransfer(transfer, in.count);
}

// A relightable bake's attributes (addRelightAttributes; formats 1-3 as written before), every
// one of them with extras.sss.relight.
void readRelightAttributes(const RelightAttributeSource& in, int format, int order,
                           BakedVertexValues& values) {
  values.radianceGain = in.vec3("_RADIANCE_GAIN");
  values.exitancePerRadiance = in.vec3("_EXITANCE_PER_RADIANCE");
  if (in.attributes.contains("_ESCAPE_PROBABILITY"))
    values.escapeProbability = in.vec3("_ESCAPE_PROBABILITY");
  values.gatherFrontHits = in.frontHits();
  if (format >= kGlbFormatVersion) {
    values.relightTransfer = readPackedTransferAttributes(in, format, order);
  } else if (in.attributes.contains("_TRANSFER_SCALE")) {
    values.relightTransfer = readQuantizedVec3Transfer(in, format, order);
  } else {  // floats, as written before the quantized form
    values.relightTransfer.resize(in.vertices * in.count);
    for (std::size_t k = 0; k < in.count; ++k) {
      const std::vector<glm::vec3> channel = in.vec3("_TRANSFER_" + std::to_string(k));
      for (std::size_t v = 0; v < in.vertices; ++v)
        values.relightTransfer[v * in.count + k] = channel[v];
    }
  }
}

}  // namespace

BakedPlyContents readBakedGlb(const std::string& path) {
  const GlbChunks chunks = readGlbChunks(path);
  BakedPlyContents contents;
  BakedMesh& baked = contents.baked;
  RawMesh raw;
  BakedVertexValues values;
  try {
    const Json document = Json::parse(chunks.json);
    if (!document.is_object()) fail(path, "glTF: the JSON chunk is not an object");
    const auto meshes = document.find("meshes");
    if (meshes == document.end() || !meshes->is_array() || meshes->size() != 1 ||
        !(*meshes)[0].is_object() || !(*meshes)[0].contains("primitives") ||
        !(*meshes)[0]["primitives"].is_array() || (*meshes)[0]["primitives"].size() != 1) {
      fail(path, "glTF: not one mesh with one primitive (what sss-bake writes)");
    }
    const Json& primitive = (*meshes)[0]["primitives"][0];
    if (!primitive.is_object() || index(path, primitive, "mode", kTriangles) != kTriangles) {
      fail(path, "glTF: the primitive is not triangles");
    }
    const Json& attributes = primitive.at("attributes");
    const std::string& bin = chunks.bin;
    raw.positions = readVec3(path, document, bin, index(path, attributes, "POSITION"), "POSITION");
    raw.normals = readVec3(path, document, bin, index(path, attributes, "NORMAL"), "NORMAL");
    if (attributes.contains("_IRRADIANCE")) {
      values.irradiance =
          readVec3(path, document, bin, index(path, attributes, "_IRRADIANCE"), "_IRRADIANCE");
      contents.hasIrradiance = true;
    }
    if (attributes.contains("_EXITANCE")) {
      values.exitance =
          readVec3(path, document, bin, index(path, attributes, "_EXITANCE"), "_EXITANCE");
      contents.hasExitance = true;
    }
    // _FAR_EXIT_SLOPE: the name before the escape walks measured a lobe too.
    const char* slopeName =
        attributes.contains("_FAR_EXIT_SLOPE") ? "_FAR_EXIT_SLOPE" : "_EXIT_SLOPE";
    contents.hasFarField = attributes.contains("_FAR_EXITANCE");
    contents.hasExitSlope = attributes.contains(slopeName);
    if (contents.hasFarField && !contents.hasExitSlope)
      fail(path, "glTF: _FAR_EXITANCE without _EXIT_SLOPE");
    if (contents.hasFarField)
      values.farExitance =
          readVec3(path, document, bin, index(path, attributes, "_FAR_EXITANCE"), "_FAR_EXITANCE");
    if (contents.hasExitSlope)
      values.exitSlope =
          readVec3(path, document, bin, index(path, attributes, slopeName), slopeName);
    raw.faceCorners = readIndices(path, document, bin, index(path, primitive, "indices"));
    const auto extras = document.at("asset").find("extras");
    int format = 0;
    if (extras != document["asset"].end() && extras->contains("sss")) {
      const Json& sss = extras->at("sss");
      readSssExtras(path, sss, contents);
      format = sss.value("format", 0);
    }
    if (contents.hasRelight) {
      const RelightAttributeSource source{.path = path,
                                          .document = document,
                                          .bin = bin,
                                          .attributes = attributes,
                                          .vertices = raw.positions.size(),
                                          .count = std::size_t(baked.relightCount())};
      readRelightAttributes(source, format, baked.relightOrder, values);
    }
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("glTF JSON: ") + e.what());
  }
  const std::size_t n = raw.positions.size();
  for (const auto* set :
       {&raw.normals, &values.irradiance, &values.exitance, &values.farExitance, &values.exitSlope,
        &values.radianceGain, &values.exitancePerRadiance, &values.escapeProbability}) {
    if (!set->empty() && set->size() != n) {
      fail(path, "glTF: the attributes have different counts");
    }
  }
  if (raw.faceCorners.size() % 3 != 0) fail(path, "glTF: index count is not a multiple of 3");
  raw.faceSizes.assign(raw.faceCorners.size() / 3, 3);
  contents.hasUnits = true;  // glTF positions are metres
  baked.mmPerUnit = 1000.0;
  contents.report.format = "glb";
  cleanBakedMesh(path, std::move(raw), values, contents);
  return contents;
}

}  // namespace sss

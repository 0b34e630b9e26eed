#include "mesh/gltf_materials.h"

#include <initializer_list>
#include <map>
#include <optional>

#include "core/error.h"
#include "core/format.h"

namespace sss {
namespace {

using gltf::Document;
using JsonValue = gltf::Json;  // not Json: a unity build may hold another file's

// An image's bytes above this are not kept (a texture of 16384^2 RGBA PNG is under it).
constexpr std::uint64_t kMaxImageBytes = std::uint64_t(1) << 30;

// A number member in [lo, hi] (`fallback` when absent); anything else is an error.
double number(const Document& doc, const JsonValue& object, const char* key, double fallback,
              double lo, double hi, const std::string& where) {
  const auto it = object.find(key);
  if (it == object.end()) return fallback;
  if (!it->is_number() || !(it->get<double>() >= lo && it->get<double>() <= hi)) {
    doc.fail(where + ": \"" + key + "\" is not a number in [" + format("%g", lo) + ", " +
             format("%g", hi) + "]");
  }
  return it->get<double>();
}

// An enum member of a sampler: one of `allowed`, 0 when absent.
int samplerEnum(const Document& doc, const JsonValue& sampler, const char* key,
                std::initializer_list<int> allowed, int fallback, const std::string& where) {
  const auto it = sampler.find(key);
  if (it == sampler.end()) return fallback;
  for (const int value : allowed)
    if (it->is_number_integer() && it->get<std::int64_t>() == value) return value;
  doc.fail(where + ": \"" + key + "\" is not a valid enum");
}

// "image/png" or "image/jpeg" from the bytes' signature (PNG: ISO/IEC 15948 5.2; JPEG: SOI and
// a marker), "" when neither.
std::string imageType(const std::string& bytes) {
  if (bytes.starts_with("\x89PNG\r\n\x1a\n")) return "image/png";
  if (bytes.size() > 3 && bytes.starts_with("\xFF\xD8\xFF")) return "image/jpeg";
  return "";
}

class MaterialReader {
 public:
  explicit MaterialReader(const Document& doc) : doc_(doc) {}

  SurfaceMaterials read() {
    const JsonValue& list = doc_.array(doc_.json(), "materials");
    for (std::uint64_t m = 0; m < list.size(); ++m) out_.materials.push_back(material(m));
    return std::move(out_);
  }

 private:
  SurfaceMaterial material(std::uint64_t m) {
    const JsonValue& json = doc_.element("materials", m);
    const std::string where = "material " + std::to_string(m);
    SurfaceMaterial s;
    s.name = doc_.string(json, "name");
    if (json.contains("pbrMetallicRoughness")) {
      const JsonValue& pbr = json["pbrMetallicRoughness"];
      if (!pbr.is_object()) doc_.fail(where + ": pbrMetallicRoughness is not an object");
      s.alpha = baseAlpha(pbr, where);
      s.roughness = number(doc_, pbr, "roughnessFactor", 1.0, 0.0, 1.0, where);
      number(doc_, pbr, "metallicFactor", 1.0, 0.0, 1.0, where);
      s.baseColor = texture(pbr, "baseColorTexture", nullptr, s.dropped);
      s.roughnessMap = texture(pbr, "metallicRoughnessTexture", nullptr, s.dropped);
    }
    s.normal = texture(json, "normalTexture", "scale", s.dropped);
    s.occlusion = texture(json, "occlusionTexture", "strength", s.dropped);
    s.alphaMode = doc_.string(json, "alphaMode");
    if (s.alphaMode.empty()) s.alphaMode = "OPAQUE";
    if (s.alphaMode != "OPAQUE" && s.alphaMode != "MASK" && s.alphaMode != "BLEND")
      doc_.fail(where + ": alphaMode is not OPAQUE, MASK or BLEND");
    s.alphaCutoff = number(doc_, json, "alphaCutoff", 0.5, 0.0, 1e30, where);
    if (json.contains("doubleSided")) {
      if (!json["doubleSided"].is_boolean()) doc_.fail(where + ": doubleSided is not a boolean");
      s.doubleSided = json["doubleSided"].get<bool>();
    }
    if (json.contains("extensions") && json["extensions"].is_object())
      for (const auto& [name, value] : json["extensions"].items())
        s.dropped.push_back(name + " (the bake writes its own material extensions)");
    return s;
  }

  double baseAlpha(const JsonValue& pbr, const std::string& where) const {
    if (!pbr.contains("baseColorFactor")) return 1.0;
    const JsonValue& f = pbr["baseColorFactor"];
    bool valid = f.is_array() && f.size() == 4;
    for (std::size_t k = 0; valid && k < 4; ++k)
      valid = f[k].is_number() && f[k].get<double>() >= 0.0 && f[k].get<double>() <= 1.0;
    if (!valid) doc_.fail(where + ": baseColorFactor is not 4 numbers in [0, 1]");
    return f[3].get<double>();
  }

  // The textureInfo `key` of `owner` (section 3.9.2; scaleKey: "scale" or "strength"), or none
  // with a note in `dropped` when it cannot be kept.
  std::optional<SurfaceTexture> texture(const JsonValue& owner, const char* key,
                                        const char* scaleKey, std::vector<std::string>& dropped) {
    if (!owner.contains(key)) return std::nullopt;
    const JsonValue& info = owner[key];
    const std::string where = std::string(key);
    if (!info.is_object()) doc_.fail(where + " is not an object");
    const std::uint64_t t = doc_.index(info, "index");
    const JsonValue& tex = doc_.element("textures", t);
    SurfaceTexture s;
    if (scaleKey) {
      const bool strength = std::string(scaleKey) == "strength";
      s.scale =
          number(doc_, info, scaleKey, 1.0, strength ? 0.0 : -1e30, strength ? 1.0 : 1e30, where);
    }
    sampler(tex, s, where);
    const std::uint64_t texCoord = doc_.index(info, "texCoord", 0);
    if (texCoord != 0) {
      dropped.push_back(where + " (TEXCOORD_" + std::to_string(texCoord) + ")");
      return std::nullopt;
    }
    if (info.contains("extensions")) {
      dropped.push_back(where + " (texture extensions such as KHR_texture_transform)");
      return std::nullopt;
    }
    if (!tex.contains("source")) {
      dropped.push_back(where + " (no PNG or JPEG source)");
      return std::nullopt;
    }
    std::string why;
    const std::optional<std::uint32_t> image = this->image(doc_.index(tex, "source"), why);
    if (!image) {
      dropped.push_back(where + " (" + why + ")");
      return std::nullopt;
    }
    s.image = *image;
    return s;
  }

  void sampler(const JsonValue& tex, SurfaceTexture& s, const std::string& where) const {
    if (!tex.contains("sampler")) return;
    const JsonValue& j = doc_.element("samplers", doc_.index(tex, "sampler"));
    s.magFilter = samplerEnum(doc_, j, "magFilter", {kGltfNearest, kGltfLinear}, 0, where);
    s.minFilter = samplerEnum(
        doc_, j, "minFilter",
        {kGltfNearest, kGltfLinear, kGltfNearestMipmapNearest, 9985, 9986, kGltfLinearMipmapLinear},
        0, where);
    const std::initializer_list<int> wraps = {kGltfClampToEdge, kGltfMirroredRepeat, kGltfRepeat};
    s.wrapS = samplerEnum(doc_, j, "wrapS", wraps, kGltfRepeat, where);
    s.wrapT = samplerEnum(doc_, j, "wrapT", wraps, kGltfRepeat, where);
  }

  // Image i's index in out_.images, read once; none (and why) when it cannot be kept.
  std::optional<std::uint32_t> image(std::uint64_t i, std::string& why) {
    if (const auto it = images_.find(i); it != images_.end()) {
      why = it->second.second;
      return it->second.first;
    }
    std::optional<std::uint32_t> index;
    SurfaceImage image = imageBytes(i, why);
    if (!image.bytes.empty()) {
      index = static_cast<std::uint32_t>(out_.images.size());
      out_.images.push_back(std::move(image));
    }
    images_[i] = {index, why};
    return index;
  }

  SurfaceImage imageBytes(std::uint64_t i, std::string& why) const {
    const JsonValue& json = doc_.element("images", i);
    const std::string what = "image " + std::to_string(i);
    const std::string declared = doc_.string(json, "mimeType");
    SurfaceImage image;
    try {
      if (json.contains("bufferView")) {
        image.bytes = doc_.viewBytes(doc_.index(json, "bufferView"), what);
        if (image.bytes.size() > kMaxImageBytes) {
          why = what + " is larger than 1 GiB (" + std::to_string(image.bytes.size()) + " bytes)";
          return {};
        }
      } else {
        image.bytes = doc_.uriBytes(doc_.string(json, "uri"), what, kMaxImageBytes);
      }
    } catch (const Error& e) {
      why = what + " cannot be read: " + e.what();
      return {};
    }
    image.mimeType = imageType(image.bytes);
    if (image.mimeType.empty() || (!declared.empty() && declared != image.mimeType)) {
      why = what + " is not a PNG or JPEG" + (declared.empty() ? "" : " (" + declared + ")");
      return {};
    }
    return image;
  }

  const Document& doc_;
  SurfaceMaterials out_;
  std::map<std::uint64_t, std::pair<std::optional<std::uint32_t>, std::string>> images_;
};

}  // namespace

SurfaceMaterials readSurfaceMaterials(const Document& doc) {
  return MaterialReader(doc).read();
}

}  // namespace sss

#include "mesh/gltf_document.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include "core/error.h"
#include "core/paths.h"
#include "mesh/glb_chunks.h"

namespace sss::gltf {

static_assert(std::endian::native == std::endian::little,
              "glTF stores little-endian values, copied here as they are");

namespace {

namespace fs = std::filesystem;

// An accessor without a bufferView is zeros (sparse values aside): its count costs memory that no
// byte of the file backs, so it may not exceed this many elements per byte of the file.
constexpr std::uint64_t kUnbackedElementsPerFileByte = 16;

int componentBytes(std::uint64_t type) {
  switch (type) {
    case kByte:
    case kUnsignedByte:
      return 1;
    case kShort:
    case kUnsignedShort:
      return 2;
    case kUnsignedInt:
    case kFloat:
      return 4;
    default:
      return 0;
  }
}

std::string componentName(std::uint64_t type) {
  switch (type) {
    case kByte:
      return "BYTE";
    case kUnsignedByte:
      return "UNSIGNED_BYTE";
    case kShort:
      return "SHORT";
    case kUnsignedShort:
      return "UNSIGNED_SHORT";
    case kUnsignedInt:
      return "UNSIGNED_INT";
    case kFloat:
      return "FLOAT";
    default:
      return "componentType " + std::to_string(type);
  }
}

template <class V>
V load(const char* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// One component as T: floats as they are, normalized integers by section 3.11's formulas.
template <class T>
T component(const char* p, std::uint64_t type, bool normalized) {
  switch (type) {
    case kFloat:
      return static_cast<T>(load<float>(p));
    case kUnsignedByte: {
      const auto v = load<std::uint8_t>(p);
      return normalized ? static_cast<T>(v / 255.0f) : static_cast<T>(v);
    }
    case kByte: {
      const auto v = load<std::int8_t>(p);
      return normalized ? static_cast<T>(std::max(v / 127.0f, -1.0f)) : static_cast<T>(v);
    }
    case kUnsignedShort: {
      const auto v = load<std::uint16_t>(p);
      return normalized ? static_cast<T>(v / 65535.0f) : static_cast<T>(v);
    }
    case kShort: {
      const auto v = load<std::int16_t>(p);
      return normalized ? static_cast<T>(std::max(v / 32767.0f, -1.0f)) : static_cast<T>(v);
    }
    default:  // kUnsignedInt (never normalized: section 3.11)
      return static_cast<T>(load<std::uint32_t>(p));
  }
}

int typeComponents(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  return 0;
}

// Extensions a reader of geometry may ignore even when required: they change how a surface looks,
// not where it is.
bool geometryNeutral(const std::string& extension) {
  for (const char* prefix : {"KHR_materials_", "KHR_texture_", "EXT_texture_"}) {
    if (extension.starts_with(prefix)) return true;
  }
  return extension == "KHR_lights_punctual";
}

std::string readWholeFile(const std::string& path) {
  checkInputFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) sss::fail(path, "cannot open");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

// Where an accessor's (or sparse part's) elements lie in a loaded buffer.
struct Document::Span {
  const char* data = nullptr;
  std::uint64_t stride = 0;
};

// An accessor's elements: how many, their components and how each is stored.
struct Document::Layout {
  std::uint64_t count = 0;
  int components = 0;
  std::uint64_t componentType = 0;
  std::uint64_t bytes = 0;  // per component
  std::uint64_t elementSize = 0;
  bool normalized = false;
};

std::string decodeBase64(const std::string& path, const std::string& text) {
  static constexpr std::string_view kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::size_t n = text.size();
  std::size_t padding = 0;
  while (n > 0 && text[n - 1] == '=' && padding < 2) --n, ++padding;
  if (n % 4 == 1 || (padding > 0 && (n + padding) % 4 != 0)) {
    sss::fail(path, "glTF: bad base64 in a data: URI (" + std::to_string(text.size()) +
                        " characters cannot encode whole bytes)");
  }
  std::string out;
  out.reserve(n / 4 * 3 + 2);
  std::uint32_t bits = 0;
  int count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t v = kAlphabet.find(text[i]);
    if (v == std::string_view::npos) {
      sss::fail(path, "glTF: bad base64 in a data: URI: character " + std::to_string(i) + " ('" +
                          std::string(1, text[i]) + "') is not in the base64 alphabet");
    }
    bits = (bits << 6) | static_cast<std::uint32_t>(v);
    if (++count == 4) {
      out += {char(bits >> 16), char(bits >> 8), char(bits)};
      bits = 0, count = 0;
    }
  }
  if (count == 2) out += char(bits >> 4);
  if (count == 3) out += {char(bits >> 10), char(bits >> 2)};
  return out;
}

std::string resolveUri(const std::string& path, const std::string& folder, const std::string& uri) {
  const auto refuse = [&](const std::string& why) {
    sss::fail(path, "glTF: buffer URI '" + uri.substr(0, 200) + "' " + why);
  };
  if (uri.empty()) refuse("is empty");
  const std::size_t colon = uri.find(':'), slash = uri.find('/');
  if (colon != std::string::npos && (slash == std::string::npos || colon < slash)) {
    refuse("has a scheme: only data: URIs and relative paths beside the file are read");
  }
  if (uri[0] == '/') refuse("is absolute: only paths relative to the file's folder are read");
  std::string decoded;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] != '%') {
      decoded += uri[i];
      continue;
    }
    const int hi = i + 2 < uri.size() ? hexValue(uri[i + 1]) : -1;
    const int lo = hi >= 0 ? hexValue(uri[i + 2]) : -1;
    if (lo < 0) refuse("has a bad percent-escape");
    decoded += static_cast<char>(hi * 16 + lo);
    i += 2;
  }
  if (decoded.find('\0') != std::string::npos || decoded.find('\\') != std::string::npos) {
    refuse("holds a NUL or a backslash");
  }
  if (decoded[0] == '/') refuse("is absolute: only paths relative to the file's folder are read");
  for (std::size_t at = 0; at <= decoded.size();) {
    const std::size_t end = std::min(decoded.find('/', at), decoded.size());
    if (decoded.compare(at, end - at, "..") == 0 && end - at == 2) {
      refuse("leaves the file's folder ('..')");
    }
    at = end + 1;
  }
  return (fs::path(folder) / decoded).string();
}

Document::Document(const std::string& path, bool glbContainer) : path_(path), glb_(glbContainer) {
  folder_ = fs::path(path).parent_path().string();
  if (folder_.empty()) folder_ = ".";
  std::string text;
  if (glb_) {
    GlbChunks chunks = readGlbChunks(path);
    fileBytes_ = 28 + chunks.json.size() + chunks.bin.size();
    text = std::move(chunks.json);
    glbBin_ = std::move(chunks.bin);
  } else {
    text = readWholeFile(path);
    fileBytes_ = text.size();
  }
  try {
    json_ = Json::parse(text);
  } catch (const Json::exception& e) {
    sss::fail(path_, std::string("glTF JSON: ") + e.what());
  }
  if (!json_.is_object()) fail("the JSON is not an object");
  const auto asset = json_.find("asset");
  if (asset == json_.end() || !asset->is_object()) fail("no \"asset\" object");
  const std::string version = string(*asset, "version");
  if (!version.starts_with("2.")) fail("asset.version is '" + version + "', not 2.x");
  for (const Json& e : array(json_, "extensionsRequired")) {
    if (!e.is_string()) fail("extensionsRequired holds a non-string");
    const std::string name = e.get<std::string>();
    if (!geometryNeutral(name)) fail("requires the extension " + name + ", which is not supported");
  }
  buffers_.resize(array(json_, "buffers").size());
}

void Document::fail(const std::string& problem) const {
  sss::fail(path_, "glTF: " + problem);
}

const Json& Document::array(const Json& object, const char* name) const {
  static const Json kEmpty = Json::array();
  const auto it = object.find(name);
  if (it == object.end()) return kEmpty;
  if (!it->is_array()) fail(std::string("\"") + name + "\" is not an array");
  return *it;
}

const Json& Document::element(const char* name, std::uint64_t i) const {
  const Json& a = array(json_, name);
  if (i >= a.size()) fail(std::string(name) + "[" + std::to_string(i) + "] does not exist");
  const Json& e = a[i];
  if (!e.is_object()) fail(std::string(name) + "[" + std::to_string(i) + "] is not an object");
  return e;
}

std::uint64_t Document::index(const Json& object, const char* key,
                              std::optional<std::uint64_t> fallback) const {
  const auto it = object.find(key);
  if (it == object.end()) {
    if (fallback) return *fallback;
    fail(std::string("missing \"") + key + "\"");
  }
  if (!it->is_number_unsigned()) fail(std::string("\"") + key + "\" is not a non-negative integer");
  return it->get<std::uint64_t>();
}

std::string Document::string(const Json& object, const char* key) const {
  const auto it = object.find(key);
  if (it == object.end()) return "";
  if (!it->is_string()) fail(std::string("\"") + key + "\" is not a string");
  return it->get<std::string>();
}

std::string Document::loadBuffer(std::uint64_t i) const {
  const Json& b = element("buffers", i);
  const std::string name = "buffer " + std::to_string(i);
  const std::uint64_t length = index(b, "byteLength");
  if (length == 0) fail(name + " is empty");
  if (!b.contains("uri")) {
    if (!glb_ || i != 0) fail(name + " has no uri (only a GLB's first buffer may)");
    if (glbBin_.size() < length) {
      fail(name + " declares " + std::to_string(length) + " bytes, the GLB's BIN chunk holds " +
           std::to_string(glbBin_.size()));
    }
    return glbBin_.substr(0, length);
  }
  const std::string uri = string(b, "uri");
  if (!uri.starts_with("data:")) return fileBytes(uri, name, length, length);
  std::string data = uriBytes(uri, name, std::numeric_limits<std::uint64_t>::max());
  if (data.size() < length) {
    fail(name + " declares " + std::to_string(length) + " bytes, its data: URI holds " +
         std::to_string(data.size()));
  }
  data.resize(length);
  return data;
}

std::string Document::fileBytes(const std::string& uri, const std::string& what,
                                std::uint64_t atLeast, std::uint64_t atMost) const {
  const std::string file = resolveUri(path_, folder_, uri);
  checkInputFile(file);
  std::ifstream in(file, std::ios::binary);
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  const std::string shown = "'" + uri.substr(0, 200) + "'";
  if (!in || ec) fail(what + ": cannot open " + shown);
  if (size < atLeast) {
    fail(what + " (" + shown + ") holds " + std::to_string(size) + " bytes, under its byteLength " +
         std::to_string(atLeast));
  }
  if (size > atMost && atLeast != atMost) {
    fail(what + " (" + shown + ") holds " + std::to_string(size) + " bytes, over the " +
         std::to_string(atMost) + " allowed");
  }
  std::string data(std::min<std::uintmax_t>(size, atMost), '\0');
  if (!in.read(data.data(), static_cast<std::streamsize>(data.size()))) {
    fail(what + ": cannot read " + shown);
  }
  return data;
}

std::string Document::uriBytes(const std::string& uri, const std::string& what,
                               std::uint64_t maxBytes) const {
  if (!uri.starts_with("data:")) return fileBytes(uri, what, 1, maxBytes);
  const std::size_t comma = uri.find(',');
  if (comma == std::string::npos || !uri.substr(0, comma).ends_with(";base64")) {
    fail(what + "'s data: URI is not base64");
  }
  if ((uri.size() - comma - 1) / 4 * 3 > maxBytes) {
    fail(what + "'s data: URI holds over the " + std::to_string(maxBytes) + " bytes allowed");
  }
  return decodeBase64(path_, uri.substr(comma + 1));
}

std::string Document::viewBytes(std::uint64_t view, const std::string& what) const {
  const std::uint64_t length = index(element("bufferViews", view), "byteLength");
  if (length == 0) fail(what + ": bufferView " + std::to_string(view) + " is empty");
  const Span span = viewSpan(view, 0, 1, length, false, what);
  return std::string(span.data, length);
}

const std::string& Document::buffer(std::uint64_t i) const {
  if (i >= buffers_.size()) fail("buffers[" + std::to_string(i) + "] does not exist");
  if (!buffers_[i]) buffers_[i] = loadBuffer(i);
  return *buffers_[i];
}

std::uint64_t Document::accessorCount(std::uint64_t accessor) const {
  const std::uint64_t count = index(element("accessors", accessor), "count");
  if (count == 0) fail("accessor " + std::to_string(accessor) + " is empty");
  return count;
}

// `count` elements of `elementSize` bytes from `offset` in bufferView `view`, with its byteStride
// when `strided` (vertex attributes), else packed; all of them inside the view and its buffer.
Document::Span Document::viewSpan(std::uint64_t view, std::uint64_t offset, std::uint64_t count,
                                  std::uint64_t elementSize, bool strided,
                                  const std::string& what) const {
  const Json& v = element("bufferViews", view);
  const std::string& data = buffer(index(v, "buffer"));
  const std::uint64_t viewOffset = index(v, "byteOffset", 0);
  const std::uint64_t viewLength = index(v, "byteLength");
  Span span;
  span.stride = elementSize;
  if (strided && v.contains("byteStride")) {
    span.stride = index(v, "byteStride");
    if (span.stride < elementSize || span.stride > 252 || span.stride % 4 != 0) {
      fail(what + ": bufferView " + std::to_string(view) + "'s byteStride " +
           std::to_string(span.stride) + " is not a multiple of 4 in [" +
           std::to_string(elementSize) + ", 252]");
    }
  }
  // Overflow-free: the product is bounded by the division.
  if (viewOffset > data.size() || viewLength > data.size() - viewOffset || offset > viewLength ||
      elementSize > viewLength - offset ||
      count - 1 > (viewLength - offset - elementSize) / span.stride) {
    fail(what + " (" + std::to_string(count) + " elements of " + std::to_string(elementSize) +
         " bytes) overruns bufferView " + std::to_string(view) + " or its buffer");
  }
  span.data = data.data() + viewOffset + offset;
  return span;
}

// Section 3.6.3: `count` strictly increasing indices below the accessor's count, and as many
// packed values, replace those elements.
template <class T>
void Document::applySparse(const Json& sparse, const Layout& l, std::vector<T>& out,
                           const std::string& where) const {
  if (!sparse.is_object()) fail(where + ": \"sparse\" is not an object");
  const std::uint64_t n = index(sparse, "count");
  if (n == 0 || n > l.count) fail(where + ": sparse count " + std::to_string(n) + " out of range");
  const Json& indices = sparse.at("indices");
  const Json& values = sparse.at("values");
  const std::uint64_t indexType = index(indices, "componentType");
  if (indexType != kUnsignedByte && indexType != kUnsignedShort && indexType != kUnsignedInt) {
    fail(where + ": sparse indices of " + componentName(indexType));
  }
  const std::uint64_t indexBytes = static_cast<std::uint64_t>(componentBytes(indexType));
  const Span at = viewSpan(index(indices, "bufferView"), index(indices, "byteOffset", 0), n,
                           indexBytes, false, where + "'s sparse indices");
  const Span value = viewSpan(index(values, "bufferView"), index(values, "byteOffset", 0), n,
                              l.elementSize, false, where + "'s sparse values");
  std::uint64_t previous = 0;
  for (std::uint64_t k = 0; k < n; ++k) {
    const std::uint64_t i = component<std::uint32_t>(at.data + k * indexBytes, indexType, false);
    if (i >= l.count || (k > 0 && i <= previous)) {
      fail(where + ": sparse index " + std::to_string(i) + " (entry " + std::to_string(k) +
           ") is not increasing or not below the count " + std::to_string(l.count));
    }
    previous = i;
    for (int c = 0; c < l.components; ++c) {
      out[i * l.components + c] =
          component<T>(value.data + k * l.elementSize + c * l.bytes, l.componentType, l.normalized);
    }
  }
}

template <class T>
std::vector<T> Document::readAccessor(std::uint64_t accessor, int components,
                                      const std::vector<int>& componentTypes,
                                      bool normalizedAllowed, const std::string& what) const {
  const Json& a = element("accessors", accessor);
  const std::string where = what + " (accessor " + std::to_string(accessor) + ")";
  const std::string type = string(a, "type");
  if (typeComponents(type) != components) fail(where + " has type '" + type + "'");
  const std::uint64_t componentType = index(a, "componentType");
  if (std::find(componentTypes.begin(), componentTypes.end(), componentType) ==
      componentTypes.end()) {
    fail(where + " has components of " + componentName(componentType) + ", not allowed here");
  }
  const auto normalizedIt = a.find("normalized");
  if (normalizedIt != a.end() && !normalizedIt->is_boolean()) fail(where + ": bad \"normalized\"");
  const bool normalized = normalizedIt != a.end() && normalizedIt->get<bool>();
  if (normalized &&
      (!normalizedAllowed || componentType == kFloat || componentType == kUnsignedInt)) {
    fail(where + " is normalized, which its use or component type does not allow");
  }
  const std::uint64_t count = accessorCount(accessor);
  if (count > std::numeric_limits<std::uint32_t>::max()) fail(where + " has too many elements");
  const std::uint64_t bytes = static_cast<std::uint64_t>(componentBytes(componentType));
  const std::uint64_t elementSize = bytes * static_cast<std::uint64_t>(components);
  const auto sparse = a.find("sparse");
  std::vector<T> out;
  if (a.contains("bufferView")) {
    const Span span = viewSpan(index(a, "bufferView"), index(a, "byteOffset", 0), count,
                               elementSize, true, where);
    out.resize(count * components);
    for (std::uint64_t i = 0; i < count; ++i) {
      for (int c = 0; c < components; ++c) {
        out[i * components + c] =
            component<T>(span.data + i * span.stride + c * bytes, componentType, normalized);
      }
    }
  } else {
    if (sparse == a.end()) fail(where + " has neither a bufferView nor sparse values");
    if (count > kUnbackedElementsPerFileByte * fileBytes_) {
      fail(where + " declares " + std::to_string(count) + " elements without data, too many for " +
           std::to_string(fileBytes_) + " bytes of file");
    }
    out.assign(count * components, T(0));
  }
  if (sparse != a.end()) {
    applySparse(*sparse, {count, components, componentType, bytes, elementSize, normalized}, out,
                where);
  }
  return out;
}

std::vector<float> Document::readFloats(std::uint64_t accessor, int components,
                                        const std::vector<int>& componentTypes,
                                        bool normalizedAllowed, const std::string& what) const {
  return readAccessor<float>(accessor, components, componentTypes, normalizedAllowed, what);
}

std::vector<std::uint32_t> Document::readIndices(std::uint64_t accessor,
                                                 const std::string& what) const {
  return readAccessor<std::uint32_t>(accessor, 1, {kUnsignedByte, kUnsignedShort, kUnsignedInt},
                                     false, what);
}

}  // namespace sss::gltf

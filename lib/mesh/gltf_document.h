// A glTF 2.0 asset's JSON and binary data, read strictly: the containers (.gltf text, .glb:
// glTF 2.0 specification section 4.4), buffers (section 3.6.1: the GLB's BIN chunk, base64 data:
// URIs, external files beside the asset), buffer views (3.6.2) and accessors (3.6.2.4 strides,
// 3.6.3 sparse accessors, 3.11 normalized integers). Every index, offset, length and count is
// checked against the data it refers to before anything is read or allocated; URIs that leave the
// asset's folder are refused. The scene graph and the meshes are gltf_reader.h's.
// All errors are sss::Error "<file>: <problem>".
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace sss::gltf {

using Json = nlohmann::json;

inline constexpr int kByte = 5120, kUnsignedByte = 5121, kShort = 5122, kUnsignedShort = 5123,
                     kUnsignedInt = 5125, kFloat = 5126;

class Document {
 public:
  // Reads `path` (.gltf or .glb, by extension: glbContainer) and its JSON; buffers load on first
  // use.
  Document(const std::string& path, bool glbContainer);

  const std::string& path() const { return path_; }
  const Json& json() const { return json_; }

  // Throws Error("<path>: glTF: <problem>").
  [[noreturn]] void fail(const std::string& problem) const;

  // The array `name` (an empty array when absent; an error when not an array).
  const Json& array(const Json& object, const char* name) const;
  // Element i of the top-level array `name`, which must be an object.
  const Json& element(const char* name, std::uint64_t i) const;
  // A non-negative integer member; `fallback` when absent (an error without one).
  std::uint64_t index(const Json& object, const char* key,
                      std::optional<std::uint64_t> fallback = std::nullopt) const;
  // A string member ("" when absent; an error when not a string).
  std::string string(const Json& object, const char* key) const;

  // The values of accessor `accessor` as `components` numbers per element (its type must have
  // that many: 1 SCALAR, 2 VEC2, 3 VEC3), converted to float: floats as they are, normalized
  // integers mapped to [0, 1] or [-1, 1] (section 3.11), others by value. `componentTypes`
  // lists the types allowed. `what` names the accessor's use in errors ("POSITION of mesh 0").
  std::vector<float> readFloats(std::uint64_t accessor, int components,
                                const std::vector<int>& componentTypes, bool normalizedAllowed,
                                const std::string& what) const;
  // An index accessor: SCALAR, unsigned byte, short or int, not normalized.
  std::vector<std::uint32_t> readIndices(std::uint64_t accessor, const std::string& what) const;
  // The element count of accessor `accessor` (checked: at least 1).
  std::uint64_t accessorCount(std::uint64_t accessor) const;

  // The bytes of bufferView `view` (inside its buffer; not empty).
  std::string viewBytes(std::uint64_t view, const std::string& what) const;
  // The bytes a URI names: a base64 data: URI or a file beside the asset; more than maxBytes is
  // an error naming `what`.
  std::string uriBytes(const std::string& uri, const std::string& what,
                       std::uint64_t maxBytes) const;

 private:
  struct Span;    // gltf_document.cpp
  struct Layout;  // gltf_document.cpp
  const std::string& buffer(std::uint64_t i) const;
  std::string loadBuffer(std::uint64_t i) const;
  // The file `uri` names beside the asset: its first atMost bytes; an error when it holds fewer
  // than atLeast, or (atLeast != atMost) more than atMost.
  std::string fileBytes(const std::string& uri, const std::string& what, std::uint64_t atLeast,
                        std::uint64_t atMost) const;
  Span viewSpan(std::uint64_t view, std::uint64_t offset, std::uint64_t count,
                std::uint64_t elementSize, bool vertexData, const std::string& what) const;
  template <class T>
  void applySparse(const Json& sparse, const Layout& layout, std::vector<T>& out,
                   const std::string& what) const;
  template <class T>
  std::vector<T> readAccessor(std::uint64_t accessor, int components,
                              const std::vector<int>& componentTypes, bool normalizedAllowed,
                              const std::string& what) const;

  std::string path_;
  std::string folder_;
  Json json_;
  std::string glbBin_;
  bool glb_ = false;
  std::uint64_t fileBytes_ = 0;
  mutable std::vector<std::optional<std::string>> buffers_;
};

// Strict base64 (RFC 4648 section 4, padding optional): throws Error naming `path` on a character
// outside the alphabet, misplaced padding or an impossible length.
std::string decodeBase64(const std::string& path, const std::string& text);

// The file a relative URI reference names (RFC 3986: percent-escapes decoded) inside `folder`.
// Refuses, naming `path`: schemes other than data: (http:, file:, ...), absolute paths, "..",
// backslashes, empty names and NUL bytes.
std::string resolveUri(const std::string& path, const std::string& folder, const std::string& uri);

}  // namespace sss::gltf

#include "mesh/ply_format.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>

#include "core/error.h"
#include "core/paths.h"

namespace sss::ply {

namespace {

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool parseType(std::string_view name, Type& type) {
  static const std::pair<std::string_view, Type> names[] = {
      {"char", Type::Int8},      {"int8", Type::Int8},       {"uchar", Type::UInt8},
      {"uint8", Type::UInt8},    {"short", Type::Int16},     {"int16", Type::Int16},
      {"ushort", Type::UInt16},  {"uint16", Type::UInt16},   {"int", Type::Int32},
      {"int32", Type::Int32},    {"uint", Type::UInt32},     {"uint32", Type::UInt32},
      {"float", Type::Float32},  {"float32", Type::Float32}, {"double", Type::Float64},
      {"float64", Type::Float64}};
  for (const auto& [n, t] : names) {
    if (n == name) {
      type = t;
      return true;
    }
  }
  return false;
}

std::size_t typeSize(Type t) {
  switch (t) {
    case Type::Int8:
    case Type::UInt8:
      return 1;
    case Type::Int16:
    case Type::UInt16:
      return 2;
    case Type::Int32:
    case Type::UInt32:
    case Type::Float32:
      return 4;
    case Type::Float64:
      return 8;
  }
  return 0;
}

bool isInteger(Type t) {
  return t != Type::Float32 && t != Type::Float64;
}

struct Property {
  std::string name;
  Type type = Type::Float32;
  bool isList = false;
  Type countType = Type::UInt8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

enum class Encoding { Ascii, BinaryLE, BinaryBE };

// A value as read: integers exactly, floats as double (exact for float32).
struct Value {
  double real = 0.0;
  std::int64_t integer = 0;
};

std::vector<std::string_view> tokens(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

constexpr std::size_t kMaxHeaderBytes = 1 << 16;

class Reader {
 public:
  Reader(const std::string& path, std::string data) : path_(path), data_(std::move(data)) {}

  PlyMesh read() {
    parseHeader();
    checkSizes();
    PlyMesh mesh;
    mesh.format = encoding_ == Encoding::Ascii      ? "ply-ascii"
                  : encoding_ == Encoding::BinaryLE ? "ply-binary-le"
                                                    : "ply-binary-be";
    mesh.comments = std::move(comments_);
    for (const Element& e : elements_) readElement(e, mesh);
    if (encoding_ == Encoding::Ascii) {
      skipSpace();
      if (pos_ < data_.size()) mesh.warnings.push_back("text after the last element ignored");
    } else if (pos_ < data_.size()) {
      mesh.warnings.push_back(std::to_string(data_.size() - pos_) +
                              " bytes after the last element ignored");
    }
    return mesh;
  }

 private:
  [[noreturn]] void error(const std::string& problem) const { fail(path_, problem); }

  void parseHeader() {
    const std::size_t limit = std::min(data_.size(), kMaxHeaderBytes);
    std::size_t lineStart = 0;
    int lineNo = 0;
    bool sawFormat = false;
    while (true) {
      const std::size_t eol = data_.find('\n', lineStart);
      if (eol == std::string::npos || eol >= limit) {
        if (lineNo == 0) error("not a PLY file (no 'ply' line)");
        error("PLY header has no end_header line within its first 64 KiB");
      }
      std::string_view line(data_.data() + lineStart, eol - lineStart);
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      lineStart = eol + 1;
      ++lineNo;
      const std::string where = "PLY header line " + std::to_string(lineNo) + ": ";
      if (lineNo == 1) {
        if (line != "ply") error("not a PLY file (first line is not 'ply')");
        continue;
      }
      const auto t = tokens(line);
      if (t.empty()) continue;
      if (t[0] == "comment") {
        const std::size_t at = line.find("comment") + 7;
        comments_.emplace_back(at < line.size() ? line.substr(at + 1) : std::string_view());
      } else if (t[0] == "obj_info") {
        continue;
      } else if (t[0] == "format") {
        if (t.size() != 3 || t[2] != "1.0") error(where + "unsupported format line");
        if (t[1] == "ascii") {
          encoding_ = Encoding::Ascii;
        } else if (t[1] == "binary_little_endian") {
          encoding_ = Encoding::BinaryLE;
        } else if (t[1] == "binary_big_endian") {
          encoding_ = Encoding::BinaryBE;
        } else {
          error(where + "unknown format '" + std::string(t[1]) + "'");
        }
        sawFormat = true;
      } else if (t[0] == "element") {
        if (t.size() != 3) error(where + "expected 'element NAME COUNT'");
        Element e;
        e.name = t[1];
        const auto [end, ec] = std::from_chars(t[2].data(), t[2].data() + t[2].size(), e.count);
        if (ec != std::errc() || end != t[2].data() + t[2].size()) {
          error(where + "bad element count '" + std::string(t[2]) + "'");
        }
        elements_.push_back(std::move(e));
      } else if (t[0] == "property") {
        if (elements_.empty()) error(where + "property before any element");
        Property p;
        if (t.size() == 5 && t[1] == "list") {
          p.isList = true;
          if (!parseType(t[2], p.countType) || !isInteger(p.countType)) {
            error(where + "bad list count type '" + std::string(t[2]) + "'");
          }
          if (!parseType(t[3], p.type)) error(where + "bad type '" + std::string(t[3]) + "'");
          p.name = t[4];
        } else if (t.size() == 3) {
          if (!parseType(t[1], p.type)) error(where + "bad type '" + std::string(t[1]) + "'");
          p.name = t[2];
        } else {
          error(where + "malformed property line");
        }
        elements_.back().properties.push_back(std::move(p));
      } else if (t[0] == "end_header") {
        if (!sawFormat) error("PLY header has no format line");
        pos_ = lineStart;
        return;
      } else {
        error(where + "unknown keyword '" + std::string(t[0]) + "'");
      }
    }
  }

  // Every item needs at least a few bytes: a huge count in a small file fails here, before
  // anything is allocated.
  void checkSizes() const {
    const std::uint64_t available = data_.size() - pos_;
    std::uint64_t needed = 0;
    for (const Element& e : elements_) {
      if (e.count == 0) continue;
      if (e.properties.empty()) error("PLY element '" + e.name + "' has no properties");
      std::uint64_t perItem = 0;
      for (const Property& p : e.properties) {
        // ascii: a token and a separator; binary: the value or the list count
        perItem += encoding_ == Encoding::Ascii ? 2 : typeSize(p.isList ? p.countType : p.type);
      }
      if (e.count > (available + 1) / perItem || needed + e.count * perItem > available + 1) {
        error("PLY header declares " + std::to_string(e.count) + " " + e.name +
              " elements (at least " + std::to_string(perItem) + " bytes each), but the file has " +
              std::to_string(available) + " bytes after the header (truncated or corrupt)");
      }
      needed += e.count * perItem;
    }
  }

  void skipSpace() {
    while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
  }

  [[noreturn]] void truncated(const Element& e, std::uint64_t item) const {
    error("file ends in " + e.name + " " + std::to_string(item) + " of " + std::to_string(e.count) +
          " (truncated)");
  }

  Value readValue(Type type, const Element& e, std::uint64_t item) {
    Value v;
    if (encoding_ == Encoding::Ascii) {
      skipSpace();
      std::size_t end = pos_;
      while (end < data_.size() && !std::isspace(static_cast<unsigned char>(data_[end]))) ++end;
      if (end == pos_) truncated(e, item);
      const char* first = data_.data() + pos_;
      const char* last = data_.data() + end;
      if (*first == '+') ++first;
      std::from_chars_result r;
      if (isInteger(type)) {
        r = std::from_chars(first, last, v.integer);
        v.real = static_cast<double>(v.integer);
      } else if (type == Type::Float32) {
        float f = 0.0f;  // parsed as float directly: "0.1" reads as the float nearest 0.1
        r = std::from_chars(first, last, f);
        v.real = f;
      } else {
        r = std::from_chars(first, last, v.real);
      }
      if (r.ec != std::errc() || r.ptr != last) {
        error("bad number '" + std::string(data_.data() + pos_, end - pos_) + "' in " + e.name +
              " " + std::to_string(item));
      }
      pos_ = end;
      return v;
    }
    const std::size_t size = typeSize(type);
    if (data_.size() - pos_ < size) truncated(e, item);
    unsigned char bytes[8];
    std::memcpy(bytes, data_.data() + pos_, size);
    pos_ += size;
    if ((encoding_ == Encoding::BinaryBE) != (std::endian::native == std::endian::big)) {
      std::reverse(bytes, bytes + size);
    }
    switch (type) {
      case Type::Int8:
        v.integer = static_cast<std::int8_t>(bytes[0]);
        break;
      case Type::UInt8:
        v.integer = bytes[0];
        break;
      case Type::Int16:
        v.integer = fromBytes<std::int16_t>(bytes);
        break;
      case Type::UInt16:
        v.integer = fromBytes<std::uint16_t>(bytes);
        break;
      case Type::Int32:
        v.integer = fromBytes<std::int32_t>(bytes);
        break;
      case Type::UInt32:
        v.integer = fromBytes<std::uint32_t>(bytes);
        break;
      case Type::Float32:
        v.real = fromBytes<float>(bytes);
        return v;
      case Type::Float64:
        v.real = fromBytes<double>(bytes);
        return v;
    }
    v.real = static_cast<double>(v.integer);
    return v;
  }

  template <class T>
  static T fromBytes(const unsigned char* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
  }

  // Where each property of an element goes: 0..5 = x y z nx ny nz, then these.
  static constexpr int kScalar = 6;   // another vertex scalar, kept by name
  static constexpr int kIndices = 7;  // the face's vertex index list
  static constexpr int kSkipped = 8;

  struct Roles {
    std::vector<int> role;
    std::vector<std::vector<float>*> scalars;  // kScalar's destination, per property
    bool hasPosition[3] = {false, false, false};
    bool hasNormal[3] = {false, false, false};
    bool hasIndices = false;
    bool normals() const { return hasNormal[0] && hasNormal[1] && hasNormal[2]; }
  };

  Roles assignRoles(const Element& e) const {
    static const char* const kVertexNames[] = {"x", "y", "z", "nx", "ny", "nz"};
    Roles r;
    r.role.assign(e.properties.size(), kSkipped);
    r.scalars.assign(e.properties.size(), nullptr);
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      const Property& p = e.properties[i];
      if (e.name == "vertex" && !p.isList) {
        r.role[i] = kScalar;
        for (int k = 0; k < 6; ++k) {
          if (p.name == kVertexNames[k]) r.role[i] = k;
        }
        if (r.role[i] < 3) r.hasPosition[r.role[i]] = true;
        if (r.role[i] >= 3 && r.role[i] < 6) r.hasNormal[r.role[i] - 3] = true;
      } else if (e.name == "face" && p.isList &&
                 (p.name == "vertex_indices" || p.name == "vertex_index")) {
        if (!isInteger(p.type)) error("PLY face indices must be integers");
        if (r.hasIndices) error("PLY face element has two index lists");
        r.role[i] = kIndices;
        r.hasIndices = true;
      }
    }
    return r;
  }

  // Sizes the mesh's vertex arrays; a lone normal component becomes a scalar.
  void prepareVertices(const Element& e, Roles& r, PlyMesh& mesh) const {
    if (!(r.hasPosition[0] && r.hasPosition[1] && r.hasPosition[2])) {
      error("PLY vertex element lacks x, y or z");
    }
    if (e.count > std::numeric_limits<std::uint32_t>::max()) error("too many vertices");
    if (!mesh.positions.empty()) error("PLY file has two vertex elements");
    const bool normals = r.normals();
    mesh.positions.resize(e.count);
    if (normals) mesh.normals.resize(e.count);
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      if (r.role[i] >= 3 && r.role[i] < 6 && !normals) r.role[i] = kScalar;
      if (r.role[i] == kScalar) {
        r.scalars[i] = &mesh.vertexScalars[e.properties[i].name];
        r.scalars[i]->resize(e.count);
      }
    }
  }

  void prepareFaces(const Element& e, const Roles& r, PlyMesh& mesh) const {
    if (!r.hasIndices) error("PLY face element has no vertex_indices list");
    if (!mesh.faceSizes.empty()) error("PLY file has two face elements");
    mesh.faceSizes.reserve(e.count);
    mesh.faceCorners.reserve(e.count * 3);
  }

  // List property p of item `item`: its entries are face indices (role kIndices) or skipped.
  void readList(const Element& e, const Property& p, int role, std::uint64_t item, PlyMesh& mesh) {
    const Value count = readValue(p.countType, e, item);
    if (count.integer < 0) error("negative list length in " + e.name);
    for (std::int64_t k = 0; k < count.integer; ++k) {
      const Value v = readValue(p.type, e, item);
      if (role == kIndices) {
        if (v.integer < 0 || v.integer > std::numeric_limits<std::uint32_t>::max()) {
          error("face " + std::to_string(item) + " has vertex index " + std::to_string(v.integer) +
                " out of range");
        }
        mesh.faceCorners.push_back(static_cast<std::uint32_t>(v.integer));
      }
    }
    if (role == kIndices) mesh.faceSizes.push_back(static_cast<std::uint32_t>(count.integer));
  }

  void readItem(const Element& e, const Roles& r, std::uint64_t item, PlyMesh& mesh) {
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      const Property& p = e.properties[i];
      if (p.isList) {
        readList(e, p, r.role[i], item, mesh);
        continue;
      }
      const Value v = readValue(p.type, e, item);
      const int role = r.role[i];
      if (role < 3) {
        mesh.positions[item][role] = static_cast<float>(v.real);
      } else if (role < 6) {
        mesh.normals[item][role - 3] = static_cast<float>(v.real);
      } else if (role == kScalar) {
        (*r.scalars[i])[item] = static_cast<float>(v.real);
      }
    }
  }

  void readElement(const Element& e, PlyMesh& mesh) {
    Roles roles = assignRoles(e);
    if (e.name == "vertex") prepareVertices(e, roles, mesh);
    if (e.name == "face") prepareFaces(e, roles, mesh);
    for (std::uint64_t item = 0; item < e.count; ++item) readItem(e, roles, item, mesh);
  }

  std::string path_;
  std::string data_;
  std::size_t pos_ = 0;
  Encoding encoding_ = Encoding::Ascii;
  std::vector<std::string> comments_;
  std::vector<Element> elements_;
};

}  // namespace

PlyMesh readPly(const std::string& path) {
  checkInputFile(path);  // not a directory or a FIFO
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open file");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  if (size <= 0) fail(path, "empty file");
  std::string data(static_cast<std::size_t>(size), '\0');
  if (!in.read(data.data(), size)) fail(path, "read error");
  return Reader(path, std::move(data)).read();
}

RawMesh takeMesh(PlyMesh& ply, MeshReport& report) {
  report.format = ply.format;
  report.warnings = std::move(ply.warnings);
  RawMesh raw;
  raw.positions = std::move(ply.positions);
  raw.normals = std::move(ply.normals);
  raw.faceCorners = std::move(ply.faceCorners);
  raw.faceSizes = std::move(ply.faceSizes);
  return raw;
}

}  // namespace sss::ply

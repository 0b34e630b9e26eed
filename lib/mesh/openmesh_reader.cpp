#include "mesh/openmesh_reader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include "core/error.h"
#include "core/paths.h"

namespace sss {

namespace {

using OpenMesh::EdgeHandle;
using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::Vec2f;
using OpenMesh::Vec3d;
using OpenMesh::Vec3f;
using OpenMesh::Vec3uc;
using OpenMesh::Vec4f;
using OpenMesh::Vec4uc;
using OpenMesh::VertexHandle;
using OpenMesh::Attributes::StatusInfo;

// Collects vertices, vertex normals and polygons exactly as the reader reports them.
class RawImporter : public OpenMesh::IO::BaseImporter {
 public:
  explicit RawImporter(RawMesh& raw) : raw_(raw) {}

  VertexHandle add_vertex(const Vec3f& p) override {
    raw_.positions.emplace_back(p[0], p[1], p[2]);
    return VertexHandle(static_cast<int>(raw_.positions.size()) - 1);
  }
  VertexHandle add_vertex() override { return add_vertex(Vec3f(0, 0, 0)); }
  FaceHandle add_face(const VHandles& corners) override {
    for (const VertexHandle& v : corners) {
      raw_.faceCorners.push_back(v.is_valid() ? static_cast<unsigned>(v.idx()) : 0xffffffffu);
    }
    raw_.faceSizes.push_back(static_cast<unsigned>(corners.size()));
    return FaceHandle(static_cast<int>(raw_.faceSizes.size()) - 1);
  }
  void set_point(VertexHandle v, const Vec3f& p) override {
    if (valid(v)) raw_.positions[v.idx()] = {p[0], p[1], p[2]};
  }
  void set_normal(VertexHandle v, const Vec3f& n) override {
    if (!valid(v)) return;
    normals_.resize(raw_.positions.size(), glm::vec3(0.0f));
    hasNormal_.resize(raw_.positions.size(), 0);
    normals_[v.idx()] = {n[0], n[1], n[2]};
    hasNormal_[v.idx()] = 1;
  }
  void set_normal(VertexHandle v, const Vec3d& n) override { set_normal(v, Vec3f(n)); }

  // Normals count only when every vertex has one.
  void finishNormals() {
    if (hasNormal_.size() != raw_.positions.size()) return;
    for (char h : hasNormal_) {
      if (!h) return;
    }
    raw_.normals = std::move(normals_);
  }

  // Topology-level calls (OM files) are not used: faces come through add_face.
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  // Attributes we do not use.
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_color(VertexHandle, const Vec3uc&) override {}
  void set_color(VertexHandle, const Vec4uc&) override {}
  void set_color(VertexHandle, const Vec3f&) override {}
  void set_color(VertexHandle, const Vec4f&) override {}
  void set_texcoord(VertexHandle, const Vec2f&) override {}
  void set_texcoord(VertexHandle, const Vec3f&) override {}
  void set_status(VertexHandle, const StatusInfo&) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
  void set_status(HalfedgeHandle, const StatusInfo&) override {}
  void set_color(EdgeHandle, const Vec3uc&) override {}
  void set_color(EdgeHandle, const Vec4uc&) override {}
  void set_color(EdgeHandle, const Vec3f&) override {}
  void set_color(EdgeHandle, const Vec4f&) override {}
  void set_status(EdgeHandle, const StatusInfo&) override {}
  void set_normal(FaceHandle, const Vec3f&) override {}
  void set_normal(FaceHandle, const Vec3d&) override {}
  void set_color(FaceHandle, const Vec3uc&) override {}
  void set_color(FaceHandle, const Vec4uc&) override {}
  void set_color(FaceHandle, const Vec3f&) override {}
  void set_color(FaceHandle, const Vec4f&) override {}
  void set_status(FaceHandle, const StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}

  size_t n_vertices() const override { return raw_.positions.size(); }
  size_t n_faces() const override { return raw_.faceSizes.size(); }
  size_t n_edges() const override { return 0; }

 private:
  bool valid(VertexHandle v) const {
    return v.is_valid() && static_cast<std::size_t>(v.idx()) < raw_.positions.size();
  }
  RawMesh& raw_;
  std::vector<glm::vec3> normals_;
  std::vector<char> hasNormal_;
};

std::string readAll(const std::string& path) {
  checkInputFile(path);  // not a directory or a FIFO
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open file");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Counts an OFF header declares, checked against the file size before OpenMesh sees them (its
// reader would loop, and allocate, for every declared element of a truncated file).
struct OffCounts {
  std::uint64_t vertices = 0, faces = 0;
  std::string keyword;  // "OFF", "NOFF", "COFF", ...
  bool binary = false;
  std::size_t records = 0;  // where the vertex records start (binary: the counts)
};

OffCounts checkOffHeader(const std::string& path, const std::string& data) {
  // OpenMesh reads the first line as the header, [ST][C][N][4][n]OFF and, one character later,
  // BINARY for a binary file, and not the rest of that line; then the counts as the next three
  // words wherever the lines break, and the records right after them (found by tests/fuzz: to it
  // "OFF 6\n0 0 4" declares no vertices and no faces).
  // Its prefix letters come in that order, each optional, and what follows OFF on the line is
  // not part of the keyword (found by tests/fuzz: "COFFNOFF" is COFF to it, without normals).
  const std::size_t firstEol = std::min(data.find('\n'), data.size());
  std::size_t p = data.compare(0, 2, "ST") == 0 ? 2 : 0;
  for (const char letter : {'C', 'N', '4', 'n'}) {
    if (p < data.size() && data[p] == letter) ++p;
  }
  if (p + 3 > firstEol || data.compare(p, 3, "OFF") != 0) {
    fail(path, "not an OFF file (no OFF keyword)");
  }
  OffCounts counts;
  counts.keyword = data.substr(0, p + 3);
  counts.binary = data.size() > p + 4 && data.compare(p + 4, 6, "BINARY") == 0;
  std::size_t at = std::min(firstEol + 1, data.size());
  // Comments are words to it too: a '#' there fails its reads, and leaves the face count
  // unset (found by tests/fuzz).
  std::vector<std::string> words;  // the counts (text)
  while (!counts.binary && words.size() < 3 && at < data.size()) {
    at = std::min(data.find_first_not_of(" \t\r\n\v\f", at), data.size());
    const std::size_t end = std::min(data.find_first_of(" \t\r\n\v\f", at), data.size());
    if (end > at) words.push_back(data.substr(at, end - at));
    at = end;
  }
  counts.records = at;
  auto tooLarge = [&] {
    fail(path, "OFF header declares " + std::to_string(counts.vertices) + " vertices and " +
                   std::to_string(counts.faces) + " faces, more than the file can hold");
  };
  if (counts.binary) {
    // int32 counts (OpenMesh writes them little-endian), then x y z floats per vertex and at
    // least a count and three indices per face.
    if (data.size() < at + 12) fail(path, "truncated OFF header");
    std::uint32_t n[2];
    std::memcpy(n, data.data() + at, 8);
    counts.vertices = n[0];
    counts.faces = n[1];
    if (counts.vertices * 12 + counts.faces * 16 > data.size() - at) tooLarge();
    return counts;
  }
  if (words.size() < 3) fail(path, "OFF header lacks the vertex and face counts");
  for (int i = 0; i < 3; ++i) {
    std::uint64_t edges = 0;
    std::uint64_t& c = i == 0 ? counts.vertices : i == 1 ? counts.faces : edges;
    const std::string& w = words[i];
    const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), c);
    if (ec != std::errc() || end != w.data() + w.size()) fail(path, "bad OFF count '" + w + "'");
  }
  // Text: one line per vertex and per face (OpenMesh's reader repeats the last face of a file
  // that ends early instead of failing, so count the lines first).
  if (counts.vertices > data.size() / 6 || counts.faces > data.size() / 8) tooLarge();
  std::uint64_t lines = 0;
  while (at < data.size()) {
    std::size_t eol = data.find('\n', at);
    if (eol == std::string::npos) eol = data.size();
    const std::size_t first = data.find_first_not_of(" \t\r", at);
    if (first < eol && data[first] != '#') ++lines;
    at = eol + 1;
  }
  if (lines < counts.vertices + counts.faces) {
    fail(path, "OFF header declares " + std::to_string(counts.vertices) + " vertices and " +
                   std::to_string(counts.faces) + " faces, but the file has only " +
                   std::to_string(lines) + " lines of data (truncated)");
  }
  return counts;
}

// What operator>> reads whole as a float: [+-]digits[.digits][(e|E)[+-]digits], a digit in the
// mantissa (no "inf", "nan" or hexadecimal).
bool isDecimalNumber(std::string_view w) {
  std::size_t i = w.starts_with('+') || w.starts_with('-') ? 1 : 0;
  std::size_t digits = 0;
  for (; i < w.size() && std::isdigit(static_cast<unsigned char>(w[i])); ++i) ++digits;
  if (i < w.size() && w[i] == '.') {
    for (++i; i < w.size() && std::isdigit(static_cast<unsigned char>(w[i])); ++i) ++digits;
  }
  if (digits == 0) return false;
  if (i < w.size() && (w[i] == 'e' || w[i] == 'E')) {
    ++i;
    if (i < w.size() && (w[i] == '+' || w[i] == '-')) ++i;
    const std::size_t start = i;
    while (i < w.size() && std::isdigit(static_cast<unsigned char>(w[i]))) ++i;
    if (i == start) return false;
  }
  return i == w.size();
}

// What operator>> reads whole as an unsigned int without failing: [+]digits, below 2^32.
bool parseUnsigned32(std::string_view w, std::uint32_t& value) {
  const char* first = w.data() + (w.starts_with('+') ? 1 : 0);
  const auto [end, ec] = std::from_chars(first, w.data() + w.size(), value);
  return ec == std::errc() && end == w.data() + w.size() && first != end;
}

// Walks the records as OpenMesh's readers do, so that no face's corner count makes them loop
// and allocate past the end of the file (they read a face's n indices whatever n is, and a
// negative text count wraps to 4 billion): text vertices are their numbers then the rest of the
// line, faces a count n, n indices and, with colours (COFF), the rest of the line; binary vertices
// are 3 floats and more with N, C or ST (below), faces an int32 n and n int32 indices.
void checkOffFaceSizes(const std::string& path, const std::string& data, const OffCounts& counts) {
  const std::string prefix = counts.keyword.substr(0, counts.keyword.size() - 3);
  const bool normals = prefix.find('N') != std::string::npos;
  const bool colours = prefix.find('C') != std::string::npos;
  auto tooMany = [&](std::uint64_t face, const std::string& n) {
    fail(path, "OFF face " + std::to_string(face) + " declares " + n +
                   " corners, more than the rest of the file holds");
  };
  // Past the end OpenMesh's reads fail and keep the last count: each face left repeats it.
  auto truncated = [&](std::uint64_t face) {
    fail(path, "OFF header declares " + std::to_string(counts.faces) +
                   " faces, but the file ends in face " + std::to_string(face) + " (truncated)");
  };
  std::size_t at = counts.records;
  if (counts.binary) {
    // Per vertex OpenMesh reads 3 floats, 3 more with N, 3 int32 colour components with C and 2
    // texture floats with ST (we ask for no colours: no alpha, no float colours), and no face
    // colours (a binary COFF's face counts need this check too: found by tests/fuzz).
    const bool texcoords = prefix.find("ST") != std::string::npos;
    at +=
        12 + counts.vertices * (12 + (normals ? 12 : 0) + (colours ? 12 : 0) + (texcoords ? 8 : 0));
    for (std::uint64_t f = 0; f < counts.faces; ++f) {
      if (at + 4 > data.size()) truncated(f);
      std::uint32_t n;
      std::memcpy(&n, data.data() + at, 4);
      at += 4;
      if (n > (data.size() - at) / 4) tooMany(f, std::to_string(n));
      at += 4 * std::size_t{n};
    }
    return;
  }
  // Text. Once one of its reads fails, every later read of OpenMesh's stream fails too and each
  // face left repeats the last count (faces x corners of work), so every word it reads as a
  // number must be one, whole: coordinates decimal, counts and indices unsigned 32-bit (found by
  // tests/fuzz: "-1x" was read as 4294967295 corners).
  auto token = [&]() -> std::string_view {
    at = std::min(data.find_first_not_of(" \t\r\n\v\f", at), data.size());
    const std::size_t end = std::min(data.find_first_of(" \t\r\n\v\f", at), data.size());
    const std::string_view word(data.data() + at, end - at);
    at = end;
    return word;
  };
  auto restOfLine = [&] { at = std::min(data.find('\n', at), data.size()); };
  auto bad = [&](const std::string& where, std::string_view word) {
    fail(path, "OFF " + where + ": bad number '" + std::string(word) + "'");
  };
  for (std::uint64_t v = 0; v < counts.vertices; ++v) {
    for (int k = 0; k < (normals ? 6 : 3); ++k) {
      const std::string_view word = token();
      if (word.empty()) {
        fail(path, "OFF header declares " + std::to_string(counts.vertices) +
                       " vertices, but the file ends in vertex " + std::to_string(v) +
                       " (truncated)");
      }
      if (!isDecimalNumber(word)) bad("vertex " + std::to_string(v), word);
    }
    restOfLine();
  }
  for (std::uint64_t f = 0; f < counts.faces; ++f) {
    const std::string_view word = token();
    if (word.empty()) truncated(f);
    std::uint32_t n = 0;
    if (word.starts_with('-') && parseUnsigned32(word.substr(1), n)) {
      fail(path, "OFF face " + std::to_string(f) + " declares " + std::string(word) + " corners");
    }
    if (!parseUnsigned32(word, n)) bad("face " + std::to_string(f) + " corner count", word);
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::string_view index = token();
      if (index.empty()) tooMany(f, std::to_string(n));
      std::uint32_t ignored;
      if (!parseUnsigned32(index, ignored)) bad("face " + std::to_string(f), index);
    }
    if (colours) restOfLine();
  }
}

void checkStl(const std::string& path, const std::string& data) {
  if (data.size() >= 84) {
    std::uint32_t n;
    std::memcpy(&n, data.data() + 80, 4);
    if (84 + 50 * std::uint64_t{n} == data.size()) return;  // binary
  }
  if (data.compare(0, 5, "solid") != 0) {
    fail(path,
         "not an STL file: neither a binary STL (size does not match its triangle count) "
         "nor an ASCII one (no 'solid')");
  }
  const std::size_t last = data.find_last_not_of(" \t\r\n");
  const std::size_t eol = last == std::string::npos ? std::string::npos : data.rfind('\n', last);
  const std::size_t lineStart =
      data.find_first_not_of(" \t", eol == std::string::npos ? 0 : eol + 1);
  if (last == std::string::npos || data.compare(lineStart, 8, "endsolid") != 0) {
    fail(path, "ASCII STL does not end with 'endsolid' (truncated)");
  }
}

// OM's header (magic "OM", mesh type, version, then little-endian uint32 counts of vertices,
// faces and edges) against the file size: OpenMesh reserves what it declares and loops over it,
// reading past the end. Every stored element takes at least a byte (a vertex 12), so a count
// beyond the file's size is a lie.
void checkOmHeader(const std::string& path, const std::string& data) {
  if (data.size() < 16 || data.compare(0, 2, "OM") != 0)
    fail(path, "not an OM file (no OM header)");
  std::uint32_t n[3];
  std::memcpy(n, data.data() + 4, 12);
  if (std::uint64_t{n[0]} + n[1] + n[2] > data.size()) {
    fail(path, "OM header declares " + std::to_string(n[0]) + " vertices, " + std::to_string(n[1]) +
                   " faces and " + std::to_string(n[2]) + " edges, more than the file can hold");
  }
}

// OpenMesh's OBJ reader aborts on an assertion when a face's first corner has no vertex index
// ("f /1/1 ...", "f //1 ..."; found by tests/fuzz) and drops such a corner elsewhere in a face.
// Lines are split as it splits them: whitespace, then the keyword.
void checkObjFaces(const std::string& path, const std::string& data) {
  std::size_t lineNo = 0;
  for (std::size_t at = 0; at < data.size(); ++lineNo) {
    const std::size_t eol = std::min(data.find('\n', at), data.size());
    const std::size_t first = data.find_first_not_of(" \t\r\v\f", at);
    if (first < eol && data[first] == 'f') {
      std::istringstream words(data.substr(first, eol - first));
      std::string word;
      if (words >> word && word == "f") {
        while (words >> word) {
          if (word[0] == '/') {
            fail(path, "OBJ line " + std::to_string(lineNo + 1) + ": face corner '" + word +
                           "' has no vertex index");
          }
        }
      }
    }
    at = eol + 1;
  }
}

// Silences OpenMesh's own error stream while it reads (our errors say what went wrong).
class QuietOpenMesh {
 public:
  QuietOpenMesh() {
    ::omerr().disable();
    ::omlog().disable();
  }
  ~QuietOpenMesh() {
    ::omerr().enable();
    ::omlog().enable();
  }
};

}  // namespace

RawMesh readWithOpenMesh(const std::string& path, const std::string& ext) {
  const std::string data = readAll(path);
  if (data.empty()) fail(path, "empty file");
  RawMesh raw;
  OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexNormal;
  QuietOpenMesh quiet;
  bool ok = false;
  if (ext == "om") {
    // OM files are OpenMesh's own: read them into its mesh and take the faces from there.
    checkOmHeader(path, data);
    OpenMesh::PolyMesh_ArrayKernelT<> mesh;
    mesh.request_vertex_normals();
    ok = OpenMesh::IO::read_mesh(mesh, path, options);
    if (ok) {
      for (const auto v : mesh.vertices()) {
        const auto& p = mesh.point(v);
        raw.positions.emplace_back(p[0], p[1], p[2]);
      }
      if (options.vertex_has_normal()) {
        for (const auto v : mesh.vertices()) {
          const auto& n = mesh.normal(v);
          raw.normals.emplace_back(n[0], n[1], n[2]);
        }
      }
      for (const auto f : mesh.faces()) {
        unsigned size = 0;
        for (const auto v : mesh.fv_range(f)) {
          raw.faceCorners.push_back(static_cast<unsigned>(v.idx()));
          ++size;
        }
        raw.faceSizes.push_back(size);
      }
    }
  } else {
    OffCounts off;
    if (ext == "off") {
      off = checkOffHeader(path, data);
      checkOffFaceSizes(path, data, off);
    }
    if (ext == "stl") checkStl(path, data);
    if (ext == "obj") checkObjFaces(path, data);
    RawImporter importer(raw);
    ok = OpenMesh::IO::IOManager().read(path, importer, options);
    importer.finishNormals();
    if (ok && ext == "off" &&
        (raw.positions.size() != off.vertices || raw.faceSizes.size() != off.faces)) {
      fail(path, "OFF header declares " + std::to_string(off.vertices) + " vertices and " +
                     std::to_string(off.faces) + " faces, but the file holds " +
                     std::to_string(raw.positions.size()) + " and " +
                     std::to_string(raw.faceSizes.size()) + " (truncated?)");
    }
  }
  if (!ok) fail(path, "not a readable " + ext + " file");
  return raw;
}

}  // namespace sss

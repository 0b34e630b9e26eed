#include "mesh/openmesh_reader.h"

#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include "core/error.h"

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
};

OffCounts checkOffHeader(const std::string& path, const std::string& data) {
  // Words of the header up to the counts (comments removed), and where its last line ends.
  std::vector<std::string> words;
  std::size_t at = 0;
  auto isBinary = [&] { return words.size() >= 2 && words[1] == "BINARY"; };
  while (at < data.size() && at < 4096 && words.size() < 4 && !isBinary()) {
    std::size_t eol = data.find('\n', at);
    if (eol == std::string::npos) eol = data.size();
    std::string line = data.substr(at, eol - at);
    line.resize(std::min(line.find('#'), line.size()));
    std::istringstream ls(line);
    for (std::string w; ls >> w;) words.push_back(w);
    at = eol + 1;
  }
  if (words.empty() || words[0].size() < 3 || words[0].substr(words[0].size() - 3) != "OFF") {
    fail(path, "not an OFF file (no OFF keyword)");
  }
  OffCounts counts;
  auto tooLarge = [&] {
    fail(path, "OFF header declares " + std::to_string(counts.vertices) + " vertices and " +
                   std::to_string(counts.faces) + " faces, more than the file can hold");
  };
  if (isBinary()) {
    // int32 counts (OpenMesh writes them little-endian), then x y z floats per vertex and at
    // least a count and three indices per face.
    if (data.size() < at + 12) fail(path, "truncated OFF header");
    std::uint32_t n[2];
    std::memcpy(n, data.data() + at, 8);
    counts = {n[0], n[1]};
    if (counts.vertices * 12 + counts.faces * 16 > data.size() - at) tooLarge();
    return counts;
  }
  if (words.size() < 4) fail(path, "OFF header lacks the vertex and face counts");
  for (int i = 0; i < 2; ++i) {
    std::uint64_t& c = i == 0 ? counts.vertices : counts.faces;
    const std::string& w = words[1 + i];
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
    if (ext == "off") off = checkOffHeader(path, data);
    if (ext == "stl") checkStl(path, data);
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

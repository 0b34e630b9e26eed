// Every loader format round trips a mesh written by OpenMesh's writers; truncated and garbage
// OFF, STL and OBJ files are errors.
#include <gtest/gtest.h>

#include <cstdint>
#include <ostream>
#include <string>

// GCC 12 sees OpenMesh's colour property (VectorT<unsigned char, 3>, left uninitialized by its
// default constructor) copied in PropertyT::push_back when this file shares a unity build's unit.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <glm/geometric.hpp>

#include "mesh/load_mesh.h"
#include "mesh/primitives.h"
#include "test_util.h"

namespace sss {
namespace {

using test::expectError;
using test::expectLoadRefused;
using test::readFile;
using test::ScratchDir;
using test::writeFile;

using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

OMesh toOpenMesh(const TriangleMesh& m) {
  OMesh om;
  om.request_vertex_normals();
  std::vector<OMesh::VertexHandle> v;
  for (std::size_t i = 0; i < m.vertexCount(); ++i) {
    const glm::vec3& p = m.positions[i];
    v.push_back(om.add_vertex(OMesh::Point(p.x, p.y, p.z)));
    om.set_normal(v.back(), OMesh::Normal(m.normals[i].x, m.normals[i].y, m.normals[i].z));
  }
  for (const glm::uvec3& t : m.triangles) om.add_face(v[t.x], v[t.y], v[t.z]);
  return om;
}

struct Format {
  const char* name;
  const char* ext;
  OpenMesh::IO::Options::Flag flags;
  bool normals;     // the format carries vertex normals
  bool exactOrder;  // vertices come back in the same order
};

// What ctest -N and a failure print for a parameter (instead of its bytes).
void PrintTo(const Format& f, std::ostream* out) {
  *out << f.name;
}

class MeshFormatRoundTrip : public ::testing::TestWithParam<Format> {};

TEST_P(MeshFormatRoundTrip, LoadsWhatOpenMeshWrote) {
  const Format f = GetParam();
  ScratchDir dir;
  const TriangleMesh sphere = makeIcosphere(2, 3.0f);
  const std::string path = dir.path(std::string("sphere.") + f.ext);
  OpenMesh::IO::Options options(f.flags);
  if (f.normals) options += OpenMesh::IO::Options::VertexNormal;
  ASSERT_TRUE(OpenMesh::IO::write_mesh(toOpenMesh(sphere), path, options));
  MeshReport report;
  const TriangleMesh m = loadMesh(path, &report);
  EXPECT_EQ(m.vertexCount(), sphere.vertexCount());
  EXPECT_EQ(m.triangleCount(), sphere.triangleCount());
  EXPECT_EQ(report.droppedDegenerate + report.droppedDuplicate + report.droppedUnreferenced, 0u);
  EXPECT_EQ(report.boundaryEdges, 0u);
  EXPECT_FALSE(report.orientationFlipped);
  EXPECT_EQ(report.normalsComputed, !f.normals);
  EXPECT_NEAR(surfaceArea(m), surfaceArea(sphere), 1e-4 * surfaceArea(sphere));
  EXPECT_NEAR(signedVolume(m), signedVolume(sphere), 1e-4 * signedVolume(sphere));
  for (std::size_t i = 0; i < m.vertexCount(); ++i) {
    if (f.exactOrder) {
      EXPECT_NEAR(glm::distance(m.positions[i], sphere.positions[i]), 0.0f, 1e-5f);
    }
    EXPECT_GT(glm::dot(m.normals[i], glm::normalize(m.positions[i])), 0.99f);
  }
}

using Opt = OpenMesh::IO::Options;
INSTANTIATE_TEST_SUITE_P(MeshFormats, MeshFormatRoundTrip,
                         ::testing::Values(Format{"PlyAscii", "ply", Opt::Default, true, true},
                                           Format{"PlyBinary", "ply", Opt::Binary, true, true},
                                           Format{"PlyBinaryNoNormals", "ply", Opt::Binary, false,
                                                  true},
                                           Format{"Obj", "obj", Opt::Default, true, true},
                                           Format{"Off", "off", Opt::Default, false, true},
                                           Format{"OffBinary", "off", Opt::Binary, false, true},
                                           Format{"StlAscii", "stl", Opt::Default, false, false},
                                           Format{"StlBinary", "stl", Opt::Binary, false, false},
                                           Format{"Om", "om", Opt::Default, true, true}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(MeshFormatErrors, TruncatedOffAndStlAndGarbage) {
  ScratchDir dir;
  const TriangleMesh box = makeBox(glm::vec3(1.0f), 2);
  for (const char* ext : {"off", "stl"}) {
    const std::string full = dir.path(std::string("box.") + ext);
    ASSERT_TRUE(OpenMesh::IO::write_mesh(toOpenMesh(box), full));
    const std::string text = readFile(full);
    const std::string cut = dir.path(std::string("cut.") + ext);
    writeFile(cut, text.substr(0, text.size() * 2 / 3));
    EXPECT_THROW(loadMesh(cut), Error) << ext;
  }
  const std::string binary = dir.path("binary.stl");
  ASSERT_TRUE(OpenMesh::IO::write_mesh(toOpenMesh(box), binary, Opt::Binary));
  const std::string bytes = readFile(binary);
  writeFile(binary, bytes.substr(0, bytes.size() - 10));
  expectError([&] { loadMesh(binary); }, binary, "not an STL file");

  expectLoadRefused(dir, "liar.off", "OFF\n2000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                    "more than the file can hold");
  expectLoadRefused(dir, "short.off",
                    "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n          \n", "truncated");
  expectLoadRefused(dir, "garbage.off", std::string(1000, 'z'), "not an OFF file");
  const std::string obj = dir.path("garbage.obj");
  writeFile(obj, "this is not\na mesh at all\n");
  EXPECT_THROW(loadMesh(obj), Error);
  expectLoadRefused(dir, "empty.obj", "", "empty file");
}

// Counts that OpenMesh's readers would loop and allocate over are checked first.
TEST(MeshFormatErrors, LyingCountsAreRefusedBeforeOpenMeshReads) {
  ScratchDir dir;
  const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n";
  expectLoadRefused(dir, "corners.off", "OFF\n3 1 0\n" + vertices + "2000000000 0 1 2\n",
                    "OFF face 0 declares 2000000000 corners, more than the rest of the file holds");
  expectLoadRefused(dir, "negative.off", "OFF\n3 1 0\n" + vertices + "-5 0 1 2\n",
                    "OFF face 0 declares -5 corners");
  expectLoadRefused(dir, "shortfaces.off", "OFF\n3 2 0\n" + vertices + "3 0 1 2\n3 0 1\n",
                    "OFF face 1 declares 3 corners, more than the rest of the file holds");
  auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  auto f32 = [](float v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  std::string binary = "OFF BINARY\n" + u32(3) + u32(1) + u32(0);
  for (float c : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) binary += f32(c);
  expectLoadRefused(dir, "corners_binary.off", binary + u32(2000000000) + u32(0) + u32(1) + u32(2),
                    "OFF face 0 declares 2000000000 corners");
  // Two faces declared, 32 bytes of face records (the size check's 16 a face), one 7-gon: past
  // the end OpenMesh would repeat the 7 for the missing face.
  std::string twoFaces = "OFF BINARY\n" + u32(3) + u32(2) + u32(0) + binary.substr(23) + u32(7);
  for (int i = 0; i < 7; ++i) twoFaces += u32(i % 3);
  expectLoadRefused(dir, "truncated_binary.off", twoFaces,
                    "OFF header declares 2 faces, but the file ends in face 1 (truncated)");
  // OM: magic, mesh type, version, then vertex, face and edge counts.
  const TriangleMesh box = makeBox(glm::vec3(1.0f), 1);
  const std::string om = dir.path("box.om");
  ASSERT_TRUE(OpenMesh::IO::write_mesh(toOpenMesh(box), om));
  std::string bytes = readFile(om);
  ASSERT_EQ(bytes.compare(0, 2, "OM"), 0);
  bytes.replace(8, 4, u32(0x7fffffff));  // faces
  expectLoadRefused(dir, "faces.om", bytes,
                    "OM header declares 8 vertices, 2147483647 faces and 18 edges, more than the "
                    "file can hold");
}

TEST(MeshFormatErrors, HugeCoordinateInEveryFormatIsAnError) {
  // Unchecked, Embree's ray.valid() assertion aborts the bake.
  ScratchDir dir;
  TriangleMesh box = makeBox(glm::vec3(1.0f), 1);
  box.positions[3].y = 1e38f;
  for (const char* ext : {"off", "obj", "stl", "om"}) {
    const std::string file = dir.path(std::string("huge.") + ext);
    ASSERT_TRUE(OpenMesh::IO::write_mesh(toOpenMesh(box), file, OpenMesh::IO::Options::Binary));
    expectError([&] { loadMesh(file); }, file, "beyond the limit of 1e+18 for float geometry");
  }
}

TEST(MeshFormatErrors, ObjWithNanAndNonManifoldFaces) {
  ScratchDir dir;
  const std::string nan = dir.path("nan.obj");
  writeFile(nan, "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n");
  EXPECT_THROW(loadMesh(nan), Error);
  // Three faces on one edge: OpenMesh's own mesh would split them; our report counts the edge.
  const std::string fin = dir.path("fin.obj");
  writeFile(fin, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  MeshReport report;
  const TriangleMesh m = loadMesh(fin, &report);
  EXPECT_EQ(m.vertexCount(), 5u);
  EXPECT_EQ(m.triangleCount(), 3u);
  EXPECT_EQ(report.nonManifoldEdges, 1u);
}

}  // namespace
}  // namespace sss

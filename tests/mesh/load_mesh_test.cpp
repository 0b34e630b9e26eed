// Validation and cleanup (cleanMesh) and the strict PLY reader's handling of bad files.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include <glm/geometric.hpp>

#include "mesh/load_mesh.h"
#include "mesh/primitives.h"
#include "test_util.h"

namespace sss {
namespace {

using test::expectError;
using test::expectLoadRefused;
using test::ScratchDir;
using test::writeFile;

RawMesh rawOf(const TriangleMesh& mesh, bool withNormals = true) {
  RawMesh raw;
  raw.positions = mesh.positions;
  if (withNormals) raw.normals = mesh.normals;
  for (const glm::uvec3& t : mesh.triangles) raw.addFace({t.x, t.y, t.z});
  return raw;
}

// A unit square (two triangles) as ASCII PLY text.
std::string asciiPly(const std::string& extraHeader = "") {
  return "ply\nformat ascii 1.0\ncomment made by hand\n" + extraHeader +
         "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
         "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
}

// asciiPly() with the first `from` replaced by `to`: one defect in an otherwise good file.
std::string asciiPlyWith(const std::string& from, const std::string& to) {
  std::string text = asciiPly();
  text.replace(text.find(from), from.size(), to);
  return text;
}

TEST(MeshClean, DropsDegenerateAndDuplicateFacesWithCounts) {
  RawMesh raw = rawOf(makeBox(glm::vec3(1.0f), 1));
  raw.positions.push_back(raw.positions[0]);  // 8: same place as vertex 0
  raw.positions.push_back({5, 5, 5});         // 9: unreferenced after the drops
  raw.addFace({0, 0, 1});                     // repeated index
  raw.addFace({0, 8, 1});                     // zero area (two corners coincide)
  raw.addFace({1, 2});                        // too few corners
  raw.addFace({raw.faceCorners[2], raw.faceCorners[1], raw.faceCorners[0]});  // duplicate
  raw.addFace({raw.faceCorners[3], raw.faceCorners[4], raw.faceCorners[5]});  // duplicate
  raw.normals.clear();
  MeshReport report;
  const TriangleMesh m = cleanMesh("m.ply", raw, &report);
  EXPECT_EQ(report.fileFaces, 12u + 5u);
  EXPECT_EQ(report.droppedDegenerate, 3u);
  EXPECT_EQ(report.droppedDuplicate, 2u);
  EXPECT_EQ(report.droppedUnreferenced, 2u);
  EXPECT_EQ(m.triangleCount(), 12u);
  EXPECT_EQ(m.vertexCount(), 8u);
  EXPECT_EQ(report.boundaryEdges, 0u);
  EXPECT_TRUE(report.normalsComputed);
  EXPECT_GE(report.warnings.size(), 3u);
}

TEST(MeshClean, TriangulatesPolygonsAndKeepsVertexOrigin) {
  RawMesh raw;
  raw.positions = {{9, 9, 9}, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  raw.addFace({1, 2, 3, 4});
  MeshReport report;
  std::vector<unsigned> origin;
  const TriangleMesh m = cleanMesh("quad.obj", raw, &report, &origin);
  EXPECT_EQ(report.triangulatedPolygons, 1u);
  ASSERT_EQ(m.triangleCount(), 2u);
  EXPECT_EQ(origin, (std::vector<unsigned>{1, 2, 3, 4}));
  EXPECT_NEAR(surfaceArea(m), 1.0, 1e-7);
  EXPECT_EQ(report.boundaryEdges, 4u);
  for (const glm::vec3& n : m.normals) EXPECT_EQ(n, glm::vec3(0, 0, 1));
}

TEST(MeshClean, NonManifoldEdgeAndVertexAreReported) {
  // Three triangles on the edge 0-1.
  RawMesh fin;
  fin.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  fin.addFace({0, 1, 2});
  fin.addFace({1, 0, 3});
  fin.addFace({0, 1, 4});
  MeshReport a;
  cleanMesh("fin.ply", fin, &a);
  EXPECT_EQ(a.nonManifoldEdges, 1u);
  EXPECT_FALSE(a.warnings.empty());

  // Two closed tetrahedra touching at one vertex (a bow tie): manifold edges, one vertex.
  RawMesh bowtie;
  bowtie.positions = {{0, 0, 0},  {1, 0, 0},  {0, 1, 0}, {0, 0, 1},
                      {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  for (unsigned o : {0u, 3u}) {
    const unsigned a1 = o == 0 ? 1 : 4, b = o == 0 ? 2 : 5, c = o == 0 ? 3 : 6;
    bowtie.addFace({0, b, a1});
    bowtie.addFace({0, a1, c});
    bowtie.addFace({0, c, b});
    bowtie.addFace({a1, b, c});
  }
  MeshReport b;
  cleanMesh("bowtie.ply", bowtie, &b);
  EXPECT_EQ(b.nonManifoldEdges, 0u);
  EXPECT_EQ(b.misorientedEdges, 0u);
  EXPECT_EQ(b.nonManifoldVertices, 1u);
  EXPECT_EQ(b.components, 1u);
  EXPECT_EQ(b.boundaryEdges, 0u);

  // A manifold box has none of these.
  MeshReport c;
  cleanMesh("box.ply", rawOf(makeBox(glm::vec3(1.0f), 2)), &c);
  EXPECT_EQ(c.nonManifoldVertices + c.nonManifoldEdges + c.misorientedEdges, 0u);
  EXPECT_TRUE(c.warnings.empty());
}

TEST(MeshClean, MisorientedFaceIsCountedAndNotFlippedGlobally) {
  RawMesh raw = rawOf(makeBox(glm::vec3(1.0f), 1));
  std::swap(raw.faceCorners[1], raw.faceCorners[2]);  // one face wound the wrong way
  MeshReport report;
  cleanMesh("box.ply", raw, &report);
  EXPECT_EQ(report.misorientedEdges, 3u);
  EXPECT_FALSE(report.orientationFlipped);
}

TEST(MeshClean, InsideOutClosedMeshIsFlipped) {
  const TriangleMesh sphere = makeIcosphere(2, 1.0f);
  RawMesh raw = rawOf(sphere);
  for (std::size_t f = 0; f < raw.faceSizes.size(); ++f) {
    std::swap(raw.faceCorners[3 * f + 1], raw.faceCorners[3 * f + 2]);
  }
  for (glm::vec3& n : raw.normals) n = -n;  // inward, consistent with the winding
  MeshReport report;
  const TriangleMesh m = cleanMesh("inside-out.ply", raw, &report);
  EXPECT_TRUE(report.orientationFlipped);
  EXPECT_TRUE(report.normalsNegated);
  EXPECT_GT(signedVolume(m), 0.0);
  for (std::size_t i = 0; i < m.vertexCount(); ++i) {
    EXPECT_GT(glm::dot(m.normals[i], m.positions[i]), 0.99f);
  }
  // An open mesh is never flipped: a plane facing -Z stays so.
  RawMesh plane = rawOf(makeGridPlane(2, 1.0f), false);
  for (std::size_t f = 0; f < plane.faceSizes.size(); ++f) {
    std::swap(plane.faceCorners[3 * f + 1], plane.faceCorners[3 * f + 2]);
  }
  MeshReport open;
  const TriangleMesh p = cleanMesh("plane.ply", plane, &open);
  EXPECT_FALSE(open.orientationFlipped);
  EXPECT_EQ(p.normals[0], glm::vec3(0, 0, -1));
}

TEST(MeshClean, RejectsNonFiniteCoordinatesBadIndicesAndNoFaces) {
  RawMesh nan = rawOf(makeBox(glm::vec3(1.0f), 1));
  nan.positions[5].y = std::numeric_limits<float>::quiet_NaN();
  expectError([&] { cleanMesh("nan.ply", nan, nullptr); }, "nan.ply", "vertex 5");
  RawMesh inf = rawOf(makeBox(glm::vec3(1.0f), 1));
  inf.positions[2].x = std::numeric_limits<float>::infinity();
  expectError([&] { cleanMesh("inf.ply", inf, nullptr); }, "inf.ply", "non-finite");
  RawMesh index = rawOf(makeBox(glm::vec3(1.0f), 1));
  index.addFace({0, 1, 99});
  expectError([&] { cleanMesh("i.ply", index, nullptr); }, "i.ply", "vertex 99");
  RawMesh points;
  points.positions = {{0, 0, 0}, {1, 0, 0}};
  expectError([&] { cleanMesh("p.ply", points, nullptr); }, "p.ply", "no faces");
  RawMesh degenerate;
  degenerate.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  degenerate.addFace({0, 1, 2});
  expectError([&] { cleanMesh("d.ply", degenerate, nullptr); }, "d.ply", "degenerate");
}

TEST(MeshPlyReader, AsciiLoadsWithCommentsAndQuads) {
  ScratchDir dir;
  const std::string path = dir.path("square.ply");
  writeFile(path,
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
            "property double z\nproperty uchar red\nelement face 1\n"
            "property list uchar uint vertex_indices\nend_header\n"
            "0 0 0 1\n1 0 0 2\n1 1 0 3\n+0 1 0 4\n4 0 1 2 3\n");
  MeshReport report;
  const TriangleMesh m = loadMesh(path, &report);
  EXPECT_EQ(report.format, "ply-ascii");
  EXPECT_EQ(m.triangleCount(), 2u);
  EXPECT_EQ(report.triangulatedPolygons, 1u);
  EXPECT_NEAR(surfaceArea(m), 1.0, 1e-7);
}

TEST(MeshPlyReader, TruncatedAsciiIsAnError) {
  ScratchDir dir;
  const std::string full = asciiPly();
  for (std::size_t cut : {std::size_t{8}, std::size_t{14}, std::size_t{30}}) {
    const std::string path = dir.path("cut" + std::to_string(cut) + ".ply");
    writeFile(path, full.substr(0, full.size() - cut));
    EXPECT_THROW(loadMesh(path), Error) << cut;
  }
  expectLoadRefused(dir, "cut.ply", full.substr(0, full.size() - 8), "truncated");  // in face 1
}

TEST(MeshPlyReader, TruncatedBinaryIsAnError) {
  ScratchDir dir;
  std::string body;
  auto putF = [&](float f) { body.append(reinterpret_cast<const char*>(&f), 4); };
  auto putI = [&](int i) { body.append(reinterpret_cast<const char*>(&i), 4); };
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 1.f, 1.f, 0.f}) putF(v);
  body.push_back(3);
  for (int i : {0, 1, 2}) putI(i);
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  const std::string good = dir.path("good.ply");
  writeFile(good, header + body);
  EXPECT_EQ(loadMesh(good).triangleCount(), 1u);
  expectLoadRefused(dir, "cut.ply", header + body.substr(0, body.size() - 3), "truncated");
  expectLoadRefused(dir, "cutv.ply", header + body.substr(0, 20), "truncated");
}

TEST(MeshPlyReader, LyingHeaderFailsFastWithoutAllocating) {
  ScratchDir dir;
  const std::string path = dir.path("liar.ply");
  for (const char* format : {"ascii", "binary_little_endian"}) {
    writeFile(path, std::string("ply\nformat ") + format +
                        " 1.0\nelement vertex 4000000000000\nproperty float x\nproperty float "
                        "y\nproperty float z\nelement face 18446744073709551615\n"
                        "property list uchar int vertex_indices\nend_header\n0 0 0\n");
    // Refused from the header alone (the fuzz targets' allocation limit checks the "without
    // allocating"; no timing here: timed tests flake under the sanitizers and load).
    expectError([&] { loadMesh(path); }, path, "declares 4000000000000 vertex");
  }
  // Face count too large for the bytes that follow the vertices.
  writeFile(path,
            "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n"
            "property float y\nproperty float z\nelement face 100000000\n"
            "property list uchar int vertex_indices\nend_header\n\x03");
  expectError([&] { loadMesh(path); }, path, "declares 100000000 face");
}

TEST(MeshPlyReader, GarbageEmptyAndMalformedFiles) {
  ScratchDir dir;
  expectLoadRefused(dir, "empty.ply", "", "empty file");
  std::string bytes(5000, '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>((i * 7919) % 251);
  expectLoadRefused(dir, "garbage.ply", bytes, "not a PLY file");
  expectLoadRefused(dir, "noend.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\n" + std::string(70000, '\n'),
                    "end_header");
  expectLoadRefused(dir, "badnumber.ply", asciiPlyWith("1 1 0", "1 x 0"), "bad number 'x'");
  expectLoadRefused(dir, "badtype.ply", asciiPlyWith("property float y", "property quad y"),
                    "bad type 'quad'");
  const std::string missing = dir.path("missing.ply");
  expectError([&] { loadMesh(missing); }, missing, "cannot open");
  expectLoadRefused(dir, "mesh.xyz", "1 2 3\n", "unknown mesh format");
}

TEST(MeshPlyReader, ZeroFacesNanAndBadIndexInFiles) {
  ScratchDir dir;
  expectLoadRefused(dir, "zero.ply",
                    "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 0\nproperty list uchar int vertex_indices\n"
                    "end_header\n0 0 0\n1 1 1\n",
                    "no faces");
  expectLoadRefused(dir, "nan.ply", asciiPlyWith("1 1 0", "1 nan 0"),
                    "vertex 2 has a non-finite coordinate");
  expectLoadRefused(dir, "index.ply", asciiPlyWith("3 0 2 3", "3 0 2 7"), "refers to vertex 7");
  expectLoadRefused(dir, "negative.ply", asciiPlyWith("3 0 2 3", "3 0 2 -1"), "out of range");
}

// Geometry float ray tracing cannot carry (kMaxCoordinate, kMaxReachInEdges).
TEST(MeshGeometryLimits, CoordinateBeyondTheLimitIsAnError) {
  TriangleMesh sphere = makeIcosphere(1, 1.0f);
  sphere.positions[7] = glm::vec3(1e38f, 0.5f, 0.25f);
  expectError([&] { cleanMesh("huge.ply", rawOf(sphere, false), nullptr); }, "huge.ply",
              "vertex 7 (1e+38, 0.5, 0.25) has a coordinate of 1e+38, beyond the limit of 1e+18 "
              "for float geometry");
  // A whole mesh scaled up: its shape is fine, its size is not.
  TriangleMesh big = makeIcosphere(1, 1e19f);
  expectError([&] { cleanMesh("big.ply", rawOf(big, false), nullptr); }, "big.ply",
              "beyond the limit of 1e+18");
  // The bake's bound in millimetres, after scaling.
  const TriangleMesh km = makeIcosphere(1, 2e7f);
  expectError([&] { checkCoordinateRange("km.ply", km, kMaxCoordinateMm, "mm"); }, "km.ply",
              "has a coordinate of 2e+07 mm, beyond the limit of 16777216 mm");
  EXPECT_NO_THROW(checkCoordinateRange("km.ply", makeIcosphere(1, 1.6e7f), kMaxCoordinateMm));
}

TEST(MeshGeometryLimits, StrayVertexOrFarMeshIsAnErrorAtOnce) {
  // Unchecked: more than 120 s in the bake.
  TriangleMesh sphere = makeIcosphere(1, 10.0f);
  ASSERT_EQ(sphere.vertexCount(), 42u);
  sphere.positions[7].x = 1.7e15f;
  expectError([&] { cleanMesh("far.ply", rawOf(sphere, false), nullptr); }, "far.ply",
              "the mesh reaches 1.7e+15 (vertex 7 at (1.7e+15, ");
  expectError([&] { cleanMesh("far.ply", rawOf(sphere, false), nullptr); }, "far.ply",
              "times its median edge length 6.18: float ray tracing resolves at most 65536 (2^16)");
  // A whole mesh far from its origin fails alike; 2^15 edges away it passes.
  TriangleMesh moved = makeIcosphere(1, 1.0f);
  const float edge =
      glm::length(moved.positions[moved.triangles[0].x] - moved.positions[moved.triangles[0].y]);
  for (glm::vec3& p : moved.positions) p.x += 32768.0f * edge;
  EXPECT_NO_THROW(cleanMesh("near.ply", rawOf(moved, false), nullptr));
  for (glm::vec3& p : moved.positions) p.x += 131072.0f * edge;
  expectError([&] { cleanMesh("moved.ply", rawOf(moved, false), nullptr); }, "moved.ply",
              "a stray vertex, or a mesh far from its origin?");
}

TEST(MeshGeometryLimits, UnreferencedFarVertexIsDroppedNotAnError) {
  const TriangleMesh sphere = makeIcosphere(1, 1.0f);
  RawMesh raw = rawOf(sphere, false);
  raw.positions.push_back(glm::vec3(1e38f));
  MeshReport report;
  const TriangleMesh m = cleanMesh("m.ply", raw, &report);
  EXPECT_EQ(report.droppedUnreferenced, 1u);
  EXPECT_EQ(m.positions, sphere.positions);
}

TEST(MeshPlyReader, DirectoryIsNamedNotAllocated) {
  // Unchecked: "std::bad_alloc" (a directory opens as a stream of unbounded size).
  ScratchDir dir;
  for (const char* name : {"d.ply", "d.off", "d.obj", "d.stl", "d.om"}) {
    const std::string folder = dir.path(name);
    std::filesystem::create_directory(folder);
    expectError([&] { loadMesh(folder); }, folder, "is a directory, not a file");
  }
}

TEST(MeshPlyReader, BigEndianMatchesLittleEndian) {
  ScratchDir dir;
  const TriangleMesh sphere = makeIcosphere(1, 1.0f);
  std::string le, be;
  auto put = [&](const void* p, std::size_t n) {
    const char* c = static_cast<const char*>(p);
    le.append(c, n);
    for (std::size_t i = 0; i < n; ++i) be.push_back(c[n - 1 - i]);
  };
  for (const glm::vec3& p : sphere.positions) {
    for (int k = 0; k < 3; ++k) put(&p[k], 4);
  }
  for (const glm::uvec3& t : sphere.triangles) {
    const unsigned char three = 3;
    put(&three, 1);
    for (int k = 0; k < 3; ++k) {
      const int i = static_cast<int>(t[k]);
      put(&i, 4);
    }
  }
  auto header = [&](const char* f) {
    return std::string("ply\nformat ") + f + " 1.0\nelement vertex " +
           std::to_string(sphere.vertexCount()) +
           "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
           std::to_string(sphere.triangleCount()) +
           "\nproperty list uchar int vertex_indices\nend_header\r\n";
  };
  writeFile(dir.path("le.ply"), header("binary_little_endian") + le);
  writeFile(dir.path("be.ply"), header("binary_big_endian") + be);
  MeshReport report;
  const TriangleMesh a = loadMesh(dir.path("le.ply"));
  const TriangleMesh b = loadMesh(dir.path("be.ply"), &report);
  EXPECT_EQ(report.format, "ply-binary-be");
  EXPECT_EQ(a.positions, sphere.positions);
  EXPECT_EQ(b.positions, sphere.positions);
  EXPECT_EQ(b.triangles, sphere.triangles);
}

}  // namespace
}  // namespace sss

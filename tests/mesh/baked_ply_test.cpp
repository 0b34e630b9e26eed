// The baked PLY: bit-exact round trip, header comments, preview colours, OpenMesh reads it,
// plain meshes load with nothing baked, and failures leave no file behind.
// GCC 12 flags OpenMesh's uninitialized default colour vectors (Vec3uc) when a mesh requests
// vertex colours; that code is OpenMesh's, not ours.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include <gtest/gtest.h>

#include <cstring>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "core/random.h"
#include "mesh/baked_ply.h"
#include "mesh/primitives.h"
#include "test_util.h"

namespace sss {
namespace {

using test::bitEqual;
using test::expectError;
using test::readFile;
using test::ScratchDir;
using test::writeFile;

BakedMesh sampleBake(int subdivisions = 2) {
  BakedMesh b;
  b.mesh = makeIcosphere(subdivisions, 75.0f);
  Pcg32 rng(7, 0);
  for (std::size_t i = 0; i < b.mesh.vertexCount(); ++i) {
    b.irradiance.push_back({rng.uniform() * 3, rng.uniform() * 3, rng.uniform() * 3});
    b.exitance.push_back({rng.uniform() * 0.1f, rng.uniform() * 1e-3f, rng.uniform() * 1e-7f});
    b.radianceNormal.push_back({rng.uniform() * 0.03f, rng.uniform() * 3e-4f, rng.uniform()});
    b.farExitance.push_back(b.exitance.back() * rng.uniform());
    b.exitSlope.push_back({rng.uniform() * 2 - 1, rng.uniform() * 5, rng.uniform() - 0.5f});
  }
  b.materialName = "marble";
  b.sigmaA = {0.0021, 0.0041, 0.0071};
  b.sigmaSPrime = {2.19, 2.62, 3.00};
  b.eta = 1.3;
  b.mmPerUnit = 0.1 + 0.2;  // not exactly representable in short decimal
  b.extraComments = {"sss method=gauss tolerance=0.01", "made by a test"};
  return b;
}

TEST(MeshBakedPly, RoundTripIsBitExact) {
  ScratchDir dir;
  const BakedMesh b = sampleBake();
  const std::string path = dir.path("baked.ply");
  writeBakedPly(path, b);
  const BakedPlyContents r = readBakedPly(path);
  EXPECT_TRUE(r.hasIrradiance);
  EXPECT_TRUE(r.hasExitance);
  EXPECT_TRUE(r.hasRadianceNormal);
  EXPECT_TRUE(r.hasFarField);
  EXPECT_TRUE(r.hasMaterial);
  EXPECT_TRUE(r.hasUnits);
  EXPECT_TRUE(r.report.warnings.empty());
  EXPECT_TRUE(bitEqual(r.baked.mesh.positions, b.mesh.positions));
  EXPECT_TRUE(bitEqual(r.baked.mesh.normals, b.mesh.normals));
  EXPECT_TRUE(bitEqual(r.baked.mesh.triangles, b.mesh.triangles));
  EXPECT_TRUE(bitEqual(r.baked.irradiance, b.irradiance));
  EXPECT_TRUE(bitEqual(r.baked.exitance, b.exitance));
  EXPECT_TRUE(bitEqual(r.baked.radianceNormal, b.radianceNormal));
  EXPECT_TRUE(bitEqual(r.baked.farExitance, b.farExitance));
  EXPECT_TRUE(bitEqual(r.baked.exitSlope, b.exitSlope));
  EXPECT_EQ(r.baked.materialName, "marble");
  EXPECT_EQ(r.baked.sigmaA, b.sigmaA);
  EXPECT_EQ(r.baked.sigmaSPrime, b.sigmaSPrime);
  EXPECT_EQ(r.baked.eta, 1.3);
  EXPECT_EQ(r.baked.mmPerUnit, 0.1 + 0.2);
  EXPECT_EQ(r.baked.extraComments, b.extraComments);
  EXPECT_GT(r.baked.previewScale, 0.0);
  // Writing what was read gives the same bytes.
  const std::string again = dir.path("again.ply");
  writeBakedPly(again, r.baked);
  EXPECT_EQ(readFile(again), readFile(path));
}

TEST(MeshBakedPly, HeaderIsDocumentedAndPreviewIsExposed) {
  ScratchDir dir;
  BakedMesh b;
  b.mesh = makeGridPlane(1, 1.0f);
  b.exitance = {{0.5f, 0.25f, 0.0f}, {1.0f, 1.0f, 1.0f}, {2.0f, 0.0f, 0.0f}, {0, 0, 0}};
  b.previewScale = 0.5;
  b.materialName = "skin1";
  const std::string path = dir.path("plane.ply");
  writeBakedPly(path, b);
  const std::string text = readFile(path);
  const std::string header = text.substr(0, text.find("end_header"));
  EXPECT_NE(header.find("format binary_little_endian 1.0\n"), std::string::npos);
  EXPECT_NE(header.find("comment sss material=skin1\n"), std::string::npos);
  EXPECT_NE(header.find("comment sss eta=1\n"), std::string::npos);
  EXPECT_NE(header.find("comment sss mm_per_unit=1\n"), std::string::npos);
  EXPECT_NE(header.find("comment sss preview_scale=0.5\n"), std::string::npos);
  EXPECT_EQ(header.find("irradiance_r"), std::string::npos);  // not given, not invented
  // Preview bytes: sRGB(0.5 * B): 0.25 -> 137, 0.125 -> 99, 0.5 -> 188, >= 1 -> 255.
  OpenMesh::TriMesh_ArrayKernelT<> om;
  om.request_vertex_colors();
  OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexColor;
  ASSERT_TRUE(OpenMesh::IO::read_mesh(om, path, options));
  ASSERT_TRUE(options.vertex_has_color());
  auto color = [&](int i) { return om.color(OpenMesh::VertexHandle(i)); };
  EXPECT_EQ(color(0), OpenMesh::Vec3uc(137, 99, 0));
  EXPECT_EQ(color(1), OpenMesh::Vec3uc(188, 188, 188));
  EXPECT_EQ(color(2), OpenMesh::Vec3uc(255, 0, 0));
  const BakedPlyContents r = readBakedPly(path);
  EXPECT_FALSE(r.hasIrradiance);
  EXPECT_TRUE(r.hasExitance);
}

TEST(MeshBakedPly, OpenMeshReadsItBack) {
  ScratchDir dir;
  const BakedMesh b = sampleBake();
  const std::string path = dir.path("baked.ply");
  writeBakedPly(path, b);
  OpenMesh::TriMesh_ArrayKernelT<> om;
  om.request_vertex_normals();
  om.request_vertex_colors();
  OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexNormal |
                                  OpenMesh::IO::Options::VertexColor |
                                  OpenMesh::IO::Options::Binary | OpenMesh::IO::Options::LSB;
  ASSERT_TRUE(OpenMesh::IO::read_mesh(om, path, options));
  EXPECT_TRUE(options.vertex_has_normal());
  EXPECT_TRUE(options.vertex_has_color());
  ASSERT_EQ(om.n_vertices(), b.mesh.vertexCount());
  ASSERT_EQ(om.n_faces(), b.mesh.triangleCount());
  for (const auto v : om.vertices()) {
    const auto& p = om.point(v);
    const glm::vec3& q = b.mesh.positions[v.idx()];
    EXPECT_EQ(p[0], q.x);
    EXPECT_EQ(p[1], q.y);
    EXPECT_EQ(p[2], q.z);
    EXPECT_EQ(om.normal(v)[2], b.mesh.normals[v.idx()].z);
  }
}

TEST(MeshBakedPly, PlainMeshesLoadWithNothingBaked) {
  ScratchDir dir;
  const TriangleMesh sphere = makeIcosphere(1, 1.0f);
  OpenMesh::TriMesh_ArrayKernelT<> om;
  std::vector<OpenMesh::VertexHandle> v;
  for (const glm::vec3& p : sphere.positions) v.push_back(om.add_vertex({p.x, p.y, p.z}));
  for (const glm::uvec3& t : sphere.triangles) om.add_face(v[t.x], v[t.y], v[t.z]);
  for (const char* name : {"plain.ply", "plain.obj"}) {
    const std::string path = dir.path(name);
    ASSERT_TRUE(OpenMesh::IO::write_mesh(om, path));
    const BakedPlyContents r = readBakedPly(path);
    EXPECT_FALSE(r.hasIrradiance || r.hasExitance || r.hasMaterial || r.hasUnits) << name;
    EXPECT_EQ(r.baked.mesh.triangleCount(), sphere.triangleCount()) << name;
    EXPECT_TRUE(r.report.normalsComputed) << name;
  }
}

TEST(MeshBakedPly, ValuesFollowTheirVerticesThroughCleanup) {
  ScratchDir dir;
  const std::string path = dir.path("unref.ply");
  // Vertex 0 is unreferenced: the values of vertices 1..3 must come back for 0..2.
  std::string body;
  auto f = [&](float x) { body.append(reinterpret_cast<const char*>(&x), 4); };
  const float data[4][4] = {{9, 9, 9, 99}, {0, 0, 0, 10}, {1, 0, 0, 11}, {0, 1, 0, 12}};
  for (const auto& row : data) {
    for (int k = 0; k < 3; ++k) f(row[k]);
    for (int k = 0; k < 3; ++k) f(row[3]);  // exitance_r/g/b
  }
  body.push_back(3);
  for (int i : {1, 2, 3}) body.append(reinterpret_cast<const char*>(&i), 4);
  writeFile(path,
            "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
            "property float y\nproperty float z\nproperty float exitance_r\nproperty float "
            "exitance_g\nproperty float exitance_b\nelement face 1\nproperty list uchar int "
            "vertex_indices\nend_header\n" +
                body);
  const BakedPlyContents r = readBakedPly(path);
  ASSERT_EQ(r.baked.exitance.size(), 3u);
  EXPECT_EQ(r.baked.exitance[0], glm::vec3(10.0f));
  EXPECT_EQ(r.baked.exitance[2], glm::vec3(12.0f));
  EXPECT_EQ(r.report.droppedUnreferenced, 1u);
}

TEST(MeshBakedPly, BadFilesAreErrors) {
  ScratchDir dir;
  const std::string good = dir.path("good.ply");
  writeBakedPly(good, sampleBake(1));
  const std::string text = readFile(good);
  auto variant = [&](const std::string& name, const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    const std::string path = dir.path(name);
    writeFile(path, t);
    return path;
  };
  const std::string partial =
      variant("partial.ply", "property float exitance_b", "property float something");
  expectError([&] { readBakedPly(partial); }, partial, "exitance_r/g/b");
  // A far field comes with the slopes its exits measured.
  const std::string lonely = variant("lonely.ply",
                                     "property float exit_slope_r\nproperty float exit_slope_g\n"
                                     "property float exit_slope_b",
                                     "property float a\nproperty float b\n"
                                     "property float c");
  expectError([&] { readBakedPly(lonely); }, lonely, "far_exitance without exit_slope");
  // Files written before the exit lobe had its own name: far_exit_slope reads as the slope.
  const std::string legacy =
      variant("legacy.ply",
              "property float exit_slope_r\nproperty float exit_slope_g\n"
              "property float exit_slope_b",
              "property float far_exit_slope_r\nproperty float far_exit_slope_g\n"
              "property float far_exit_slope_b");
  const BakedPlyContents old = readBakedPly(legacy), now = readBakedPly(good);
  EXPECT_TRUE(old.hasExitSlope);
  EXPECT_TRUE(bitEqual(old.baked.exitSlope, now.baked.exitSlope));
  const std::string eta = variant("eta.ply", "comment sss eta=1.3", "comment sss eta=abc");
  expectError([&] { readBakedPly(eta); }, eta, "eta=abc");
  const std::string noEta = variant("noeta.ply", "comment sss eta=1.3", "comment nothing");
  expectError([&] { readBakedPly(noEta); }, noEta, "incomplete material");
  const std::string unscattered = variant("unscattered.ply", "comment sss eta=1.3",
                                          "comment sss eta=1.3\ncomment sss unscattered=yes");
  expectError([&] { readBakedPly(unscattered); }, unscattered, "unscattered=yes");
  const std::string newer = variant("newer.ply", "sss format=1", "sss format=4");
  expectError([&] { readBakedPly(newer); }, newer, "newer");
  const std::string cut = dir.path("cut.ply");
  writeFile(cut, text.substr(0, text.size() - 100));
  expectError([&] { readBakedPly(cut); }, cut, "truncated");
}

TEST(MeshBakedPly, FailedWritesLeaveNoFile) {
  ScratchDir dir;
  const std::string path = dir.path("out.ply");
  BakedMesh nan = sampleBake(1);
  nan.exitance[3].y = std::numeric_limits<float>::quiet_NaN();
  expectError([&] { writeBakedPly(path, nan); }, path, "exitance of vertex 3");
  BakedMesh count = sampleBake(1);
  count.irradiance.pop_back();
  expectError([&] { writeBakedPly(path, count); }, path, "irradiance has");
  BakedMesh name = sampleBake(1);
  name.materialName = "my marble";
  expectError([&] { writeBakedPly(path, name); }, path, "material name");
  BakedMesh slope = sampleBake(1);
  slope.exitSlope[2].x = -1.5f;  // would make the interior radiance negative
  expectError([&] { writeBakedPly(path, slope); }, path, "exit_slope of vertex 2");
  BakedMesh half = sampleBake(1);
  half.exitSlope.clear();
  expectError([&] { writeBakedPly(path, half); }, path, "far_exitance without exit_slope");
  EXPECT_EQ(dir.fileCount(), 0u);
  // An existing file is replaced whole or left alone.
  writeFile(path, "old");
  EXPECT_THROW(writeBakedPly(path, nan), Error);
  EXPECT_EQ(readFile(path), "old");
  EXPECT_EQ(dir.fileCount(), 1u);
  const std::string missingDir = dir.path("no/such/dir/out.ply");
  EXPECT_THROW(writeBakedPly(missingDir, sampleBake(1)), Error);
}

}  // namespace
}  // namespace sss

// The glTF 2.0 reader (mesh/gltf_reader.h through loadMesh): our own GLB writer's output reads
// back as the mesh it wrote, a node hierarchy's transforms (translation, rotation, scale, a
// mirror) against hand-computed positions and normals, every index component type, strips and
// fans, strided, offset, sparse and normalized accessors, .glb, .gltf with a data: URI and with an
// external .bin give one mesh, primitives weld into one object with a part and material per
// triangle and texture coordinates per corner, and hostile files end in one error naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <functional>

#include "mesh/baked_glb.h"
#include "mesh/baked_mesh.h"
#include "mesh/gltf_reader.h"
#include "mesh/load_mesh.h"
#include "mesh/primitives.h"
#include "support/glb_test.h"
#include "support/gltf_builder.h"
#include "test_util.h"

namespace sss {
namespace {

using test::bitEqual;
using test::expectError;
using test::GltfBuilder;
using test::ScratchDir;
using test::writeFile;
using Json = nlohmann::json;

// A tetrahedron placed by one node; `index` picks the index accessor's component type (0: none).
GltfBuilder tetrahedron(int indexType = 5125, const Json& node = Json::object()) {
  GltfBuilder b;
  const std::vector<glm::vec3> p = test::tetrahedronPositions();
  const std::vector<unsigned> idx = test::tetrahedronIndices();
  GltfBuilder::Primitive prim;
  if (indexType == 0) {  // unindexed: each corner its own vertex
    std::vector<glm::vec3> corners;
    for (unsigned i : idx) corners.push_back(p[i]);
    prim.attributes = {{"POSITION", b.positions(corners)}};
  } else {
    prim.attributes = {{"POSITION", b.positions(p)}};
    prim.indices = b.indices(idx, indexType);
  }
  Json n = node;
  n["mesh"] = b.mesh({prim}, "tetra");
  n["name"] = "tetra node";
  b.scene({b.node(n)});
  return b;
}

TriangleMesh loadBytes(const ScratchDir& dir, const std::string& name, const std::string& bytes,
                       MeshReport* report = nullptr, MeshParts* parts = nullptr) {
  writeFile(dir.path(name), bytes);
  return loadMesh(dir.path(name), report, parts);
}

TEST(MeshGltf, OurGlbWriterReadsBackAsTheMesh) {
  ScratchDir dir;
  BakedMesh baked;
  baked.mesh = makeIcosphere(2, 0.05f);
  baked.mmPerUnit = 1000.0;  // metres: written as they are
  writeBakedGlb(dir.path("ico.glb"), baked);
  MeshReport report;
  MeshParts parts;
  const TriangleMesh m = loadMesh(dir.path("ico.glb"), &report, &parts);
  EXPECT_TRUE(bitEqual(m.positions, baked.mesh.positions));
  EXPECT_TRUE(bitEqual(m.triangles, baked.mesh.triangles));
  EXPECT_TRUE(bitEqual(m.normals, baked.mesh.normals));
  EXPECT_EQ(report.format, "glb");
  EXPECT_EQ(parts.mmPerUnit, 1000.0);
  EXPECT_EQ(parts.weldedVertices, 0u);
  ASSERT_EQ(parts.parts.size(), 1u);
  EXPECT_EQ(parts.parts[0].material, "baked (baked radiance, vertex colour)");
}

// World transform of the test's hierarchy, computed by hand: parent T(1, 2, 3) R_z(90) S(2, 1, 1),
// child T(0, 0, 1): p -> T + R_z(90) S (p + (0, 0, 1)), R_z(90) (x, y, z) = (-y, x, z).
glm::dvec3 placed(glm::dvec3 p) {
  p += glm::dvec3(0, 0, 1);
  p.x *= 2.0;
  return glm::dvec3(1, 2, 3) + glm::dvec3(-p.y, p.x, p.z);
}

TEST(MeshGltf, NodeHierarchyTransformsPositionsAndNormalsAsComputedByHand) {
  ScratchDir dir;
  GltfBuilder b;
  const std::vector<glm::vec3> p = test::tetrahedronPositions();
  // Flat normals would be averaged by the weld; these are per vertex, one each.
  const std::vector<glm::vec3> n = {{0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {0.6f, 0, 0.8f}};
  GltfBuilder::Primitive prim;
  prim.attributes = {{"POSITION", b.positions(p)},
                     {"NORMAL", b.accessor(b.view(GltfBuilder::bytesOf(n)), 5126, 4, "VEC3")}};
  prim.indices = b.indices(test::tetrahedronIndices());
  const int mesh = b.mesh({prim}, "tetra");
  const int child = b.node({{"name", "child"}, {"mesh", mesh}, {"translation", {0, 0, 1}}});
  const double s = std::sqrt(0.5);
  const int parent = b.node({{"name", "parent"},
                             {"children", {child}},
                             {"translation", {1, 2, 3}},
                             {"rotation", {0, 0, s, s}},
                             {"scale", {2, 1, 1}}});
  b.scene({parent});
  const GltfMesh g = [&] {
    writeFile(dir.path("h.gltf"), b.gltf());
    return readGltf(dir.path("h.gltf"));
  }();
  ASSERT_EQ(g.raw.positions.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    const glm::dvec3 want = placed(glm::dvec3(p[i]));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(g.raw.positions[i][k], want[k], 1e-6) << i;
    // Normals: the inverse transpose of R S is R S^-1: n -> R_z(90) (n.x / 2, n.y, n.z), unit.
    const glm::dvec3 m(n[i].x / 2.0, n[i].y, n[i].z);
    const glm::dvec3 wantNormal = glm::normalize(glm::dvec3(-m.y, m.x, m.z));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(g.raw.normals[i][k], wantNormal[k], 1e-6) << i;
  }
  ASSERT_EQ(g.parts.size(), 1u);
  EXPECT_EQ(g.parts[0].node, "child");
  EXPECT_EQ(g.parts[0].mesh, "tetra");
  EXPECT_EQ(g.parts[0].nodeIndex, unsigned(child));
  EXPECT_NEAR(g.parts[0].transform[3][0], 1.0, 1e-12);
  EXPECT_NEAR(g.parts[0].transform[3][1], 2.0, 1e-12);  // T + R_z(90) S (0, 0, 1)
  EXPECT_NEAR(g.parts[0].transform[3][2], 4.0, 1e-12);
  // The placed tetrahedron still faces outwards: no flip, positive volume (scale 2: 2/6).
  MeshReport report;
  const TriangleMesh m = loadMesh(dir.path("h.gltf"), &report);
  EXPECT_FALSE(report.orientationFlipped);
  EXPECT_NEAR(signedVolume(m), 2.0 / 6.0, 1e-6);
}

TEST(MeshGltf, AMirroringNodeKeepsTheTrianglesFacingOutwards) {
  ScratchDir dir;
  for (const Json& node : {Json{{"scale", {-1, 1, 1}}},
                           Json{{"matrix", {1, 0, 0, 0, 0, -3, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1}}}}) {
    SCOPED_TRACE(node.dump());
    MeshReport report;
    const TriangleMesh m = loadBytes(dir, "mirror.glb", tetrahedron(5125, node).glb(), &report);
    EXPECT_FALSE(report.orientationFlipped);  // wound back by the reader, not by the cleanup
    const double det = node.contains("scale") ? 1.0 : 3.0;
    EXPECT_NEAR(signedVolume(m), det / 6.0, 1e-6);
    EXPECT_EQ(report.boundaryEdges, 0u);
  }
}

TEST(MeshGltf, EveryIndexComponentTypeAndNoIndicesGiveOneMesh) {
  ScratchDir dir;
  const TriangleMesh reference = loadBytes(dir, "uint.glb", tetrahedron(5125).glb());
  // Each triangle's corners' positions (unindexed, the weld numbers vertices as the corners
  // first use them).
  const auto corners = [](const TriangleMesh& m) {
    std::vector<glm::vec3> out;
    for (const glm::uvec3& t : m.triangles)
      for (int k = 0; k < 3; ++k) out.push_back(m.positions[t[k]]);
    return out;
  };
  for (int type : {5121, 5123, 0}) {
    SCOPED_TRACE(type);
    MeshParts parts;
    const TriangleMesh m = loadBytes(dir, "t.glb", tetrahedron(type).glb(), nullptr, &parts);
    EXPECT_TRUE(bitEqual(corners(m), corners(reference)));
    EXPECT_EQ(m.vertexCount(), 4u);
    if (type != 0) {
      EXPECT_TRUE(bitEqual(m.triangles, reference.triangles));
    }
    EXPECT_EQ(parts.weldedVertices, type == 0 ? 8u : 0u);  // 12 corners, 4 positions
  }
}

TEST(MeshGltf, StripsAndFansAreTheTrianglesTheyName) {
  ScratchDir dir;
  // A square as a strip (0 1 2 3: triangles 0 1 2 and 2 1 3) and as a fan (0 1 2 3: 1 2 0, 2 3 0).
  const std::vector<glm::vec3> strip = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  const std::vector<glm::vec3> fan = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (const auto& [positions, mode] : {std::pair{strip, 5}, std::pair{fan, 6}}) {
    GltfBuilder b;
    GltfBuilder::Primitive prim;
    prim.attributes = {{"POSITION", b.positions(positions)}};
    prim.mode = mode;
    b.scene({b.node({{"mesh", b.mesh({prim})}})});
    const TriangleMesh m = loadBytes(dir, "s.glb", b.glb());
    ASSERT_EQ(m.triangleCount(), 2u) << mode;
    for (const glm::uvec3& t : m.triangles) {  // both wind counter-clockwise seen from +z
      const glm::vec3 normal =
          glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
      EXPECT_GT(normal.z, 0.0f) << mode;
    }
  }
}

// Positions and normals interleaved in one strided view, the texture coordinates as normalized
// unsigned shorts after an offset, and the positions' last element replaced by a sparse value.
TEST(MeshGltf, StridedOffsetSparseAndNormalizedAccessors) {
  ScratchDir dir;
  const std::vector<glm::vec3> p = test::tetrahedronPositions();
  std::vector<glm::vec3> interleaved;
  for (const glm::vec3& v : p) interleaved.insert(interleaved.end(), {v, glm::vec3(9.0f)});
  interleaved[6] = glm::vec3(7.0f);  // vertex 3's position: replaced by the sparse value
  GltfBuilder b;
  const int view = b.view(GltfBuilder::bytesOf(interleaved), 24);
  const int position = b.accessor(view, 5126, 4, "VEC3");
  const std::vector<std::uint16_t> uv = {0, 0, 0, 0, 65535, 0, 0, 65535, 32768, 65535};
  const int texcoord = b.accessor(b.view(GltfBuilder::bytesOf(uv)), 5123, 4, "VEC2", 4, true);
  const std::vector<std::uint8_t> sparseIndex = {3};
  b.doc["accessors"][position]["sparse"] = {
      {"count", 1},
      {"indices",
       {{"bufferView", b.view(GltfBuilder::bytesOf(sparseIndex))}, {"componentType", 5121}}},
      {"values", {{"bufferView", b.view(GltfBuilder::bytesOf(std::vector{p[3]}))}}}};
  GltfBuilder::Primitive prim;
  prim.attributes = {{"POSITION", position}, {"TEXCOORD_0", texcoord}};
  prim.indices = b.indices(test::tetrahedronIndices(), 5123);
  b.scene({b.node({{"mesh", b.mesh({prim})}})});
  MeshParts parts;
  const TriangleMesh m = loadBytes(dir, "s.glb", b.glb(), nullptr, &parts);
  const TriangleMesh reference = loadBytes(dir, "r.glb", tetrahedron().glb());
  EXPECT_TRUE(bitEqual(m.positions, reference.positions));
  EXPECT_TRUE(bitEqual(m.triangles, reference.triangles));
  ASSERT_EQ(parts.cornerTexcoords.size(), 3 * m.triangleCount());
  for (std::size_t t = 0; t < m.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const unsigned v = m.triangles[t][k];
      const glm::vec2 want(uv[2 + 2 * v] / 65535.0f, uv[3 + 2 * v] / 65535.0f);  // offset 4
      EXPECT_EQ(parts.cornerTexcoords[3 * t + k], want) << t << " " << k;
    }
  }
}

TEST(MeshGltf, GlbDataUriAndExternalBinGiveOneMesh) {
  ScratchDir dir;
  const GltfBuilder b = tetrahedron();
  const TriangleMesh glb = loadBytes(dir, "t.glb", b.glb());
  const TriangleMesh data = loadBytes(dir, "data.gltf", b.gltf());
  writeFile(dir.path("tetra data.bin"), b.bin);
  const TriangleMesh external = loadBytes(dir, "external.gltf", b.gltf("tetra%20data.bin"));
  for (const TriangleMesh* m : {&data, &external}) {
    EXPECT_TRUE(bitEqual(m->positions, glb.positions));
    EXPECT_TRUE(bitEqual(m->triangles, glb.triangles));
  }
  MeshReport report;
  loadBytes(dir, "data.gltf", b.gltf(), &report);
  EXPECT_EQ(report.format, "gltf");
}

// Two primitives with their own materials and vertices, meeting along a square's edges (a cube
// split into a lid and a box): welded into one closed object, each triangle keeping its part.
TEST(MeshGltf, PrimitivesWeldIntoOneObjectWithAPartPerTriangle) {
  ScratchDir dir;
  const TriangleMesh cube = makeBox(glm::vec3(1.0f), 1);  // 8 vertices, 12 triangles
  GltfBuilder b;
  std::vector<GltfBuilder::Primitive> prims(2);
  for (int part = 0; part < 2; ++part) {
    std::vector<glm::vec3> corners;
    std::vector<glm::vec2> uv;
    for (const glm::uvec3& t : cube.triangles) {
      const bool lid =
          cube.positions[t.x].z > 0 && cube.positions[t.y].z > 0 && cube.positions[t.z].z > 0;
      if (lid != (part == 0)) continue;
      for (int k = 0; k < 3; ++k) {
        corners.push_back(cube.positions[t[k]]);
        uv.push_back({float(part), float(k)});
      }
    }
    prims[part].attributes = {{"POSITION", b.positions(corners)}, {"TEXCOORD_0", b.texcoords(uv)}};
    prims[part].material = b.material(part == 0 ? "Lid" : "");
  }
  b.scene({b.node({{"mesh", b.mesh(prims, "box")}})});
  MeshReport report;
  MeshParts parts;
  const TriangleMesh m = loadBytes(dir, "box.glb", b.glb(), &report, &parts);
  EXPECT_EQ(m.vertexCount(), 8u);
  EXPECT_EQ(m.triangleCount(), 12u);
  EXPECT_EQ(report.boundaryEdges, 0u);  // closed: the two parts share their edges
  EXPECT_EQ(report.components, 1u);
  EXPECT_EQ(parts.weldedVertices, 36u - 8u);
  EXPECT_EQ(parts.materials(), (std::vector<std::string>{"Lid", "#1"}));
  ASSERT_EQ(parts.trianglePart.size(), 12u);
  ASSERT_EQ(parts.cornerTexcoords.size(), 36u);
  for (std::size_t t = 0; t < 12; ++t) {
    const std::uint32_t part = parts.trianglePart[t];
    bool lid = true;
    for (int k = 0; k < 3; ++k) lid = lid && m.positions[m.triangles[t][k]].z > 0;
    EXPECT_EQ(part, lid ? 0u : 1u) << t;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(parts.cornerTexcoords[3 * t + k].x, float(part));
  }
}

// assimp as an independent writer: a box of two materials (an OBJ's usemtl groups) exported as
// .glb and .gltf reads back as one closed box, the primitives welded, each material a part.
TEST(MeshGltf, AssimpsGltfOfATwoMaterialBoxReadsAsOneClosedBox) {
  ScratchDir dir;
  writeFile(dir.path("box.mtl"), "newmtl Stone\nKd 1 1 1\nnewmtl Wood\nKd 1 0 0\n");
  writeFile(dir.path("box.obj"),
            "mtllib box.mtl\nv -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\n"
            "v 1 -1 1\nv 1 1 1\nv -1 1 1\nusemtl Stone\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\n"
            "usemtl Wood\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");
  for (const char* format : {"glb2", "gltf2"}) {
    SCOPED_TRACE(format);
    const std::string out = dir.path(std::string("box.") + (format[2] == 'b' ? "glb" : "gltf"));
    const test::ToolRun r = test::runCommand(
        "cd '" + dir.path("") + "' && assimp export box.obj '" + out + "' -f" + format + " 2>&1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    MeshReport report;
    MeshParts parts;
    const TriangleMesh m = loadMesh(out, &report, &parts);
    EXPECT_EQ(m.vertexCount(), 8u);
    EXPECT_EQ(m.triangleCount(), 12u);
    EXPECT_EQ(report.boundaryEdges, 0u);
    EXPECT_NEAR(signedVolume(m), 8.0, 1e-5);
    EXPECT_EQ(parts.materials(), (std::vector<std::string>{"Stone", "Wood"}));
  }
}

TEST(MeshGltf, TheTestsAssetsAreValidGltf) {
  ScratchDir dir;
  const GltfBuilder b = tetrahedron(5123);
  writeFile(dir.path("t.glb"), b.glb());
  writeFile(dir.path("t.gltf"), b.gltf());
  test::expectValidGltf(dir.path("t.glb"));
  test::expectValidGltf(dir.path("t.gltf"));
}

// The cleanup turns an inside-out closed mesh: each corner's texture coordinates follow its
// vertex, not its place in the triangle.
TEST(MeshGltf, TextureCoordinatesFollowTheirVertexWhenTheCleanupTurnsATriangle) {
  ScratchDir dir;
  GltfBuilder b;
  std::vector<unsigned> inverted = test::tetrahedronIndices();
  for (std::size_t t = 0; t < inverted.size(); t += 3) std::swap(inverted[t + 1], inverted[t + 2]);
  GltfBuilder::Primitive prim;
  prim.attributes = {{"POSITION", b.positions(test::tetrahedronPositions())},
                     {"TEXCOORD_0", b.texcoords({{0, 0}, {1, 0}, {2, 0}, {3, 0}})}};
  prim.indices = b.indices(inverted);
  b.scene({b.node({{"mesh", b.mesh({prim})}})});
  MeshReport report;
  MeshParts parts;
  const TriangleMesh m = loadBytes(dir, "inside_out.glb", b.glb(), &report, &parts);
  EXPECT_TRUE(report.orientationFlipped);
  ASSERT_EQ(parts.cornerTexcoords.size(), 12u);
  for (std::size_t t = 0; t < 4; ++t) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(parts.cornerTexcoords[3 * t + k].x, float(m.triangles[t][k])) << t << " " << k;
    }
  }
}

TEST(MeshGltf, OtherFormatsHaveNoPartsAndNoUnit) {
  ScratchDir dir;
  writeFile(dir.path("t.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  MeshParts parts;
  parts.mmPerUnit = 5.0;
  loadMesh(dir.path("t.off"), nullptr, &parts);
  EXPECT_EQ(parts.mmPerUnit, 0.0);
  EXPECT_TRUE(parts.parts.empty());
}

// Each hostile change to a valid tetrahedron, and what the error must say.
struct Hostile {
  const char* name;
  std::function<void(GltfBuilder&)> change;
  const char* error;
  bool glb = true;
};

TEST(MeshGltf, HostileFilesEndInOneErrorNamingTheFile) {
  ScratchDir dir;
  const std::vector<Hostile> cases = {
      {"count beyond the view", [](GltfBuilder& b) { b.doc["accessors"][0]["count"] = 5; },
       "overruns bufferView 0"},
      {"large count", [](GltfBuilder& b) { b.doc["accessors"][0]["count"] = 100000; }, "overruns"},
      {"view beyond the buffer",
       [](GltfBuilder& b) { b.doc["bufferViews"][0]["byteLength"] = 4096; }, "overruns"},
      {"view offset beyond the buffer",
       [](GltfBuilder& b) { b.doc["bufferViews"][1]["byteOffset"] = 1ull << 40; }, "overruns"},
      {"accessor offset", [](GltfBuilder& b) { b.doc["accessors"][1]["byteOffset"] = 4; },
       "overruns"},
      {"bad stride", [](GltfBuilder& b) { b.doc["bufferViews"][0]["byteStride"] = 6; },
       "byteStride 6"},
      {"index out of range", [](GltfBuilder& b) { b.bin[48] = 9; }, "index 0 is 9"},
      {"NaN position",
       [](GltfBuilder& b) {
         const float nan = std::nanf("");
         std::memcpy(&b.bin[4], &nan, 4);
       },
       "POSITION element 0 is not finite"},
      {"huge position",
       [](GltfBuilder& b) {
         const float big = 1e30f;
         std::memcpy(&b.bin[0], &big, 4);
       },
       "beyond the limit of 1e+18"},
      {"huge translation",
       [](GltfBuilder& b) {
         b.doc["nodes"][0]["translation"] = {1e300, 0, 0};
       },
       "beyond float range"},
      {"two parents",
       [](GltfBuilder& b) {
         b.doc["nodes"].push_back({{"children", {0}}});
         b.doc["nodes"].push_back({{"children", {0}}});
       },
       "two parents"},
      {"cycle",
       [](GltfBuilder& b) {
         b.doc["nodes"].push_back({{"children", {2}}});
         b.doc["nodes"].push_back({{"children", {1}}});
       },
       "cycle"},
      {"own child", [](GltfBuilder& b) { b.doc["nodes"][0]["children"] = {0}; }, "its own child"},
      {"missing child", [](GltfBuilder& b) { b.doc["nodes"][0]["children"] = {7}; },
       "child that does not exist"},
      {"root with a parent",
       [](GltfBuilder& b) {
         b.doc["nodes"].push_back({{"children", {0}}});
       },
       "node with a parent"},
      {"missing scene node", [](GltfBuilder& b) { b.doc["scenes"][0]["nodes"] = {3}; },
       "does not exist"},
      {"no scene", [](GltfBuilder& b) { b.doc.erase("scenes"); }, "no scene"},
      {"missing mesh", [](GltfBuilder& b) { b.doc["nodes"][0]["mesh"] = 4; },
       "meshes[4] does not exist"},
      {"lines", [](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["mode"] = 1; },
       "mesh 0 primitive 0 has mode LINES (1)"},
      {"float indices", [](GltfBuilder& b) { b.doc["accessors"][1]["componentType"] = 5126; },
       "components of FLOAT"},
      {"sparse not increasing",
       [](GltfBuilder& b) {
         b.doc["accessors"][0]["sparse"] = {
             {"count", 3},
             {"indices", {{"bufferView", 1}, {"componentType", 5125}}},
             {"values", {{"bufferView", 0}}}};
       },
       "not increasing"},
      {"unbacked huge count",
       [](GltfBuilder& b) {
         b.doc["accessors"][0].erase("bufferView");
         b.doc["accessors"][0]["count"] = 1000000;
         b.doc["accessors"][0]["sparse"] = {
             {"count", 1},
             {"indices", {{"bufferView", 1}, {"componentType", 5125}}},
             {"values", {{"bufferView", 0}}}};
       },
       "without data"},
      {"draco",
       [](GltfBuilder& b) { b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"}; },
       "requires the extension KHR_draco_mesh_compression"},
      {"version 1", [](GltfBuilder& b) { b.doc["asset"]["version"] = "1.0"; }, "not 2.x"},
      {"missing material",
       [](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["material"] = 5; },
       "materials[5] does not exist"},
      {"matrix and TRS",
       [](GltfBuilder& b) {
         b.doc["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
         b.doc["nodes"][0]["scale"] = {1, 1, 1};
       },
       "both a matrix and"},
      {"zero quaternion",
       [](GltfBuilder& b) {
         b.doc["nodes"][0]["rotation"] = {0, 0, 0, 0};
       },
       "not a quaternion"},
      {"no POSITION",
       [](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["attributes"].erase("POSITION"); },
       "has no POSITION"},
      {"negative index",
       [](GltfBuilder& b) { b.doc["meshes"][0]["primitives"][0]["indices"] = -1; },
       "not a non-negative integer"},
      {"absolute uri", [](GltfBuilder&) {}, "is absolute", false},
  };
  for (const Hostile& c : cases) {
    SCOPED_TRACE(c.name);
    GltfBuilder b = tetrahedron();
    c.change(b);
    const std::string file = dir.path(c.glb ? "hostile.glb" : "hostile.gltf");
    writeFile(file, c.glb ? b.glb() : b.gltf("/etc/passwd"));
    expectError([&] { loadMesh(file); }, file, c.error);
  }
}

// A small file that places a mesh many times is refused before the copies are allocated.
TEST(MeshGltf, ASceneBeyondTheMemoryIsRefusedBeforeAllocating) {
  ScratchDir dir;
  GltfBuilder b;
  GltfBuilder::Primitive prim;
  prim.attributes = {{"POSITION", b.positions(std::vector<glm::vec3>(1024, glm::vec3(0.0f)))}};
  prim.indices = b.indices({0, 1, 2});
  const int mesh = b.mesh({prim});
  std::vector<int> roots;
  for (int i = 0; i < 200; ++i) roots.push_back(b.node({{"mesh", mesh}}));
  b.scene(roots);
  writeFile(dir.path("many.glb"), b.glb());
  ::setenv("SSS_MEMORY_LIMIT_MB", "1", 1);
  expectError([&] { loadMesh(dir.path("many.glb")); }, dir.path("many.glb"),
              "reading 204800 vertices needs about");
  ::unsetenv("SSS_MEMORY_LIMIT_MB");
}

TEST(MeshGltf, HostileUrisAndContainersAreRefused) {
  ScratchDir dir;
  const GltfBuilder b = tetrahedron();
  const auto refused = [&](const std::string& name, const std::string& bytes,
                           const std::string& part) {
    SCOPED_TRACE(name);
    test::expectLoadRefused(dir, name, bytes, part);
  };
  refused("up.gltf", b.gltf("../t.bin"), "leaves the file's folder");
  refused("up2.gltf", b.gltf("a/%2e%2e/%2E%2E/t.bin"), "leaves the file's folder");
  refused("http.gltf", b.gltf("http://example.com/t.bin"), "has a scheme");
  refused("file.gltf", b.gltf("file:///etc/passwd"), "has a scheme");
  refused("escape.gltf", b.gltf("t%zz.bin"), "bad percent-escape");
  refused("missing.gltf", b.gltf("absent.bin"), "cannot open 'absent.bin'");
  writeFile(dir.path("short.bin"), b.bin.substr(0, 10));
  refused("short.gltf", b.gltf("short.bin"), "under its byteLength");
  std::string badBase64 = b.gltf();
  badBase64.replace(badBase64.find("base64,") + 7, 1, "*");
  refused("base64.gltf", badBase64, "not in the base64 alphabet");
  std::string cut = b.gltf();
  const std::size_t end = cut.find('"', cut.find("base64,"));
  cut.erase(end - 5, 3);
  refused("cut64.gltf", cut, "cannot encode whole bytes");
  refused("text.gltf", "{\"asset\": ", "glTF JSON");
  refused("array.gltf", "[1, 2]", "not an object");
  // GLB containers that lie about their lengths, and every truncation.
  const std::string glb = b.glb();
  std::string total = glb;
  total[8] += 4;
  refused("total.glb", total, "GLB header declares");
  std::string json = glb;
  json[13] = 0x7f;
  refused("json.glb", json, "does not fit");
  std::string binLength = glb;
  const std::size_t binAt = 20 + (std::uint8_t(glb[12]) | std::uint8_t(glb[13]) << 8);
  binLength[binAt] += 8;
  refused("bin.glb", binLength, "BIN chunk");
  for (std::size_t n = 0; n < glb.size(); n += 7) {
    writeFile(dir.path("cut.glb"), glb.substr(0, n));
    EXPECT_THROW(loadMesh(dir.path("cut.glb")), Error) << n;
  }
}

TEST(MeshGltf, RenderReadsAGltfSceneAsAPlainMeshInMetres) {
  ScratchDir dir;
  writeFile(dir.path("t.gltf"), tetrahedron().gltf());
  const BakedPlyContents r = readBakedMesh(dir.path("t.gltf"));
  EXPECT_FALSE(r.hasExitance);
  EXPECT_TRUE(r.hasUnits);
  EXPECT_EQ(r.baked.mmPerUnit, 1000.0);
  EXPECT_EQ(r.baked.mesh.triangleCount(), 4u);
  writeFile(dir.path("t.glb"), tetrahedron().glb());  // not ours: no asset.extras.sss
  EXPECT_EQ(readBakedMesh(dir.path("t.glb")).baked.mesh.triangleCount(), 4u);
}

}  // namespace
}  // namespace sss

// The baked GLB: bit-exact round trip through our reader, the Khronos validator and assimp read
// every file written here, COLOR_0 is the exposed radiance along the normal (clamped only with a
// warning), the extras carry the material and report, hostile files are refused with one error
// naming the file, and a checked mesh does not repeat its topology warnings.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "core/random.h"
#include "core/tool.h"
#include "mesh/baked_glb.h"
#include "mesh/baked_mesh.h"
#include "mesh/primitives.h"
#include "optics/exit_lobe.h"
#include "optics/fresnel.h"
#include "support/glb_test.h"
#include "test_util.h"

namespace sss {
namespace {

using test::bitEqual;
using test::expectError;
using test::GlbFile;
using test::readFile;
using test::ScratchDir;
using test::writeFile;

BakedMesh sampleBake(double mmPerUnit) {
  BakedMesh b;
  b.mesh = makeIcosphere(2, 75.0f);
  Pcg32 rng(11, 0);
  for (std::size_t i = 0; i < b.mesh.vertexCount(); ++i) {
    b.irradiance.push_back({rng.uniform() * 3, rng.uniform() * 3, rng.uniform() * 3});
    b.exitance.push_back({rng.uniform() * 0.1f, rng.uniform() * 1e-3f, rng.uniform() * 1e-7f});
  }
  b.materialName = "marble";
  b.sigmaA = {0.0021, 0.0041, 0.0071};
  b.sigmaSPrime = {2.19, 2.62, 3.00};
  b.eta = 1.3;
  b.mmPerUnit = mmPerUnit;
  b.extraComments = {"bake method=gauss profile=dipole", "made by a test"};
  b.meshChecked = true;
  return b;
}

TEST(MeshBakedGlb, RoundTripIsBitExactAndBothValidatorsReadIt) {
  ScratchDir dir;
  const BakedMesh b = sampleBake(1000.0);  // metres: positions are stored as they are
  const std::string path = dir.path("baked.glb");
  writeBakedGlb(path, b);
  const BakedPlyContents r = readBakedGlb(path);
  EXPECT_TRUE(r.hasIrradiance && r.hasExitance && r.hasMaterial && r.hasUnits);
  EXPECT_TRUE(bitEqual(r.baked.mesh.positions, b.mesh.positions));
  EXPECT_TRUE(bitEqual(r.baked.mesh.normals, b.mesh.normals));
  EXPECT_TRUE(bitEqual(r.baked.mesh.triangles, b.mesh.triangles));
  EXPECT_TRUE(bitEqual(r.baked.irradiance, b.irradiance));
  EXPECT_TRUE(bitEqual(r.baked.exitance, b.exitance));
  EXPECT_EQ(r.baked.materialName, "marble");
  EXPECT_EQ(r.baked.sigmaA, b.sigmaA);
  EXPECT_EQ(r.baked.sigmaSPrime, b.sigmaSPrime);
  EXPECT_EQ(r.baked.eta, 1.3);
  EXPECT_EQ(r.baked.mmPerUnit, 1000.0);
  EXPECT_EQ(r.baked.extraComments, b.extraComments);
  EXPECT_EQ(r.baked.previewScale, previewScaleFor(b));
  EXPECT_TRUE(r.baked.meshChecked);
  // Writing what was read gives the same bytes.
  writeBakedGlb(dir.path("again.glb"), r.baked);
  EXPECT_EQ(readFile(dir.path("again.glb")), readFile(path));
  test::expectValidGltf(path);
  test::expectAssimpReads(path, b.mesh.vertexCount(), b.mesh.triangleCount());
}

TEST(MeshBakedGlb, PositionsAreMetresAndTheSourceUnitIsRecorded) {
  ScratchDir dir;
  const BakedMesh b = sampleBake(0.1 + 0.2);  // not a short decimal
  const std::string path = dir.path("baked.glb");
  writeBakedGlb(path, b);
  const GlbFile glb(path);
  EXPECT_EQ(glb.sssExtras()["mm_per_unit"].get<double>(), 0.1 + 0.2);
  EXPECT_EQ(glb.sssExtras()["position_unit"], "m");
  const std::vector<glm::vec3> stored = glb.vec3("POSITION");
  const BakedPlyContents r = readBakedGlb(path);
  ASSERT_EQ(stored.size(), b.mesh.vertexCount());
  for (std::size_t i = 0; i < stored.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const float metres = static_cast<float>(double(b.mesh.positions[i][k]) * (0.1 + 0.2) / 1e3);
      ASSERT_EQ(stored[i][k], metres) << i;
      ASSERT_EQ(r.baked.mesh.positions[i][k], metres) << i;
    }
  }
  // The bounds glTF requires on POSITION are those of the stored values.
  const auto& accessor =
      glb.json["accessors"]
              [glb.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()];
  float lo = stored[0].x;
  for (const glm::vec3& p : stored) lo = std::min(lo, p.x);
  EXPECT_EQ(accessor["min"][0].get<float>(), lo);
  test::expectValidGltf(path);
}

// COLOR_0 = min(1, exposure * B * F_t(1, eta) / (pi (1 - 2 C_1(eta)))): what sss-render draws
// along the normal (shaders/surface.vert) under the PLY preview's exposure.
TEST(MeshBakedGlb, Color0IsTheExposedRadianceAlongTheNormal) {
  ScratchDir dir;
  BakedMesh b = sampleBake(1.0);
  b.eta = 1.5;
  const std::string path = dir.path("baked.glb");
  writeBakedGlb(path, b, R"({"tolerance": 0.01, "method": "gauss"})");
  const GlbFile glb(path);
  const auto& color = glb.sssExtras()["color"];
  const double perExitance =
      (1.0 - (0.5 / 2.5) * (0.5 / 2.5)) / (M_PI * (1.0 - diffuseFresnelReflectance(1.5f)));
  EXPECT_NEAR(color["radiance_per_exitance"].get<double>(), perExitance, 1e-6);
  EXPECT_EQ(color["exposure"].get<double>(), previewScaleFor(b));
  EXPECT_EQ(color["exit_model"], "normalized");
  EXPECT_EQ(color["clamped_vertices"], 0);
  const std::vector<glm::vec3> colors = glb.vec3("COLOR_0");
  ASSERT_EQ(colors.size(), b.exitance.size());
  for (std::size_t i = 0; i < colors.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const double expected = previewScaleFor(b) * perExitance * b.exitance[i][k];
      ASSERT_NEAR(colors[i][k], expected, 1e-6 * expected + 1e-30) << i;
    }
  }
  EXPECT_TRUE(bitEqual(glb.vec3("_EXITANCE"), b.exitance));
  EXPECT_TRUE(bitEqual(glb.vec3("_IRRADIANCE"), b.irradiance));
  // The material shows the vertex colour as is; the bake's material and report are in extras.
  EXPECT_EQ(glb.json["extensionsUsed"][0], "KHR_materials_unlit");
  const auto& material = glb.json["materials"][0];
  EXPECT_TRUE(material["extensions"].contains("KHR_materials_unlit"));
  EXPECT_EQ(material["pbrMetallicRoughness"]["baseColorFactor"],
            nlohmann::json({1.0, 1.0, 1.0, 1.0}));
  EXPECT_EQ(glb.sssExtras()["material"]["eta"].get<double>(), 1.5);
  EXPECT_EQ(glb.sssExtras()["material"]["sigma_s_prime_per_mm"][2].get<double>(), 3.0);
  EXPECT_EQ(glb.sssExtras()["report"]["tolerance"].get<double>(), 0.01);
  EXPECT_EQ(glb.sssExtras()["checked"], true);
  test::expectValidGltf(path);
}

// A traced far field travels as _FAR_EXITANCE and _EXIT_SLOPE (so that sss-render draws the
// same picture from the GLB as from the PLY), and COLOR_0 takes B through the far field's exit
// lobe, as sss-render's default exit model does.
TEST(MeshBakedGlb, FarFieldRoundTripsAndColor0LeavesThroughItsLobe) {
  ScratchDir dir;
  BakedMesh b = sampleBake(1.0);
  Pcg32 rng(5, 0);
  for (const glm::vec3& e : b.exitance) {
    b.farExitance.push_back(e * rng.uniform());
    b.exitSlope.push_back({rng.uniform() * 2 - 1, rng.uniform() * 4, rng.uniform()});
  }
  const std::string path = dir.path("far.glb");
  writeBakedGlb(path, b);
  const BakedPlyContents r = readBakedGlb(path);
  EXPECT_TRUE(r.hasFarField);
  EXPECT_TRUE(bitEqual(r.baked.farExitance, b.farExitance));
  EXPECT_TRUE(bitEqual(r.baked.exitSlope, b.exitSlope));
  const GlbFile glb(path);
  EXPECT_EQ(glb.sssExtras()["color"]["exit_model"], "auto");
  const std::vector<glm::vec3> colors = glb.vec3("COLOR_0");
  const ExitLobe lobe(1.3f);
  for (std::size_t i = 0; i < colors.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const double expected =
          previewScaleFor(b) * b.exitance[i][k] * lobe.radiance(b.exitSlope[i][k], 1.0f);
      ASSERT_NEAR(colors[i][k], expected, 1e-5 * expected + 1e-30) << i;
    }
  test::expectValidGltf(path);
}

// Exit slopes without a far field (the half-space's lobe, bake.cpp) travel alone as _EXIT_SLOPE.
TEST(MeshBakedGlb, ExitSlopesWithoutAFarFieldRoundTrip) {
  ScratchDir dir;
  BakedMesh b = sampleBake(1.0);
  b.exitSlope.assign(b.exitance.size(), glm::vec3(-0.2f, -0.3f, -0.3f));
  const std::string path = dir.path("lobe.glb");
  writeBakedGlb(path, b);
  const BakedPlyContents r = readBakedGlb(path);
  EXPECT_FALSE(r.hasFarField);
  EXPECT_TRUE(r.hasExitSlope);
  EXPECT_TRUE(bitEqual(r.baked.exitSlope, b.exitSlope));
  EXPECT_EQ(GlbFile(path).sssExtras()["color"]["exit_model"], "auto");
  test::expectValidGltf(path);
}

TEST(MeshBakedGlb, ValuesAboveOneAreClampedWithAWarningNamingHowMany) {
  ScratchDir dir;
  BakedMesh b = sampleBake(1.0);
  b.previewScale = 40.0;  // B up to 0.1: radiance * 40 up to ~1.3
  const double perExitance = fresnelTransmittance(1.0f, 1.3f) * exitRadianceScale(1.3f);
  std::size_t over = 0;
  for (const glm::vec3& e : b.exitance) over += 40.0 * perExitance * e.x > 1.0;
  ASSERT_GT(over, 0u);
  ASSERT_LT(over, b.exitance.size());
  const std::string path = dir.path("hot.glb");
  ::testing::internal::CaptureStderr();
  writeBakedGlb(path, b);
  const std::string warnings = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(warnings.find("warning: " + path + ": COLOR_0 clamped to 1 at " + std::to_string(over) +
                          " of " + std::to_string(b.exitance.size())),
            std::string::npos)
      << warnings;
  const GlbFile glb(path);
  EXPECT_EQ(glb.sssExtras()["color"]["clamped_vertices"], over);
  for (const glm::vec3& c : glb.vec3("COLOR_0")) ASSERT_LE(c.x, 1.0f);
  test::expectValidGltf(path);
}

TEST(MeshBakedGlb, WriterAndReaderArePickedByExtension) {
  ScratchDir dir;
  const BakedMesh b = sampleBake(1000.0);
  writeBakedMesh(dir.path("a.GLB"), b);
  writeBakedMesh(dir.path("a.ply"), b);
  EXPECT_EQ(readFile(dir.path("a.GLB")).substr(0, 4), "glTF");
  EXPECT_EQ(readFile(dir.path("a.ply")).substr(0, 4), "ply\n");
  EXPECT_TRUE(bitEqual(readBakedMesh(dir.path("a.GLB")).baked.exitance, b.exitance));
  EXPECT_TRUE(bitEqual(readBakedMesh(dir.path("a.ply")).baked.exitance, b.exitance));
  for (const char* name : {"a.txt", "a.obj", "noextension", "dir.glb/x"}) {
    EXPECT_THROW(checkBakedMeshPath(name), UsageError) << name;
    EXPECT_THROW(writeBakedMesh(dir.path(name), b), UsageError) << name;
  }
  EXPECT_EQ(dir.fileCount(), 2u);
}

// A mesh with a fin (a third triangle on an edge): the cleanup warns about it unless the file
// says the mesh was checked when it was baked; the counts stay (culling depends on them).
TEST(MeshBakedGlb, CheckedMeshesDoNotRepeatTopologyWarnings) {
  ScratchDir dir;
  BakedMesh b = sampleBake(1000.0);
  const glm::uvec3 t = b.mesh.triangles[0];
  b.mesh.positions.push_back(b.mesh.positions[t.x] * 1.5f);
  b.mesh.normals.push_back(b.mesh.normals[t.x]);
  b.irradiance.push_back(glm::vec3(1.0f));
  b.exitance.push_back(glm::vec3(0.01f));
  b.mesh.triangles.push_back({t.x, t.y, static_cast<unsigned>(b.mesh.positions.size() - 1)});
  for (const char* name : {"fin.glb", "fin.ply"}) {
    SCOPED_TRACE(name);
    for (const bool checked : {false, true}) {
      b.meshChecked = checked;
      writeBakedMesh(dir.path(name), b);
      const BakedPlyContents r = readBakedMesh(dir.path(name));
      EXPECT_EQ(r.baked.meshChecked, checked);
      EXPECT_GT(r.report.nonManifoldEdges, 0u);
      EXPECT_EQ(r.report.warnings.empty(), checked);
    }
  }
  EXPECT_NE(readFile(dir.path("fin.ply")).find("comment sss checked=1\n"), std::string::npos);
}

// Whether the bake traced the unscattered light (sss-render draws it then) survives both formats.
TEST(MeshBakedGlb, TheUnscatteredFlagRoundTrips) {
  ScratchDir dir;
  BakedMesh b = sampleBake(1000.0);
  for (const char* name : {"a.glb", "a.ply"})
    for (const bool traced : {false, true}) {
      b.unscatteredTraced = traced;
      writeBakedMesh(dir.path(name), b);
      EXPECT_EQ(readBakedMesh(dir.path(name)).baked.unscatteredTraced, traced) << name;
      EXPECT_EQ(readFile(dir.path(name)).find("unscattered=1") != std::string::npos,
                traced && std::string(name) == "a.ply");
    }
}

// ------------------------------------------------------------------ hostile files

std::string u32(std::uint32_t v) {
  return std::string(reinterpret_cast<const char*>(&v), 4);
}

// A GLB from a JSON text and a BIN chunk, lengths as declared unless overridden.
std::string glbBytes(std::string json, std::string bin, std::int64_t totalOverride = -1) {
  json.resize((json.size() + 3) / 4 * 4, ' ');
  bin.resize((bin.size() + 3) / 4 * 4, '\0');
  const std::size_t total = 12 + 8 + json.size() + 8 + bin.size();
  return "glTF" + u32(2) +
         u32(static_cast<std::uint32_t>(totalOverride >= 0 ? totalOverride : total)) +
         u32(static_cast<std::uint32_t>(json.size())) + "JSON" + json +
         u32(static_cast<std::uint32_t>(bin.size())) + std::string("BIN\0", 4) + bin;
}

// One triangle: positions (36 bytes), normals (36), indices (12) in one buffer.
std::string triangleBin(float nan = 0.0f) {
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, nan};
  const float n[9] = {0, 0, 1, 0, 0, 1, 0, 0, 1};
  const std::uint32_t i[3] = {0, 1, 2};
  return std::string(reinterpret_cast<const char*>(p), 36) +
         std::string(reinterpret_cast<const char*>(n), 36) +
         std::string(reinterpret_cast<const char*>(i), 12);
}

// The JSON of that triangle with `replace` applied: "key": value pairs substituted textually.
std::string triangleJson(const std::string& from = "", const std::string& to = "") {
  std::string json = R"({"asset": {"version": "2.0"},
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
    "buffers": [{"byteLength": 84}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                    {"buffer": 0, "byteOffset": 36, "byteLength": 36},
                    {"buffer": 0, "byteOffset": 72, "byteLength": 12}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                  {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
                  {"bufferView": 2, "componentType": 5125, "count": 3, "type": "SCALAR"}]})";
  if (!from.empty()) {
    const std::size_t at = json.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) json.replace(at, from.size(), to);
  }
  return json;
}

TEST(MeshBakedGlb, AHandWrittenTriangleLoadsAsAPlainMesh) {
  ScratchDir dir;
  const std::string path = dir.path("tri.glb");
  writeFile(path, glbBytes(triangleJson(), triangleBin()));
  const BakedPlyContents r = readBakedGlb(path);
  EXPECT_EQ(r.baked.mesh.vertexCount(), 3u);
  EXPECT_FALSE(r.hasExitance || r.hasIrradiance || r.hasMaterial);
  EXPECT_EQ(r.baked.mesh.positions[1], glm::vec3(1, 0, 0));
}

TEST(MeshBakedGlb, HostileFilesAreRefusedWithOneErrorNamingTheFile) {
  ScratchDir dir;
  const std::string good = glbBytes(triangleJson(), triangleBin());
  const std::uint32_t maxU32 = std::numeric_limits<std::uint32_t>::max();
  const struct {
    const char* name;
    std::string bytes;
    const char* error;
  } cases[] = {
      {"empty", "", "not a GLB"},
      {"magic", "GLTF" + good.substr(4), "no 'glTF' magic"},
      {"version", "glTF" + u32(1) + good.substr(8), "GLB version 1"},
      {"truncated", good.substr(0, good.size() - 4), "truncated"},
      {"longer", glbBytes(triangleJson(), triangleBin(), good.size() + 4), "declares"},
      {"json_length", good.substr(0, 12) + u32(maxU32 - 3) + good.substr(16), "JSON chunk of"},
      {"bin_length",
       good.substr(0, good.size() - 92) + u32(maxU32 - 3) + good.substr(good.size() - 88),
       "BIN chunk of"},
      {"not_json", glbBytes("{not json", triangleBin()), "glTF JSON"},
      {"no_bin", glbBytes(triangleJson(), "").substr(0, 20 + triangleJson().size() / 4 * 4 + 4),
       "declares"},
      {"count",
       glbBytes(triangleJson(R"("count": 3, "type": "VEC3"},
                  {"bufferView": 1)",
                             R"("count": 4294967296, "type": "VEC3"},
                  {"bufferView": 1)"),
                triangleBin()),
       "POSITION accessor (4294967296 elements) overruns"},
      {"offset",
       glbBytes(triangleJson(R"("byteOffset": 36, "byteLength": 36)",
                             R"("byteOffset": 18446744073709551615, "byteLength": 36)"),
                triangleBin()),
       "NORMAL accessor"},
      {"view_length",
       glbBytes(triangleJson(R"("byteLength": 12})", R"("byteLength": 4000})"), triangleBin()),
       "indices accessor"},
      {"stride",
       glbBytes(triangleJson(R"("byteOffset": 0, "byteLength": 36})",
                             R"("byteOffset": 0, "byteLength": 36, "byteStride": 4})"),
                triangleBin()),
       "byteStride"},
      {"view_index",
       glbBytes(triangleJson(R"("bufferView": 2,)", R"("bufferView": 7,)"), triangleBin()),
       "bufferViews[7] does not exist"},
      {"accessor_index", glbBytes(triangleJson(R"("NORMAL": 1)", R"("NORMAL": 99)"), triangleBin()),
       "accessors[99] does not exist"},
      {"negative", glbBytes(triangleJson(R"("NORMAL": 1)", R"("NORMAL": -1)"), triangleBin()),
       "\"NORMAL\" is not an index"},
      {"external_buffer",
       glbBytes(
           triangleJson(R"("buffer": 0, "byteOffset": 36)", R"("buffer": 1, "byteOffset": 36)"),
           triangleBin()),
       "not in the GLB's buffer"},
      {"sparse",
       glbBytes(triangleJson(R"("count": 3, "type": "SCALAR")",
                             R"("count": 3, "type": "SCALAR", "sparse": {})"),
                triangleBin()),
       "sparse"},
      {"float_indices",
       glbBytes(triangleJson(R"("componentType": 5125)", R"("componentType": 5126)"),
                triangleBin()),
       "indices are float"},
      {"points",
       glbBytes(triangleJson(R"("indices": 2)", R"("indices": 2, "mode": 0)"), triangleBin()),
       "not triangles"},
      {"two_meshes",
       glbBytes(triangleJson(R"("meshes": [{)", R"("meshes": [{}, {)"), triangleBin()),
       "not one mesh with one primitive"},
      {"index_range", glbBytes(triangleJson(), triangleBin().substr(0, 80) + u32(3)),
       "refers to vertex 3"},
      {"nan", glbBytes(triangleJson(), triangleBin(std::nanf(""))), "finite"},
      {"bad_extras",
       glbBytes(triangleJson(R"({"version": "2.0"})",
                             R"({"version": "2.0", "extras": {"sss": {"material": 1}}})"),
                triangleBin()),
       "glTF JSON"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir.path(std::string(c.name) + ".glb");
    writeFile(path, c.bytes);
    expectError([&] { readBakedGlb(path); }, path, c.error);
  }
}

}  // namespace
}  // namespace sss

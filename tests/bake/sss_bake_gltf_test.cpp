// sss-bake on glTF 2.0 input: the same mesh baked from a PLY and from a GLB gives the same light,
// a glTF needs no unit option (metres) and says so in the report, its parts and materials are in
// the report, and --material-map bakes each part with its material.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/relative_rms.h"
#include "envmap/cubemap_io.h"
#include "mesh/baked_glb.h"
#include "mesh/baked_mesh.h"
#include "mesh/primitives.h"
#include "support/gltf_builder.h"
#include "support/tool_test.h"

namespace sss {
namespace {

using test::Capture;
using test::GltfBuilder;
using test::ScratchDir;
using test::ToolRun;

// Fast settings: the half-space energy (no escape walks, no far field) and a fixed ray count.
const std::string kFast = " --energy halfspace --samples 16 --unscattered off -q";

class BakeGltf : public ::testing::Test {
 protected:
  void SetUp() override { writeCubemap(dir_.path("white.exr"), Cubemap(8, glm::vec3(1.0f))); }
  ToolRun bake(const std::string& mesh, const std::string& out, const std::string& extra) const {
    return test::runTool("sss-bake",
                         dir_.path(mesh) + " -e " + dir_.path("white.exr") + " -o " +
                             dir_.path(out) + kFast + " " + extra,
                         Capture::StdoutAndStderr);
  }
  // Two primitives of one box (its lid, and the rest) with materials "Lid" and "Body".
  void writeTwoPartBox(const std::string& name) const {
    const TriangleMesh cube = makeBox(glm::vec3(0.02f), 2);
    GltfBuilder b;
    std::vector<GltfBuilder::Primitive> prims(2);
    for (int part = 0; part < 2; ++part) {
      std::vector<unsigned> idx;
      for (const glm::uvec3& t : cube.triangles) {
        bool lid = true;
        for (int k = 0; k < 3; ++k) lid = lid && cube.positions[t[k]].z > 0.0099f;
        if (lid == (part == 0)) idx.insert(idx.end(), {t.x, t.y, t.z});
      }
      prims[part].attributes = {{"POSITION", b.positions(cube.positions)}};
      prims[part].indices = b.indices(idx);
      prims[part].material = b.material(part == 0 ? "Lid" : "Body");
    }
    b.scene({b.node({{"name", "box"}, {"mesh", b.mesh(prims, "box mesh")}})});
    test::writeText(dir_.path(name), b.glb());
  }
  ScratchDir dir_;
};

TEST_F(BakeGltf, PlyAndGlbOfOneMeshBakeAlike) {
  BakedMesh mesh;
  mesh.mesh = makeIcosphere(2, 0.01f);  // a 2 cm sphere, in metres
  mesh.mmPerUnit = 1000.0;
  writeBakedPly(dir_.path("sphere.ply"), mesh);
  writeBakedGlb(dir_.path("sphere.glb"), mesh);
  ASSERT_EQ(bake("sphere.ply", "from_ply.ply", "-m marble --unit m").exitCode, 0);
  const ToolRun glb = bake("sphere.glb", "from_glb.ply", "-m marble --json " + dir_.path("r.json"));
  ASSERT_EQ(glb.exitCode, 0) << glb.output;
  const BakedPlyContents a = readBakedPly(dir_.path("from_ply.ply"));
  const BakedPlyContents b = readBakedPly(dir_.path("from_glb.ply"));
  EXPECT_EQ(a.baked.mesh.positions, b.baked.mesh.positions);
  EXPECT_EQ(a.baked.mesh.triangles, b.baked.mesh.triangles);
  EXPECT_EQ(a.baked.irradiance, b.baked.irradiance);
  EXPECT_EQ(a.baked.exitance, b.baked.exitance);
  EXPECT_EQ(a.baked.radianceNormal, b.baked.radianceNormal);
  EXPECT_EQ(a.baked.mmPerUnit, 1000.0);
  EXPECT_EQ(b.baked.mmPerUnit, 1000.0);
  const auto report = nlohmann::json::parse(test::readFile(dir_.path("r.json")));
  EXPECT_EQ(report["units"]["mm_per_unit"], 1000.0);
  EXPECT_EQ(report["units"]["from_file"], true);
  EXPECT_EQ(report["mesh"]["format"], "glb");
  ASSERT_EQ(report["mesh"]["parts"].size(), 1u);
}

TEST_F(BakeGltf, AUnitOptionOverridesTheMetres) {
  BakedMesh mesh;
  mesh.mesh = makeIcosphere(1, 10.0f);  // exported in millimetres, labelled metres
  mesh.mmPerUnit = 1000.0;
  writeBakedGlb(dir_.path("mm.glb"), mesh);
  const ToolRun r = bake("mm.glb", "out.ply", "-m marble --unit mm --json " + dir_.path("r.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto report = nlohmann::json::parse(test::readFile(dir_.path("r.json")));
  EXPECT_EQ(report["units"]["mm_per_unit"], 1.0);
  EXPECT_FALSE(report["units"].contains("from_file"));
}

TEST_F(BakeGltf, OtherFormatsStillNeedAUnit) {
  BakedMesh mesh;
  mesh.mesh = makeIcosphere(1, 10.0f);
  writeBakedPly(dir_.path("s.ply"), mesh);
  const ToolRun r = bake("s.ply", "out.ply", "-m marble");
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("--mm-per-unit,--unit,--size-mm"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir_.path("out.ply")));
}

TEST_F(BakeGltf, PartsWeldAndAMaterialMapToOneMaterialBakes) {
  writeTwoPartBox("box.glb");
  const ToolRun r =
      bake("box.glb", "out.glb",
           "-m marble --material-map Lid=skin1,Body=skin1 --json " + dir_.path("r.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const BakedPlyContents out = readBakedMesh(dir_.path("out.glb"));
  EXPECT_EQ(out.baked.materialName, "skin1");
  EXPECT_EQ(out.baked.mesh.vertexCount(), makeBox(glm::vec3(1.0f), 2).vertexCount());
  const auto report = nlohmann::json::parse(test::readFile(dir_.path("r.json")));
  EXPECT_EQ(report["mesh"]["boundary_edges"], 0);  // welded: the lid closes the box
  ASSERT_EQ(report["mesh"]["parts"].size(), 2u);
  EXPECT_EQ(report["mesh"]["parts"][0]["material"], "Lid");
  EXPECT_EQ(report["mesh"]["parts"][1]["material"], "Body");
  EXPECT_EQ(report["mesh"]["parts"][1]["node"], "box");
  EXPECT_EQ(report["mesh"]["parts"][1]["mesh"], "box mesh");
  EXPECT_EQ(report["material"]["name"], "skin1");
  // The JSON form, and the default material for the part the map leaves out.
  test::writeText(dir_.path("map.json"), R"({"Lid": "marble"})");
  const ToolRun json =
      bake("box.glb", "json.ply", "-m marble --material-map " + dir_.path("map.json"));
  EXPECT_EQ(json.exitCode, 0) << json.output;
}

// Each part keeps its own material's light (bake/material_parts.h): a vertex whose triangles are
// all of one part has exactly the E, and nearly the radiance, of the object baked all of that
// part's material (the other part's light changes it by half the difference of the two
// transports), and a vertex on the border between the parts a blend of the two.
TEST_F(BakeGltf, TwoMaterialsBakeEachPartWithItsOwnTransport) {
  writeTwoPartBox("box.glb");
  const std::string json = " --json " + dir_.path("r.json");
  ASSERT_EQ(bake("box.glb", "mixed.ply", "-m marble --material-map Lid=skin1" + json).exitCode, 0);
  const auto report = nlohmann::json::parse(test::readFile(dir_.path("r.json")));
  ASSERT_EQ(bake("box.glb", "skin1.ply", "-m skin1").exitCode, 0);
  ASSERT_EQ(bake("box.glb", "marble.ply", "-m marble").exitCode, 0);
  const BakedMesh mixed = readBakedPly(dir_.path("mixed.ply")).baked;
  const BakedMesh skin = readBakedPly(dir_.path("skin1.ply")).baked;
  const BakedMesh marble = readBakedPly(dir_.path("marble.ply")).baked;
  ASSERT_EQ(mixed.mesh.positions, marble.mesh.positions);
  int lid = 0, body = 0, border = 0;
  for (std::size_t i = 0; i < mixed.mesh.vertexCount(); ++i) {
    const float z = mixed.mesh.positions[i].z;  // the lid is the face z = +half, its rim the border
    const BakedMesh& own = z > 0.0099f ? skin : marble;
    const bool onBorder = std::abs(std::abs(mixed.mesh.positions[i].x) - 0.01f) < 1e-4f ||
                          std::abs(std::abs(mixed.mesh.positions[i].y) - 0.01f) < 1e-4f;
    if (z > 0.0099f && onBorder) {
      ++border;
      for (int c = 0; c < 3; ++c) {
        const float a = skin.radianceNormal[i][c], b = marble.radianceNormal[i][c];
        EXPECT_GT(mixed.radianceNormal[i][c], std::min(a, b) + 0.05f * std::abs(a - b)) << i;
        EXPECT_LT(mixed.radianceNormal[i][c], std::max(a, b) - 0.05f * std::abs(a - b)) << i;
      }
      continue;
    }
    ++(z > 0.0099f ? lid : body);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(mixed.irradiance[i][c], own.irradiance[i][c], 1e-5f * own.irradiance[i][c]) << i;
      EXPECT_NEAR(mixed.radianceNormal[i][c], own.radianceNormal[i][c],
                  0.05f * own.radianceNormal[i][c])
          << i;
    }
  }
  EXPECT_GT(lid, 0);
  EXPECT_GT(body, 0);
  EXPECT_EQ(border, 8);  // a 2 x 2 face's rim
  // The two materials differ enough on this box for the test to tell them apart.
  EXPECT_GT(relativeRms(skin.radianceNormal, marble.radianceNormal), 0.1);
  EXPECT_EQ(mixed.materialName, "marble");  // the larger part's, for the header
  EXPECT_NE(std::find(mixed.extraComments.begin(), mixed.extraComments.end(),
                      "bake part_materials=Lid:skin1,Body:marble"),
            mixed.extraComments.end());
  ASSERT_EQ(report["part_materials"].size(), 2u);
  EXPECT_EQ(report["part_materials"][0]["name"], "skin1");
  EXPECT_EQ(report["part_materials"][0]["parts"], nlohmann::json::array({"Lid"}));
  EXPECT_EQ(report["part_materials"][1]["name"], "marble");
  const double lidShare = report["part_materials"][0]["area_share"].get<double>();
  EXPECT_NEAR(lidShare, 1.0 / 6.0, 0.02);  // a face of six, less its border's half
  EXPECT_NEAR(lidShare + report["part_materials"][1]["area_share"].get<double>(), 1.0, 1e-6);
  EXPECT_EQ(report["material"]["name"], "marble");
}

TEST_F(BakeGltf, MaterialMapErrors) {
  writeTwoPartBox("box.glb");
  const auto refused = [&](const std::string& options, int exitCode, const std::string& text) {
    SCOPED_TRACE(options);
    const ToolRun r = bake("box.glb", "out.ply", options);
    EXPECT_EQ(r.exitCode, exitCode) << r.output;
    EXPECT_NE(r.output.find("sss-bake: error:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(text), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir_.path("out.ply")));
  };
  refused("-m marble --material-map Lid=skin1 --method pathtrace", 1,
          "2 materials, and --method pathtrace traces one homogeneous medium");
  refused("-m marble --material-map Lid=skin1 --relightable", 1,
          "--relightable stores one material's transfer");
  refused("-m marble --eta 1.5 --material-map Lid=skin1", 1, "materials of different eta");
  refused("-m marble --material-map Top=skin1", 1, "names the material 'Top', which no part");
  refused("-m marble --material-map Lid=chalk", 2, "chalk");
  refused("-m marble --material-map Lid", 2, "is not name=preset");
  refused("-m marble --material-map Lid=skin1,Lid=marble", 2, "twice");
  test::writeText(dir_.path("bad.json"), "[1]");
  refused("-m marble --material-map " + dir_.path("bad.json"), 2, "not a JSON object");
  // Hostile map files: one line naming the file and the problem (the fuzz target's corpus has
  // more).
  const auto hostile = [&](const std::string& bytes, const std::string& text) {
    test::writeText(dir_.path("hostile.json"), bytes);
    refused("-m marble --material-map " + dir_.path("hostile.json"), 2, text);
  };
  hostile("", "hostile.json: material map");
  hostile("{\"Lid\": ", "hostile.json: material map");
  hostile("{\"Lid\": 3}", "'Lid' is not a preset name");
  hostile("{\"Lid\": \"skin1\", \"Lid\": \"marble\"}", "names the material 'Lid' twice");
  hostile(std::string(2 << 20, ' ') + "{}", "more than a map's 1 MiB");
}

TEST_F(BakeGltf, AHostileGltfIsOneErrorAndNoOutput) {
  test::writeText(dir_.path("bad.gltf"),
                  R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 12,)"
                  R"( "uri": "../../etc/passwd"}]})");
  const ToolRun r = bake("bad.gltf", "out.ply", "-m marble");
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("sss-bake: error: " + dir_.path("bad.gltf") + ": glTF:"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir_.path("out.ply")));
}

}  // namespace
}  // namespace sss

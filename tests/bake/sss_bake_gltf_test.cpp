// sss-bake on glTF 2.0 input: the same mesh baked from a PLY and from a GLB gives the same light,
// a glTF needs no unit option (metres) and says so in the report, its parts and materials are in
// the report, and --material-map bakes parts mapped to one material and refuses several.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

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
  refused("-m marble --material-map Lid=skin1", 1, "a material per part is not yet supported");
  refused("-m marble --material-map Lid=marble,Body=ketchup", 1, "not yet supported");
  refused("-m marble --material-map Top=skin1", 1, "names the material 'Top', which no part");
  refused("-m marble --material-map Lid=chalk", 2, "chalk");
  refused("-m marble --material-map Lid", 2, "is not name=preset");
  refused("-m marble --material-map Lid=skin1,Lid=marble", 2, "twice");
  test::writeText(dir_.path("bad.json"), "[1]");
  refused("-m marble --material-map " + dir_.path("bad.json"), 2, "not a JSON object");
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

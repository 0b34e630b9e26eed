// sss-relight as a binary: a relightable bake relit under another sky matches what the library
// gives, PLY and GLB out, batches, and its refusals (a plain bake, an output that names the input,
// no environment).
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bake/relight.h"
#include "core/relative_rms.h"
#include "envmap/environment.h"
#include "image/image.h"
#include "material/material.h"
#include "mesh/baked_glb.h"
#include "mesh/baked_ply.h"
#include "mesh/primitives.h"
#include "support/tool_test.h"

namespace sss {
namespace {

using test::Capture;

class SssRelightTool : public ::testing::Test {
 protected:
  // One folder and one relightable bake for every test of the suite.
  static void SetUpTestSuite() {
    dir_ = std::filesystem::temp_directory_path() /
           ("sss-test-" + std::to_string(::getpid()) + "-relight-tool");
    std::filesystem::create_directories(dir_);
  }
  static void TearDownTestSuite() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  void SetUp() override {
    if (std::filesystem::exists(path("baked.ply"))) return;
    BakedMesh mesh;
    mesh.mesh = makeIcosphere(3, 10.0f);
    writeBakedPly(path("sphere.ply"), mesh);
    const test::ToolRun r =
        test::runTool("sss-bake",
                      path("sphere.ply") +
                          " --sky elevation=40,azimuth=10 -m skin1 --mm-per-unit 1 "
                          "--relightable 2 --far-field off --tolerance 0.03 -q -o " +
                          path("baked.ply"),
                      Capture::StdoutAndStderr);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    test::runTool("sss-bake",
                  path("sphere.ply") +
                      " --sky -m skin1 --mm-per-unit 1 --far-field off --tolerance 0.03 -q -o " +
                      path("plain.ply"),
                  Capture::StdoutAndStderr);
  }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static test::ToolRun relight(const std::string& args) {
    return test::runTool("sss-relight", args, Capture::StdoutAndStderr);
  }
  static std::filesystem::path dir_;
};
std::filesystem::path SssRelightTool::dir_;

TEST_F(SssRelightTool, WritesWhatTheLibraryRelights) {
  const std::string sky = "sky:elevation=15,azimuth=200";
  const test::ToolRun r =
      relight(path("baked.ply") + " --sky elevation=15,azimuth=200 --env-rotate 30 -q -o " +
              path("relit.ply"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const BakedPlyContents relit = readBakedPly(path("relit.ply"));
  EXPECT_TRUE(relit.hasExitance);
  EXPECT_TRUE(relit.hasRadianceNormal);
  EXPECT_FALSE(relit.hasRelight);
  EXPECT_FALSE(relit.hasIrradiance);
  // The library on the same file and environment.
  const BakedPlyContents baked = readBakedPly(path("baked.ply"));
  TriangleMesh mm = baked.baked.mesh;
  const Material material = findMaterialPreset("skin1");
  const RelightTransfer transfer = relightTransferOf(baked.baked);
  EnvironmentOptions options;
  options.orientation.rotateDeg = 30.0;
  const RelitLight want =
      sss::relight(path("baked.ply"), {mm, material, transfer}, loadEnvironment(sky, options), {});
  EXPECT_LT(relativeRms(relit.baked.radianceNormal, want.radianceNormal), 1e-6);
  EXPECT_LT(relativeRms(relit.baked.exitance, want.exitance), 1e-6);
  // Skin1's exit lobe (no far field) is the material's and the object's, not the light's: kept,
  // so that B leaves the relit file as it left the bake.
  ASSERT_TRUE(baked.hasExitSlope);
  EXPECT_FALSE(baked.hasFarField);
  EXPECT_TRUE(relit.hasExitSlope);
  EXPECT_EQ(relit.baked.exitSlope, baked.baked.exitSlope);
  // Another light than the bake's.
  EXPECT_GT(relativeRms(relit.baked.radianceNormal, baked.baked.radianceNormal), 0.1);
}

TEST_F(SssRelightTool, ARelightableGlbRelightsAsThePlyDoes) {
  test::ToolRun r = test::runTool("sss-bake",
                                  path("sphere.ply") +
                                      " --sky elevation=40,azimuth=10 -m skin1 --mm-per-unit 1 "
                                      "--relightable 2 --far-field off --tolerance 0.03 -q -o " +
                                      path("baked.glb"),
                                  Capture::StdoutAndStderr);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  r = relight(path("baked.glb") + " --sky elevation=5,azimuth=90 -q -o " + path("from_glb.ply"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  r = relight(path("baked.ply") + " --sky elevation=5,azimuth=90 -q -o " + path("from_ply.ply"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const BakedPlyContents glb = readBakedPly(path("from_glb.ply"));
  const BakedPlyContents ply = readBakedPly(path("from_ply.ply"));
  // The same bake written twice (the seed fixes it); the GLB's positions pass through metres.
  EXPECT_LT(relativeRms(glb.baked.radianceNormal, ply.baked.radianceNormal), 1e-4);
}

TEST_F(SssRelightTool, WritesGlbAndBatches) {
  test::ToolRun r = relight(path("baked.ply") + " --sky -q -o " + path("relit.glb"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(readBakedGlb(path("relit.glb")).baked.exitance.size(), 642u);
  std::filesystem::copy_file(path("baked.ply"), path("second.ply"),
                             std::filesystem::copy_options::overwrite_existing);
  r = relight(path("baked.ply") + " " + path("second.ply") + " --sky -q -o " + path("out/"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(path("out/baked.ply")));
  EXPECT_TRUE(std::filesystem::exists(path("out/second.ply")));
}

// Several environments for one bake (its rays traced once): each output is byte for byte what
// relighting under that environment alone writes, named after the bake and the environment; with
// a file output or two environments of one name, a usage error and no output.
TEST_F(SssRelightTool, SeveralEnvironmentsWriteWhatEachAloneWould) {
  for (const char* spec : {"a elevation=10,azimuth=250", "b elevation=40,azimuth=30"}) {
    const std::string name(spec, 1), sky(spec + 2);
    ASSERT_EQ(test::runTool("sss-irrmap",
                            "--sky " + sky + " --radiance " + path("sky_" + name + ".exr") +
                                " -o " + path("irr_" + name + ".exr") + " -q",
                            Capture::StdoutAndStderr)
                  .exitCode,
              0);
  }
  const std::string envs = " -e " + path("sky_a.exr") + " -e " + path("sky_b.exr");
  test::ToolRun r = relight(path("baked.ply") + envs + " -q -o " + path("multi/") + " --json " +
                            path("reports/"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  // Each report says where its relight's time went: the stages, none negative, within its total.
  for (const char* name : {"a", "b"}) {
    const auto report = nlohmann::json::parse(
        test::readFile(path(std::string("reports/baked_sky_") + name + ".json")));
    double stages = 0.0;
    for (const char* stage :
         {"compact_lights_s", "smooth_s", "compact_transport_s", "gather_s", "bounces_s"}) {
      ASSERT_TRUE(report["stages"].contains(stage)) << stage;
      EXPECT_GE(report["stages"][stage].get<double>(), 0.0) << stage;
      stages += report["stages"][stage].get<double>();
    }
    EXPECT_LE(stages, report["seconds"].get<double>()) << name;
  }
  for (const char* name : {"a", "b"}) {
    const std::string alone = path(std::string("alone_") + name + ".ply");
    r = relight(path("baked.ply") + " -e " + path(std::string("sky_") + name + ".exr") + " -q -o " +
                alone);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(test::readFile(path(std::string("multi/baked_sky_") + name + ".ply")),
              test::readFile(alone))
        << name;
  }
  EXPECT_NE(test::readFile(path("alone_a.ply")), test::readFile(path("alone_b.ply")));
  r = relight(path("baked.ply") + envs + " -q -o " + path("two.ply"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("-o names a folder"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(path("two.ply")));
  std::filesystem::create_directories(path("other"));
  std::filesystem::copy_file(path("sky_b.exr"), path("other/sky_a.exr"),
                             std::filesystem::copy_options::overwrite_existing);
  r = relight(path("baked.ply") + " -e " + path("sky_a.exr") + " -e " + path("other/sky_a.exr") +
              " -q -o " + path("same/"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("two environments named sky_a"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(path("same/baked_sky_a.ply")));
}

TEST_F(SssRelightTool, SssRenderRelightsAsSssRelightDoes) {
  const auto render = [&](const std::string& args) {
    return test::runTool("sss-render", args + " --size 64x64 -q", Capture::StdoutAndStderr);
  };
  // sss-render takes -e only: the sky as a radiance cubemap file, for both tools.
  const std::string sky = " --sky elevation=10,azimuth=250";
  const std::string env = path("sky.exr");
  ASSERT_EQ(
      test::runTool("sss-irrmap", sky + " --radiance " + env + " -o " + path("irr.exr") + " -q",
                    Capture::StdoutAndStderr)
          .exitCode,
      0);
  ASSERT_EQ(relight(path("baked.ply") + " -e " + env + " -q -o " + path("relit_env.ply")).exitCode,
            0);
  test::ToolRun r =
      render(path("baked.ply") + " -e " + env + " --relight-on cpu -o " + path("a.png"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  r = render(path("relit_env.ply") + " -e " + env + " -o " + path("b.png"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(test::readFile(path("a.png")), test::readFile(path("b.png")));
  r = render(path("baked.ply") + " -e " + env + " --no-relight -o " + path("c.png"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(test::readFile(path("a.png")), test::readFile(path("c.png")));
  // The turntable: N frames and their contact sheet.
  r = render(path("baked.ply") + " -e " + env + " --relight-on cpu --light-turntable 3 -o " +
             path("turn.png"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const char* frame : {"turn_000.png", "turn_001.png", "turn_002.png"})
    EXPECT_TRUE(std::filesystem::exists(path(frame))) << frame;
  EXPECT_EQ(test::readFile(path("turn_000.png")), test::readFile(path("a.png")));
  EXPECT_NE(test::readFile(path("turn_001.png")), test::readFile(path("a.png")));
  const ImageRgb sheet = readImage(path("turn.png"));
  EXPECT_EQ(sheet.width, 128);
  EXPECT_EQ(sheet.height, 128);
}

// sss-render relights on the GPU by default: the smooth light's SH summed against the transfer in
// the vertex shader, the compact lights' B (the sky's sun) computed before. Its images are those
// relit on the CPU (which draws what sss-relight writes, above) within 1e-3, frame by frame as the
// light turns, and far from the bake drawn as baked.
TEST_F(SssRelightTool, SssRenderRelightsOnTheGpuAsOnTheCpu) {
  const std::string env = path("sky_gpu.exr");
  ASSERT_EQ(test::runTool("sss-irrmap",
                          "--sky elevation=25,azimuth=120 --radiance " + env + " -o " +
                              path("irr_gpu.exr") + " -q",
                          Capture::StdoutAndStderr)
                .exitCode,
            0);
  const std::string common = path("baked.ply") + " -e " + env + " --size 64x64 -q --tonemap none";
  for (const char* device : {"gpu", "cpu"}) {
    const test::ToolRun r = test::runTool("sss-render",
                                          common + " --light-turntable 4 --relight-on " + device +
                                              " -o " + path(std::string(device) + ".exr") +
                                              " --json " + path(std::string(device) + "_turn.json"),
                                          Capture::StdoutAndStderr);
    ASSERT_EQ(r.exitCode, 0) << r.output;
  }
  for (const std::string& args : {" --no-relight -o " + path("as_baked.exr"),
                                  " -o " + path("gpu_one.exr") + " --json " + path("gpu.json")})
    ASSERT_EQ(test::runTool("sss-render", common + args, Capture::StdoutAndStderr).exitCode, 0);
  const auto largestDifference = [](const ImageRgb& a, const ImageRgb& b) {
    double worst = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, double(std::abs(a.pixels[i][c] - b.pixels[i][c])) /
                                    std::max(double(b.pixels[i][c]), 1e-2));
    return worst;
  };
  for (const char* frame : {"_000.exr", "_001.exr", "_002.exr", "_003.exr"}) {
    const ImageRgb gpu = readImage(path(std::string("gpu") + frame));
    const ImageRgb cpu = readImage(path(std::string("cpu") + frame));
    ASSERT_EQ(gpu.pixels.size(), cpu.pixels.size());
    EXPECT_LT(largestDifference(gpu, cpu), 1e-3) << frame;
  }
  EXPECT_GT(largestDifference(readImage(path("gpu_001.exr")), readImage(path("as_baked.exr"))),
            0.1);
  EXPECT_TRUE(readImage(path("gpu_one.exr")).pixels == readImage(path("gpu_000.exr")).pixels);
  EXPECT_EQ(nlohmann::json::parse(test::readFile(path("gpu.json")))["relit_on"], "gpu");
  // The turntable's report: its frames and what each further one took.
  const nlohmann::json turn = nlohmann::json::parse(test::readFile(path("gpu_turn.json")));
  EXPECT_EQ(turn["relit_on"], "gpu");
  EXPECT_EQ(turn["light_turntable"]["frames"], 4);
  const nlohmann::json& perFrame = turn["light_turntable"]["further_frame_median_ms"];
  EXPECT_GT(perFrame["relight"].get<double>(), 0.0);
  EXPECT_GE(perFrame["total"].get<double>(),
            perFrame["environment"].get<double>() + perFrame["relight"].get<double>());
}

TEST_F(SssRelightTool, SssBakeRefusesNonsenseRelightOptions) {
  const struct {
    std::string args;
    int exitCode;
    std::string message;
  } cases[] = {
      {"--relightable x", 2, "--relightable x: the SH order must be a whole number"},
      {"--relightable 9", 2, "--relightable 9: the SH order must be in [0, 8]"},
      {"--relightable -2", 2, "the SH order must be in [0, 8]"},
      {"--relightable --method pathtrace", 1, "--relightable needs a diffusion method"},
  };
  for (const auto& c : cases) {
    const test::ToolRun r =
        test::runTool("sss-bake",
                      path("sphere.ply") + " --sky -m skin1 --mm-per-unit 1 -q " + c.args + " -o " +
                          path("refused.ply"),
                      Capture::StdoutAndStderr);
    EXPECT_EQ(r.exitCode, c.exitCode) << c.args << ": " << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(std::filesystem::exists(path("refused.ply"))) << c.args;
  }
}

TEST_F(SssRelightTool, RefusesWithOneClearLine) {
  const std::string before = test::readFile(path("baked.ply"));
  test::ToolRun r = relight(path("plain.ply") + " --sky -q -o " + path("x.ply"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("plain.ply: not a relightable bake"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(path("x.ply")));
  r = relight(path("baked.ply") + " --sky -q -o " + path("baked.ply"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_EQ(test::readFile(path("baked.ply")), before);
  r = relight(path("baked.ply") + " -q -o " + path("x.ply"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  r = relight(path("missing.ply") + " --sky -q -o " + path("x.ply"));
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("missing.ply"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

}  // namespace
}  // namespace sss

// The sss-irrmap tool end to end: outputs, reports, and every kind of bad input.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "envmap/cubemap_io.h"
#include "envmap/environment.h"
#include "optics/fresnel.h"
#include "support/tool_test.h"

namespace sss {
namespace {

namespace fs = std::filesystem;

using test::Capture;
using test::ToolRun;

class SssIrrmap : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return scratch_.path(name); }
  std::vector<std::string> files() const { return scratch_.fileNames(); }
  ToolRun run(const std::string& args) const {
    return test::runTool("sss-irrmap", args, Capture::Stderr);
  }
  // A bad input: exit 1, one error line naming the file and the problem, nothing written.
  void expectRefused(const std::string& input, const std::string& message) {
    const auto before = files();
    const ToolRun r = run(input + " -o " + path("e.exr") + " --radiance " + path("r.exr") +
                          " --json " + path("r.json"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_EQ(r.output, "sss-irrmap: error: " + message + "\n");
    EXPECT_EQ(files(), before);
  }
  test::ScratchDir scratch_;
};

ImageRgb constantImage(int w, int h, glm::vec3 value) {
  ImageRgb image;
  image.width = w;
  image.height = h;
  image.pixels.assign(static_cast<std::size_t>(w) * h, value);
  return image;
}

nlohmann::json readJson(const std::string& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

TEST_F(SssIrrmap, SkyToEveryOutput) {
  const ToolRun r =
      run("--sky=elevation=30,azimuth=45 --radiance " + path("r.exr") + " -o " + path("e.exr") +
          " --sh " + path("sh.json") + " --json " + path("report.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("sss-irrmap: auto: "), std::string::npos)
      << r.output;  // says what it chose
  EXPECT_EQ(files(), (std::vector<std::string>{"e.exr", "e.png", "r.exr", "r.png", "report.json",
                                               "sh.json"}));
  const Cubemap radiance = readCubemap(path("r.exr"));
  EXPECT_EQ(radiance.size(), 128);
  const Cubemap irradiance = readCubemap(path("e.exr"));
  const nlohmann::json report = readJson(path("report.json"));
  EXPECT_EQ(report["irradiance_face_size"], irradiance.size());
  EXPECT_LE(report["estimated_error"].get<double>(), 0.01);
  EXPECT_FALSE(report["reason"].get<std::string>().empty());
  for (const char* stage : {"read", "to_cubemap", "reference", "evaluation", "write", "total"}) {
    EXPECT_TRUE(report["timings_ms"].contains(stage)) << stage;
  }
  const nlohmann::json sh = readJson(path("sh.json"));
  EXPECT_EQ(sh["order"], 2);
  EXPECT_EQ(sh["radiance"].size(), 9u);
  EXPECT_EQ(sh["irradiance"].size(), 9u);
  // The sky is brighter above than below: so is its irradiance.
  EXPECT_GT(irradiance.sample({0, 1, 0}).y, 2.0f * irradiance.sample({0, -1, 0}).y);
  // The quiet run prints nothing.
  EXPECT_EQ(run("--sky -q -o " + path("e2.exr")).output, "");
}

TEST_F(SssIrrmap, UniformEquirectGivesPiLBothMethods) {
  // 256 x 128: the sum straight from the equirect rows takes each texel (at this tolerance) as
  // its exact first moment, which loses a little where the horizon of n cuts a texel: 1.7e-4 of
  // pi L on a 128 x 64 map, 1e-5 on 512 x 256.
  writeImage(path("uniform.exr"), constantImage(256, 128, glm::vec3(2.0f, 1.0f, 0.5f)));
  for (const char* method : {"sh", "brute"}) {
    for (float eta : {1.0f, 1.33f}) {
      const ToolRun r =
          run(path("uniform.exr") + " --method " + method + " --eta " + std::to_string(eta) +
              " --tolerance 1e-6 --size 8 --no-preview -q -o " + path("e.exr"));
      ASSERT_EQ(r.exitCode, 0) << r.output;
      const Cubemap e = readCubemap(path("e.exr"));
      const double scale = M_PI * (1.0 - diffuseFresnelReflectance(eta));
      for (std::size_t i = 0; i < e.texelCount(); ++i) {
        EXPECT_NEAR(e.data()[i].x, 2.0 * scale, 2e-4 * scale) << method;
        EXPECT_NEAR(e.data()[i].z, 0.5 * scale, 0.5e-4 * scale) << method;
      }
    }
  }
}

TEST_F(SssIrrmap, CubemapAndCrossInputsGiveTheSameIrradiance) {
  ASSERT_EQ(run("--sky -q --radiance-size 32 --no-preview --radiance " + path("r.exr") + " -o " +
                path("e1.exr") + " --size 16")
                .exitCode,
            0);
  writeImage(path("cross.exr"), cubemapToCross(readCubemap(path("r.exr"))));
  ASSERT_EQ(run(path("r.exr") + " -q --no-preview -o " + path("e2.exr") + " --size 16").exitCode,
            0);
  ASSERT_EQ(
      run(path("cross.exr") + " -q --no-preview -o " + path("e3.exr") + " --size 16").exitCode, 0);
  const Cubemap e1 = readCubemap(path("e1.exr")), e2 = readCubemap(path("e2.exr")),
                e3 = readCubemap(path("e3.exr"));
  for (std::size_t i = 0; i < e1.texelCount(); ++i) {
    EXPECT_EQ(e1.data()[i], e2.data()[i]);
    EXPECT_EQ(e1.data()[i], e3.data()[i]);
  }
}

TEST_F(SssIrrmap, MissingAndUnreadableFiles) {
  expectRefused(path("missing.exr"), path("missing.exr") + ": no such file");
  std::ofstream(path("junk.exr")) << "not an image";
  const ToolRun r = run(path("junk.exr") + " -o " + path("e.exr"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_EQ(r.output.rfind("sss-irrmap: error: " + path("junk.exr") + ": cannot read image", 0), 0u)
      << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1);
  EXPECT_FALSE(fs::exists(path("e.exr")));
}

TEST_F(SssIrrmap, WrongAspectAndZeroSize) {
  writeImage(path("wide.exr"), constantImage(100, 30, glm::vec3(1.0f)));
  expectRefused(path("wide.exr"), path("wide.exr") +
                                      ": unsupported shape 100x30: expected 2:1 equirect, 4:3 or "
                                      "3:4 cross, or an N x 6N cubemap stack");
  std::ofstream(path("zero.pfm"), std::ios::binary) << "PF\n0 0\n-1.0\n";
  expectRefused(path("zero.pfm"), path("zero.pfm") + ": image has zero size (0x0)");
}

TEST_F(SssIrrmap, NonFiniteTexelsFailUnlessSanitized) {
  ImageRgb image = constantImage(64, 32, glm::vec3(1.0f));
  image.at(10, 3).x = std::numeric_limits<float>::quiet_NaN();
  image.at(2, 7).y = std::numeric_limits<float>::infinity();
  writeImage(path("nan.exr"), image);
  expectRefused(path("nan.exr"), path("nan.exr") +
                                     ": 2 NaN/Inf texel values, first at (10, 3) (use --sanitize "
                                     "to replace them by 0)");
  const ToolRun r = run(path("nan.exr") + " --sanitize --no-preview -o " + path("e.exr"));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("sss-irrmap: warning: "), std::string::npos);
  EXPECT_TRUE(fs::exists(path("e.exr")));
  // --quiet silences the warning too.
  const ToolRun quiet = run(path("nan.exr") + " --sanitize -q --no-preview -o " + path("e.exr"));
  EXPECT_EQ(quiet.exitCode, 0) << quiet.output;
  EXPECT_EQ(quiet.output, "");
}

TEST_F(SssIrrmap, NegativeTexelsAreClampedWithAWarning) {
  ImageRgb image = constantImage(64, 32, glm::vec3(1.0f));
  image.at(5, 5) = glm::vec3(-3.0f);
  writeImage(path("neg.exr"), image);
  const ToolRun quiet = run(path("neg.exr") + " -q --no-preview --radiance " + path("r.exr"));
  EXPECT_EQ(quiet.exitCode, 0) << quiet.output;
  EXPECT_EQ(quiet.output, "");  // --quiet silences environment warnings
  const ToolRun r = run(path("neg.exr") + " --no-preview --radiance " + path("r.exr"));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("sss-irrmap: warning: " + path("neg.exr") +
                          ": 3 negative texel values clamped to 0\n"),
            std::string::npos)
      << r.output;
  const Cubemap radiance = readCubemap(path("r.exr"));
  for (std::size_t i = 0; i < radiance.texelCount(); ++i) EXPECT_GE(radiance.data()[i].x, 0.0f);
}

// A usage error (the command line itself is wrong): one error line, exit 2, nothing written.
TEST_F(SssIrrmap, BadOptions) {
  auto expectUsageError = [&](const std::string& args, const std::string& message) {
    const ToolRun r = run(args);
    EXPECT_EQ(r.exitCode, 2) << args;
    EXPECT_EQ(r.output, "sss-irrmap: error: " + message + "\n") << args;
  };
  expectUsageError("-o " + path("e.exr"),
                   "no environment: give INPUT (equirect, cross or cubemap image) or --sky");
  expectUsageError("--sky", "nothing to write: give --radiance, -o/--irradiance, --sh or --json");
  expectUsageError("--sky -o " + path("e.png"), path("e.png") + ": --irradiance needs a .exr file");
  expectUsageError("--sky=elevation=95 -o " + path("e.exr"),
                   "--sky: elevation must be in [0, 90] degrees");
  expectUsageError("--sky --method fast -o " + path("e.exr"),
                   "--method: unknown irradiance method 'fast' (use auto, brute or sh)");
  // CLI11's own parse errors get the same line and status.
  expectUsageError("--sky --size abc -o " + path("e.exr"), "Could not convert: --size = abc");
  expectUsageError("--sky --size -1 -o " + path("e.exr"),
                   "--size: a cubemap face size must be 1 to 8192 texels, got -1");
  // The material's range, as sss-bake and sss-render check it.
  expectUsageError("--sky --eta 0 -o " + path("e.exr"), "--eta: eta 0 is outside [1, 3]");
  expectUsageError("--sky --frobnicate -o " + path("e.exr"),
                   "The following argument was not expected: --frobnicate");
  expectUsageError(path("x.exr") + " --sky -o " + path("e.exr"), "INPUT excludes --sky");
  // A missing output folder is a failure of the run, not of the command line.
  EXPECT_EQ(run("--sky -o " + path("no/such/dir/e.exr")).exitCode, 1);
  EXPECT_TRUE(files().empty());
}

TEST_F(SssIrrmap, LyingHeaderAndDirectoryAreNamedErrors) {
  // Unchecked: "sss-irrmap: error: std::bad_alloc" for both.
  std::ofstream(path("tall.hdr"), std::ios::binary)
      << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 99999999999 +X 64\n\x01\x02\x03\x04";
  std::ofstream(path("short.hdr"), std::ios::binary)
      << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 512 +X 1024\n\x01\x02\x03\x04";
  const auto before = scratch_.contents();
  expectRefused(path("tall.hdr"), path("tall.hdr") +
                                      ": header declares 64x99999999999 pixels, more than the "
                                      "268435456 (2^28) an image may have");
  expectRefused(path("short.hdr"), path("short.hdr") +
                                       ": header declares 1024x512 pixels, which take at least "
                                       "38912 bytes, but the file has 54 (truncated?)");
  EXPECT_EQ(scratch_.contents(), before);
  fs::create_directory(path("folder.exr"));
  expectRefused(path("folder.exr"), path("folder.exr") + ": is a directory, not a file");
}

TEST_F(SssIrrmap, OutputNamingTheInputIsAUsageError) {
  // Unchecked, -o naming the environment would overwrite it and exit 0.
  writeImage(path("env.exr"), constantImage(32, 16, glm::vec3(1.0f)));
  writeImage(path("env.png"), constantImage(32, 16, glm::vec3(0.5f)));
  const std::string dotted = (fs::path(path("")) / "." / "env.exr").string();
  struct Case {
    std::string args, message;
  };
  for (const Case& c : std::vector<Case>{
           {path("env.exr") + " -o " + path("env.exr"),
            "-o " + path("env.exr") + " is the same file as the input (" + path("env.exr") +
                "): refusing to overwrite an input"},
           {path("env.exr") + " --radiance " + dotted,
            "--radiance " + dotted + " is the same file as the input (" + path("env.exr") +
                "): refusing to overwrite an input"},
           // The PNG preview beside -o env.exr would replace the input env.png.
           {path("env.png") + " -o " + path("env.exr"),
            "the preview of -o " + path("env.png") + " is the same file as the input (" +
                path("env.png") + "): refusing to overwrite an input"},
           {"--sky -o " + path("e.exr") + " --radiance " + path("e.exr"),
            "-o " + path("e.exr") + " is the same file as --radiance (" + path("e.exr") +
                "): two outputs cannot share a file"}}) {
    const auto before = scratch_.contents();
    const ToolRun r = run(c.args);
    EXPECT_EQ(r.exitCode, 2) << c.args;
    EXPECT_EQ(r.output, "sss-irrmap: error: " + c.message + "\n");
    EXPECT_EQ(scratch_.contents(), before) << c.args;
  }
}

TEST_F(SssIrrmap, FaceSizesAndEtaAreCheckedAsInTheOtherTools) {
  // --size 0 and --eta 0.5 are refused, as sss-bake refuses eta outside [1, 3].
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {"--size 0", "--size: a cubemap face size must be 1 to 8192 texels, got 0"},
           {"--radiance-size 0",
            "--radiance-size: a cubemap face size must be 1 to 8192 texels, got 0"},
           {"--size 100000", "--size: a cubemap face size must be 1 to 8192 texels, got 100000"},
           {"--eta 0.5", "--eta: eta 0.5 is outside [1, 3]"},
           {"--eta 3.5", "--eta: eta 3.5 is outside [1, 3]"}}) {
    const ToolRun r = run("--sky -q -o " + path("e.exr") + " " + args);
    EXPECT_EQ(r.exitCode, 2) << args;
    EXPECT_EQ(r.output, "sss-irrmap: error: " + message + "\n");
  }
  EXPECT_TRUE(files().empty());
}

TEST_F(SssIrrmap, HelpGoesToStdoutWithStatusZero) {
  const ToolRun r = test::runTool("sss-irrmap", "--help", Capture::StdoutAndStderr);
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_NE(r.output.find("--method auto|brute|sh"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("sss-irrmap: error"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace sss

// sss-irrmap on several environments in one process (core/batch.h): a bad file is named and the
// others still give their cubemaps, each under DIR/<stem>_radiance.exr, _irradiance.exr, .json.
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "envmap/cubemap_io.h"
#include "image/image.h"
#include "support/tool_test.h"

namespace sss {
namespace {

using test::Capture;

class SssIrrmapBatch : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return scratch_.path(name); }
  test::ToolRun irrmap(const std::string& args) const {
    return test::runTool("sss-irrmap", args + " -q --no-preview", Capture::StdoutAndStderr);
  }
  void writeConstant(const std::string& name, float value) const {
    ImageRgb image;
    image.width = 32;
    image.height = 16;
    image.pixels.assign(32 * 16, glm::vec3(value));
    writeImage(path(name), image);
  }
  test::ScratchDir scratch_;
};

TEST_F(SssIrrmapBatch, BadFileIsNamedAndTheOthersAreConverted) {
  writeConstant("one.exr", 1.0f);
  writeConstant("two.hdr", 2.0f);
  test::writeText(path("bad.exr"), "not an image");
  const test::ToolRun r =
      irrmap(path("one.exr") + " " + path("bad.exr") + " " + path("two.hdr") + " -o " +
             path("out/") + " --radiance " + path("out/") + " --json " + path("out/"));
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_EQ(r.output.rfind("sss-irrmap: error: " + path("bad.exr") + ": ", 0), 0u) << r.output;
  EXPECT_EQ(test::fileNamesIn(path("out")),
            (std::vector<std::string>{"one.json", "one_irradiance.exr", "one_radiance.exr",
                                      "two.json", "two_irradiance.exr", "two_radiance.exr"}));
  // Uniform radiance L gives E = pi L: each output is its own input's.
  EXPECT_NEAR(readCubemap(path("out/two_irradiance.exr")).at(0, 0, 0).x, 2.0 * M_PI, 1e-3);
  EXPECT_NEAR(readCubemap(path("out/one_irradiance.exr")).at(0, 0, 0).x, M_PI, 1e-3);
}

TEST_F(SssIrrmapBatch, SeveralInputsNeedFolders) {
  writeConstant("one.exr", 1.0f);
  writeConstant("two.exr", 2.0f);
  const test::ToolRun r = irrmap(path("one.exr") + " " + path("two.exr") + " -o " + path("e.exr"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("every output names a folder"), std::string::npos) << r.output;
  EXPECT_EQ(scratch_.fileCount(), 2u);
}

}  // namespace
}  // namespace sss

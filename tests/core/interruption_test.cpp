// Long real runs of sss-bake (the path tracer with 10^5 walks per vertex: minutes) and
// sss-render (10^5 timed frames), interrupted a moment after they start: SIGINT and SIGTERM
// exit 130 and 143 with one error line, leaving no output and no temporary (an older output
// stays whole); SIGKILL leaves no file under the output's name, and a later run succeeds.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "child_process.h"
#include "image/image.h"
#include "mesh/baked_ply.h"
#include "mesh/primitives.h"
#include "support/tool_test.h"

namespace fs = std::filesystem;

namespace sss {
namespace {

using test::ChildProcess;
using test::describeStatus;

const std::string kBake = SSS_BINARY_DIR "/tools/sss-bake";
const std::string kRender = SSS_BINARY_DIR "/tools/sss-render";

using test::readFile;

class Interruption : public ::testing::Test {
 protected:
  void SetUp() override {
    BakedMesh sphere;  // positions and normals only: a plain PLY
    sphere.mesh = makeIcosphere(2, 10.0f);
    writeBakedPly(path("sphere.ply"), sphere);
    sphereBytes_ = readFile(path("sphere.ply"));
  }
  std::string path(const std::string& name) const { return scratch_.path(name); }

  std::vector<std::string> bakeArgs(const std::string& method) const {
    std::vector<std::string> args{path("sphere.ply"), "--sky",       "-m", "marble",
                                  "--mm-per-unit",    "1",           "-o", path("out.ply"),
                                  "--json",           path("r.json")};
    if (method == "long") {
      args.insert(args.end(), {"--method", "pathtrace", "--walks", "100000"});
    } else {
      args.insert(args.end(), {"--samples", "16", "-q"});
    }
    return args;
  }

  // Starts `tool`, waits for `started` on its stderr (runTool's handlers are installed by then)
  // and a little more, sends `sig`; returns the waitpid status.
  int interrupt(const std::string& tool, const std::vector<std::string>& args,
                const std::string& started, int sig) {
    ChildProcess child(tool, args);
    EXPECT_TRUE(child.started());
    const bool running = child.waitForStderr(started, 60.0);
    EXPECT_TRUE(running) << "no '" << started << "' in: " << child.stderrText();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    child.signal(sig);
    const int status = child.wait();
    stderr_ = child.stderrText();
    return status;
  }

  void expectOnly(const std::vector<std::string>& names) const {
    EXPECT_EQ(scratch_.fileNames(), names) << "left behind by: " << stderr_;
    EXPECT_EQ(readFile(path("sphere.ply")), sphereBytes_) << "the input changed";
  }

  test::ScratchDir scratch_;
  std::string sphereBytes_;
  std::string stderr_;
};

TEST_F(Interruption, SigintDuringABakeExits130AndLeavesNoOutput) {
  const int status = interrupt(kBake, bakeArgs("long"), "mesh: ", SIGINT);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << describeStatus(status);
  EXPECT_NE(stderr_.find("sss-bake: error: interrupted by SIGINT (unfinished output files "
                         "removed)\n"),
            std::string::npos)
      << stderr_;
  expectOnly({"sphere.ply"});
}

TEST_F(Interruption, SigtermDuringABakeExits143AndKeepsTheOlderOutputWhole) {
  std::ofstream(path("out.ply"), std::ios::binary) << "an older bake";
  const int status = interrupt(kBake, bakeArgs("long"), "mesh: ", SIGTERM);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 143) << describeStatus(status);
  EXPECT_NE(stderr_.find("sss-bake: error: interrupted by SIGTERM"), std::string::npos) << stderr_;
  expectOnly({"out.ply", "sphere.ply"});
  EXPECT_EQ(readFile(path("out.ply")), "an older bake");
}

TEST_F(Interruption, SigkillLeavesNoFileUnderTheOutputNameAndALaterBakeSucceeds) {
  const int status = interrupt(kBake, bakeArgs("long"), "mesh: ", SIGKILL);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << describeStatus(status);
  EXPECT_FALSE(fs::exists(path("out.ply")));
  EXPECT_FALSE(fs::exists(path("r.json")));
  // Whatever a killed run left (at most its temporaries) does not disturb the next one.
  const test::ToolRun again = test::runTool(
      "sss-bake",
      [&] {
        std::string words;
        for (const std::string& a : bakeArgs("short")) words += a + " ";
        return words;
      }(),
      test::Capture::StdoutAndStderr);
  ASSERT_EQ(again.exitCode, 0) << again.output;
  EXPECT_EQ(readBakedPly(path("out.ply")).baked.mesh.vertexCount(), 162u);
  for (const std::string& name : scratch_.fileNames()) {
    EXPECT_EQ(name.find(".tmp."), std::string::npos) << name << " left by the later run";
  }
}

TEST_F(Interruption, SigintDuringARenderExits130AndLeavesNoImage) {
  BakedMesh baked;
  baked.mesh = makeIcosphere(2, 10.0f);
  baked.exitance.assign(baked.mesh.vertexCount(), glm::vec3(0.5f));
  baked.irradiance.assign(baked.mesh.vertexCount(), glm::vec3(1.0f));
  baked.materialName = "marble";
  baked.sigmaA = glm::dvec3(0.0021, 0.0041, 0.0071);
  baked.sigmaSPrime = glm::dvec3(2.19, 2.62, 3.00);
  baked.eta = 1.3;
  writeBakedPly(path("baked.ply"), baked);
  ImageRgb white;  // a uniform equirect environment
  white.width = 32;
  white.height = 16;
  white.pixels.assign(32 * 16, glm::vec3(1.0f));
  writeImage(path("white.exr"), white);
  const std::vector<std::string> args{path("baked.ply"), "-e",       path("white.exr"), "-o",
                                      path("image.png"), "--json",   path("r.json"),    "--size",
                                      "64x64",           "--frames", "100000",          "-v"};
  const int status = interrupt(kRender, args, "GL_RENDERER", SIGINT);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << describeStatus(status);
  EXPECT_NE(stderr_.find("sss-render: error: interrupted by SIGINT"), std::string::npos) << stderr_;
  expectOnly({"baked.ply", "sphere.ply", "white.exr"});
}

}  // namespace
}  // namespace sss

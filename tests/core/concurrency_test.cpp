// Two sss-bake processes at once: into the same output they leave one whole baked PLY, byte for
// byte one of the two bakes; two meshes baked into one folder come out as each alone would. No
// temporary is left in either case.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "child_process.h"
#include "mesh/baked_ply.h"
#include "mesh/primitives.h"
#include "support/tool_test.h"

namespace sss {
namespace {

using test::ChildProcess;
using test::describeStatus;

const std::string kBake = SSS_BINARY_DIR "/tools/sss-bake";

using test::readFile;

class Concurrency : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const auto& [name, level] : {std::pair{"small.ply", 2}, std::pair{"large.ply", 3}}) {
      BakedMesh sphere;  // positions and normals only: a plain PLY
      sphere.mesh = makeIcosphere(level, 10.0f);
      writeBakedPly(path(name), sphere);
    }
  }
  std::string path(const std::string& name) const { return scratch_.path(name); }

  std::vector<std::string> bakeArgs(const std::string& mesh, const std::string& material,
                                    const std::string& output) const {
    // The far field off: these tests are about the files, and it is the slow part of a bake of
    // a small sphere under a sun (far_field_test.cpp covers it).
    return {path(mesh),  "--sky",       "-m", material,     "--mm-per-unit", "1",
            "--samples", "32",          "-o", path(output), "--json",        path(output + ".json"),
            "-q",        "--far-field", "off"};
  }

  // Runs the bakes at once; each must exit 0.
  void bakeAtOnce(const std::vector<std::vector<std::string>>& runs) const {
    std::vector<std::unique_ptr<ChildProcess>> children;
    for (const auto& args : runs) children.push_back(std::make_unique<ChildProcess>(kBake, args));
    for (auto& child : children) {
      const int status = child->wait();
      EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
          << describeStatus(status) << ": " << child->stderrText();
    }
  }

  void expectNoTemporary() const {
    for (const std::string& name : scratch_.fileNames()) {
      EXPECT_EQ(name.find(".tmp."), std::string::npos) << "left behind: " << name;
    }
  }

  test::ScratchDir scratch_;
};

TEST_F(Concurrency, TwoBakesIntoOneOutputLeaveOneWholeBake) {
  bakeAtOnce({bakeArgs("small.ply", "marble", "marble.ply")});
  bakeAtOnce({bakeArgs("small.ply", "skin1", "skin1.ply")});
  const std::string marble = readFile(path("marble.ply")), skin = readFile(path("skin1.ply"));
  ASSERT_NE(marble, skin);
  for (int round = 0; round < 3; ++round) {
    bakeAtOnce(
        {bakeArgs("small.ply", "marble", "out.ply"), bakeArgs("small.ply", "skin1", "out.ply")});
    const std::string out = readFile(path("out.ply"));
    EXPECT_TRUE(out == marble || out == skin)
        << "round " << round << ": " << out.size() << " bytes";
    const BakedPlyContents baked = readBakedPly(path("out.ply"));
    EXPECT_TRUE(baked.baked.materialName == "marble" || baked.baked.materialName == "skin1");
    EXPECT_EQ(baked.baked.mesh.vertexCount(), 162u);
    expectNoTemporary();
  }
}

TEST_F(Concurrency, TwoMeshesBakedIntoOneFolderComeOutAsAlone) {
  bakeAtOnce({bakeArgs("small.ply", "marble", "small_alone.ply")});
  bakeAtOnce({bakeArgs("large.ply", "marble", "large_alone.ply")});
  bakeAtOnce({bakeArgs("small.ply", "marble", "small_out.ply"),
              bakeArgs("large.ply", "marble", "large_out.ply")});
  EXPECT_EQ(readFile(path("small_out.ply")), readFile(path("small_alone.ply")));
  EXPECT_EQ(readFile(path("large_out.ply")), readFile(path("large_alone.ply")));
  EXPECT_EQ(readBakedPly(path("large_out.ply")).baked.mesh.vertexCount(), 642u);
  EXPECT_EQ(scratch_.fileCount(), 2u + 4u * 2u) << "the meshes, and each bake's PLY and JSON";
  expectNoTemporary();
}

}  // namespace
}  // namespace sss

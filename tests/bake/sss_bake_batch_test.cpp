// sss-bake on several meshes in one process (core/batch.h) and the environment's orientation
// (--env-rotate): a bad mesh in a batch is named and skipped, names are checked before any work,
// and turning the environment by 90 degrees bakes what turning the mesh by -90 degrees bakes.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "envmap/environment.h"
#include "envmap/equirect.h"
#include "envmap/orientation.h"
#include "image/image.h"
#include "mesh/baked_ply.h"
#include "mesh/primitives.h"
#include "support/tool_test.h"

namespace sss {
namespace {

using test::Capture;

// An asymmetric lumpy ellipsoid (no symmetry a quarter turn about +Y could hide), 642 vertices.
TriangleMesh lumpyMesh(float scale) {
  TriangleMesh mesh = makeIcosphere(3, 1.0f);
  for (glm::vec3& p : mesh.positions) {
    p = scale * glm::vec3(1.3f * p.x, p.y, 0.7f * p.z) * (1.0f + 0.1f * std::sin(3.0f * p.x + p.y));
  }
  mesh.normals = computeVertexNormals(mesh);
  return mesh;
}

// A mesh as an input file (a PLY without E or B).
void writeMesh(const std::string& path, TriangleMesh mesh) {
  BakedMesh file;
  file.mesh = std::move(mesh);
  writeBakedPly(path, file);
}

// A smooth environment whose colour tells directions apart, as an equirect EXR.
void writeDirectionalEnvironment(const std::string& path) {
  ImageRgb image;
  image.width = 128;
  image.height = 64;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const glm::vec3 d = equirectDirection((x + 0.5f) / image.width, (y + 0.5f) / image.height);
      image.pixels.push_back(glm::vec3(1.0f) + glm::vec3(2.0f * std::max(d.x, 0.0f),
                                                         std::max(d.y, 0.0f),
                                                         3.0f * std::max(-d.z, 0.0f)));
    }
  }
  writeImage(path, image);
}

class SssBakeBatch : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return scratch_.path(name); }
  test::ToolRun bake(const std::string& args) const {
    return test::runTool(
        "sss-bake",
        // No far field: what these tests check is the batch and the orientation, and under this
        // light auto would trace it to its path cap on every mesh (seconds each under ASan).
        args + " -e " + path("env.exr") +
            " -m marble --mm-per-unit 10 --visibility none --far-field off -q",
        Capture::StdoutAndStderr);
  }
  void SetUp() override {
    writeDirectionalEnvironment(path("env.exr"));
    writeMesh(path("a.ply"), lumpyMesh(1.0f));
    writeMesh(path("c.ply"), makeIcosphere(2, 1.0f));
  }
  test::ScratchDir scratch_;
};

TEST_F(SssBakeBatch, BadMeshIsNamedAndTheOthersAreBaked) {
  test::writeText(path("b.ply"), "ply\nthis is not a mesh\n");
  const test::ToolRun r = bake(path("a.ply") + " " + path("b.ply") + " " + path("c.ply") + " -o " +
                               path("out/") + " --json " + path("out/"));
  EXPECT_EQ(r.exitCode, 1) << r.output;
  // One error line naming the bad file; nothing about the good ones.
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_EQ(r.output.rfind("sss-bake: error: " + path("b.ply") + ": ", 0), 0u) << r.output;
  const std::vector<std::string> written = test::fileNamesIn(path("out"));
  EXPECT_EQ(written, (std::vector<std::string>{"a.json", "a.ply", "c.json", "c.ply"}));
  EXPECT_EQ(readBakedPly(path("out/a.ply")).baked.mesh.vertexCount(), 642u);
  EXPECT_TRUE(readBakedPly(path("out/c.ply")).hasExitance);
}

TEST_F(SssBakeBatch, SeveralMeshesNeedAFolderAndOneMayGoIntoOne) {
  // -o without '/' that does not exist is a file: a usage error with several meshes.
  const test::ToolRun r = bake(path("a.ply") + " " + path("c.ply") + " -o " + path("out"));
  ASSERT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("with several meshes, -o names a folder"), std::string::npos);
  const test::ToolRun ok = bake(path("a.ply") + " -o " + path("out/"));
  EXPECT_EQ(ok.exitCode, 0) << ok.output;
  EXPECT_EQ(test::fileNamesIn(path("out")), (std::vector<std::string>{"a.ply"}));
}

TEST_F(SssBakeBatch, NamesAreCheckedBeforeAnyWork) {
  scratch_.makeDir("other");
  writeMesh(path("other/a.ply"), makeIcosphere(1, 1.0f));
  // Two inputs with one stem would share DIR/a.ply: a usage error, nothing written.
  test::ToolRun r = bake(path("a.ply") + " " + path("other/a.ply") + " -o " + path("out/"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("would both write"), std::string::npos) << r.output;
  EXPECT_TRUE(test::fileNamesIn(path("out")).empty());
  // An output folder holding an input: DIR/a.ply would overwrite the input a.ply.
  r = bake(path("a.ply") + " " + path("c.ply") + " -o " + path(""));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("refusing to overwrite an input"), std::string::npos) << r.output;
}

// E and B per vertex of two bakes, the second's vertices in the same order.
double largestRelativeDifference(const BakedMesh& a, const BakedMesh& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.exitance.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      worst = std::max<double>(
          worst, std::abs(a.exitance[i][k] - b.exitance[i][k]) / std::max(1e-6f, a.exitance[i][k]));
      worst = std::max<double>(worst, std::abs(a.irradiance[i][k] - b.irradiance[i][k]) /
                                          std::max(1e-6f, a.irradiance[i][k]));
    }
  }
  return worst;
}

TEST_F(SssBakeBatch, TurningTheEnvironmentEqualsTurningTheMeshBack) {
  TriangleMesh turned = lumpyMesh(1.0f);
  for (glm::vec3& p : turned.positions) p = rotationAboutY(-90.0) * p;
  for (glm::vec3& n : turned.normals) n = rotationAboutY(-90.0) * n;
  writeMesh(path("turned.ply"), turned);
  // Exact sums and the half-space energy: no random walks whose paths depend on the frame.
  const std::string exact = " --method exact --energy halfspace";
  ASSERT_EQ(bake(path("a.ply") + " -o " + path("env90.ply") + " --env-rotate 90" + exact).exitCode,
            0);
  ASSERT_EQ(bake(path("turned.ply") + " -o " + path("mesh-90.ply") + exact).exitCode, 0);
  ASSERT_EQ(bake(path("a.ply") + " -o " + path("plain.ply") + exact).exitCode, 0);
  const BakedMesh env90 = readBakedPly(path("env90.ply")).baked;
  const BakedMesh mesh90 = readBakedPly(path("mesh-90.ply")).baked;
  const BakedMesh plain = readBakedPly(path("plain.ply")).baked;
  // A quarter turn maps the cube's texels onto each other: the same E and B to rounding.
  EXPECT_LT(largestRelativeDifference(env90, mesh90), 1e-3);
  // ... and the turn matters: without it the light comes from elsewhere.
  EXPECT_GT(largestRelativeDifference(env90, plain), 0.05);
}

TEST_F(SssBakeBatch, SkySunTurnsWithTheEnvironment) {
  // --sky azimuth=20 turned by 90 (counter-clockwise) is --sky azimuth=-70.
  const auto skyBake = [&](const std::string& sky, const std::string& extra,
                           const std::string& out) {
    return test::runTool("sss-bake",
                         path("a.ply") + " --sky=elevation=30,azimuth=" + sky +
                             " -m marble --mm-per-unit 10 --visibility none "
                             "--method exact --energy halfspace -q -o " +
                             path(out) + extra,
                         Capture::StdoutAndStderr);
  };
  ASSERT_EQ(skyBake("20", " --env-rotate 90", "turned.ply").exitCode, 0);
  ASSERT_EQ(skyBake("-70", "", "spec.ply").exitCode, 0);
  EXPECT_LT(largestRelativeDifference(readBakedPly(path("turned.ply")).baked,
                                      readBakedPly(path("spec.ply")).baked),
            1e-3);
}

}  // namespace
}  // namespace sss

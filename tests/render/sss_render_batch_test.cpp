// sss-render on several baked meshes in one process (core/batch.h), and --env-rotate: turning the
// environment by 90 degrees about +Y renders what turning the mesh by -90 degrees renders from a
// camera turned with it (background, reflections and all).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "envmap/equirect.h"
#include "envmap/orientation.h"
#include "image/image.h"
#include "mesh/baked_ply.h"
#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"
#include "support/tool_test.h"

namespace sss {
namespace {

using test::Capture;

// A baked marble mesh, lumpy and with an exitance that varies over it, so that a quarter turn
// shows.
BakedMesh lumpyBake() {
  BakedMesh baked;
  baked.mesh = makeIcosphere(3, 1.0f);
  for (glm::vec3& p : baked.mesh.positions) {
    p = glm::vec3(1.3f * p.x, p.y, 0.7f * p.z) * (1.0f + 0.1f * std::sin(3.0f * p.x + p.y));
  }
  baked.mesh.normals = computeVertexNormals(baked.mesh);
  for (const glm::vec3& p : baked.mesh.positions) {
    baked.exitance.push_back(glm::vec3(0.5f + 0.4f * p.x, 0.4f, 0.5f - 0.3f * p.z));
    baked.irradiance.push_back(glm::vec3(1.0f));
  }
  baked.materialName = "marble";
  baked.sigmaA = glm::dvec3(0.0021, 0.0041, 0.0071);
  baked.sigmaSPrime = glm::dvec3(2.19, 2.62, 3.00);
  baked.eta = 1.3;
  return baked;
}

void writeDirectionalEnvironment(const std::string& path) {
  ImageRgb image;
  image.width = 256;
  image.height = 128;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const glm::vec3 d = equirectDirection((x + 0.5f) / image.width, (y + 0.5f) / image.height);
      image.pixels.push_back(glm::vec3(0.2f) + glm::vec3(std::max(d.x, 0.0f),
                                                         0.5f * std::max(d.y, 0.0f),
                                                         std::max(-d.z, 0.0f)));
    }
  }
  writeImage(path, image);
}

class SssRenderBatch : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return scratch_.path(name); }
  test::ToolRun render(const std::string& args) const {
    return test::runTool("sss-render", args + " -e " + path("env.exr") + " --size 64x64 -q",
                         Capture::StdoutAndStderr);
  }
  void SetUp() override {
    writeDirectionalEnvironment(path("env.exr"));
    writeBakedPly(path("a.ply"), lumpyBake());
    writeBakedPly(path("c.ply"), lumpyBake());
  }
  test::ScratchDir scratch_;
};

TEST_F(SssRenderBatch, BadMeshIsNamedAndTheOthersAreRendered) {
  test::writeText(path("b.ply"), "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n");
  const test::ToolRun r =
      render(path("a.ply") + " " + path("b.ply") + " " + path("c.ply") + " -o " + path("out/"));
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_EQ(r.output.rfind("sss-render: error: " + path("b.ply") + ": ", 0), 0u) << r.output;
  EXPECT_EQ(test::fileNamesIn(path("out")), (std::vector<std::string>{"a.png", "c.png"}));
  EXPECT_EQ(readImage(path("out/a.png")).width, 64);
}

// Mean relative difference of two images, and the fraction of pixels off by more than 2%.
struct ImageDifference {
  double mean = 0.0, outliers = 0.0;
};
ImageDifference difference(const ImageRgb& a, const ImageRgb& b) {
  ImageDifference d;
  double sum = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const float off = glm::length(a.pixels[i] - b.pixels[i]);
    sum += off;
    scale += glm::length(b.pixels[i]);
    if (off > 0.02f * std::max(glm::length(b.pixels[i]), 0.05f)) d.outliers += 1.0;
  }
  d.mean = sum / scale;
  d.outliers /= static_cast<double>(a.pixels.size());
  return d;
}

TEST_F(SssRenderBatch, TurningTheEnvironmentEqualsTurningMeshAndCameraBack) {
  BakedMesh turned = lumpyBake();
  for (glm::vec3& p : turned.mesh.positions) p = rotationAboutY(-90.0) * p;
  for (glm::vec3& n : turned.mesh.normals) n = rotationAboutY(-90.0) * n;
  writeBakedPly(path("turned.ply"), turned);
  // Scene A (mesh a, environment turned by +90) is scene B (mesh turned by -90, environment as
  // it is) turned by +90: a camera at azimuth 30 + 90 in A sees what azimuth 30 sees in B.
  const std::string common = " --tonemap none --samples 1 --elevation 20";
  ASSERT_EQ(render(path("a.ply") + " --env-rotate 90 --azimuth 120 -o " + path("A.exr") + common)
                .exitCode,
            0);
  ASSERT_EQ(render(path("turned.ply") + " --azimuth 30 -o " + path("B.exr") + common).exitCode, 0);
  ASSERT_EQ(render(path("a.ply") + " --azimuth 120 -o " + path("plain.exr") + common).exitCode, 0);
  const ImageRgb a = readImage(path("A.exr")), b = readImage(path("B.exr"));
  const ImageDifference same = difference(a, b);
  EXPECT_LT(same.mean, 0.005);
  EXPECT_LT(same.outliers, 0.01);  // rasterization of rotated floats: a few edge pixels at most
  // Without the turn the picture differs (the environment is not symmetric).
  EXPECT_GT(difference(readImage(path("plain.exr")), b).mean, 0.05);
}

}  // namespace
}  // namespace sss

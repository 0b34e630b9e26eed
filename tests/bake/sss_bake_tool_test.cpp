// sss-bake through its binary: a good bake, determinism across threads, and every bad input
// (stderr text, exit code, no output file and no temporary left behind).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/relative_rms.h"
#include "envmap/cubemap_io.h"
#include "lighting/visibility_noise_model.h"
#include "mesh/baked_mesh.h"
#include "mesh/baked_ply.h"
#include "mesh/primitives.h"
#include "optics/fresnel.h"
#include "support/box_with_pit.h"
#include "support/glb_test.h"
#include "support/tool_test.h"
#include "transport/model_error.h"

namespace fs = std::filesystem;

namespace sss {
namespace {

const std::string kTool = SSS_BINARY_DIR "/tools/sss-bake";
// For the tests about files and determinism, not light: the half-space energy model (no escape
// walks, so no far field either) keeps each bake to milliseconds of light (under ASan the walks
// take seconds per bake).
const std::string kHalfSpaceEnergy = " --energy halfspace";

struct RunResult {
  int exitCode;
  std::string output;  // stdout and stderr
};

RunResult run(const std::string& arguments) {
  const std::string command = kTool + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  char buffer[4096];
  while (std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

using test::readFile;

// ASCII PLY with optional normals; faces as given.
void writeAsciiPly(const fs::path& path, const TriangleMesh& mesh, bool normals) {
  std::ofstream out(path);
  out << "ply\nformat ascii 1.0\nelement vertex " << mesh.positions.size()
      << "\nproperty float x\nproperty float y\nproperty float z\n";
  if (normals) out << "property float nx\nproperty float ny\nproperty float nz\n";
  out << "element face " << mesh.triangles.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3 p = mesh.positions[i];
    out << p.x << " " << p.y << " " << p.z;
    if (normals)
      out << " " << mesh.normals[i].x << " " << mesh.normals[i].y << " " << mesh.normals[i].z;
    out << "\n";
  }
  for (const glm::uvec3& t : mesh.triangles) out << "3 " << t.x << " " << t.y << " " << t.z << "\n";
}

void writeBinaryPly(const fs::path& path, const TriangleMesh& mesh) {
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat binary_little_endian 1.0\nelement vertex " << mesh.positions.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face "
      << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const glm::vec3& p : mesh.positions) out.write(reinterpret_cast<const char*>(&p), 12);
  for (const glm::uvec3& t : mesh.triangles) {
    const unsigned char three = 3;
    out.write(reinterpret_cast<const char*>(&three), 1);
    out.write(reinterpret_cast<const char*>(&t), 12);
  }
}

class BakeTool : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(SSS_BINARY_DIR) / "tests" / "bake" /
           ("tmp_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    writeCubemap((dir_ / "white.exr").string(), Cubemap(8, glm::vec3(1.0f)));
    sphere_ = makeIcosphere(2, 10.0f);
    writeAsciiPly(dir_ / "sphere.ply", sphere_, true);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // Common arguments for mesh `name` with output out.ply.
  std::string args(const std::string& mesh, const std::string& extra, int samples = 16) const {
    return path(mesh) + " -e " + path("white.exr") + " -o " + path("out.ply") + " --samples " +
           std::to_string(samples) + " -q " + extra;
  }
  // An error: exit code 1 (bad input; 2 for a usage error, core/tool.h), one "sss-bake: error:"
  // line containing `text`, nothing written.
  void expectError(const RunResult& r, const std::string& text, int exitCode = 1) const {
    EXPECT_EQ(r.exitCode, exitCode) << r.output;
    EXPECT_NE(r.output.find("sss-bake: error:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(text), std::string::npos) << "expected '" << text << "' in:\n"
                                                      << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "out.ply"));
    for (const auto& entry : fs::directory_iterator(dir_)) {
      EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos)
          << "left behind: " << entry.path();
    }
  }

  void expectUsageError(const RunResult& r, const std::string& text) const {
    expectError(r, text, 2);
  }

  // The mesh's warnings are printed without --quiet and only then (warnings obey -q).
  RunResult runExpectingWarning(const std::string& arguments, const std::string& warning) const {
    const RunResult quiet = run(arguments);
    EXPECT_EQ(quiet.exitCode, 0) << quiet.output;
    EXPECT_EQ(quiet.output.find("warning"), std::string::npos) << quiet.output;
    const std::size_t quietAt = arguments.find(" -q ");
    const RunResult r = run(arguments.substr(0, quietAt) + arguments.substr(quietAt + 3));
    EXPECT_NE(r.output.find(warning), std::string::npos) << r.output;
    return r;
  }

  fs::path dir_;
  TriangleMesh sphere_;
};

TEST_F(BakeTool, BakesASphereUnderUniformLight) {
  const RunResult r =
      run(args("sphere.ply", "-m marble --mm-per-unit 1 --json " + path("r.json"), 128));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const BakedPlyContents baked = readBakedPly(path("out.ply"));
  ASSERT_TRUE(baked.hasIrradiance && baked.hasExitance && baked.hasMaterial && baked.hasUnits);
  EXPECT_EQ(baked.baked.materialName, "marble");
  EXPECT_EQ(baked.baked.mmPerUnit, 1.0);
  ASSERT_EQ(baked.baked.mesh.vertexCount(), sphere_.vertexCount());
  // Convex, uniform unit radiance: E = pi (1 - 2 C_1(eta)) at every vertex, no shadows.
  const double expected = M_PI * (1.0 - diffuseFresnelReflectance(1.3f));
  // Monte Carlo: 128 rays give ~1.5% RMS per vertex; the mean has no bias.
  double mean = 0.0;
  for (const glm::vec3& e : baked.baked.irradiance) {
    ASSERT_NEAR(e.g / expected, 1.0, 0.06);
    mean += e.g / expected / static_cast<double>(sphere_.vertexCount());
  }
  EXPECT_NEAR(mean, 1.0, 0.005);
  for (const glm::vec3& b : baked.baked.exitance) {
    ASSERT_TRUE(b.r > 0.0f && b.r < expected);  // total reflectance < 1
  }
  // Radiance along the normal: the normalized exit model of B, L = B F_t(1) / (pi (1 - 2 C_1)).
  ASSERT_TRUE(baked.hasRadianceNormal);
  const double exitScale = fresnelTransmittance(1.0f, 1.3f) / expected;
  for (std::size_t v = 0; v < baked.baked.exitance.size(); ++v)
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(baked.baked.radianceNormal[v][c], baked.baked.exitance[v][c] * exitScale,
                  1e-5 * baked.baked.exitance[v][c]);
  const auto report = nlohmann::json::parse(readFile(dir_ / "r.json"));
  EXPECT_EQ(report["mesh"]["vertices"], sphere_.vertexCount());
  EXPECT_EQ(report["material"]["name"], "marble");
  EXPECT_EQ(report["visibility"]["mode"], "rays");
  // Uniform light: the far field has nothing to move (far_field.h), so auto does not trace it.
  if (report["energy"]["model"] == "escape") {
    EXPECT_FALSE(report["far_field"]["traced"].get<bool>()) << report["far_field"].dump();
    EXPECT_LT(report["far_field"]["sensitivity"].get<double>(), 0.005);
  }
  EXPECT_EQ(report["visibility"]["occluded_fraction"], 0.0);
  // Nothing crosses 20 mm of marble unscattered: the pilot alone.
  EXPECT_FALSE(report["unscattered"]["traced"].get<bool>()) << report["unscattered"].dump();
  EXPECT_LT(report["unscattered"]["share"].get<double>(), 0.003);
  EXPECT_TRUE(report["exitance"].contains("profile_fit"));
  // Auto picks exact for so few vertices; every other method reports its fit.
  const std::string method = report["exitance"]["method"];
  EXPECT_EQ(report["exitance"]["profile_fit"]["gaussians"].get<int>() > 0, method != "exact");
  EXPECT_TRUE(report["stages"].contains("irradiance_s"));

  // Without visibility: the irradiance cubemap lookup, within its 1% tolerance.
  const RunResult none = run(args("sphere.ply", "-m marble --mm-per-unit 1 --visibility none"));
  ASSERT_EQ(none.exitCode, 0) << none.output;
  for (const glm::vec3& e : readBakedPly(path("out.ply")).baked.irradiance) {
    ASSERT_NEAR(e.g / expected, 1.0, 0.01);
  }
}

// --albedo A --mfp D means the albedo the bake returns: a lit plane (an open sheet: the bake's
// auto keeps the half-space energy) gives B / E = A on the default bake (the inversion of the
// dipole's total instead would return 0.525 for 0.5).
TEST_F(BakeTool, AlbedoComesBackFromALitPlane) {
  writeAsciiPly(dir_ / "plane.ply", makeGridPlane(16, 200.0f), true);
  const glm::dvec3 asked(0.5, 0.8, 0.3);
  const RunResult r =
      run(args("plane.ply", "--albedo 0.5,0.8,0.3 --mfp 1,2,0.5 --mm-per-unit 1", 64));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const BakedPlyContents baked = readBakedPly(path("out.ply"));
  int vertices = 0;
  for (std::size_t v = 0; v < baked.baked.mesh.vertexCount(); ++v) {
    const glm::vec3 p = baked.baked.mesh.positions[v];
    if (std::abs(p.x) > 60.0f || std::abs(p.y) > 60.0f) continue;
    ++vertices;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(baked.baked.exitance[v][c] / baked.baked.irradiance[v][c], asked[c],
                  0.01 * asked[c])
          << "vertex " << v << " channel " << c;
  }
  EXPECT_GE(vertices, 9);
}

// A bake whose predicted error is above --tolerance says so (unless -q) with its parts, and the
// JSON's estimated_error.tolerance_met says it either way: the pit without bounces at 1 % (its
// missing light alone is far above it), and the convex sphere under uniform light at 50 %.
TEST_F(BakeTool, ABakeAboveItsToleranceSaysSo) {
  writeAsciiPly(dir_ / "pit.ply", boxWithPit(), true);
  const RunResult above = runExpectingWarning(
      args("pit.ply",
           "-m marble --unit mm --bounces 0 --json " + path("above.json") + kHalfSpaceEnergy, 64),
      "is above --tolerance 1%: numerical");
  ASSERT_EQ(above.exitCode, 0) << above.output;
  EXPECT_TRUE(fs::exists(path("out.ply")));
  const auto a = nlohmann::json::parse(readFile(dir_ / "above.json"))["estimated_error"];
  EXPECT_GT(a["total"].get<double>(), 0.01);
  EXPECT_FALSE(a["tolerance_met"].get<bool>());
  std::string within = args("sphere.ply", "-m marble --unit mm --tolerance 0.5 --json " +
                                              path("within.json") + kHalfSpaceEnergy);
  within.erase(within.find(" -q "), 3);
  const RunResult r = run(within);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find("above --tolerance"), std::string::npos) << r.output;
  const auto w = nlohmann::json::parse(readFile(dir_ / "within.json"))["estimated_error"];
  EXPECT_LE(w["total"].get<double>(), 0.5);
  EXPECT_TRUE(w["tolerance_met"].get<bool>());
}

// --bounces auto: a pit in a box gets the light its walls send it, and the JSON says how many
// bounces it took. Without bounces the bake warns, and its reported error holds the change the
// bounces make. (The half-space energy: the escape walks would triple the test's time and are not
// what it checks; with the half-space the estimate is 0.81x the change, interreflection.h.)
TEST_F(BakeTool, InterreflectionBrightensAPit) {
  const TriangleMesh box = boxWithPit();
  writeAsciiPly(dir_ / "pit.ply", box, true);
  const RunResult without = runExpectingWarning(
      args("pit.ply",
           "-m marble --unit mm --bounces 0 --json " + path("r0.json") + kHalfSpaceEnergy, 64),
      "--bounces auto adds it");
  ASSERT_EQ(without.exitCode, 0) << without.output;
  const BakedPlyContents dark = readBakedPly(path("out.ply"));
  const auto report0 = nlohmann::json::parse(readFile(dir_ / "r0.json"));
  const double missing = report0["interreflection"]["estimated_missing"].get<double>();
  EXPECT_EQ(report0["estimated_error"]["interreflection"].get<double>(), missing);
  EXPECT_GE(report0["estimated_error"]["total"].get<double>(), missing);
  const RunResult r = run(
      args("pit.ply",
           "-m marble --unit mm --bounces auto --json " + path("r.json") + kHalfSpaceEnergy, 64));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const BakedPlyContents lit = readBakedPly(path("out.ply"));
  const auto report = nlohmann::json::parse(readFile(dir_ / "r.json"));
  EXPECT_TRUE(report["interreflection"]["enabled"].get<bool>());
  EXPECT_GE(report["interreflection"]["bounces"].get<int>(), 2);
  // Auto ends with the series' geometric tail, once what the tail may miss is below a tenth of
  // the tolerance.
  EXPECT_TRUE(report["interreflection"]["geometric_tail"].get<bool>());
  EXPECT_LT(report["interreflection"]["remaining"].get<double>(), 0.001);
  double darkPit = 0.0, litPit = 0.0;
  for (std::size_t v = 0; v < box.positions.size(); ++v) {
    if (std::hypot(box.positions[v].x, box.positions[v].y) > 3.0f || box.normals[v].z < 0.5f)
      continue;
    darkPit += dark.baked.irradiance[v].g;
    litPit += lit.baked.irradiance[v].g;
  }
  EXPECT_GT(litPit, 1.15 * darkPit);  // marble: 1.43x measured
  // What the bounces changed, against B without them.
  const double change = relativeRms(lit.baked.exitance, dark.baked.exitance);
  EXPECT_GT(change, 0.02);
  EXPECT_NEAR(missing / change, 1.0, 0.35) << missing << " against " << change;
  // The model error's interreflection term: its weight times the share of the radiance the
  // bounces carry (the bake's B without bounces is the dark bake's: same seed and rays; one exit
  // model for both, and marble's unscattered light is negligible), 0 without bounces.
  const auto modelTerm = [](const nlohmann::json& j) {
    return j["estimated_error"]["model"]["interreflection"].get<double>();
  };
  EXPECT_EQ(modelTerm(report0), 0.0);
  EXPECT_NEAR(modelTerm(report),
              kInterreflectionWeight * relativeRms(dark.baked.exitance, lit.baked.exitance),
              0.02 * modelTerm(report));
  // With bounces the interreflection term is the gather's noise and what the bounces not done
  // would add (interreflection_test measures both): small against the light the bounces added.
  const double gatherNoise = report["interreflection"]["gather_noise"].get<double>();
  const double remaining = report["interreflection"]["remaining"].get<double>();
  EXPECT_NEAR(report["estimated_error"]["interreflection"].get<double>(),
              std::hypot(gatherNoise, remaining), 1e-12);
  EXPECT_GT(gatherNoise, 0.0);
  EXPECT_LT(gatherNoise, 0.2 * change);
  EXPECT_LT(remaining, 0.2 * change);
  // A convex object: auto finds nothing to bounce and leaves it at the pilot.
  ASSERT_EQ(
      run(args("sphere.ply",
               "-m marble --unit mm --bounces auto --json " + path("r1.json") + kHalfSpaceEnergy,
               16))
          .exitCode,
      0);
  const auto convex = nlohmann::json::parse(readFile(dir_ / "r1.json"));
  EXPECT_FALSE(convex["interreflection"]["enabled"].get<bool>());
  EXPECT_EQ(convex["interreflection"]["bounces_requested"], "auto");
  EXPECT_EQ(convex["interreflection"]["estimated_missing"].get<double>(), 0.0);
  fs::remove(dir_ / "out.ply");
  expectUsageError(run(args("pit.ply", "-m marble --unit mm --bounces -3")), "bounces");
  expectUsageError(run(args("pit.ply", "-m marble --unit mm --bounces many")), "many");
}

// Each stage once: visibility and transport (half-space energy), the auto-samples pilot, the
// escape walks. The far field's own determinism is tested in far_field_test.
TEST_F(BakeTool, SameOutputForOneAndTwoThreads) {
  ASSERT_EQ(run(args("sphere.ply", "-m skin1 --unit cm --threads 1" + kHalfSpaceEnergy)).exitCode,
            0);
  fs::rename(dir_ / "out.ply", dir_ / "one.ply");
  ASSERT_EQ(run(args("sphere.ply", "-m skin1 --unit cm --threads 2" + kHalfSpaceEnergy)).exitCode,
            0);
  EXPECT_EQ(readFile(dir_ / "one.ply"), readFile(dir_ / "out.ply"));
  // Auto samples: the pilot and the count it picks do not depend on the threads either.
  const std::string autoArgs = path("sphere.ply") + " --sky -m skin1 --unit cm -q" +
                               kHalfSpaceEnergy + " -o " + path("out.ply") + " --threads ";
  ASSERT_EQ(run(autoArgs + "1").exitCode, 0);
  fs::rename(dir_ / "out.ply", dir_ / "one.ply");
  ASSERT_EQ(run(autoArgs + "2").exitCode, 0);
  EXPECT_EQ(readFile(dir_ / "one.ply"), readFile(dir_ / "out.ply"));
  // The escape energy model's walks (a 20 mm marble sphere under a sky with a sun) and the far
  // field they trace too (at 2 %: 54 walks per probe and 106K far-field paths, a third of the 1 %
  // bake's time). Under even light E is exact on a convex mesh and neither has work to do.
  const std::string escape = path("sphere.ply") + " --sky=elevation=40 -o " + path("out.ply") +
                             " -q --samples 16 -m marble --unit mm --energy escape" +
                             " --tolerance 0.02 --threads ";
  ASSERT_EQ(run(escape + "1 --json " + path("walks.json")).exitCode, 0);
  const auto walks = nlohmann::json::parse(readFile(dir_ / "walks.json"));
  EXPECT_TRUE(walks["far_field"]["traced"].get<bool>());
  EXPECT_GT(walks["energy"]["walks_per_probe"].get<int>(), 16);
  fs::rename(dir_ / "out.ply", dir_ / "one.ply");
  ASSERT_EQ(run(escape + "2").exitCode, 0);
  EXPECT_EQ(readFile(dir_ / "one.ply"), readFile(dir_ / "out.ply"));
}

TEST_F(BakeTool, PathTraceReferenceWritesTheSameFormat) {
  const RunResult r = run(args(
      "sphere.ply", "-m marble --unit mm --method pathtrace --walks 8 --json " + path("r.json")));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const BakedPlyContents baked = readBakedPly(path("out.ply"));
  ASSERT_TRUE(baked.hasIrradiance && baked.hasExitance);
  double sumB = 0.0, sumE = 0.0;
  for (std::size_t v = 0; v < baked.baked.exitance.size(); ++v) {
    ASSERT_TRUE(std::isfinite(baked.baked.exitance[v].g) && baked.baked.exitance[v].g >= 0.0f);
    sumB += baked.baked.exitance[v].g;
    sumE += baked.baked.irradiance[v].g;
  }
  // Energy: under uniform light a convex body returns less than enters, but most of it for
  // marble (albedo ~0.999).
  EXPECT_GT(sumB / sumE, 0.3);
  EXPECT_LT(sumB / sumE, 1.0);
  const auto report = nlohmann::json::parse(readFile(dir_ / "r.json"));
  EXPECT_EQ(report["exitance"]["method"], "pathtrace");
  EXPECT_GT(report["exitance"]["estimated_error"].get<double>(), 0.0);
}

TEST_F(BakeTool, ArtistMaterialUnderTheProceduralSky) {
  // (--far-field off: tracing it under the sun is most of the test's time, and it is not what the
  // test checks.)
  const RunResult r = run(path("sphere.ply") + " --sky=elevation=40 --albedo 0.8,0.6,0.4 --mfp 2 " +
                          "--size-mm 30 --samples 16 --far-field off -q -o " + path("out.ply") +
                          " --json " + path("r.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto report = nlohmann::json::parse(readFile(dir_ / "r.json"));
  EXPECT_EQ(report["environment"]["source"], "sky:elevation=40");
  EXPECT_DOUBLE_EQ(report["units"]["longest_side_mm"].get<double>(), 30.0);
  EXPECT_EQ(report["material"]["eta"], 1.3);
  // The inversion hits the requested diffuse mean free path.
  EXPECT_NEAR(report["material"]["diffuse_mean_free_path_mm"][1].get<double>(), 2.0, 1e-6);
  // Sunlit from above: the top of the sphere is brighter than the bottom.
  const BakedPlyContents baked = readBakedPly(path("out.ply"));
  float top = 0.0f, bottom = 0.0f;
  for (std::size_t v = 0; v < baked.baked.mesh.vertexCount(); ++v) {
    if (baked.baked.mesh.normals[v].y > 0.9f) top = std::max(top, baked.baked.exitance[v].g);
    if (baked.baked.mesh.normals[v].y < -0.9f) bottom = std::max(bottom, baked.baked.exitance[v].g);
  }
  EXPECT_GT(top, 2.0f * bottom);
}

// A 10 mm ketchup sphere under a sun: its red light crosses it unscattered (sigma_t 0.24 /mm).
// That light is added to the radiance along the normal, not to B (it leaves collimated); the
// JSON's share is the relative RMS it adds there.
TEST_F(BakeTool, UnscatteredLightIsInTheRadianceAlongTheNormalOnly) {
  // The far field off: it does not touch the unscattered light, and traced to its cap on this
  // small ketchup sphere it takes most of the test's time.
  auto bake = [&](const std::string& name, const std::string& extra) {
    const RunResult r = run(path("sphere.ply") +
                            " --sky=elevation=40 -m ketchup --size-mm 10 --far-field off -q -o " +
                            path(name + ".ply") + " --json " + path(name + ".json") + " " + extra);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return readBakedPly(path(name + ".ply")).baked;
  };
  const BakedMesh off = bake("off", "--unscattered off");
  const BakedMesh on = bake("auto", "");
  const auto report = nlohmann::json::parse(readFile(dir_ / "auto.json"));
  ASSERT_TRUE(report["unscattered"]["traced"].get<bool>()) << report["unscattered"].dump();
  EXPECT_EQ(report["unscattered"]["requested"], "auto");
  EXPECT_GT(report["unscattered"]["paths"].get<double>(), 0.0);
  const double noise = report["unscattered"]["estimated_error"].get<double>();
  EXPECT_DOUBLE_EQ(report["estimated_error"]["unscattered"].get<double>(), noise);
  EXPECT_FALSE(nlohmann::json::parse(readFile(dir_ / "off.json"))["unscattered"]["traced"]);
  EXPECT_EQ(on.exitance, off.exitance);
  EXPECT_EQ(on.irradiance, off.irradiance);
  // The file says so: sss-render draws it by default then.
  EXPECT_TRUE(on.unscatteredTraced);
  EXPECT_FALSE(off.unscatteredTraced);
  double added = 0.0, total = 0.0;
  for (std::size_t v = 0; v < on.exitance.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      const double d = on.radianceNormal[v][c] - off.radianceNormal[v][c];
      ASSERT_GE(d, 0.0);
      added += d * d;
      total += double(on.radianceNormal[v][c]) * on.radianceNormal[v][c];
    }
  // The icosphere's vertex areas are within 20 % of each other: unweighted sums will do.
  const double share = std::sqrt(added / total);
  EXPECT_GT(share, 0.02);
  EXPECT_NEAR(share, report["unscattered"]["share"].get<double>(), 0.3 * share + 2.0 * noise);
}

TEST_F(BakeTool, AutoSamplesFollowTheTolerance) {
  // Default --samples auto: a pilot predicts the visibility noise in B and picks the rays.
  auto bake = [&](const std::string& tolerance) {
    const RunResult r =
        run(path("sphere.ply") + " --sky=elevation=40 -m ketchup --size-mm 30 -q -o " +
            path("out.ply") + " --json " + path("r.json") + " --tolerance " + tolerance);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return nlohmann::json::parse(readFile(dir_ / "r.json"));
  };
  const auto loose = bake("0.2");
  const auto tight = bake("0.01");  // its walks at their cap, as at 0.005 (3x the time)
  EXPECT_EQ(loose["visibility"]["samples_requested"], "auto");
  // Nothing is in the way of a convex sphere's light: the visibility estimator's ratio to the
  // unoccluded light is exact, and both take the fewest rays (visibility_vertex_estimator.h).
  for (const auto& report : {loose, tight}) {
    EXPECT_EQ(report["visibility"]["samples"].get<int>(), kMinAutoSamples);
    EXPECT_EQ(report["visibility"]["estimated_error"].get<double>(), 0.0);
  }
  // A box with a pit, whose floor and walls see part of the sky, needs more rays at 0.2 % than at
  // 20 % (64 and 32; 32 at 1 %: marble's diffusion averages its 20 mm's noise away).
  writeAsciiPly(dir_ / "pit.ply", boxWithPit(), true);
  const auto pitSamples = [&](const std::string& tolerance) {
    const RunResult r =
        run(path("pit.ply") + " --sky=elevation=40 -m marble --unit mm -q -o " + path("out.ply") +
            " --json " + path("r.json") + " --tolerance " + tolerance + kHalfSpaceEnergy);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return nlohmann::json::parse(readFile(dir_ / "r.json"))["visibility"]["samples"].get<int>();
  };
  const int looseSamples = pitSamples("0.2"), tightSamples = pitSamples("0.002");
  EXPECT_LT(looseSamples, tightSamples);
  EXPECT_GE(looseSamples, kMinAutoSamples);
  EXPECT_LE(tightSamples, 1024);
  for (const auto& report : {loose, tight}) {
    const double tolerance = report["estimated_error"]["tolerance"].get<double>();
    const double visibility = report["visibility"]["estimated_error"].get<double>();
    const double exitance = report["exitance"]["estimated_error"].get<double>();
    // The transport's error holds the noise of the near part's calibration where the far field
    // is traced (far_field.h, calibrateNearPart).
    const double nearNoise = report["exitance"]["near_part_noise"].get<double>();
    if (report["far_field"]["traced"].get<bool>()) {
      EXPECT_GT(nearNoise, 0.0);
    } else {
      EXPECT_EQ(nearNoise, 0.0);
    }
    EXPECT_GE(exitance, nearNoise);
    // A 30 mm ketchup sphere is small against its red diffusion length: the escape energy model's
    // walks add their noise as a third term.
    ASSERT_EQ(report["energy"]["model"], "escape") << report["energy"].dump();
    const double energy = report["energy"]["estimated_error"].get<double>();
    EXPECT_DOUBLE_EQ(report["estimated_error"]["visibility"].get<double>(), visibility);
    EXPECT_DOUBLE_EQ(report["estimated_error"]["energy"].get<double>(), energy);
    // Beside them, what the pilot of interreflection finds missing (nothing on a sphere) and the
    // unscattered light's noise (ketchup's red crosses 30 mm), which the radiance along the
    // normal has and B has not.
    const double interreflection = report["estimated_error"]["interreflection"].get<double>();
    const double unscattered = report["estimated_error"]["unscattered"].get<double>();
    EXPECT_EQ(interreflection, 0.0);
    EXPECT_GT(unscattered, 0.0);
    // And the noise the exit lobe leaves in the radiance: a traced far field's, or (ketchup's low
    // albedo) the escape walks' part of the half-space's lobe.
    const double exitLobe = report["estimated_error"]["exit_lobe"].get<double>();
    EXPECT_EQ(exitLobe, report["exit_lobe"]["noise"].get<double>());
    if (report["far_field"]["traced"].get<bool>()) {
      EXPECT_EQ(report["exit_lobe"]["source"], "far field");
      EXPECT_EQ(exitLobe, report["far_field"]["lobe_noise"].get<double>());
    } else {
      EXPECT_EQ(report["exit_lobe"]["source"], "half-space");
      EXPECT_GT(exitLobe, 0.0);
    }
    const double numerical = std::hypot(std::hypot(visibility, exitance, energy),
                                        std::hypot(interreflection, unscattered), exitLobe);
    EXPECT_NEAR(report["estimated_error"]["numerical"].get<double>(), numerical, 1e-12);
    // Beside it the model's own error (model_error.h): ketchup's exit models part by 7-12 %, of
    // which the exit term takes kExitModelWeight (0.35), for the radiance that leaves through
    // them: with a traced far field B_far's paths met the facets themselves, and the term shrinks
    // with B - B_far.
    const auto& model = report["estimated_error"]["model"];
    const auto term = [&](const char* name) { return model[name].get<double>(); };
    EXPECT_GT(term("exit_model"), 0.0);
    if (report["far_field"]["traced"].get<bool>())
      EXPECT_LT(term("exit_model"), 0.02);
    else
      EXPECT_GT(term("exit_model"), 0.02);
    EXPECT_NEAR(term("total"),
                std::sqrt(std::pow(term("exit_model"), 2) + std::pow(term("facets"), 2) +
                          std::pow(term("facet_light"), 2) + std::pow(term("far_field"), 2) +
                          std::pow(term("interreflection"), 2)),
                1e-12);
    EXPECT_NEAR(report["estimated_error"]["total"].get<double>(),
                std::hypot(numerical, model["total"].get<double>()), 1e-12);
    // Visibility takes at most 0.7 of the budget and the walks 0.6 (unless capped), the diffusion
    // sum the rest in quadrature, so the total meets the tolerance.
    const bool capped = report["visibility"]["samples"].get<int>() >= 1024 ||
                        report["energy"]["walks_per_probe"].get<int>() >= 128;
    if (!capped) {
      EXPECT_LE(visibility, 0.7 * tolerance);
      EXPECT_LE(energy, 0.6 * tolerance);
      EXPECT_NEAR(report["exitance"]["tolerance"].get<double>(),
                  std::sqrt(tolerance * tolerance - visibility * visibility - energy * energy),
                  1e-12);
      EXPECT_LE(std::hypot(visibility, exitance, energy), tolerance);
      EXPECT_LE(unscattered, 0.3 * tolerance);  // ErrorBudget::kUnscatteredShare
    }
    EXPECT_FALSE(report["visibility"]["samples_reason"].get<std::string>().empty());
  }
  // A forced count is kept, and its predicted noise is reported.
  const RunResult r =
      run(args("pit.ply", "-m marble --unit mm --json " + path("r.json") + kHalfSpaceEnergy, 32));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto forced = nlohmann::json::parse(readFile(dir_ / "r.json"));
  EXPECT_EQ(forced["visibility"]["samples"], 32);
  EXPECT_EQ(forced["visibility"]["samples_requested"], 32);
  EXPECT_GT(forced["visibility"]["estimated_error"].get<double>(), 0.0);
}

TEST_F(BakeTool, EnergyModelFollowsTheObjectSize) {
  // Uniform light, no shadows on a convex sphere: E is uniform, so with the escape energy model
  // B = E P exactly (finite_object_energy.h), P the sphere's own escape probability.
  auto bake = [&](const std::string& extra) {
    const RunResult r = run(
        args("sphere.ply", "-m marble --visibility none --json " + path("r.json") + " " + extra));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return std::make_pair(readBakedPly(path("out.ply")).baked,
                          nlohmann::json::parse(readFile(dir_ / "r.json")));
  };
  auto meanRatio = [](const BakedMesh& baked, int c) {
    double sum = 0.0;
    for (std::size_t v = 0; v < baked.exitance.size(); ++v)
      sum += baked.exitance[v][c] / baked.irradiance[v][c];
    return sum / static_cast<double>(baked.exitance.size());
  };

  // A marble sphere 20 mm across, about two diffusion lengths: auto models its energy.
  const auto [small, smallReport] = bake("--unit mm");
  const auto& energy = smallReport["energy"];
  EXPECT_EQ(energy["model"], "escape") << energy.dump();
  EXPECT_EQ(smallReport["profile"]["name"], "dipole");
  const double noise = energy["estimated_error"].get<double>();
  EXPECT_GT(noise, 0.0);
  EXPECT_LT(noise, 0.6 * 0.01);
  for (int c = 0; c < 3; ++c) {
    const double p = energy["mean_escape_probability"][c].get<double>();
    const double halfSpace = energy["halfspace_albedo"][c].get<double>();
    // Walks leave a small sphere sooner than a half-space: less is absorbed (0.955 vs 0.881 red).
    EXPECT_GT(p, halfSpace + 0.04) << c;
    EXPECT_LT(p, 1.0) << c;
    EXPECT_NEAR(meanRatio(small, c), p, 4.0 * noise * p) << c;
  }

  // The half-space model on the same sphere returns about R_total (minus the profile's tail
  // beyond the sphere), well below the walks' answer.
  const auto [halfSpace, halfSpaceReport] = bake("--unit mm --energy halfspace --profile dipole");
  EXPECT_EQ(halfSpaceReport["energy"]["model"], "halfspace");
  EXPECT_LT(meanRatio(halfSpace, 0), energy["mean_escape_probability"][0].get<double>() - 0.05);

  // The same sphere 2 m across is a half-space at marble's diffusion length: auto keeps the cheap
  // model and Burley's profile, whose total is calibrated to the Monte Carlo half-space albedo.
  const auto [large, largeReport] = bake("--mm-per-unit 100");
  EXPECT_EQ(largeReport["energy"]["model"], "halfspace") << largeReport["energy"].dump();
  EXPECT_EQ(largeReport["profile"]["name"], "burley");
  EXPECT_NEAR(meanRatio(large, 0), largeReport["energy"]["halfspace_albedo"][0].get<double>(),
              0.02);
}

// -o picks the format by extension: the GLB holds the bake the PLY holds (same seed: the same
// floats), validates with zero errors and warnings, assimp reads it, and it embeds the report.
TEST_F(BakeTool, WritesGlbChosenByTheOutputExtension) {
  const std::string common = path("sphere.ply") + " -e " + path("white.exr") +
                             " --samples 16 -q -m marble --mm-per-unit 1" + kHalfSpaceEnergy +
                             " -o ";
  RunResult r = run(common + path("out.glb") + " --json " + path("r.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  r = run(common + path("out.ply"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  test::expectValidGltf(path("out.glb"));
  test::expectAssimpReads(path("out.glb"), sphere_.vertexCount(), sphere_.triangleCount());
  const BakedPlyContents glb = readBakedMesh(path("out.glb"));
  const BakedPlyContents ply = readBakedMesh(path("out.ply"));
  ASSERT_TRUE(glb.hasExitance && glb.hasIrradiance && glb.hasMaterial);
  EXPECT_EQ(glb.baked.exitance, ply.baked.exitance);
  EXPECT_EQ(glb.baked.irradiance, ply.baked.irradiance);
  EXPECT_EQ(glb.baked.extraComments, ply.baked.extraComments);
  EXPECT_TRUE(glb.baked.meshChecked && ply.baked.meshChecked);
  EXPECT_NE(readFile(dir_ / "out.ply").find("comment sss checked=1\n"), std::string::npos);
  // Positions in metres: 1 mm per unit.
  EXPECT_FLOAT_EQ(glb.baked.mesh.positions[5].y, ply.baked.mesh.positions[5].y / 1000.0f);
  const test::GlbFile file(path("out.glb"));
  const auto report = nlohmann::json::parse(readFile(dir_ / "r.json"));
  EXPECT_EQ(file.sssExtras()["report"]["material"], report["material"]);
  EXPECT_EQ(file.sssExtras()["report"]["exitance"], report["exitance"]);
  EXPECT_EQ(file.sssExtras()["mm_per_unit"], 1.0);
}

TEST_F(BakeTool, AnOutputExtensionNoWriterKnowsIsAUsageError) {
  for (const char* name : {"out.txt", "out.obj", "out"}) {
    SCOPED_TRACE(name);
    const RunResult r = run(path("sphere.ply") + " -e " + path("white.exr") +
                            " -m marble --mm-per-unit 1 -o " + path(name));
    expectUsageError(r, "the output's extension must be .ply or .glb");
    EXPECT_FALSE(fs::exists(dir_ / name));
  }
}

// Every tool: --version prints the CMake project version; --help ends with the exit statuses
// and two or three typical command lines of that tool.
TEST_F(BakeTool, EveryToolHasVersionAndHelpEndsWithExamples) {
  for (const std::string tool : {"sss-irrmap", "sss-bake", "sss-render", "sss-relight"}) {
    SCOPED_TRACE(tool);
    const std::string binary = SSS_BINARY_DIR "/tools/" + tool;
    test::ToolRun r = test::runCommand(binary + " --version");
    EXPECT_EQ(r.exitCode, 0);
    EXPECT_EQ(r.output, tool + " (sss-tools) " SSS_VERSION "\n");
    r = test::runCommand(binary + " --help");
    EXPECT_EQ(r.exitCode, 0);
    const std::size_t exits = r.output.find("\nExit status:\n  0 ");
    const std::size_t examples = r.output.find("\nExamples:\n");
    ASSERT_NE(exits, std::string::npos) << r.output;
    ASSERT_NE(examples, std::string::npos) << r.output;
    EXPECT_LT(exits, examples);
    std::istringstream lines(r.output.substr(examples + 11));
    int count = 0;
    for (std::string line; std::getline(lines, line);) {
      if (line.empty()) continue;
      EXPECT_EQ(line.rfind("  " + tool + " ", 0), 0u) << line;
      ++count;
    }
    EXPECT_GE(count, 2);
    EXPECT_LE(count, 3);
#ifdef SSS_MAN_DIR
    const std::string page = readFile(SSS_MAN_DIR "/" + tool + ".1");
    EXPECT_NE(page.find("\"sss-tools " SSS_VERSION "\""), std::string::npos) << page;
    EXPECT_NE(page.find("Exit status"), std::string::npos);
    EXPECT_NE(page.find(".SH EXAMPLES"), std::string::npos);
#endif
  }
}

TEST_F(BakeTool, ListsMaterials) {
  const RunResult r = run("--list-materials");
  EXPECT_EQ(r.exitCode, 0);
  for (const char* name : {"apple", "marble", "skimmilk", "wholemilk", "ketchup"}) {
    EXPECT_NE(r.output.find(name), std::string::npos) << name;
  }
}

TEST_F(BakeTool, MissingUnitsIsAnError) {
  expectUsageError(run(args("sphere.ply", "-m marble")), "--mm-per-unit,--unit,--size-mm");
}

TEST_F(BakeTool, MissingMeshIsAnError) {
  expectError(run(args("nothere.ply", "-m marble --unit mm")), "nothere.ply");
}

TEST_F(BakeTool, CorruptMeshIsAnError) {
  std::ofstream(dir_ / "garbage.ply") << "this is not a mesh\n\x01\x02\x03";
  expectError(run(args("garbage.ply", "-m marble --unit mm")), "garbage.ply");
}

TEST_F(BakeTool, TruncatedMeshIsAnError) {
  writeBinaryPly(dir_ / "full.ply", sphere_);
  const std::string bytes = readFile(dir_ / "full.ply");
  std::ofstream(dir_ / "cut.ply", std::ios::binary) << bytes.substr(0, bytes.size() * 2 / 3);
  expectError(run(args("cut.ply", "-m marble --unit mm")), "cut.ply");
}

TEST_F(BakeTool, ZeroFacesIsAnError) {
  TriangleMesh points = sphere_;
  points.triangles.clear();
  writeAsciiPly(dir_ / "points.ply", points, false);
  expectError(run(args("points.ply", "-m marble --unit mm")), "points.ply");
}

TEST_F(BakeTool, NanCoordinatesAreAnError) {
  TriangleMesh bad = sphere_;
  bad.positions[5].y = std::nanf("");
  writeAsciiPly(dir_ / "nan.ply", bad, false);
  expectError(run(args("nan.ply", "-m marble --unit mm")), "nan.ply");
}

TEST_F(BakeTool, DegenerateAndDuplicateFacesAreDroppedWithACount) {
  TriangleMesh mesh = sphere_;
  mesh.triangles.push_back(mesh.triangles[0]);    // duplicate
  mesh.triangles.push_back(glm::uvec3(4, 4, 7));  // degenerate
  writeAsciiPly(dir_ / "dirty.ply", mesh, false);
  const RunResult r = runExpectingWarning(
      args("dirty.ply", "-m marble --unit mm" + kHalfSpaceEnergy + " --json " + path("r.json")),
      "warning");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto report = nlohmann::json::parse(readFile(dir_ / "r.json"));
  EXPECT_EQ(report["mesh"]["dropped_duplicate"], 1);
  EXPECT_EQ(report["mesh"]["dropped_degenerate"], 1);
  EXPECT_EQ(report["mesh"]["triangles"], sphere_.triangleCount());
  EXPECT_TRUE(report["mesh"]["normals_computed"].get<bool>());
}

TEST_F(BakeTool, NonManifoldMeshGivesAWarning) {
  TriangleMesh mesh = sphere_;
  // A fin: a third triangle on an existing edge.
  const glm::uvec3 t = mesh.triangles[0];
  mesh.positions.push_back(mesh.positions[t.x] * 1.5f);
  mesh.normals.push_back(mesh.normals[t.x]);
  mesh.triangles.push_back(glm::uvec3(t.x, t.y, static_cast<unsigned>(mesh.positions.size() - 1)));
  writeAsciiPly(dir_ / "fin.ply", mesh, true);
  const RunResult r = runExpectingWarning(
      args("fin.ply", "-m marble --unit mm" + kHalfSpaceEnergy + " --json " + path("r.json")),
      "non-manifold");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_GT(nlohmann::json::parse(readFile(dir_ / "r.json"))["mesh"]["non_manifold_edges"], 0);
}

TEST_F(BakeTool, InsideOutMeshIsFlippedWithAWarning) {
  TriangleMesh mesh = sphere_;
  for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
  writeAsciiPly(dir_ / "inverted.ply", mesh, false);
  const RunResult r = runExpectingWarning(
      args("inverted.ply", "-m marble --unit mm" + kHalfSpaceEnergy + " --json " + path("r.json")),
      "warning");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(
      nlohmann::json::parse(readFile(dir_ / "r.json"))["mesh"]["orientation_flipped"].get<bool>());
}

TEST_F(BakeTool, BadCoefficientsAreErrors) {
  expectError(run(args("sphere.ply", "--sigma-a -0.1,0.1,0.1 --sigma-s 1 --unit mm")), "negative");
  expectError(run(args("sphere.ply", "--sigma-a 1e9 --sigma-s 1 --unit mm")), "material");
  expectUsageError(run(args("sphere.ply", "-m marble --eta 0.9 --unit mm")), "--eta");
  expectUsageError(run(args("sphere.ply", "--sigma-a 0.1,x,0.1 --sigma-s 1 --unit mm")),
                   "--sigma-a");
  expectUsageError(run(args("sphere.ply", "--sigma-a 0.1 --unit mm")), "--sigma-s");
}

TEST_F(BakeTool, BadChoicesAreErrors) {
  expectUsageError(run(args("sphere.ply", "-m jelly --unit mm")), "marble");  // names the presets
  expectUsageError(run(args("sphere.ply", "-m marble --unit furlong")), "furlong");
  expectUsageError(run(args("sphere.ply", "-m marble --mm-per-unit -2")), "--mm-per-unit");
  expectUsageError(run(args("sphere.ply", "-m marble --unit mm --method fastest")), "fastest");
  expectUsageError(run(args("sphere.ply", "-m marble --unit mm --visibility some")), "some");
  expectUsageError(run(args("sphere.ply", "-m marble --unit mm --energy lots")), "lots");
  expectUsageError(run(args("sphere.ply", "-m marble --unit mm --entry sideways")), "sideways");
  expectUsageError(run(args("sphere.ply", "-m marble --unit mm --far-field maybe")), "maybe");
  expectUsageError(run(args("sphere.ply", "-m marble --unit mm --unscattered sometimes")),
                   "sometimes");
  expectUsageError(run(args("sphere.ply", "-m marble --unit mm --profile gaussian")), "gaussian");
  expectUsageError(run(args("sphere.ply", "-m marble --unit mm", 1)), "--samples");
  expectUsageError(run(path("sphere.ply") + " -e " + path("white.exr") + " -o " + path("out.ply") +
                       " -m marble --unit mm --samples many"),
                   "--samples");
  expectUsageError(run(args("sphere.ply", "-m marble --unit mm --tolerance 0")), "--tolerance");
  expectUsageError(run(path("sphere.ply") + " -m marble --unit mm -o " + path("out.ply")),
                   "-e,--env,--sky");
}

TEST_F(BakeTool, BadEnvironmentIsAnError) {
  std::ofstream(dir_ / "env.exr") << "not an image";
  expectError(run(path("sphere.ply") + " -e " + path("env.exr") + " -m marble --unit mm -q -o " +
                  path("out.ply")),
              "env.exr");
}

// Hostile inputs. Each bad input is refused with one line naming the file and the
// problem, the inputs keep their bytes and nothing else is left in the directory.
class BakeToolHostileInput : public BakeTool {
 protected:
  // The directory's files and their bytes: what a refused run must leave as it was.
  std::vector<std::pair<std::string, std::string>> snapshot() const {
    std::vector<std::pair<std::string, std::string>> files;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      files.emplace_back(entry.path().filename().string(),
                         fs::is_regular_file(entry.path()) ? readFile(entry.path()) : "<dir>");
    }
    std::sort(files.begin(), files.end());
    return files;
  }
  // Runs `arguments`; expects `exitCode`, "sss-bake: error: " and every part of `parts` in one
  // line, and the directory unchanged.
  RunResult expectRefused(const std::string& arguments, const std::vector<std::string>& parts,
                          int exitCode = 1) const {
    const auto before = snapshot();
    const RunResult r = run(arguments);
    EXPECT_EQ(r.exitCode, exitCode) << r.output;
    const std::size_t at = r.output.find("sss-bake: error: ");
    EXPECT_NE(at, std::string::npos) << r.output;
    const std::string line = at == std::string::npos ? "" : r.output.substr(at);
    EXPECT_EQ(std::count(line.begin(), line.end(), '\n'), 1) << r.output;
    for (const std::string& part : parts) {
      EXPECT_NE(line.find(part), std::string::npos) << "expected '" << part << "' in:\n" << line;
    }
    EXPECT_EQ(snapshot(), before) << arguments;
    return r;
  }
};

TEST_F(BakeToolHostileInput, CoordinateBeyondFloatRangeIsAnError) {
  // Unchecked, Embree's ray.valid() assertion aborts the bake (SIGABRT).
  TriangleMesh mesh = sphere_;
  mesh.positions[7].x = 1e38f;
  writeAsciiPly(dir_ / "huge.ply", mesh, false);
  expectRefused(args("huge.ply", "-m marble --unit mm"),
                {path("huge.ply") + ": vertex 7 ", "coordinate of 1e+38", "limit of 1e+18"});
}

TEST_F(BakeToolHostileInput, StrayVertexFailsAtOnce) {
  // Unchecked, 42 vertices, one 1.7e15 mm away, run for more than 120 s (escape walks that cannot
  // move a point).
  TriangleMesh mesh = makeIcosphere(1, 10.0f);
  ASSERT_EQ(mesh.positions.size(), 42u);
  mesh.positions[7].x = 1.7e15f;
  writeAsciiPly(dir_ / "far.ply", mesh, false);
  // The loader refuses it before any work (no timing asserted: timed tests flake under load).
  for (const char* unit : {"--unit mm", "--unit m"}) {
    expectRefused(
        args("far.ply", std::string("-m marble ") + unit),
        {path("far.ply") + ": the mesh reaches 1.7e+15", "vertex 7", "median edge", "65536"});
  }
}

TEST_F(BakeToolHostileInput, MeshBeyondTheMillimetreLimitAfterScalingIsAnError) {
  // A sphere of radius 10 units at 1e6 mm per unit: coordinates of 1e7 mm pass, 2e7 do not.
  expectRefused(args("sphere.ply", "-m marble --mm-per-unit 2e6"),
                {path("sphere.ply") + ": vertex ", "2e+07 mm", "limit of 16777216 mm"});
}

TEST_F(BakeToolHostileInput, DirectoryAsMeshIsAnError) {
  // Unchecked: "error: std::bad_alloc" (a directory opens as a stream of unbounded size).
  fs::create_directory(dir_ / "folder.ply");
  fs::create_directory(dir_ / "folder.off");
  for (const char* name : {"folder.ply", "folder.off"}) {
    expectRefused(args(name, "-m marble --unit mm"), {path(name) + ": is a directory, not a file"});
  }
}

TEST_F(BakeToolHostileInput, LyingHeadersAreErrors) {
  std::ofstream(dir_ / "faces.off") << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2000000000 0 1 2\n";
  expectRefused(args("faces.off", "-m marble --unit mm"),
                {path("faces.off") + ": OFF face 0 declares 2000000000 corners"});
  std::ofstream(dir_ / "tall.hdr")
      << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 99999999999 +X 64\n";
  expectRefused(path("sphere.ply") + " -e " + path("tall.hdr") + " -m marble --unit mm -q -o " +
                    path("out.ply"),
                {path("tall.hdr") + ": header declares 64x", "2^28"});
}

TEST_F(BakeToolHostileInput, OutputNamingAnInputIsAUsageError) {
  // Unchecked, -o naming the mesh would overwrite it and exit 0.
  fs::create_symlink(dir_ / "sphere.ply", dir_ / "link.ply");
  fs::create_hard_link(dir_ / "sphere.ply", dir_ / "hard.ply");
  const std::string tail = " -e " + path("white.exr") + " -m marble --unit mm -q";
  for (const std::string& output : {path("sphere.ply"), (dir_ / "." / "sphere.ply").string(),
                                    path("link.ply"), path("hard.ply")}) {
    expectRefused(path("sphere.ply") + tail + " -o " + output,
                  {"-o " + output + " is the same file as the mesh (" + path("sphere.ply") + ")",
                   "refusing to overwrite an input"},
                  2);
  }
  expectRefused(
      path("sphere.ply") + tail + " -o " + path("out.ply") + " --json " + path("white.exr"),
      {"--json " + path("white.exr") + " is the same file as the environment"}, 2);
  expectRefused(path("sphere.ply") + tail + " -o " + path("out.ply") + " --json " +
                    (dir_ / "." / "out.ply").string(),
                {"is the same file as -o (" + path("out.ply") + "): two outputs"}, 2);
}

TEST_F(BakeToolHostileInput, ParametersOutsideTheirRangeAreUsageErrors) {
  expectRefused(args("sphere.ply", "-m marble --unit mm --eta 0"),
                {"--eta: eta 0 is outside [1, 3]"}, 2);
  expectRefused(args("sphere.ply", "-m marble --unit mm --env-size 9000"),
                {"--env-size: a cubemap face size must be 1 to 8192 texels, got 9000"}, 2);
}

}  // namespace
}  // namespace sss

// sss-render end to end on llvmpipe: output formats, brdf vs sss, and every bad input.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "image/image.h"
#include "material/dipole_profile.h"
#include "material/halfspace_albedo.h"
#include "mesh/baked_glb.h"
#include "mesh/baked_mesh.h"
#include "mesh/baked_ply.h"
#include "mesh/primitives.h"
#include "optics/exit_lobe.h"
#include "optics/fresnel.h"
#include "support/glb_test.h"
#include "support/tool_test.h"

namespace fs = std::filesystem;

namespace sss {
namespace {

using test::Capture;
using test::ToolRun;

class SssRenderTool : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return scratch_.path(name); }

  ToolRun run(const std::string& args, const std::string& environment = "") const {
    return test::runTool("sss-render", args, Capture::StdoutAndStderr, environment);
  }

  // Only the inputs are left: no output, no temporary file.
  void expectOnlyInputs(std::size_t inputs) const {
    EXPECT_EQ(scratch_.fileCount(), inputs) << "a failed run left a file behind";
  }

  void writeUniformEnvironment(const std::string& name, glm::vec3 radiance) const {
    ImageRgb image;
    image.width = 32;
    image.height = 16;
    image.pixels.assign(32 * 16, radiance);
    writeImage(path(name), image);
  }

  // `mesh` baked in marble (eta 1.3, 1 mm per unit) with a constant exitance, unit irradiance.
  static BakedMesh marbleBake(TriangleMesh mesh, glm::vec3 exitance) {
    BakedMesh baked;
    baked.mesh = std::move(mesh);
    baked.exitance.assign(baked.mesh.positions.size(), exitance);
    baked.irradiance.assign(baked.mesh.positions.size(), glm::vec3(1.0f));
    baked.materialName = "marble";
    baked.sigmaA = glm::dvec3(0.0021, 0.0041, 0.0071);
    baked.sigmaSPrime = glm::dvec3(2.19, 2.62, 3.00);
    baked.eta = 1.3;
    baked.mmPerUnit = 1.0;
    return baked;
  }

  static BakedMesh bakedSphere() {
    return marbleBake(makeIcosphere(4, 10.0f), glm::vec3(0.8f, 0.5f, 0.3f));
  }

  // A mesh file with positions and faces only, as a scanner or modeller writes it.
  void writePlainPly(const std::string& name) const {
    const TriangleMesh mesh = makeIcosphere(2, 1.0f);
    std::ofstream out(path(name));
    out << "ply\nformat ascii 1.0\nelement vertex " << mesh.positions.size()
        << "\nproperty float x\nproperty float y\nproperty float z\nelement face "
        << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const glm::vec3& p : mesh.positions) out << p.x << " " << p.y << " " << p.z << "\n";
    for (const glm::uvec3& t : mesh.triangles)
      out << "3 " << t.x << " " << t.y << " " << t.z << "\n";
  }

  test::ScratchDir scratch_;
};

TEST_F(SssRenderTool, WritesAPngOfTheRequestedSizeWithThreeChannels) {
  writeBakedPly(path("sphere.ply"), bakedSphere());
  writeUniformEnvironment("env.exr", glm::vec3(0.5f));
  const ToolRun r = run(path("sphere.ply") + " -e " + path("env.exr") + " -o " + path("out.png") +
                        " --size 96x64 --samples 4 --quiet");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  auto in = OIIO::ImageInput::open(path("out.png"));
  ASSERT_TRUE(in);
  const OIIO::ImageSpec& spec = in->spec();
  EXPECT_EQ(spec.width, 96);
  EXPECT_EQ(spec.height, 64);
  EXPECT_EQ(spec.nchannels, 3);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
  // The sphere is in the middle, lighter than nothing; the corner is the environment.
  std::vector<uint8_t> pixels(96 * 64 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data()));
  EXPECT_GT(pixels[(32 * 96 + 48) * 3], 60);
  EXPECT_NE(pixels[(32 * 96 + 48) * 3], pixels[0]);
}

// The brdf mode is a Lambertian surface with the material's total diffuse reflectance lit by
// the transmitted irradiance cubemap: on a flat region under uniform light it must match a
// baked B = R_d E_t, and differ where the bake darkened B (a shadow, a thin part).
TEST_F(SssRenderTool, BrdfAndSssAgreeOnAFlatUniformRegionAndDifferInAShadow) {
  const float eta = 1.5f;
  const glm::vec3 radiance(0.5f, 0.4f, 0.3f);
  writeUniformEnvironment("env.exr", radiance);
  BakedMesh baked = marbleBake(makeGridPlane(32, 2.0f), glm::vec3(0.0f));
  baked.eta = eta;
  const double transmitted = M_PI * (1.0 - diffuseFresnelReflectance(eta));
  glm::vec3 b;
  for (int c = 0; c < 3; ++c) {
    const double alpha = baked.sigmaSPrime[c] / (baked.sigmaSPrime[c] + baked.sigmaA[c]);
    b[c] = static_cast<float>(halfSpaceDiffuseAlbedo(alpha, eta) * transmitted * radiance[c]);
  }
  for (std::size_t i = 0; i < baked.mesh.positions.size(); ++i) {
    baked.exitance[i] = baked.mesh.positions[i].x < 0.0f ? 0.3f * b : b;  // left half: a shadow
  }
  writeBakedPly(path("plane.ply"), baked);
  const std::string common = path("plane.ply") + " -e " + path("env.exr") +
                             " --eye 0,0,3 --target 0,0,0 --fov 30 --size 64x64 --samples 1"
                             " --tonemap none --quiet";
  ToolRun r = run(common + " --mode sss -o " + path("sss.exr"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  r = run(common + " --mode brdf -o " + path("brdf.exr"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const ImageRgb sss = readImage(path("sss.exr")), brdf = readImage(path("brdf.exr"));
  ASSERT_EQ(sss.width, 64);
  int lit = 0, shadowed = 0;
  for (int y = 4; y < 60; ++y) {
    for (int x = 4; x < 60; ++x) {
      if (x > 36) {
        for (int c = 0; c < 3; ++c) {
          ASSERT_NEAR(sss.at(x, y)[c], brdf.at(x, y)[c], 0.01f * brdf.at(x, y)[c]) << x << "," << y;
        }
        ++lit;
      } else if (x < 28) {
        EXPECT_LT(sss.at(x, y).g, 0.8f * brdf.at(x, y).g) << x << "," << y;
        ++shadowed;
      }
    }
  }
  EXPECT_GT(lit, 1000);
  EXPECT_GT(shadowed, 1000);
}

// The GLB's COLOR_0 divided by its exposure is the radiance sss-render draws along the normal: a
// plane facing the camera in a black environment (no reflection) shows only the exit term. The
// GLB and the PLY of the same bake render alike, with a traced far field too (B through its lobe,
// by default; --exit-model normalized leaves it out).
TEST_F(SssRenderTool, GlbColorIsTheRenderedRadianceAlongTheNormal) {
  writeUniformEnvironment("black.exr", glm::vec3(0.0f));
  for (bool far : {false, true}) {
    BakedMesh baked = marbleBake(makeGridPlane(8, 2.0f), glm::vec3(0.8f, 0.5f, 0.3f));
    baked.mmPerUnit = 1000.0;  // metres: the GLB and the PLY hold the same positions
    if (far) {
      baked.farExitance.assign(baked.exitance.size(), glm::vec3(0.4f, 0.25f, 0.15f));
      baked.exitSlope.assign(baked.exitance.size(), glm::vec3(-0.8f, 0.2f, 3.0f));
    }
    writeBakedGlb(path("plane.glb"), baked);
    writeBakedPly(path("plane.ply"), baked);
    const std::string common = " -e " + path("black.exr") +
                               " --eye 0,0,3 --target 0,0,0 --fov 30 --size 32x32 --samples 1"
                               " --tonemap none --background 0,0,0 --quiet -o ";
    ToolRun r = run(path("plane.glb") + common + path("glb.exr") + " --json " + path("r.json"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(nlohmann::json::parse(test::readFile(path("r.json")))["exit_lobe"], far);
    r = run(path("plane.ply") + common + path("ply.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run(path("plane.ply") + common + path("normalized.exr") + " --exit-model normalized");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const test::GlbFile glb(path("plane.glb"));
    const double exposure = glb.sssExtras()["color"]["exposure"].get<double>();
    const glm::vec3 color = glb.vec3("COLOR_0")[0];
    const ImageRgb fromGlb = readImage(path("glb.exr")), fromPly = readImage(path("ply.exr"));
    const ImageRgb normalized = readImage(path("normalized.exr"));
    for (int c = 0; c < 3; ++c) {
      const double radiance = color[c] / exposure;
      EXPECT_GT(radiance, 0.05);
      // Per-vertex Fresnel and lobe at the plane's corners (25 degrees off the normal) move it by
      // 2e-4, and by 1.6e-3 with red's grazing lobe (slope -0.8).
      EXPECT_NEAR(fromGlb.at(16, 16)[c], radiance, 2.5e-3 * radiance) << c << " far " << far;
      EXPECT_NEAR(fromGlb.at(16, 16)[c], fromPly.at(16, 16)[c], 1e-5) << c << " far " << far;
      // The lobes of slope -0.8 (grazing), 0.2 and 3 (forward) take B to 0.56x, 1.03x and 1.18x
      // along the normal; without a far field nothing changes.
      const double ratio = fromPly.at(16, 16)[c] / normalized.at(16, 16)[c];
      const ExitLobe lobe(float(baked.eta));
      const double slope = far ? baked.exitSlope[0][c] : 0.0;
      EXPECT_NEAR(ratio, lobe.radiance(slope, 1.0f) / lobe.radiance(0.0, 1.0f), 0.005)
          << c << " far " << far;
    }
  }
}

// The light that crosses a thin skim-milk slab unscattered: drawn by default where the bake
// traced it (the file says so, the GLB as the PLY), from the file's material and units, its
// closed form at the centre seen straight on (F_r L + F_t^2 e^(-tau) / (1 - F_r^2 e^(-2 tau)) L,
// tau = sigma_t h in mm); with --unscattered on wherever it can; never with off, nor on an open
// mesh.
TEST_F(SssRenderTool, UnscatteredLightCrossesAThinSlab) {
  writeUniformEnvironment("white.exr", glm::vec3(1.0f));
  BakedMesh baked = marbleBake(makeSlab(20.0f, 0.5f, 8), glm::vec3(0.0f));
  baked.materialName = "skimmilk";
  baked.sigmaA = glm::dvec3(0.0014, 0.0025, 0.0142);
  baked.sigmaSPrime = glm::dvec3(0.70, 1.22, 1.90);
  baked.mmPerUnit = 2.0;  // 1 mm thick
  writeBakedPly(path("untraced.ply"), baked);
  baked.unscatteredTraced = true;
  writeBakedPly(path("slab.ply"), baked);
  writeBakedGlb(path("slab.glb"), baked);
  writeBakedPly(path("plane.ply"), marbleBake(makeGridPlane(8, 20.0f), glm::vec3(0.0f)));
  const std::string common = " -e " + path("white.exr") +
                             " --eye 0,0,30 --target 0,0,0 --fov 20 --size 33x33 --samples 1"
                             " --tonemap none --background 0,0,0 --quiet --json " +
                             path("r.json") + " -o " + path("out.exr");
  const float fr = fresnelDielectric(1.0f, 1.3f);
  // The centre pixel, and whether the report says the unscattered light was drawn.
  const auto render = [&](const std::string& args) {
    const ToolRun r = run(args + common);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    const bool drawn = nlohmann::json::parse(test::readFile(path("r.json")))["unscattered"];
    return std::make_pair(glm::vec3(readImage(path("out.exr")).at(16, 16)), drawn);
  };
  for (const std::string& args :
       {path("slab.ply"), path("slab.glb"), path("untraced.ply") + " --unscattered on"}) {
    const auto [centre, drawn] = render(args);
    EXPECT_TRUE(drawn) << args;
    for (int c = 0; c < 3; ++c) {
      const double t = std::exp(-(baked.sigmaA[c] + baked.sigmaSPrime[c]) * 1.0);
      const double expected = fr + (1 - fr) * (1 - fr) * t / (1 - fr * fr * t * t);
      EXPECT_NEAR(centre[c], expected, 5e-3 * expected) << args << " channel " << c;
    }
  }
  for (const std::string& args : {path("untraced.ply"), path("slab.ply") + " --unscattered off",
                                  path("plane.ply") + " --unscattered on"}) {
    const auto [centre, drawn] = render(args);
    EXPECT_FALSE(drawn) << args;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(centre[c], fr, 1e-4) << args << " channel " << c;
  }
}

// A mesh that sss-bake checked (and warned about) says so in the file: sss-render does not repeat
// its topology warnings, and still warns about the same mesh from elsewhere.
TEST_F(SssRenderTool, TopologyWarningsOfACheckedBakeAreNotRepeated) {
  writeUniformEnvironment("env.exr", glm::vec3(0.5f));
  BakedMesh baked = marbleBake(makeIcosphere(1, 1.0f), glm::vec3(0.5f));
  const glm::uvec3 t = baked.mesh.triangles[0];
  baked.mesh.positions.push_back(baked.mesh.positions[t.x] * 1.5f);  // a fin: non-manifold edge
  baked.mesh.normals.push_back(baked.mesh.normals[t.x]);
  baked.exitance.push_back(glm::vec3(0.5f));
  baked.irradiance.push_back(glm::vec3(1.0f));
  baked.mesh.triangles.push_back(
      {t.x, t.y, static_cast<unsigned>(baked.mesh.positions.size() - 1)});
  for (const char* name : {"fin.ply", "fin.glb"}) {
    for (const bool checked : {false, true}) {
      SCOPED_TRACE(std::string(name) + (checked ? " checked" : " unchecked"));
      baked.meshChecked = checked;
      writeBakedMesh(path(name), baked);
      const ToolRun r = run(path(name) + " -e " + path("env.exr") + " -o " + path("out.png") +
                            " --size 16x16 --samples 1");
      ASSERT_EQ(r.exitCode, 0) << r.output;
      EXPECT_EQ(r.output.find("non-manifold") == std::string::npos, checked) << r.output;
      EXPECT_EQ(r.output.find("warning") == std::string::npos, checked) << r.output;
    }
  }
}

// An open mesh is drawn from both sides unless culling is asked for: seen from behind, the
// plane covers the middle of the picture with --cull auto and vanishes with --cull back.
TEST_F(SssRenderTool, CullingIsAutomaticForOpenMeshes) {
  writeBakedPly(path("plane.ply"), marbleBake(makeGridPlane(8, 2.0f), glm::vec3(1.0f)));
  writeUniformEnvironment("env.exr", glm::vec3(0.5f));
  const std::string common = path("plane.ply") + " -e " + path("env.exr") +
                             " --eye 0,0,-3 --target 0,0,0 --size 16x16 --samples 1"
                             " --background 0,0,0 --tonemap none --quiet";
  ASSERT_EQ(run(common + " -o " + path("auto.exr")).exitCode, 0);
  ASSERT_EQ(run(common + " --cull back -o " + path("back.exr")).exitCode, 0);
  EXPECT_GT(readImage(path("auto.exr")).at(8, 8).g, 0.1f);
  EXPECT_EQ(readImage(path("back.exr")).at(8, 8), glm::vec3(0.0f));
}

TEST_F(SssRenderTool, AMeshWithoutBakedAttributesNamesThemAndSuggestsSssBake) {
  writePlainPly("plain.ply");
  writeUniformEnvironment("env.exr", glm::vec3(0.5f));
  ToolRun r = run(path("plain.ply") + " -e " + path("env.exr") + " -o " + path("out.png"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("exitance_r, exitance_g, exitance_b"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("sss-bake"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--mode brdf"), std::string::npos) << r.output;
  r = run(path("plain.ply") + " -e " + path("env.exr") + " -o " + path("out.png") +
          " --mode irradiance");
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("irradiance_r, irradiance_g, irradiance_b"), std::string::npos);
  expectOnlyInputs(2);
  // The brdf mode needs none of them.
  r = run(path("plain.ply") + " -e " + path("env.exr") + " -o " + path("out.png") +
          " --mode brdf --size 32x32 --quiet");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(fs::exists(path("out.png")));
}

TEST_F(SssRenderTool, NoEglDisplayIsAClearError) {
  writeBakedPly(path("sphere.ply"), bakedSphere());
  writeUniformEnvironment("env.exr", glm::vec3(0.5f));
  // glvnd with no vendor library: no EGL implementation at all.
  const ToolRun r = run(path("sphere.ply") + " -e " + path("env.exr") + " -o " + path("out.png"),
                        "__EGL_VENDOR_LIBRARY_FILENAMES=" + path("none.json"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("sss-render: error: no EGL display gives an OpenGL 4.5 core context"),
            std::string::npos)
      << r.output;
  expectOnlyInputs(2);
}

TEST_F(SssRenderTool, TooOldAnOpenGlIsAClearError) {
  writeBakedPly(path("sphere.ply"), bakedSphere());
  writeUniformEnvironment("env.exr", glm::vec3(0.5f));
  // Mesa pretending to offer OpenGL 3.3 only.
  const ToolRun r = run(path("sphere.ply") + " -e " + path("env.exr") + " -o " + path("out.png"),
                        "MESA_GL_VERSION_OVERRIDE=3.3");
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("no EGL display gives an OpenGL 4.5 core context"), std::string::npos)
      << r.output;
  expectOnlyInputs(2);
}

TEST_F(SssRenderTool, AShaderCompileErrorPrintsTheGlslLog) {
  writeBakedPly(path("sphere.ply"), bakedSphere());
  writeUniformEnvironment("env.exr", glm::vec3(0.5f));
  fs::create_directory(path("shaders"));
  for (const auto& entry : fs::directory_iterator(fs::path(SSS_SOURCE_DIR) / "shaders")) {
    fs::copy_file(entry.path(), path("shaders/" + entry.path().filename().string()));
  }
  std::ofstream(path("shaders/surface.frag"), std::ios::app) << "\nthis is not GLSL\n";
  const ToolRun r = run(path("sphere.ply") + " -e " + path("env.exr") + " -o " + path("out.png") +
                        " --shader-dir " + path("shaders"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("shaders/surface.frag: GLSL compile error"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("error", r.output.find("GLSL compile error") + 20), std::string::npos)
      << "no GLSL log: " << r.output;
  EXPECT_FALSE(fs::exists(path("out.png")));
  expectOnlyInputs(3);
}

TEST_F(SssRenderTool, BadOptionsAreRejectedBeforeAnyOutput) {
  writeBakedPly(path("sphere.ply"), bakedSphere());
  writeUniformEnvironment("env.exr", glm::vec3(0.5f));
  const std::string mesh = path("sphere.ply"), env = " -e " + path("env.exr");
  // Usage errors (the command line itself is wrong): exit 2.
  for (const std::string& args :
       {mesh + env + " -o " + path("out.png") + " --size 0x64",
        mesh + env + " -o " + path("out.png") + " --background 1,2",
        mesh + env + " -o " + path("out"), mesh + env + " -o " + path("out.png") + " --mode fast",
        mesh + env + " -o " + path("out.png") + " --eta abc",
        mesh + env + " -o " + path("out.png") + " --relight-on tpu", mesh + env}) {
    const ToolRun r = run(args);
    EXPECT_EQ(r.exitCode, 2) << args;
    EXPECT_EQ(r.output.rfind("sss-render: error: ", 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
  EXPECT_EQ(run(mesh + env + " -o " + path("out.png") + " --mode fast").output,
            "sss-render: error: --mode: unknown shading mode 'fast' (use sss, brdf, irradiance or "
            "normals)\n");
  EXPECT_EQ(run(mesh + env + " -o " + path("out.png") + " --relight-on tpu").output,
            "sss-render: error: --relight-on: unknown relight device 'tpu' (use gpu or cpu)\n");
  // Bad input files: exit 1.
  for (const std::string& args : {mesh + " -e " + path("missing.exr") + " -o " + path("out.png"),
                                  path("missing.ply") + env + " -o " + path("out.png")}) {
    const ToolRun r = run(args);
    EXPECT_EQ(r.exitCode, 1) << args;
    EXPECT_NE(r.output.find("sss-render: error:"), std::string::npos) << r.output;
  }
  expectOnlyInputs(2);
}

TEST_F(SssRenderTool, HostileInputsAreRefusedAndLeaveTheFilesAsTheyWere) {
  writeBakedPly(path("sphere.ply"), bakedSphere());
  BakedMesh far = bakedSphere();
  far.mesh.positions[7].x = 1e38f;  // unchecked: an empty picture, exit 0
  writeBakedPly(path("huge.ply"), far);
  writeUniformEnvironment("env.exr", glm::vec3(0.5f));
  // A far field with one slope outside the exit lobe's range (its bytes patched after writing,
  // which refuses it), and a GLB with a far field but no exit slopes.
  BakedMesh withFar = bakedSphere();
  withFar.farExitance.assign(withFar.exitance.size(), glm::vec3(0.1f));
  withFar.exitSlope.assign(withFar.exitance.size(), glm::vec3(0.25f));
  withFar.exitSlope[3].x = 0.3173f;  // a value found once in the file
  writeBakedPly(path("slope.ply"), withFar);
  {
    std::string bytes = test::readFile(path("slope.ply"));
    const float from = 0.3173f, to = -1.5f;
    const std::string a(reinterpret_cast<const char*>(&from), 4);
    ASSERT_EQ(bytes.find(a), bytes.rfind(a));
    bytes.replace(bytes.find(a), 4, std::string(reinterpret_cast<const char*>(&to), 4));
    std::ofstream(path("slope.ply"), std::ios::binary) << bytes;
  }
  writeBakedGlb(path("half.glb"), withFar);
  {
    std::string bytes = test::readFile(path("half.glb"));
    const std::size_t at = bytes.find("_EXIT_SLOPE");
    ASSERT_NE(at, std::string::npos);
    bytes.replace(at, 11, "_EXIT_SLOPX");  // same length: the chunks stay well formed
    std::ofstream(path("half.glb"), std::ios::binary) << bytes;
  }
  fs::create_directory(path("folder.ply"));  // unchecked: "error: std::bad_alloc"
  std::ofstream(path("tall.hdr"), std::ios::binary)
      << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 99999999999 +X 64\n";
  const std::string env = " -e " + path("env.exr"), out = " -o " + path("out.png");
  struct Case {
    std::string args, message;
    int exitCode;
  };
  for (const Case& c : std::vector<Case>{
           {path("huge.ply") + env + out, path("huge.ply") + ": vertex 7 (1e+38, ", 1},
           {path("folder.ply") + env + out, path("folder.ply") + ": is a directory, not a file", 1},
           {path("slope.ply") + env + out,
            path("slope.ply") + ": exit_slope of vertex 3 is outside [-1, 100]", 1},
           {path("half.glb") + env + out,
            path("half.glb") + ": glTF: _FAR_EXITANCE without _EXIT_SLOPE", 1},
           {path("sphere.ply") + " -e " + path("tall.hdr") + out,
            path("tall.hdr") + ": header declares 64x99999999999 pixels", 1},
           // Unchecked, -o naming the environment would overwrite it.
           {path("sphere.ply") + env + " -o " + path("env.exr"),
            "-o " + path("env.exr") + " is the same file as the environment (" + path("env.exr") +
                "): refusing to overwrite an input",
            2},
           {path("sphere.ply") + env + out + " --json " + path("sphere.ply"),
            "--json " + path("sphere.ply") + " is the same file as the mesh", 2},
           {path("sphere.ply") + env + out + " --albedo 2,0.5,0.5 --mode brdf",
            "--albedo: albedo 2,0.5,0.5 must lie in [0, 1]", 2},
           {path("sphere.ply") + env + out + " --fov nan",
            "--fov: must be a finite number in [1, 170], got 'nan'", 2},
           {path("sphere.ply") + env + out + " --exposure inf",
            "--exposure: must be a finite number, got 'inf'", 2},
           {path("sphere.ply") + env + out + " --env-size 9000",
            "--env-size: a cubemap face size must be 1 to 8192 texels, got 9000", 2},
           {path("sphere.ply") + env + out + " --eta 0.5", "--eta: eta 0.5 is outside [1, 3]",
            2}}) {
    const auto before = scratch_.contents();
    const ToolRun r = run(c.args + " -q");
    EXPECT_EQ(r.exitCode, c.exitCode) << c.args << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("sss-render: error: " + c.message, 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_EQ(scratch_.contents(), before) << c.args;
  }
}

TEST_F(SssRenderTool, FramesAreTimedAndReported) {
  writeBakedPly(path("sphere.ply"), bakedSphere());
  writeUniformEnvironment("env.exr", glm::vec3(0.5f));
  const ToolRun r =
      run(path("sphere.ply") + " -e " + path("env.exr") + " -o " + path("out.png") +
          " --size 64x64 --frames 3 --warmup 1 --verbose --json " + path("report.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("GL_RENDERER: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" FPS"), std::string::npos) << r.output;
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(path("report.json")));
  EXPECT_EQ(report["frames"]["count"], 3);
  EXPECT_GT(report["frames"]["fps"].get<double>(), 0.0);
  EXPECT_GT(report["frames"]["median_ms"].get<double>(), 0.0);
  EXPECT_EQ(report["triangles"], 20 * 256);
  EXPECT_FALSE(report["gl"]["renderer"].get<std::string>().empty());
}

}  // namespace
}  // namespace sss

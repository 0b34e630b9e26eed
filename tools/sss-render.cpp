// sss-render: a baked mesh (sss-bake's PLY) in an environment, drawn with OpenGL 4.5 on a
// headless EGL context (the GPU where there is one, Mesa llvmpipe otherwise) into a PNG
// (8-bit sRGB) or EXR (linear float). See lib/render/renderer.h and shaders/surface.frag.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/timer.h"
#include "core/tool.h"
#include "envmap/environment.h"
#include "irradiance/irradiance.h"
#include "material/dipole_profile.h"
#include "mesh/baked_ply.h"
#include "optics/fresnel.h"
#include "render/camera.h"
#include "render/gl_context.h"
#include "render/image_output.h"
#include "render/renderer.h"

namespace {

using sss::Error;

glm::vec3 parseVec3(const std::string& text, const std::string& option) {
  glm::vec3 v;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%f,%f,%f%c", &v.x, &v.y, &v.z, &tail) != 3 ||
      !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
    throw Error(option + " " + text + ": expected three numbers x,y,z");
  }
  return v;
}

void parseSize(const std::string& text, int& width, int& height) {
  char tail = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &width, &height, &tail) != 2 || width < 1 ||
      height < 1 || width > 16384 || height > 16384) {
    throw Error("--size " + text + ": expected WIDTHxHEIGHT, each 1 to 16384");
  }
}

std::string missingProperties(const char* prefix) {
  return std::string(prefix) + "_r, " + prefix + "_g, " + prefix + "_b";
}

}  // namespace

int main(int argc, char** argv) {
  return sss::runTool("sss-render", [&]() -> int {
    CLI::App app{"Render a baked mesh in an environment with headless OpenGL (EGL)."};
    std::string input, envSource, output, modeName = "sss", fresnelName = "exact";
    std::string exitModelName = "normalized", tonemapName = "aces", backgroundSpec = "env";
    std::string sizeSpec = "1024x1024", eyeSpec, targetSpec, upSpec = "0,1,0", shaderDir;
    std::string jsonPath, albedoSpec, cullName = "auto";
    std::optional<float> reflectFactor, etaOverride;
    float azimuth = 30.0f, elevation = 15.0f, distance = 0.0f, fov = 35.0f, exposure = 0.0f;
    int samples = 4, frames = 0, warmup = 3, envSize = 0, threads = 0;
    bool verbose = false, quiet = false;

    app.add_option("mesh", input, "Baked mesh (sss-bake's PLY; any mesh for --mode brdf)")
        ->required();
    app.add_option("-e,--env", envSource,
                   "Environment: equirect, cross or cubemap image (sss-irrmap --radiance), "
                   "or sky[:spec]")
        ->required();
    app.add_option("-o,--output", output, ".png (8-bit sRGB) or .exr (linear float)")->required();
    app.add_option("--mode", modeName, "sss | brdf | irradiance | normals")
        ->check(CLI::IsMember({"sss", "brdf", "irradiance", "normals"}));
    app.add_option("--fresnel", fresnelName, "exact | schlick")
        ->check(CLI::IsMember({"exact", "schlick"}));
    app.add_option("--exit-model", exitModelName,
                   "normalized: B F_t / (pi (1 - 2 C_1)), flux = B | jensen: B F_t / pi")
        ->check(CLI::IsMember({"normalized", "jensen"}));
    app.add_option("--reflect-factor", reflectFactor,
                   "The paper's constant mix(base, reflection, F) instead of Fresnel weights")
        ->check(CLI::Range(0.0f, 1.0f));
    app.add_option("--eta", etaOverride, "Relative index (default: the material's)")
        ->check(CLI::Range(1.0f, 3.0f));
    app.add_option("--albedo", albedoSpec,
                   "brdf: diffuse albedo r,g,b (default: the material's dipole total "
                   "reflectance)");
    app.add_option("--azimuth", azimuth, "Camera azimuth about +Y in degrees (0: from +Z)");
    app.add_option("--elevation", elevation, "Camera elevation in degrees");
    app.add_option("--distance", distance, "Camera distance in mesh units (default: framed)");
    app.add_option("--eye", eyeSpec, "Camera position x,y,z (overrides the orbit)");
    app.add_option("--target", targetSpec,
                   "Look-at point x,y,z (default: the bounding sphere's centre)");
    app.add_option("--up", upSpec, "Up vector x,y,z");
    app.add_option("--fov", fov, "Vertical field of view in degrees")
        ->check(CLI::Range(1.0f, 170.0f));
    app.add_option("--size", sizeSpec, "Image size WxH");
    app.add_option("--samples", samples, "MSAA samples (1: none)")->check(CLI::Range(1, 64));
    app.add_option("--background", backgroundSpec,
                   "env, or a colour r,g,b stored as given (0..1 display values)");
    app.add_option("--exposure", exposure, "Exposure in EV (stops)");
    app.add_option("--tonemap", tonemapName, "none | reinhard | aces")
        ->check(CLI::IsMember({"none", "reinhard", "aces"}));
    app.add_option("--env-size", envSize, "Radiance cubemap face size (0: from the source)")
        ->check(CLI::Range(0, 4096));
    app.add_option("--cull", cullName,
                   "Back-face culling: auto (only for closed, consistently wound meshes), back, "
                   "none")
        ->check(CLI::IsMember({"auto", "back", "none"}));
    app.add_option("--frames", frames,
                   "Render N timed frames and report ms/frame (wall clock, GL timer) and FPS")
        ->check(CLI::Range(0, 100000));
    app.add_option("--warmup", warmup, "Untimed frames before --frames")
        ->check(CLI::Range(0, 1000));
    app.add_option("--threads", threads, "Threads for the irradiance cubemap (0: all cores)");
    app.add_option("--shader-dir", shaderDir, "Read shaders from this folder (development)");
    app.add_option("--json", jsonPath, "Report: GL renderer, sizes, timings");
    app.add_flag("-v,--verbose", verbose, "Print the EGL path and the GL vendor/renderer/version");
    app.add_flag("-q,--quiet", quiet, "No progress messages");
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      return app.exit(e);
    }
    if (verbose) quiet = false;
    sss::Stopwatch total;

    // Everything that can be checked before the work starts.
    sss::FrameOptions frameOptions;
    parseSize(sizeSpec, frameOptions.width, frameOptions.height);
    frameOptions.samples = samples;
    frameOptions.linear = sss::isLinearImagePath(output);
    {
      const auto dot = output.find_last_of('.');
      if (dot == std::string::npos || output.find('/', dot) != std::string::npos) {
        throw Error(output + ": no file extension to choose the image format (.png or .exr)");
      }
    }
    sss::ShadingOptions shading;
    shading.mode = modeName == "sss"          ? sss::ShadingMode::Sss
                   : modeName == "brdf"       ? sss::ShadingMode::Brdf
                   : modeName == "irradiance" ? sss::ShadingMode::Irradiance
                                              : sss::ShadingMode::Normals;
    shading.fresnel =
        fresnelName == "schlick" ? sss::FresnelModel::Schlick : sss::FresnelModel::Exact;
    shading.tonemap = tonemapName == "none"       ? sss::Tonemap::None
                      : tonemapName == "reinhard" ? sss::Tonemap::Reinhard
                                                  : sss::Tonemap::Aces;
    shading.exposureEv = exposure;
    shading.reflectFactor = reflectFactor;
    if (backgroundSpec != "env")
      shading.backgroundColor = parseVec3(backgroundSpec, "--background");

    // The GL context first: without one nothing else is worth doing.
    sss::Stopwatch stage;
    sss::GlContext context;
    if (verbose) {
      sss::info("EGL: " + context.eglPath() + ", vendor " + context.eglVendor(), false);
      sss::info("GL_VENDOR: " + context.glVendor(), false);
      sss::info("GL_RENDERER: " + context.glRenderer(), false);
      sss::info("GL_VERSION: " + context.glVersion(), false);
    }
    const double contextMs = stage.milliseconds();

    // Mesh and what it carries.
    stage.restart();
    const sss::BakedPlyContents contents = sss::readBakedPly(input);
    const sss::BakedMesh& baked = contents.baked;
    for (const std::string& w : contents.report.warnings) sss::warn(input + ": " + w);
    if (shading.mode == sss::ShadingMode::Sss && !contents.hasExitance) {
      sss::fail(input, "missing " + missingProperties("exitance") +
                           ": run sss-bake on it first (or use --mode brdf, which needs none)");
    }
    if (shading.mode == sss::ShadingMode::Irradiance && !contents.hasIrradiance) {
      sss::fail(input, "missing " + missingProperties("irradiance") +
                           ": run sss-bake on it first (or use --mode brdf, which needs none)");
    }
    float eta = contents.hasMaterial ? static_cast<float>(baked.eta) : 1.3f;
    if (etaOverride) eta = *etaOverride;
    if (!contents.hasMaterial && !etaOverride && shading.mode == sss::ShadingMode::Sss) {
      sss::warn(input + ": no material recorded in the header: eta 1.3 (set --eta)");
    }
    shading.eta = eta;
    shading.exitScale = exitModelName == "jensen" ? static_cast<float>(1.0 / M_PI)
                                                  : static_cast<float>(sss::exitRadianceScale(eta));
    if (shading.mode == sss::ShadingMode::Brdf) {
      if (!albedoSpec.empty()) {
        shading.albedo = parseVec3(albedoSpec, "--albedo");
      } else if (contents.hasMaterial) {
        // The total diffuse reflectance of the material's dipole, so that a flat region under
        // uniform light looks the same in both modes (B = R_d E).
        const glm::dvec3 albedo = baked.sigmaSPrime / (baked.sigmaA + baked.sigmaSPrime);
        for (int c = 0; c < 3; ++c) {
          shading.albedo[c] = static_cast<float>(sss::dipoleTotalReflectance(albedo[c], eta));
        }
      } else {
        shading.albedo = glm::vec3(0.8f);
        sss::warn(input + ": no material recorded in the header: albedo 0.8 (set --albedo)");
      }
    }
    sss::RenderMesh renderMesh;
    renderMesh.positions = baked.mesh.positions;
    renderMesh.normals = baked.mesh.normals;
    if (shading.mode == sss::ShadingMode::Sss) renderMesh.values = baked.exitance;
    if (shading.mode == sss::ShadingMode::Irradiance) renderMesh.values = baked.irradiance;
    renderMesh.indices.reserve(baked.mesh.triangles.size() * 3);
    // Culling would punch holes where a scan's triangles are wound the wrong way.
    const sss::MeshReport& report = contents.report;
    const bool closedAndConsistent =
        report.boundaryEdges == 0 && report.misorientedEdges == 0 && report.nonManifoldEdges == 0;
    shading.cullBackFaces = cullName == "back" || (cullName == "auto" && closedAndConsistent);
    const sss::BoundingSphere bounds = sss::boundingSphere(baked.mesh.positions);
    for (const glm::uvec3& t : baked.mesh.triangles) {
      renderMesh.indices.insert(renderMesh.indices.end(), {t.x, t.y, t.z});
    }
    const double loadMs = stage.milliseconds();

    // Environment, and the brdf mode's transmitted irradiance E(n).
    stage.restart();
    sss::EnvironmentOptions envOptions;
    envOptions.faceSize = envSize;
    const sss::Cubemap radiance = sss::loadEnvironment(envSource, envOptions);
    sss::Cubemap irradiance;
    std::string irradianceReason;
    if (shading.mode == sss::ShadingMode::Brdf) {
      sss::IrradianceOptions irrOptions;
      irrOptions.eta = eta;
      irrOptions.threads = threads;
      sss::IrradianceResult result = sss::computeIrradiance(radiance, irrOptions);
      irradiance = std::move(result.irradiance);
      irradianceReason = result.reason;
      sss::info("irradiance: " + result.reason, quiet);
    }
    const double envMs = stage.milliseconds();

    // GL.
    stage.restart();
    if (frameOptions.samples > context.maxSamples()) {
      sss::warn("--samples " + std::to_string(frameOptions.samples) + ": this GL allows at most " +
                std::to_string(context.maxSamples()) + "; using that");
      frameOptions.samples = context.maxSamples();
    }
    const sss::ShaderSources shaders(shaderDir);
    sss::Renderer renderer(shaders, frameOptions, shading);
    renderer.setMesh(renderMesh);
    renderer.setEnvironment(radiance, irradiance.empty() ? nullptr : &irradiance);
    const float aspect =
        static_cast<float>(frameOptions.width) / static_cast<float>(frameOptions.height);
    sss::Camera camera;
    if (!eyeSpec.empty()) {
      camera.eye = parseVec3(eyeSpec, "--eye");
      camera.target = targetSpec.empty() ? bounds.centre : parseVec3(targetSpec, "--target");
      camera.up = parseVec3(upSpec, "--up");
      camera.fovYDeg = fov;
      if (glm::length(camera.eye - camera.target) < 1e-12f) {
        throw Error("--eye and --target are the same point");
      }
      sss::fitClipPlanes(camera, bounds);
    } else {
      camera = sss::orbitCamera(bounds, azimuth, elevation, distance, fov, aspect);
      if (!targetSpec.empty()) {
        camera.target = parseVec3(targetSpec, "--target");
        sss::fitClipPlanes(camera, bounds);
      }
    }
    renderer.setCamera(camera);
    const double setupMs = stage.milliseconds();

    stage.restart();
    renderer.draw();
    const sss::RenderedImage image = renderer.readBack();
    const double renderMs = stage.milliseconds();
    sss::FrameTimings timings;
    if (frames > 0) {
      timings = renderer.timeFrames(frames, warmup);
      std::printf(
          "%s: %zu triangles, %dx%d, %d sample(s), %d frames: median %.2f ms/frame "
          "(wall clock, glFinish each frame; min %.2f, max %.2f) = %.1f FPS; pipelined %.2f "
          "ms/frame; GL timer %.2f ms/frame%s; CPU %.2f ms/frame [%s]\n",
          input.c_str(), baked.mesh.triangles.size(), frameOptions.width, frameOptions.height,
          frameOptions.samples, timings.frames, timings.medianWallMs, timings.minWallMs,
          timings.maxWallMs, timings.fps(), timings.pipelinedMs, timings.medianGpuMs,
          context.isSoftware() ? " (not a measure on a software renderer)" : "", timings.cpuMs,
          context.glRenderer().c_str());
    }
    sss::writeRenderedImage(output, image);
    sss::info("wrote " + output, quiet);

    if (!jsonPath.empty()) {
      nlohmann::json report = {{"input", input},
                               {"output", output},
                               {"mode", modeName},
                               {"vertices", baked.mesh.positions.size()},
                               {"triangles", baked.mesh.triangles.size()},
                               {"width", frameOptions.width},
                               {"height", frameOptions.height},
                               {"samples", frameOptions.samples},
                               {"cull_back_faces", shading.cullBackFaces},
                               {"eta", eta},
                               {"fresnel", fresnelName},
                               {"exit_model", exitModelName},
                               {"environment", envSource},
                               {"environment_face_size", radiance.size()},
                               {"gl",
                                {{"egl_path", context.eglPath()},
                                 {"egl_vendor", context.eglVendor()},
                                 {"vendor", context.glVendor()},
                                 {"renderer", context.glRenderer()},
                                 {"version", context.glVersion()},
                                 {"software", context.isSoftware()}}},
                               {"times_ms",
                                {{"gl_context", contextMs},
                                 {"load", loadMs},
                                 {"environment", envMs},
                                 {"gl_setup", setupMs},
                                 {"first_frame_and_readback", renderMs},
                                 {"total", total.milliseconds()}}}};
      if (!irradianceReason.empty()) report["irradiance"] = irradianceReason;
      if (frames > 0) {
        report["frames"] = {{"count", timings.frames},
                            {"warmup", warmup},
                            {"median_ms", timings.medianWallMs},
                            {"min_ms", timings.minWallMs},
                            {"max_ms", timings.maxWallMs},
                            {"fps", timings.fps()},
                            {"pipelined_ms", timings.pipelinedMs},
                            {"cpu_ms", timings.cpuMs},
                            {"gl_timer_median_ms", timings.medianGpuMs}};
      }
      sss::AtomicOutput out(jsonPath);
      std::ofstream file(out.tempPath());
      file << report.dump(2) << "\n";
      file.close();
      if (!file) sss::fail(jsonPath, "cannot write");
      out.commit();
    }
    return 0;
  });
}

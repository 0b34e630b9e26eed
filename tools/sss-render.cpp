// sss-render: a baked mesh (sss-bake's PLY) in an environment, drawn with OpenGL 4.5 on a
// headless EGL context (the GPU where there is one, Mesa llvmpipe otherwise) into a PNG
// (8-bit sRGB) or EXR (linear float). See lib/render/renderer.h and shaders/surface.frag.
// Several meshes with -o DIR/ render in one process: one GL context, the environment loaded once.
#include <array>
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "bake/relight.h"
#include "core/atomic_output.h"
#include "core/batch.h"
#include "core/cli.h"
#include "core/error.h"
#include "core/format.h"
#include "core/median.h"
#include "core/paths.h"
#include "core/timer.h"
#include "core/tool.h"
#include "envmap/environment.h"
#include "envmap/orientation_options.h"
#include "irradiance/irradiance.h"
#include "material/material.h"
#include "mesh/baked_mesh.h"
#include "render/baked_shading.h"
#include "render/camera.h"
#include "render/gl_context.h"
#include "render/image_output.h"
#include "render/renderer.h"

namespace {

using namespace sss;

// Where a relightable bake is relit: in the vertex shader (the smooth light's SH summed against
// the stored transfer; the compact lights and the bounces, where there are any, computed before
// drawing: bake/relight.h, RelitSplit), or wholly before drawing, as sss-relight does.
enum class RelightDevice { Gpu, Cpu };
constexpr EnumNames<RelightDevice, 2> kRelightDeviceNames{
    "relight device", {{{RelightDevice::Gpu, "gpu"}, {RelightDevice::Cpu, "cpu"}}}};

struct Arguments {
  std::vector<std::string> inputs;  // one, or several for a batch
  std::string input, environment, output, shaderDir, jsonPath;
  EnvironmentOrientation orientation;
  ShadingRequest request;
  FresnelModel fresnel = FresnelModel::Exact;
  Tonemap tonemap = Tonemap::Aces;
  std::optional<float> reflectFactor;
  std::optional<glm::vec3> background;  // unset: the environment
  float exposure = 0.0f;
  std::array<int, 2> size{1024, 1024};
  float azimuth = 30.0f, elevation = 15.0f, distance = 0.0f, fov = 35.0f;
  std::optional<glm::vec3> eye, target;
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  int samples = 4, frames = 0, warmup = 3, envSize = 0, threads = 0;
  int lightTurntable = 0;  // > 0: frames with the environment turning a full circle
  bool verbose = false, quiet = false;
  bool relight = true;  // a relightable bake is relit under -e (--no-relight: drawn as baked)
  RelightDevice relightOn = RelightDevice::Gpu;
};

glm::vec3 parseXyz(const std::string& text) {
  return cli::parseTriple<float>(text);
}

// "WxH", each 1 to 16384.
std::array<int, 2> parseImageSize(const std::string& text) {
  const std::size_t x = text.find('x');
  std::array<int, 2> size{0, 0};
  if (x == std::string::npos || !CLI::detail::lexical_cast(text.substr(0, x), size[0]) ||
      !CLI::detail::lexical_cast(text.substr(x + 1), size[1]) || size[0] < 1 || size[1] < 1 ||
      size[0] > 16384 || size[1] > 16384) {
    throw Error("expected WIDTHxHEIGHT, each 1 to 16384, got '" + text + "'");
  }
  return size;
}

// A BRDF's diffuse albedo: each channel in [0, 1] (checkDiffuseAlbedo).
glm::vec3 parseAlbedo(const std::string& text) {
  const glm::vec3 albedo = parseXyz(text);
  checkDiffuseAlbedo(albedo);
  return albedo;
}

std::optional<glm::vec3> parseBackground(const std::string& text) {
  if (text == "env") return std::nullopt;
  return parseXyz(text);
}

// The mesh as drawn: its file contents, the shading taken from the bake, and its bounds.
struct LoadedMesh {
  BakedPlyContents contents;
  // A relightable bake relit under the environment, by this (kept for a light turntable's frames).
  std::unique_ptr<BakedMeshRelighter> relighter;
  RelightDevice relitOn = RelightDevice::Cpu;  // where a relighter is: where it relights
  ShadingParameters shading;
  RenderMesh renderMesh;
  BoundingSphere bounds;
};

// Whether the bake is relightable (sss-bake --relightable) and to be relit under -e.
bool relights(const Arguments& a, const BakedPlyContents& contents) {
  return a.relight && contents.hasRelight && a.request.mode != ShadingMode::Brdf;
}

// The far field's values of a relit bake dropped (its bake environment's, its exit slopes
// included); exit slopes without a far field (the material's and the object's lobe) kept.
void dropBakeEnvironmentLight(BakedPlyContents& contents) {
  if (!contents.hasFarField) return;
  contents.baked.farExitance.clear();
  contents.baked.exitSlope.clear();
  contents.hasFarField = false;
  contents.hasExitSlope = false;
}

void reportRelit(const Arguments& a, RelightDevice device, int compactLights) {
  info("relit under " + a.environment + " on the " + kRelightDeviceNames.name(device) + " (" +
           std::to_string(compactLights) + " compact lights)",
       a.quiet);
}

// The bake's light replaced by `relit` (bake/relight.h, on the CPU): B and the radiance along
// the normal.
void takeRelitLight(const Arguments& a, RelitLight relit, BakedPlyContents& contents) {
  contents.baked.exitance = std::move(relit.exitance);
  contents.baked.radianceNormal = std::move(relit.radianceNormal);
  dropBakeEnvironmentLight(contents);
  reportRelit(a, RelightDevice::Cpu, relit.compactLights);
}

// The transfer and g b of a mesh relit on the GPU (renderer.h, RenderMesh), from the relighter's.
void addRelightTransfer(const RelightTransfer& transfer, RenderMesh& mesh) {
  mesh.relightTransfer = transfer.relightTransfer;
  mesh.exitanceGain.resize(transfer.radianceGain.size());
  for (std::size_t v = 0; v < mesh.exitanceGain.size(); ++v)
    mesh.exitanceGain[v] = transfer.radianceGain[v] * transfer.exitancePerRadiance[v];
}

// Where a relightable bake is relit: on the GPU where asked, in the sss mode, and where this GL's
// vertex shaders can read its transfer (GlContext::maxVertexStorageBytes); else on the CPU, with a
// warning where the GPU was asked but cannot.
RelightDevice relightDeviceFor(const Arguments& a, const BakedMesh& baked,
                               std::size_t maxVertexStorageBytes) {
  if (a.relightOn != RelightDevice::Gpu || a.request.mode != ShadingMode::Sss)
    return RelightDevice::Cpu;
  const std::size_t bytes =
      relightStorageBytes(baked.mesh.positions.size(), std::size_t(baked.relightCount()));
  if (bytes <= maxVertexStorageBytes) return RelightDevice::Gpu;
  warn(a.input + ": relit on the CPU: its transfer takes " + format("%.1f", bytes / 1048576.0) +
       " MiB, and this GL's vertex shaders read " +
       (maxVertexStorageBytes == 0
            ? std::string("no storage buffer")
            : format("storage buffers of %.1f MiB at most", maxVertexStorageBytes / 1048576.0)));
  return RelightDevice::Cpu;
}

// A relightable bake relit under the environment drawn around it, by the relighter returned
// (null: not relit), which a light turntable's frames reuse. On the GPU only the bake's own
// light is dropped here: the renderer takes the relit light (relightOnGpu).
std::unique_ptr<BakedMeshRelighter> relightUnder(const Arguments& a, const Cubemap& radiance,
                                                 RelightDevice device, BakedPlyContents& contents) {
  if (!relights(a, contents)) return nullptr;
  auto relighter = std::make_unique<BakedMeshRelighter>(
      a.input, contents.baked, RunContext{.threads = a.threads, .quiet = true},
      a.lightTurntable > 1);
  if (device == RelightDevice::Gpu)
    dropBakeEnvironmentLight(contents);
  else
    takeRelitLight(a, relighter->relight(radiance), contents);
  return relighter;
}

// Reads the baked mesh; names what the asked mode needs and the file lacks, and the defaults
// taken for what the file does not record. A relightable bake is relit under `radiance` on the
// CPU; where this GL can relight it (relightDeviceFor), its render mesh takes the transfer instead.
LoadedMesh loadMesh(const Arguments& a, const Cubemap& radiance, const GlContext& context) {
  LoadedMesh m;
  m.contents = readBakedMesh(a.input);
  if (!a.quiet) {
    for (const std::string& w : m.contents.report.warnings) warn(a.input + ": " + w);
  }
  if (relights(a, m.contents))
    m.relitOn = relightDeviceFor(a, m.contents.baked, context.maxVertexStorageBytes());
  m.relighter = relightUnder(a, radiance, m.relitOn, m.contents);
  const std::string missing = missingBakedValues(m.contents, a.request.mode);
  if (!missing.empty()) {
    fail(a.input, "missing " + missing +
                      ": run sss-bake on it first (or use --mode brdf, which needs none)");
  }
  m.shading = shadingFor(m.contents, a.request);
  const std::string noMaterial = a.input + ": no material recorded in the header: ";
  if (m.shading.etaIsFallback) warn(noMaterial + format("eta %g (set --eta)", m.shading.eta));
  if (m.shading.albedoIsFallback) {
    warn(noMaterial + format("albedo %g (set --albedo)", m.shading.albedo.x));
  }
  m.renderMesh = renderMeshFor(m.contents.baked, a.request.mode, m.shading.exitLobe);
  if (m.relighter && m.relitOn == RelightDevice::Gpu) {
    addRelightTransfer(m.relighter->transfer(), m.renderMesh);
    m.renderMesh.values.clear();  // the rest of B: written with the light (relightOnGpu)
  }
  m.bounds = boundingSphere(m.contents.baked.mesh.positions);
  return m;
}

ShadingOptions shadingOptions(const Arguments& a, const ShadingParameters& p) {
  ShadingOptions s;
  s.mode = a.request.mode;
  s.fresnel = a.fresnel;
  s.tonemap = a.tonemap;
  s.exposureEv = a.exposure;
  s.reflectFactor = a.reflectFactor;
  s.backgroundColor = a.background;
  s.eta = p.eta;
  s.exitScale = p.exitScale;
  s.exitWeight = p.exitWeight;
  s.lobeMoment0 = p.lobeMoment0;
  s.lobeMoment1 = p.lobeMoment1;
  s.albedo = p.albedo;
  s.cullBackFaces = p.cullBackFaces;
  s.unscatteredSigmaT = p.unscatteredSigmaT;
  return s;
}

// The radiance cubemap, and for the brdf mode the transmitted irradiance E(n) it is lit by.
struct Environment {
  Cubemap radiance, irradiance;
  std::string irradianceReason;
};

// The environment, loaded at its first use and kept for the next meshes of a batch; the brdf
// mode's irradiance is computed once per eta.
class EnvironmentCache {
 public:
  explicit EnvironmentCache(const Arguments& a) : a_(a) {}

  const Cubemap& radiance() {
    if (radiance_.empty()) {
      EnvironmentOptions options;
      options.faceSize = a_.envSize;
      options.orientation = a_.orientation;
      options.threads = a_.threads;
      options.read.quiet = a_.quiet;
      radiance_ = loadEnvironment(a_.environment, options);
    }
    return radiance_;
  }

  const Environment& lighting(float eta) {
    auto found = byEta_.find(a_.request.mode == ShadingMode::Brdf ? eta : 0.0f);
    if (found != byEta_.end()) return found->second;
    Environment env;
    env.radiance = radiance();
    if (a_.request.mode == ShadingMode::Brdf) {
      IrradianceOptions irradiance;
      irradiance.eta = eta;
      irradiance.threads = a_.threads;
      IrradianceResult result = computeIrradiance(env.radiance, irradiance);
      env.irradiance = std::move(result.irradiance);
      env.irradianceReason = result.reason;
      info("irradiance: " + result.reason, a_.quiet);
    }
    return byEta_.emplace(a_.request.mode == ShadingMode::Brdf ? eta : 0.0f, std::move(env))
        .first->second;
  }

 private:
  const Arguments& a_;
  Cubemap radiance_;
  std::map<float, Environment> byEta_;
};

// --eye places the camera (looking at --target, else the bounding sphere's centre); otherwise
// the orbit of --azimuth, --elevation and --distance frames the mesh.
Camera placeCamera(const Arguments& a, const BoundingSphere& bounds, float aspect) {
  Camera camera;
  if (a.eye) {
    camera.eye = *a.eye;
    camera.target = a.target ? *a.target : bounds.centre;
    camera.up = a.up;
    camera.fovYDeg = a.fov;
    if (glm::length(camera.eye - camera.target) < 1e-12f) {
      throw Error("--eye and --target are the same point");
    }
    fitClipPlanes(camera, bounds);
  } else {
    camera = orbitCamera(bounds, a.azimuth, a.elevation, a.distance, a.fov, aspect);
    if (a.target) {
      camera.target = *a.target;
      fitClipPlanes(camera, bounds);
    }
  }
  return camera;
}

void printFrameTimings(const Arguments& a, const LoadedMesh& mesh, const FrameOptions& frame,
                       const FrameTimings& t, const GlContext& context) {
  std::printf(
      "%s: %zu triangles, %dx%d, %d sample(s), %d frames: median %.2f ms/frame "
      "(wall clock, glFinish each frame; min %.2f, max %.2f) = %.1f FPS; pipelined %.2f "
      "ms/frame; GL timer %.2f ms/frame%s; CPU %.2f ms/frame [%s]\n",
      a.input.c_str(), mesh.contents.baked.mesh.triangles.size(), frame.width, frame.height,
      frame.samples, t.frames, t.medianWallMs, t.minWallMs, t.maxWallMs, t.fps(), t.pipelinedMs,
      t.medianGpuMs, context.isSoftware() ? " (not a measure on a software renderer)" : "", t.cpuMs,
      context.glRenderer().c_str());
}

// Stage times of the report, in milliseconds.
struct StageTimes {
  double context = 0, load = 0, environment = 0, setup = 0, render = 0;
};

// A light turntable's further frames (all but the first), medians per frame in milliseconds: the
// environment turned (its cubemap made again), the bake relit, the frame drawn and read back, and
// all of it.
struct TurntableTimes {
  int frames = 0;
  double environment = 0, relight = 0, draw = 0, total = 0;
};

nlohmann::json glJson(const GlContext& context) {
  return {{"egl_path", context.eglPath()},  {"egl_vendor", context.eglVendor()},
          {"vendor", context.glVendor()},   {"renderer", context.glRenderer()},
          {"version", context.glVersion()}, {"software", context.isSoftware()}};
}

nlohmann::json framesJson(const FrameTimings& t, int warmup) {
  return {{"count", t.frames},
          {"warmup", warmup},
          {"median_ms", t.medianWallMs},
          {"min_ms", t.minWallMs},
          {"max_ms", t.maxWallMs},
          {"fps", t.fps()},
          {"pipelined_ms", t.pipelinedMs},
          {"cpu_ms", t.cpuMs},
          {"gl_timer_median_ms", t.medianGpuMs}};
}

void writeReport(const Arguments& a, const LoadedMesh& mesh, const Environment& env,
                 const FrameOptions& frame, const GlContext& context, const StageTimes& ms,
                 const FrameTimings& timings, const TurntableTimes& turntable,
                 const Stopwatch& total) {
  const TriangleMesh& triangles = mesh.contents.baked.mesh;
  nlohmann::json report = {{"input", a.input},
                           {"output", a.output},
                           {"mode", kShadingModeNames.name(a.request.mode)},
                           {"vertices", triangles.positions.size()},
                           {"triangles", triangles.triangles.size()},
                           {"width", frame.width},
                           {"height", frame.height},
                           {"samples", frame.samples},
                           {"cull_back_faces", mesh.shading.cullBackFaces},
                           {"eta", mesh.shading.eta},
                           {"fresnel", kFresnelModelNames.name(a.fresnel)},
                           {"exit_model", kExitModelNames.name(a.request.exitModel)},
                           {"exit_lobe", mesh.shading.exitLobe},
                           {"unscattered", shadingOptions(a, mesh.shading).drawsUnscattered()},
                           {"environment", a.environment},
                           {"environment_face_size", env.radiance.size()},
                           {"gl", glJson(context)},
                           {"times_ms",
                            {{"gl_context", ms.context},
                             {"load", ms.load},
                             {"environment", ms.environment},
                             {"gl_setup", ms.setup},
                             {"first_frame_and_readback", ms.render},
                             {"total", total.milliseconds()}}}};
  report["environment_convention"] = kEquirectConventionNames.name(a.orientation.convention);
  report["environment_rotate_deg"] = a.orientation.rotateDeg;
  report["relit"] = mesh.relighter != nullptr;
  if (mesh.relighter) report["relit_on"] = kRelightDeviceNames.name(mesh.relitOn);
  if (!env.irradianceReason.empty()) report["irradiance"] = env.irradianceReason;
  if (a.frames > 0) report["frames"] = framesJson(timings, a.warmup);
  if (turntable.frames > 0) {
    report["light_turntable"] = {{"frames", turntable.frames},
                                 {"further_frame_median_ms",
                                  {{"environment", turntable.environment},
                                   {"relight", turntable.relight},
                                   {"draw_and_readback", turntable.draw},
                                   {"total", turntable.total}}}};
  }
  writeFileAtomically(a.jsonPath, report.dump(2) + "\n");
}

void describeContext(const GlContext& context) {
  info("EGL: " + context.eglPath() + ", vendor " + context.eglVendor(), false);
  info("GL_VENDOR: " + context.glVendor(), false);
  info("GL_RENDERER: " + context.glRenderer(), false);
  info("GL_VERSION: " + context.glVersion(), false);
  info(format("vertex shader storage buffers: %.0f MiB at most (a relit mesh's transfer)",
              context.maxVertexStorageBytes() / 1048576.0),
       false);
}

RenderedImage readBackOf(Renderer& renderer) {
  renderer.draw();
  return renderer.readBack();
}

// --light-turntable's frame k: OUT_<kkk>.ext beside OUT.
std::string turntableFramePath(const std::string& output, int k) {
  const std::size_t dot = output.find_last_of('.');
  char number[16];
  std::snprintf(number, sizeof number, "_%03d", k);
  return output.substr(0, dot) + number + output.substr(dot);
}

// The frames side by side, ceil(sqrt(n)) a row, in one image (the contact sheet).
RenderedImage contactSheet(const std::vector<RenderedImage>& frames) {
  const int n = int(frames.size()), columns = int(std::ceil(std::sqrt(double(n))));
  const int rows = (n + columns - 1) / columns, w = frames[0].width, h = frames[0].height;
  RenderedImage sheet;
  sheet.width = w * columns;
  sheet.height = h * rows;
  sheet.linear = frames[0].linear;
  const auto tile = [&](const auto& pixels, auto& out) {
    const std::size_t channels = pixels(0).size() / (std::size_t(w) * h);
    out.assign(std::size_t(sheet.width) * sheet.height * channels, 0);
    for (int k = 0; k < n; ++k)
      for (int y = 0; y < h; ++y) {
        const auto& from = pixels(k);
        const std::size_t row = std::size_t(w) * channels;
        std::copy_n(from.begin() + std::ptrdiff_t(y * row), row,
                    out.begin() + std::ptrdiff_t(((k / columns) * h + y) *
                                                     std::size_t(sheet.width) * channels +
                                                 (k % columns) * row));
      }
  };
  if (sheet.linear)
    tile([&](int k) -> const std::vector<float>& { return frames[k].linearRgb; }, sheet.linearRgb);
  else
    tile([&](int k) -> const std::vector<uint8_t>& { return frames[k].srgb8; }, sheet.srgb8);
  return sheet;
}

// The number of SH coefficients a mesh relit on the GPU sums in the shader (0: not relit there).
int gpuRelightCoefficients(const LoadedMesh& mesh) {
  if (!mesh.relighter || mesh.relitOn != RelightDevice::Gpu) return 0;
  return mesh.contents.baked.relightCount();
}

// A mesh relit on the GPU under `radiance` (each frame's): the renderer's smooth light and the
// mesh's rest of B (zero where there is none).
void relightOnGpu(const Arguments& a, const LoadedMesh& mesh, Renderer& renderer,
                  const Cubemap& radiance) {
  const RelitSplit split = mesh.relighter->relightSplit(radiance);
  renderer.setValues(split.restExitance);
  renderer.setSmoothLight(split.smoothLight.coefficients());
  reportRelit(a, RelightDevice::Gpu, split.compactLights);
}

// --light-turntable N: frame k with the environment turned 360 k / N degrees past --env-rotate,
// a relightable bake relit under each (a plain bake keeps its light: the background and the
// reflections turn), each to OUT_<kkk>.ext, and OUT the contact sheet of them.
// The mesh read once (`mesh`, the first frame's) is relit again from its transfer for each frame
// by the first frame's relighter (bake/relight.h, RelightSession: its rays traced once).
TurntableTimes writeLightTurntable(const Arguments& a, const LoadedMesh& mesh, Renderer& renderer,
                                   RenderedImage first) {
  std::vector<RenderedImage> frames{std::move(first)};
  std::vector<double> environmentMs, relightMs, drawMs, totalMs;
  for (int k = 1; k < a.lightTurntable; ++k) {
    Stopwatch frameClock, clock;
    Arguments turned = a;
    turned.orientation.rotateDeg = a.orientation.rotateDeg + 360.0 * k / a.lightTurntable;
    turned.quiet = true;
    EnvironmentCache environment(turned);
    const Cubemap& radiance = environment.radiance();
    environmentMs.push_back(clock.lap() * 1e3);
    if (gpuRelightCoefficients(mesh) > 0) {
      relightOnGpu(turned, mesh, renderer, radiance);
    } else if (mesh.relighter) {
      BakedPlyContents contents = mesh.contents;
      takeRelitLight(turned, mesh.relighter->relight(radiance), contents);
      renderer.setMesh(renderMeshFor(contents.baked, a.request.mode, mesh.shading.exitLobe));
    }
    relightMs.push_back(clock.lap() * 1e3);
    const Environment& env = environment.lighting(mesh.shading.eta);
    renderer.setEnvironment(env.radiance, env.irradiance.empty() ? nullptr : &env.irradiance);
    frames.push_back(readBackOf(renderer));
    drawMs.push_back(clock.lap() * 1e3);
    totalMs.push_back(frameClock.milliseconds());
  }
  for (int k = 0; k < a.lightTurntable; ++k)
    writeRenderedImage(turntableFramePath(a.output, k), frames[k]);
  writeRenderedImage(a.output, contactSheet(frames));
  info("wrote " + std::to_string(a.lightTurntable) + " frames " + turntableFramePath(a.output, 0) +
           " ... and their contact sheet " + a.output,
       a.quiet);
  return {.frames = a.lightTurntable,
          .environment = median(environmentMs),
          .relight = median(relightMs),
          .draw = median(drawMs),
          .total = median(totalMs)};
}

// One mesh (a.input) into a.output (and a.jsonPath) with the shared context and environment.
int renderOne(const Arguments& a, const GlContext& context, EnvironmentCache& environments,
              double contextMs) {
  const Stopwatch total;
  FrameOptions frame;
  frame.width = a.size[0];
  frame.height = a.size[1];
  frame.samples = a.samples;
  frame.linear = isLinearImagePath(a.output);
  StageTimes ms;
  ms.context = contextMs;

  Stopwatch stage;
  const Cubemap& radiance = environments.radiance();
  ms.environment = stage.milliseconds();

  stage.restart();
  const LoadedMesh mesh = loadMesh(a, radiance, context);
  ms.load = stage.milliseconds();

  stage.restart();
  const Environment& env = environments.lighting(mesh.shading.eta);
  ms.environment += stage.milliseconds();

  stage.restart();
  if (frame.samples > context.maxSamples()) {
    warn("--samples " + std::to_string(frame.samples) + ": this GL allows at most " +
         std::to_string(context.maxSamples()) + "; using that");
    frame.samples = context.maxSamples();
  }
  const ShaderSources shaders(a.shaderDir);
  ShadingOptions shading = shadingOptions(a, mesh.shading);
  shading.relightCoefficients = gpuRelightCoefficients(mesh);
  Renderer renderer(shaders, frame, shading);
  renderer.setMesh(mesh.renderMesh);
  if (shading.relightCoefficients > 0) relightOnGpu(a, mesh, renderer, radiance);
  renderer.setEnvironment(env.radiance, env.irradiance.empty() ? nullptr : &env.irradiance);
  const float aspect = static_cast<float>(frame.width) / static_cast<float>(frame.height);
  renderer.setCamera(placeCamera(a, mesh.bounds, aspect));
  ms.setup = stage.milliseconds();

  stage.restart();
  const RenderedImage image = readBackOf(renderer);
  ms.render = stage.milliseconds();
  FrameTimings timings;
  TurntableTimes turntable;
  if (a.lightTurntable > 0) {
    turntable = writeLightTurntable(a, mesh, renderer, image);
  } else {
    if (a.frames > 0) {
      timings = renderer.timeFrames(a.frames, a.warmup);
      printFrameTimings(a, mesh, frame, timings, context);
    }
    writeRenderedImage(a.output, image);
    info("wrote " + a.output, a.quiet);
  }
  if (!a.jsonPath.empty()) writeReport(a, mesh, env, frame, context, ms, timings, turntable, total);
  return 0;
}

int run(const Arguments& a) {
  checkOutputsAreNotInputs({{"-o", a.output}, {"--json", a.jsonPath}},
                           {{"the mesh", a.input}, {"the environment", a.environment}});
  // The GL context first: without one nothing else is worth doing.
  Stopwatch stage;
  const GlContext context;
  if (a.verbose) describeContext(context);
  const double contextMs = stage.milliseconds();
  EnvironmentCache environments(a);
  return renderOne(a, context, environments, contextMs);
}

// The image of each input in a batch folder: DIR/<stem> + this.
constexpr const char* kBatchImageSuffix = ".png";

// Several meshes (or -o DIR/): one GL context and environment, DIR/<stem>.png per mesh (and its
// report in the --json folder); a bad mesh is reported and the others still render.
int renderBatch(const Arguments& a) {
  if (!namesFolder(a.output)) {
    throw UsageError("-o " + a.output + ": with several meshes, -o names a folder (DIR/)");
  }
  if (!a.jsonPath.empty() && !namesFolder(a.jsonPath)) {
    throw UsageError("--json " + a.jsonPath +
                     ": with several meshes, --json names a folder (DIR/)");
  }
  const std::vector<BatchItem> items =
      planBatch(a.inputs, {{"-o", a.output, kBatchImageSuffix}, {"--json", a.jsonPath, ".json"}},
                {{"the environment", a.environment}});
  Stopwatch stage;
  const GlContext context;
  if (a.verbose) describeContext(context);
  const double contextMs = stage.milliseconds();
  EnvironmentCache environments(a);
  environments.radiance();  // a bad environment fails the whole batch, once
  return runBatch(
      items,
      [&](const BatchItem& item) {
        Arguments one = a;
        one.input = item.input;
        one.output = item.outputs[0];
        one.jsonPath = item.outputs[1];
        renderOne(one, context, environments, contextMs);
      },
      a.quiet);
}

void addInputOptions(CLI::App& app, Arguments& a) {
  app.add_option("mesh", a.inputs,
                 "Baked mesh (sss-bake's PLY or GLB; any mesh for --mode brdf); several with -o "
                 "DIR/")
      ->required();
  app.add_option("-e,--env", a.environment,
                 "Environment: equirect, cross or cubemap image (sss-irrmap --radiance), "
                 "or sky[:spec]")
      ->required();
  app.add_option("-o,--output", a.output,
                 ".png (8-bit sRGB) or .exr (linear float), or a folder DIR/ (DIR/<stem>.png)")
      ->required()
      ->check(cli::parsedBy([](const std::string& path) {
        if (!namesFolder(path)) checkRenderedImagePath(path);
      }));
  app.add_option("--env-size", a.envSize, "Radiance cubemap face size (0: from the source)")
      ->check(cli::checkedBy<int>([](int size) {
        if (size != 0) checkFaceSize(size);
      }));
  cli::addOrientationOptions(app, a.orientation);
  app.add_option("--shader-dir", a.shaderDir, "Read shaders from this folder (development)");
  app.add_option("--json", a.jsonPath, "Report: GL renderer, sizes, timings");
}

void addShadingOptions(CLI::App& app, Arguments& a) {
  cli::addEnumOption(app, "--mode", a.request.mode, kShadingModeNames,
                     "Baked subsurface light, a BRDF lit by the irradiance cubemap, or the "
                     "baked irradiance or normals");
  cli::addEnumOption(app, "--fresnel", a.fresnel, kFresnelModelNames, "Fresnel terms");
  cli::addEnumOption(app, "--exit-model", a.request.exitModel, kExitModelNames,
                     "auto: normalized, or where the file has a traced far field the exit lobe "
                     "its light paths measured; normalized: B F_t / (pi "
                     "(1 - 2 C_1)), flux = B; calibrated: times w, the half-space Monte Carlo's "
                     "angular shape for the material; jensen: B F_t / pi");
  app.add_option("--reflect-factor", a.reflectFactor,
                 "The paper's constant mix(base, reflection, F) instead of Fresnel weights")
      ->check(cli::finiteIn(0.0, 1.0));
  app.add_option("--eta", a.request.eta, "Relative index (default: the material's)")
      ->check(cli::checkedBy<double>([](double eta) { checkMaterialEta(eta); }));
  cli::addParsedOption(app, "--albedo", a.request.albedo, parseAlbedo,
                       "brdf: diffuse albedo r,g,b (default: the material's half-space "
                       "albedo, what the bake returns on a lit plane)")
      ->type_name("R,G,B");
  cli::addParsedOption(app, "--background", a.background, parseBackground,
                       "env, or a colour r,g,b stored as given (0..1 display values)")
      ->type_name("env|R,G,B")
      ->default_str("env");
  app.add_option("--exposure", a.exposure, "Exposure in EV (stops)")->check(cli::finiteIn());
  cli::addEnumOption(app, "--tonemap", a.tonemap, kTonemapNames, "Display transform");
  cli::addEnumOption(app, "--cull", a.request.cull, kCullModeNames,
                     "Back-face culling (auto: only for closed, consistently wound meshes)");
  cli::addEnumOption(app, "--unscattered", a.request.unscattered, kUnscatteredDrawingNames,
                     "The light that crosses the object without scattering, from the "
                     "environment behind, in the sss mode on a closed mesh whose file records "
                     "its material and units (auto: where the bake traced it)");
}

void addCameraOptions(CLI::App& app, Arguments& a) {
  app.add_option("--azimuth", a.azimuth, "Camera azimuth about +Y in degrees (0: from +Z)")
      ->check(cli::finiteIn());
  app.add_option("--elevation", a.elevation, "Camera elevation in degrees")->check(cli::finiteIn());
  app.add_option("--distance", a.distance, "Camera distance in mesh units (default: framed)")
      ->check(cli::finiteAtLeast(0.0));
  cli::addParsedOption(app, "--eye", a.eye, parseXyz, "Camera position x,y,z (overrides the orbit)")
      ->type_name("X,Y,Z");
  cli::addParsedOption(app, "--target", a.target, parseXyz,
                       "Look-at point x,y,z (default: the bounding sphere's centre)")
      ->type_name("X,Y,Z");
  cli::addParsedOption(app, "--up", a.up, parseXyz, "Up vector x,y,z")
      ->type_name("X,Y,Z")
      ->default_str("0,1,0");
  app.add_option("--fov", a.fov, "Vertical field of view in degrees")
      ->check(cli::finiteIn(1.0, 170.0));
}

void addFrameOptions(CLI::App& app, Arguments& a) {
  cli::addParsedOption(app, "--size", a.size, parseImageSize, "Image size")
      ->type_name("WxH")
      ->default_str("1024x1024");
  app.add_option("--samples", a.samples, "MSAA samples (1: none)")->check(CLI::Range(1, 64));
  app.add_option("--frames", a.frames,
                 "Render N timed frames and report ms/frame (wall clock, GL timer) and FPS")
      ->check(CLI::Range(0, 100000));
  app.add_option("--warmup", a.warmup, "Untimed frames before --frames")
      ->check(CLI::Range(0, 1000));
  cli::addThreadsOption(app, a.threads);
  app.add_option("--light-turntable", a.lightTurntable,
                 "Render N frames with the environment turning a full circle (a relightable bake "
                 "relit in each): OUT_000.png ... and OUT, their contact sheet")
      ->check(CLI::Range(1, 360));
  app.add_flag("!--no-relight", a.relight,
               "Draw a relightable bake (sss-bake --relightable) as baked, not relit under -e");
  cli::addEnumOption(app, "--relight-on", a.relightOn, kRelightDeviceNames,
                     "Where a relightable bake is relit: gpu (its smooth light summed in the "
                     "vertex shader) or cpu (wholly before drawing, as sss-relight)");
  app.add_flag("-v,--verbose", a.verbose, "Print the EGL path and the GL vendor/renderer/version");
  cli::addQuietFlag(app, a.quiet);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Render a baked mesh in an environment with headless OpenGL (EGL)."};
  Arguments a;
  addInputOptions(app, a);
  addShadingOptions(app, a);
  addCameraOptions(app, a);
  addFrameOptions(app, a);
  app.footer(
      "Examples:\n"
      "  sss-render bunny_baked.ply -e forest.exr -o bunny.png --azimuth 30\n"
      "  sss-render dragon.glb -e forest_radiance.exr -o dragon.exr --size 512x512\n"
      "  sss-render bunny_baked.ply -e forest.exr -o bunny_brdf.png --mode brdf");
  return runTool("sss-render", app, argc, argv, [&] {
    if (a.verbose) a.quiet = false;
    if (isBatch(a.inputs, a.output)) return renderBatch(a);
    a.input = a.inputs.front();
    return run(a);
  });
}

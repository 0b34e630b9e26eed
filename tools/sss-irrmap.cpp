// sss-irrmap: an HDR environment (or a procedural sky) -> radiance and diffuse irradiance
// cubemaps, SH coefficients and a JSON report. See README (sss-irrmap) for the conventions.
#include <filesystem>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "core/atomic_output.h"
#include "core/cli.h"
#include "core/error.h"
#include "core/file_extension.h"
#include "core/paths.h"
#include "core/timer.h"
#include "core/tool.h"
#include "envmap/cubemap_io.h"
#include "envmap/environment.h"
#include "irradiance/irradiance.h"
#include "material/material.h"

namespace {

using namespace sss;
namespace fs = std::filesystem;

struct Arguments {
  std::string input, skySpec, radiance, irradiance, sh, json;
  bool sky = false, sanitize = false, quiet = false, preview = true;
  IrradianceMethod method = IrradianceMethod::Auto;
  ShWindow window = ShWindow::None;
  int shOrder = 2, size = 0, radianceSize = 0, threads = 0;
  double tolerance = 0.01;
  float eta = 1.0f;
};

// Refuses an output with the wrong extension (usage) or whose folder is missing, before any work.
void checkOutput(const std::string& path, const std::string& ext, const char* option) {
  if (path.empty()) return;
  if (lowerExtension(path) != ext) {
    throw UsageError(path + ": " + option + " needs a ." + ext + " file");
  }
  const fs::path dir = fs::path(path).parent_path();
  if (!dir.empty() && !fs::is_directory(dir))
    fail(path, "folder " + dir.string() + " does not exist");
}

// What CLI11 cannot say: one environment source, at least one output, and the outputs' types.
void checkArguments(const Arguments& a) {
  if (!a.sky && a.input.empty()) {
    throw UsageError("no environment: give INPUT (equirect, cross or cubemap image) or --sky");
  }
  if (a.radiance.empty() && a.irradiance.empty() && a.sh.empty() && a.json.empty()) {
    throw UsageError("nothing to write: give --radiance, -o/--irradiance, --sh or --json");
  }
  checkOutput(a.radiance, "exr", "--radiance");
  checkOutput(a.irradiance, "exr", "--irradiance");
  checkOutput(a.sh, "json", "--sh");
  checkOutput(a.json, "json", "--json");
  auto preview = [&](const std::string& cube) {
    return a.preview && !cube.empty() ? cubemapPreviewPath(cube) : std::string();
  };
  checkOutputsAreNotInputs({{"--radiance", a.radiance},
                            {"-o", a.irradiance},
                            {"--sh", a.sh},
                            {"--json", a.json},
                            {"the preview of --radiance", preview(a.radiance)},
                            {"the preview of -o", preview(a.irradiance)}},
                           {{"the input", a.input}});
}

IrradianceOptions irradianceOptions(const Arguments& a) {
  IrradianceOptions options;
  options.method = a.method;
  options.window = a.window;
  options.shOrder = a.shOrder;
  options.faceSize = a.size;
  options.tolerance = a.tolerance;
  options.eta = a.eta;
  options.threads = a.threads;
  options.quiet = a.quiet;
  return options;
}

// The input image; a non-finite texel names the flag that accepts it.
ImageRgb readInputImage(const Arguments& a) {
  try {
    return readImage(a.input, {a.sanitize});
  } catch (const NonFiniteTexelsError& e) {
    throw Error(std::string(e.what()) + " (use --sanitize to replace them by 0)");
  }
}

// The radiance cubemap from the sky or the input image; the report's input and read timings.
Cubemap loadRadiance(const Arguments& a, nlohmann::json& report) {
  Stopwatch watch;
  if (a.sky) {
    const SkyParameters sky = parseSkySpec(a.skySpec);
    Cubemap radiance = makeSky(sky, a.radianceSize > 0 ? a.radianceSize : 128, a.threads);
    report["input"] = "sky:" + a.skySpec;
    report["layout"] = "procedural";
    report["timings_ms"]["read"] = 0.0;
    report["timings_ms"]["to_cubemap"] = watch.milliseconds();
    return radiance;
  }
  const ImageRgb image = readInputImage(a);
  report["timings_ms"]["read"] = watch.milliseconds();
  const EnvironmentLayout layout = detectLayout(a.input, image.width, image.height);
  watch.restart();
  Cubemap radiance = cubemapFromImage(image, layout, a.radianceSize, a.threads);
  report["timings_ms"]["to_cubemap"] = watch.milliseconds();
  report["input"] = a.input;
  report["input_size"] = {image.width, image.height};
  report["layout"] = kEnvironmentLayoutNames.name(layout);
  return radiance;
}

nlohmann::json shJson(const SphericalHarmonics& sh) {
  nlohmann::json a = nlohmann::json::array();
  for (const glm::vec3& c : sh.coefficients()) a.push_back({c.x, c.y, c.z});
  return a;
}

void writeShFile(const Arguments& a, const SphericalHarmonics& radianceSh) {
  const TransmittedCosineKernel kernel(a.eta);
  nlohmann::json sh;
  sh["order"] = radianceSh.order();
  sh["basis"] =
      "real orthonormal spherical harmonics, index l(l+1)+m, polar axis +Z, "
      "Y_1-1 ~ y, Y_10 ~ z, Y_11 ~ x (no Condon-Shortley phase)";
  sh["eta"] = a.eta;
  sh["window"] = kShWindowNames.name(a.window);
  sh["radiance"] = shJson(radianceSh);
  sh["irradiance"] = shJson(radianceSh.convolved(kernel, a.window));
  writeFileAtomically(a.sh, sh.dump(2) + "\n");
}

void writeCubemapWithPreview(const std::string& path, const Cubemap& cube, bool preview) {
  if (path.empty()) return;
  writeCubemap(path, cube);
  if (preview) writeCubemapPreview(cubemapPreviewPath(path), cube);
}

// The report's method, error, sizes, stage times and outputs (after loadRadiance's part).
void addResultToReport(const Arguments& a, const IrradianceResult& result, nlohmann::json& report) {
  report["method"] = kIrradianceMethodNames.name(result.method);
  report["method_asked"] = kIrradianceMethodNames.name(a.method);
  report["reason"] = result.reason;
  report["estimated_error"] = result.estimatedError;
  report["tolerance"] = a.tolerance;
  report["eta"] = a.eta;
  report["sh_order"] = result.shOrder;
  report["window"] = kShWindowNames.name(a.window);
  report["irradiance_face_size"] = result.irradiance.size();
  report["source_texels"] = result.sourceTexels;
  report["brute_terms"] = result.bruteClusters;
  report["threads"] = a.threads;
  report["timings_ms"]["reference"] = result.timings.referenceMs;
  report["timings_ms"]["projection"] = result.timings.projectionMs;
  report["timings_ms"]["evaluation"] = result.timings.evaluationMs;
  report["timings_ms"]["irradiance"] = result.timings.totalMs;
  nlohmann::json outputs = nlohmann::json::object();
  if (!a.radiance.empty()) outputs["radiance"] = a.radiance;
  if (!a.irradiance.empty()) outputs["irradiance"] = a.irradiance;
  if (!a.sh.empty()) outputs["sh"] = a.sh;
  report["outputs"] = outputs;
}

int run(const Arguments& a) {
  const Stopwatch total;
  checkArguments(a);
  nlohmann::json report;
  report["tool"] = "sss-irrmap";
  const Cubemap radiance = loadRadiance(a, report);
  report["radiance_face_size"] = radiance.size();

  IrradianceResult result;
  if (!a.irradiance.empty() || !a.json.empty()) {
    result = computeIrradiance(radiance, irradianceOptions(a));
    info(std::string(kIrradianceMethodNames.name(a.method)) + ": " + result.reason, a.quiet);
  }
  SphericalHarmonics radianceSh = result.radianceSh;
  if (!a.sh.empty() && radianceSh.order() != a.shOrder) {
    const Stopwatch watch;
    radianceSh = SphericalHarmonics::project(radiance, a.shOrder, a.threads);
    result.timings.projectionMs += watch.milliseconds();
  }

  const Stopwatch watch;
  writeCubemapWithPreview(a.radiance, radiance, a.preview);
  writeCubemapWithPreview(a.irradiance, result.irradiance, a.preview);
  if (!a.sh.empty()) writeShFile(a, radianceSh);
  const double writeMs = watch.milliseconds();

  if (!a.json.empty()) {
    addResultToReport(a, result, report);
    report["timings_ms"]["write"] = writeMs;
    report["timings_ms"]["total"] = total.milliseconds();
    writeFileAtomically(a.json, report.dump(2) + "\n");
  }
  return 0;
}

void addOptions(CLI::App& app, Arguments& a) {
  CLI::Option* input = app.add_option(
      "INPUT", a.input,
      "Environment image (.hdr .exr .pfm .tif): equirect 2:1 (centre looks to -Z), cross 4:3 / "
      "3:4, or an N x 6N cubemap stack");
  app.add_option("--sky", a.skySpec,
                 "Procedural sun and sky instead of INPUT; optional spec "
                 "elevation=DEG,azimuth=DEG (0: -Z, 90: +X),turbidity=2..10,sun=SCALE,"
                 "radius=DEG,ground=ALBEDO")
      ->expected(0, 1)
      ->check(cli::parsedBy(parseSkySpec))
      ->excludes(input);
  app.add_option("--radiance", a.radiance, "Write the radiance cubemap (.exr)");
  app.add_option("-o,--irradiance", a.irradiance, "Write the diffuse irradiance cubemap (.exr)");
  app.add_option("--eta", a.eta,
                 "Relative index: irradiance transmitted through a smooth dielectric "
                 "(exact Fresnel); 1 = plain irradiance")
      ->capture_default_str()
      ->check(cli::checkedBy<float>([](float eta) { checkMaterialEta(eta); }));
  app.add_option("--sh", a.sh, "Write the SH coefficients of radiance and irradiance (.json)");
  app.add_option("--json", a.json, "Write a report: method, estimated error, timings (.json)");
  cli::addEnumOption(app, "--method", a.method, kIrradianceMethodNames,
                     "Direct sum, spherical harmonics, or the cheaper that meets --tolerance");
  app.add_option("--sh-order", a.shOrder, "SH order for --method sh and --sh")
      ->capture_default_str()
      ->check(CLI::Range(0, SphericalHarmonics::kMaxOrder));
  cli::addEnumOption(app, "--window", a.window, kShWindowNames, "SH window against ringing");
  app.add_option("--tolerance", a.tolerance,
                 "Relative RMS error allowed on the sphere, estimated for this environment "
                 "(0: the exact sum over every texel)")
      ->capture_default_str()
      ->check(cli::finiteAtLeast(0.0));
  app.add_option("--size", a.size, "Irradiance face size (default: from the content)")
      ->check(cli::checkedBy<int>(checkFaceSize));
  app.add_option("--radiance-size", a.radianceSize,
                 "Radiance face size (default: the source's resolution; 128 for --sky)")
      ->check(cli::checkedBy<int>(checkFaceSize));
  app.add_flag("--sanitize", a.sanitize, "Replace NaN/Inf texels by 0 instead of failing");
  app.add_flag(
      "--no-preview", [&a](std::int64_t) { a.preview = false; },
      "No PNG preview (FILE.png beside each cubemap FILE.exr)");
  cli::addThreadsOption(app, a.threads);
  cli::addQuietFlag(app, a.quiet);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "sss-irrmap: environment image -> radiance and diffuse irradiance cubemaps (+X -X +Y -Y +Z "
      "-Z stacked, OpenGL orientation, Y up)"};
  Arguments a;
  addOptions(app, a);
  app.footer(
      "Examples:\n"
      "  sss-irrmap forest.exr --radiance forest_radiance.exr -o forest_irradiance.exr --eta 1.3\n"
      "  sss-irrmap --sky=elevation=30,azimuth=90 -o sky_irradiance.exr --sh sky_sh.json\n"
      "  sss-irrmap studio.hdr -o studio_irradiance.exr --method brute --tolerance 0.002");
  return runTool("sss-irrmap", app, argc, argv, [&] {
    a.sky = app.count("--sky") > 0;
    return run(a);
  });
}

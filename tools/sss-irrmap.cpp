// sss-irrmap: an HDR environment (or a procedural sky) -> radiance and diffuse irradiance
// cubemaps, SH coefficients and a JSON report. The conventions: docs/tools/sss-irrmap.md,
// "Conventions", and docs/conventions.md.
// Several inputs (or output folders DIR/) run as a batch in one process (core/batch.h).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "core/atomic_output.h"
#include "core/batch.h"
#include "core/cli.h"
#include "core/error.h"
#include "core/file_extension.h"
#include "core/paths.h"
#include "core/timer.h"
#include "core/tool.h"
#include "envmap/cubemap_io.h"
#include "envmap/environment.h"
#include "envmap/orientation_options.h"
#include "irradiance/irradiance.h"
#include "material/material.h"

namespace {

using namespace sss;
namespace fs = std::filesystem;

struct Arguments {
  std::vector<std::string> inputs;  // one, or several for a batch
  std::string input, skySpec, radiance, irradiance, sh, json;
  EnvironmentOrientation orientation;
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
    return readImage(a.input, {a.sanitize, a.quiet});
  } catch (const NonFiniteTexelsError& e) {
    throw Error(std::string(e.what()) + " (use --sanitize to replace them by 0)");
  }
}

// The environment: an equirect image kept as it is when no radiance cubemap is asked (the
// irradiance is summed straight from its rows), else the radiance cubemap.
struct Environment {
  std::optional<ImageRgb> equirect;
  Cubemap radiance;
};

// The environment from the sky or the input image; the report's input and read timings.
Environment loadEnvironmentSource(const Arguments& a, nlohmann::json& report) {
  Stopwatch watch;
  Environment env;
  if (a.sky) {
    const SkyParameters sky = rotatedSky(parseSkySpec(a.skySpec), a.orientation);
    env.radiance = makeSky(sky, a.radianceSize > 0 ? a.radianceSize : 128, a.threads);
    report["input"] = "sky:" + a.skySpec;
    report["layout"] = "procedural";
    report["rotate_deg"] = a.orientation.rotateDeg;
    report["timings_ms"]["read"] = 0.0;
    report["timings_ms"]["to_cubemap"] = watch.milliseconds();
    return env;
  }
  ImageRgb image = readInputImage(a);
  report["timings_ms"]["read"] = watch.milliseconds();
  const EnvironmentLayout layout = detectLayout(a.input, image.width, image.height);
  report["input"] = a.input;
  report["input_size"] = {image.width, image.height};
  report["layout"] = kEnvironmentLayoutNames.name(layout);
  report["convention"] = kEquirectConventionNames.name(a.orientation.convention);
  report["rotate_deg"] = a.orientation.rotateDeg;
  watch.restart();
  // The rows are summed in the image's own frame: a turned environment goes through the cubemap,
  // where the turn is applied to every lookup direction.
  if (layout == EnvironmentLayout::Equirect && a.radiance.empty() &&
      isIdentity(a.orientation, true)) {
    env.equirect = std::move(image);
  } else {
    env.radiance = cubemapFromImage(image, layout, a.radianceSize, a.threads, a.orientation);
  }
  report["timings_ms"]["to_cubemap"] = watch.milliseconds();
  return env;
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

// The report's method, error, sizes, stage times and outputs (after loadEnvironmentSource's part).
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
  report["timings_ms"]["grid"] = result.timings.gridMs;
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
  const double cpuStart = processCpuMilliseconds();
  checkArguments(a);
  nlohmann::json report;
  report["tool"] = "sss-irrmap";
  const Environment env = loadEnvironmentSource(a, report);
  report["radiance_face_size"] = env.radiance.size();

  IrradianceResult result;
  if (!a.irradiance.empty() || !a.json.empty()) {
    result = env.equirect ? computeIrradianceFromEquirect(*env.equirect, irradianceOptions(a))
                          : computeIrradiance(env.radiance, irradianceOptions(a));
    info(std::string(kIrradianceMethodNames.name(a.method)) + ": " + result.reason, a.quiet);
  }
  // An equirect's SH for the file from every texel (auto's order-2 trial projects cells).
  SphericalHarmonics radianceSh = result.radianceSh;
  const bool fromCells = env.equirect && a.method != IrradianceMethod::Sh;
  if (!a.sh.empty() && (fromCells || radianceSh.order() != a.shOrder)) {
    const Stopwatch watch;
    radianceSh = env.equirect
                     ? SphericalHarmonics::projectEquirect(*env.equirect, a.shOrder, a.threads)
                     : SphericalHarmonics::project(env.radiance, a.shOrder, a.threads);
    result.timings.projectionMs += watch.milliseconds();
  }

  const Stopwatch watch;
  writeCubemapWithPreview(a.radiance, env.radiance, a.preview);
  writeCubemapWithPreview(a.irradiance, result.irradiance, a.preview);
  if (!a.sh.empty()) writeShFile(a, radianceSh);
  const double writeMs = watch.milliseconds();

  if (!a.json.empty()) {
    addResultToReport(a, result, report);
    report["timings_ms"]["write"] = writeMs;
    report["timings_ms"]["total"] = total.milliseconds();
    report["timings_ms"]["cpu"] = processCpuMilliseconds() - cpuStart;  // all threads
    writeFileAtomically(a.json, report.dump(2) + "\n");
  }
  return 0;
}

// The outputs of a batch, each a folder: DIR/<stem>_radiance.exr, _irradiance.exr, _sh.json,
// .json.
std::vector<BatchOutput> batchOutputs(const Arguments& a) {
  return {{"--radiance", a.radiance, "_radiance.exr"},
          {"-o", a.irradiance, "_irradiance.exr"},
          {"--sh", a.sh, "_sh.json"},
          {"--json", a.json, ".json"}};
}

Arguments itemArguments(const Arguments& a, const BatchItem& item) {
  Arguments one = a;
  one.input = item.input;
  one.radiance = item.outputs[0];
  one.irradiance = item.outputs[1];
  one.sh = item.outputs[2];
  one.json = item.outputs[3];
  return one;
}

// Several inputs (or folder outputs): each input's outputs in the folders given; a bad input is
// reported and the others still run.
int irrmapBatch(const Arguments& a) {
  if (a.sky) throw UsageError("--sky makes one environment: give output files, not folders");
  for (const BatchOutput& output : batchOutputs(a)) {
    if (!output.dir.empty() && !namesFolder(output.dir)) {
      throw UsageError(output.option + " " + output.dir +
                       ": with several inputs, every output names a folder (DIR/)");
    }
  }
  const std::vector<BatchItem> items = planBatch(a.inputs, batchOutputs(a), {});
  checkArguments(itemArguments(a, items.front()));  // usage errors before any work
  return runBatch(
      items, [&](const BatchItem& item) { run(itemArguments(a, item)); }, a.quiet);
}

void addOptions(CLI::App& app, Arguments& a) {
  CLI::Option* input = app.add_option(
      "INPUT", a.inputs,
      "Environment image (.hdr .exr .pfm .tif): equirect 2:1 (centre looks to -Z), cross 4:3 / "
      "3:4, or an N x 6N cubemap stack; several with output folders DIR/ (one process)");
  app.add_option("--sky", a.skySpec,
                 "Procedural sun and sky instead of INPUT; optional spec "
                 "elevation=DEG,azimuth=DEG (0: -Z, 90: +X),turbidity=2..10,sun=SCALE,"
                 "radius=DEG,ground=ALBEDO")
      ->expected(0, 1)
      ->check(cli::parsedBy(parseSkySpec))
      ->excludes(input);
  app.add_option("--radiance", a.radiance,
                 "Write the radiance cubemap (.exr; a folder DIR/ for several inputs)");
  app.add_option("-o,--irradiance", a.irradiance,
                 "Write the diffuse irradiance cubemap (.exr; a folder DIR/ for several inputs)");
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
  cli::addOrientationOptions(app, a.orientation);
  cli::addThreadsOption(app, a.threads);
  cli::addQuietFlag(app, a.quiet);
}

bool isBatchRun(const Arguments& a) {
  for (const std::string& output : {a.radiance, a.irradiance, a.sh, a.json}) {
    if (isBatch(a.inputs, output)) return true;
  }
  return false;
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
    if (!a.sky && isBatchRun(a)) return irrmapBatch(a);
    if (!a.inputs.empty()) a.input = a.inputs.front();
    return run(a);
  });
}

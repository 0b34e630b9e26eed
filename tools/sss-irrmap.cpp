// sss-irrmap: an HDR environment (or a procedural sky) -> radiance and diffuse irradiance
// cubemaps, SH coefficients and a JSON report. See README (sss-irrmap) for the conventions.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/file_extension.h"
#include "core/timer.h"
#include "core/tool.h"
#include "envmap/cubemap_io.h"
#include "envmap/environment.h"
#include "irradiance/irradiance.h"

namespace {

using namespace sss;
namespace fs = std::filesystem;

struct Arguments {
  std::string input, skySpec, radiance, irradiance, sh, json;
  bool sky = false, sanitize = false, quiet = false, preview = true;
  std::string method = "auto", window = "none";
  int shOrder = 2, size = 0, radianceSize = 0, threads = 0;
  double tolerance = 0.01;
  float eta = 1.0f;
};

// Refuses an output whose folder is missing or whose extension is wrong, before any work.
void checkOutput(const std::string& path, const std::string& ext, const char* option) {
  if (path.empty()) return;
  if (lowerExtension(path) != ext) fail(path, std::string(option) + " needs a ." + ext + " file");
  const fs::path dir = fs::path(path).parent_path();
  if (!dir.empty() && !fs::is_directory(dir))
    fail(path, "folder " + dir.string() + " does not exist");
}

// The preview of a cubemap output: FILE.exr -> FILE.png, the unfolded cross (faces of at least
// 128 pixels, small irradiance cubemaps magnified bilinearly), exposed so that the log-average
// luminance maps to 0.18 (Reinhard's key value), clamped, sRGB.
std::string previewPath(const std::string& path) {
  return fs::path(path).replace_extension(".png").string();
}

void writePreview(const std::string& path, const Cubemap& cube) {
  ImageRgb cross = cubemapToCross(cube.size() < 128 ? cube.resized(128) : cube);
  double logSum = 0.0;
  for (std::size_t i = 0; i < cube.texelCount(); ++i) {
    const glm::vec3 c = cube.data()[i];
    logSum += std::log(1e-6 + 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z);
  }
  const float scale = static_cast<float>(0.18 / std::exp(logSum / cube.texelCount()));
  for (glm::vec3& p : cross.pixels) p *= scale;
  writeImage(path, cross);
}

nlohmann::json shJson(const SphericalHarmonics& sh) {
  nlohmann::json a = nlohmann::json::array();
  for (const glm::vec3& c : sh.coefficients()) a.push_back({c.x, c.y, c.z});
  return a;
}

void writeText(const std::string& path, const std::string& text) {
  AtomicOutput out(path);
  {
    std::ofstream f(out.tempPath());
    f << text;
    if (!f.flush()) fail(path, "cannot write");
  }
  out.commit();
}

int run(const Arguments& a) {
  const Stopwatch total;
  if (a.sky == !a.input.empty()) {
    throw Error(a.sky ? "give either INPUT or --sky, not both"
                      : "no environment: give INPUT (equirect, cross or cubemap image) or --sky");
  }
  if (a.radiance.empty() && a.irradiance.empty() && a.sh.empty() && a.json.empty()) {
    throw Error("nothing to write: give --radiance, -o/--irradiance, --sh or --json");
  }
  checkOutput(a.radiance, "exr", "--radiance");
  checkOutput(a.irradiance, "exr", "--irradiance");
  checkOutput(a.sh, "json", "--sh");
  checkOutput(a.json, "json", "--json");
  if (a.size < 0 || a.radianceSize < 0)
    throw Error("--size and --radiance-size must not be negative");
  if (!(a.tolerance >= 0.0) || !std::isfinite(a.tolerance)) throw Error("--tolerance must be >= 0");
  if (!(a.eta > 0.0f) || !std::isfinite(a.eta)) throw Error("--eta must be > 0");

  IrradianceOptions options;
  options.method = parseIrradianceMethod(a.method);
  options.window = parseShWindow(a.window);
  options.shOrder = a.shOrder;
  options.faceSize = a.size;
  options.tolerance = a.tolerance;
  options.eta = a.eta;
  options.threads = a.threads;
  options.quiet = a.quiet;

  nlohmann::json report;
  report["tool"] = "sss-irrmap";
  Stopwatch watch;
  Cubemap radiance;
  if (a.sky) {
    const SkyParameters sky = parseSkySpec(a.skySpec);
    radiance = makeSky(sky, a.radianceSize > 0 ? a.radianceSize : 128, a.threads);
    report["input"] = "sky:" + a.skySpec;
    report["layout"] = "procedural";
    report["timings_ms"]["read"] = 0.0;
    report["timings_ms"]["to_cubemap"] = watch.milliseconds();
  } else {
    const ImageRgb image = readImage(a.input, {a.sanitize});
    report["timings_ms"]["read"] = watch.milliseconds();
    const EnvironmentLayout layout = detectLayout(a.input, image.width, image.height);
    watch.restart();
    radiance = cubemapFromImage(image, layout, a.radianceSize, a.threads);
    report["timings_ms"]["to_cubemap"] = watch.milliseconds();
    report["input"] = a.input;
    report["input_size"] = {image.width, image.height};
    report["layout"] = layout == EnvironmentLayout::Equirect ? "equirect"
                       : layout == EnvironmentLayout::Cross  ? "cross"
                                                             : "cubemap-stack";
  }
  report["radiance_face_size"] = radiance.size();

  IrradianceResult result;
  if (!a.irradiance.empty() || !a.json.empty()) {
    result = computeIrradiance(radiance, options);
    info(std::string(irradianceMethodName(options.method)) + ": " + result.reason, a.quiet);
  }
  SphericalHarmonics radianceSh = result.radianceSh;
  if (!a.sh.empty() && radianceSh.order() != a.shOrder) {
    watch.restart();
    radianceSh = SphericalHarmonics::project(radiance, a.shOrder, a.threads);
    result.timings.projectionMs += watch.milliseconds();
  }

  watch.restart();
  if (!a.radiance.empty()) {
    writeCubemap(a.radiance, radiance);
    if (a.preview) writePreview(previewPath(a.radiance), radiance);
  }
  if (!a.irradiance.empty()) {
    writeCubemap(a.irradiance, result.irradiance);
    if (a.preview) writePreview(previewPath(a.irradiance), result.irradiance);
  }
  if (!a.sh.empty()) {
    const TransmittedCosineKernel kernel(a.eta);
    nlohmann::json sh;
    sh["order"] = radianceSh.order();
    sh["basis"] =
        "real orthonormal spherical harmonics, index l(l+1)+m, polar axis +Z, "
        "Y_1-1 ~ y, Y_10 ~ z, Y_11 ~ x (no Condon-Shortley phase)";
    sh["eta"] = a.eta;
    sh["window"] = a.window;
    sh["radiance"] = shJson(radianceSh);
    sh["irradiance"] = shJson(radianceSh.convolved(kernel, options.window));
    writeText(a.sh, sh.dump(2) + "\n");
  }
  const double writeMs = watch.milliseconds();

  if (!a.json.empty()) {
    report["method"] = irradianceMethodName(result.method);
    report["method_asked"] = a.method;
    report["reason"] = result.reason;
    report["estimated_error"] = result.estimatedError;
    report["tolerance"] = a.tolerance;
    report["eta"] = a.eta;
    report["sh_order"] = result.shOrder;
    report["window"] = a.window;
    report["irradiance_face_size"] = result.irradiance.size();
    report["source_texels"] = result.sourceTexels;
    report["brute_terms"] = result.bruteClusters;
    report["threads"] = a.threads;
    report["timings_ms"]["reference"] = result.timings.referenceMs;
    report["timings_ms"]["projection"] = result.timings.projectionMs;
    report["timings_ms"]["evaluation"] = result.timings.evaluationMs;
    report["timings_ms"]["irradiance"] = result.timings.totalMs;
    report["timings_ms"]["write"] = writeMs;
    report["timings_ms"]["total"] = total.milliseconds();
    nlohmann::json outputs = nlohmann::json::object();
    if (!a.radiance.empty()) outputs["radiance"] = a.radiance;
    if (!a.irradiance.empty()) outputs["irradiance"] = a.irradiance;
    if (!a.sh.empty()) outputs["sh"] = a.sh;
    report["outputs"] = outputs;
    writeText(a.json, report.dump(2) + "\n");
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "sss-irrmap: environment image -> radiance and diffuse irradiance cubemaps (+X -X +Y -Y +Z "
      "-Z stacked, OpenGL orientation, Y up)"};
  Arguments a;
  app.add_option("INPUT", a.input,
                 "environment image (.hdr .exr .pfm .tif): equirect 2:1 (centre looks to -Z), "
                 "cross 4:3 / 3:4, or an N x 6N cubemap stack");
  app.add_option("--sky", a.skySpec,
                 "procedural sun and sky instead of INPUT; optional spec "
                 "elevation=DEG,azimuth=DEG (0: -Z, 90: +X),turbidity=2..10,sun=SCALE,"
                 "radius=DEG,ground=ALBEDO")
      ->expected(0, 1);
  app.add_option("--radiance", a.radiance, "write the radiance cubemap (.exr)");
  app.add_option("-o,--irradiance", a.irradiance, "write the diffuse irradiance cubemap (.exr)");
  app.add_option("--eta", a.eta,
                 "relative index: irradiance transmitted through a smooth dielectric "
                 "(exact Fresnel); 1 = plain irradiance")
      ->capture_default_str();
  app.add_option("--sh", a.sh, "write the SH coefficients of radiance and irradiance (.json)");
  app.add_option("--json", a.json, "write a report: method, estimated error, timings (.json)");
  app.add_option("--method", a.method, "auto | brute | sh")->capture_default_str();
  app.add_option("--sh-order", a.shOrder, "SH order for --method sh and --sh")
      ->capture_default_str();
  app.add_option("--window", a.window, "SH window against ringing: none | hann | lanczos")
      ->capture_default_str();
  app.add_option("--tolerance", a.tolerance,
                 "relative RMS error allowed on the sphere, estimated for this environment "
                 "(0: the exact sum over every texel)")
      ->capture_default_str();
  app.add_option("--size", a.size, "irradiance face size (default: from the content)");
  app.add_option("--radiance-size", a.radianceSize,
                 "radiance face size (default: the source's resolution; 128 for --sky)");
  app.add_flag("--sanitize", a.sanitize, "replace NaN/Inf texels by 0 instead of failing");
  app.add_flag(
      "--no-preview", [&](std::int64_t) { a.preview = false; },
      "no PNG preview (FILE.png beside each cubemap FILE.exr)");
  app.add_option("--threads", a.threads, "worker threads (default: all cores)");
  app.add_flag("-q,--quiet", a.quiet, "no progress or informational messages");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  a.sky = app.count("--sky") > 0;
  return runTool("sss-irrmap", [&] { return run(a); });
}

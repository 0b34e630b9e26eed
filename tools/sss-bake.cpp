// sss-bake MESH -e ENV -m MATERIAL --mm-per-unit S -o OUT.ply [options]
// sss-bake MESH... -e ENV ... -o DIR/ [--json DIR/]   (batch: the environment loaded once)
// Per-vertex transmitted irradiance (with the mesh's own shadows) and subsurface exitance, written
// as a binary PLY that sss-render only has to look up. The stages are in lib/bake/bake.h.
#include <charconv>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bake/bake.h"
#include "bake/bake_report_json.h"
#include "bake/relight.h"
#include "core/atomic_output.h"
#include "core/batch.h"
#include "core/cli.h"
#include "core/error.h"
#include "core/file_extension.h"
#include "core/paths.h"
#include "core/timer.h"
#include "core/tool.h"
#include "envmap/environment.h"
#include "envmap/orientation_options.h"
#include "image/image.h"
#include "material/material.h"
#include "mesh/baked_mesh.h"
#include "mesh/lightmapped_glb.h"
#include "mesh/units.h"

namespace {

namespace cli = sss::cli;

// One of -m PRESET, --sigma-a with --sigma-s, or --albedo with --mfp; and eta, g.
struct MaterialOptions {
  std::string preset;
  glm::dvec3 sigmaA{0.0}, sigmaS{0.0}, albedo{0.0}, mfp{0.0};
  CLI::Option* sigmaAOption = nullptr;
  double eta = 0.0;  // 0: the preset's, or 1.3
  double g = 0.0;
};

glm::dvec3 parseRgb(const std::string& text) {
  return cli::parseTriple<double>(text, /*allowOne=*/true);
}

void addMaterialOptions(CLI::App& app, MaterialOptions& m) {
  auto* group = app.add_option_group(
      "material", "Exactly one: -m PRESET, --sigma-a and --sigma-s, or --albedo and --mfp");
  auto* preset =
      group->add_option("-m,--material", m.preset, "Measured preset (see --list-materials)")
          ->check(cli::parsedBy(sss::findMaterialPreset));
  m.sigmaAOption = cli::addParsedOption(*group, "--sigma-a", m.sigmaA, parseRgb,
                                        "Absorption coefficient r,g,b in 1/mm (with --sigma-s)");
  auto* albedo = cli::addParsedOption(*group, "--albedo", m.albedo, parseRgb,
                                      "Total diffuse reflectance r,g,b (with --mfp)");
  group->require_option(1);
  auto* sigmaS = cli::addParsedOption(app, "--sigma-s", m.sigmaS, parseRgb,
                                      "Reduced scattering coefficient sigma_s' r,g,b in 1/mm");
  auto* mfp = cli::addParsedOption(app, "--mfp", m.mfp, parseRgb,
                                   "Diffuse mean free path r,g,b in mm (with --albedo)");
  m.sigmaAOption->needs(sigmaS);
  sigmaS->needs(m.sigmaAOption);
  albedo->needs(mfp);
  mfp->needs(albedo);
  preset->excludes(sigmaS)->excludes(mfp);
  m.sigmaAOption->excludes(mfp);
  app.add_option("--eta", m.eta, "Relative index of refraction (default: the preset's, or 1.3)")
      ->check(cli::checkedBy<double>([](double eta) { sss::checkMaterialEta(eta); }));
  app.add_option("--g", m.g, "Henyey-Greenstein mean cosine (--method pathtrace)")
      ->capture_default_str();
  app.add_flag_callback(
      "--list-materials",
      [] {
        std::printf("%-10s %-26s %-26s %s\n", "name", "sigma_a (1/mm)", "sigma_s' (1/mm)", "eta");
        for (const sss::Material& p : sss::materialPresets()) {
          std::printf("%-10s %-8.4g %-8.4g %-8.4g %-8.4g %-8.4g %-8.4g %g\n", p.name.c_str(),
                      p.sigmaA.r, p.sigmaA.g, p.sigmaA.b, p.sigmaSPrime.r, p.sigmaSPrime.g,
                      p.sigmaSPrime.b, p.eta);
        }
        throw CLI::Success();
      },
      "List the presets and exit");
}

sss::Material materialFrom(const MaterialOptions& m) {
  const double eta = m.eta != 0.0 ? m.eta : 1.3;
  sss::Material material;
  if (!m.preset.empty()) {
    material = sss::findMaterialPreset(m.preset);
    if (m.eta != 0.0) material.eta = m.eta;
  } else if (m.sigmaAOption->count() > 0) {
    material.name = "custom";
    material.sigmaA = m.sigmaA;
    material.sigmaSPrime = m.sigmaS;
    material.eta = eta;
  } else {
    material = sss::materialFromAlbedoMfp(m.albedo, m.mfp, eta);
  }
  material.g = m.g;
  return material;
}

void addUnitOptions(CLI::App& app, sss::BakeSettings& s) {
  auto* group = app.add_option_group(
      "units",
      "One of --mm-per-unit, --unit or --size-mm (translucency depends on size); required but "
      "for glTF meshes, which are in metres");
  group->add_option("--mm-per-unit", s.mmPerUnit, "Millimetres per mesh unit")
      ->check(cli::checkedBy<double>([](double v) { sss::checkMmPerUnit(v, ""); }));
  cli::addParsedOption(*group, "--unit", s.mmPerUnit, sss::parseUnit, "Mesh unit: mm, cm or m");
  group->add_option("--size-mm", s.sizeMm, "Scale the longest bounding-box side to this many mm")
      ->check(cli::checkedBy<double>(sss::checkSizeMm));
  group->require_option(0, 1);
}

// Without a unit option every mesh must fix its own unit: glTF's metres.
void checkUnitsGiven(const std::vector<std::string>& meshes, const sss::BakeSettings& s) {
  if (s.mmPerUnit > 0.0 || s.sizeMm > 0.0) return;
  for (const std::string& mesh : meshes) {
    const std::string ext = sss::lowerExtension(mesh);
    if (ext != "gltf" && ext != "glb") {
      throw sss::UsageError("a unit is required: one of --mm-per-unit,--unit,--size-mm (" +
                            sss::escapeControl(mesh) + " does not fix one; glTF files are metres)");
    }
  }
}

// --samples auto|N: auto is 0.
int parseSamples(const std::string& text) {
  if (text == "auto") return 0;
  int n = 0;
  if (!CLI::detail::lexical_cast(text, n)) {
    throw sss::Error("'" + text + "' is neither auto nor an integer");
  }
  sss::checkVisibilitySamples(n == 0 ? 1 : n);
  return n;
}

int parseBounces(const std::string& text) {
  if (text == "auto") return sss::kAutoBounces;
  int n = 0;
  if (!CLI::detail::lexical_cast(text, n)) {
    throw sss::Error("'" + text + "' is neither auto nor an integer");
  }
  sss::checkBounces(n);
  return n;
}

void addBakeOptions(CLI::App& app, sss::BakeSettings& s) {
  cli::addEnumOption(app, "--visibility", s.visibility, sss::kVisibilityModeNames,
                     "E per vertex: the irradiance cubemap (none) or Embree shadow rays");
  cli::addParsedOption(app, "--samples", s.samples, parseSamples,
                       "Visibility rays per vertex (>= 2), or auto (from --tolerance and a pilot)")
      ->default_str("auto");
  app.add_option("--seed", s.run.seed, "Random seed")->capture_default_str();
  cli::addEnumOption(
      app, "--method", s.method, sss::kBakeMethodNames,
      "Diffusion sum (auto: the cheapest that meets --tolerance), or the path tracer");
  cli::addEnumOption(app, "--profile", s.profile, sss::kProfileChoiceNames,
                     "Diffusion profile (auto: dipole with the escape energy, else burley)");
  cli::addEnumOption(app, "--energy", s.energy, sss::kEnergyModelNames,
                     "escape rescales B by the object's own escape probability (random walks), "
                     "for objects small against the diffusion length");
  cli::addEnumOption(app, "--entry", s.entry, sss::kEntryModelNames,
                     "directional weighs light by how much of it a half-space returns from its "
                     "angle (a sun); diffuse counts every angle alike, as the profiles assume");
  cli::addEnumOption(app, "--far-field", s.farField, sss::kFarFieldModeNames,
                     "Trace the light that leaves far from where it entered (through a small or "
                     "thin object from a sun) from the environment; auto: escape energy and "
                     "uneven light");
  cli::addEnumOption(app, "--unscattered", s.unscattered, sss::kUnscatteredModeNames,
                     "Trace the light that crosses thin or low-density parts without scattering "
                     "into the radiance along the normal; auto: where a pilot finds it");
  app.add_option("--tolerance", s.tolerance, "Target relative RMS error of the exitance")
      ->check(cli::checkedBy<double>(sss::checkTolerance))
      ->capture_default_str();
  cli::addParsedOption(app, "--bounces", s.bounces, parseBounces,
                       "Interreflection: rays that meet the object bring back its light, "
                       "iterated N times, or until converged and ended with the series' "
                       "geometric tail (auto: none where a pilot finds them negligible); 0: "
                       "none, only the pilot's estimate of what is missed")
      ->default_str("auto");
  app.add_option("--walks", s.walks, "Random walks per vertex (--method pathtrace)")
      ->check(cli::checkedBy<int>(sss::checkPathTracerWalks))
      ->capture_default_str();
  app.add_option("--env-size", s.environmentFaceSize,
                 "Cubemap face size for the environment (0: from the source)")
      ->check(cli::checkedBy<int>([](int size) {
        if (size != 0) sss::checkFaceSize(size);
      }))
      ->capture_default_str();
  app.add_option("--texture", s.texture.size,
                 "Bake a SIZE x SIZE UV lightmap (TEXCOORD_0), the mesh refined to the texels: "
                 "-o NAME.exr writes it (radiance along the normal) and NAME_exitance.exr, "
                 "-o NAME.glb the asset with the lightmap as its emission")
      ->check(cli::checkedBy<int>(
          [](int size) { sss::checkTextureSettings({.size = size == 0 ? 16 : size}); }));
  app.add_option("--texture-padding", s.texture.padding,
                 "Texels of gutter filled around each UV chart (--texture)")
      ->check(
          cli::checkedBy<int>([](int padding) { sss::checkTextureSettings({.padding = padding}); }))
      ->capture_default_str();
  cli::addOrientationOptions(app, s.orientation);
  cli::addThreadsOption(app, s.run.threads);
  cli::addQuietFlag(app, s.run.quiet);
}

// --texture's second map, beside -o's: "light.exr" -> "light_exitance.exr".
std::string exitanceMapPath(const std::string& output) {
  return output.substr(0, output.size() - 4) + "_exitance.exr";
}

// The lightmaps (linear float EXR, row 0 at v = 0): the radiance along the normal at `output`,
// B beside it; both appear or neither does.
void writeLightmaps(const std::string& output, const sss::Lightmap& map) {
  const char* quantities[] = {"radiance along the normal", "exitance B (radiance x sr)"};
  const std::string paths[] = {output, exitanceMapPath(output)};
  std::vector<std::unique_ptr<sss::AtomicOutput>> files;
  for (int i = 0; i < 2; ++i) {
    files.push_back(std::make_unique<sss::AtomicOutput>(paths[i]));
    sss::ImageRgb image{.width = map.size, .height = map.size, .pixels = map.images[i]};
    sss::writeImage(files.back()->tempPath(), image,
                    {{"sss:quantity", quantities[i]}, {"sss:units", "the environment's radiance"}});
  }
  for (auto& file : files) file->commit();
}

// Writes the baked mesh (or with --texture its lightmaps) and, beside it, the report: the
// report's temporary file is created first, so both appear or neither does. A GLB embeds the
// report (without the write time).
void writeOutputs(const std::string& output, const std::string& jsonPath,
                  const sss::BakeOutput& result, const sss::Stopwatch& toolClock, bool quiet) {
  std::unique_ptr<sss::AtomicOutput> jsonOutput;
  std::ofstream jsonFile;
  if (!jsonPath.empty()) {
    jsonOutput = std::make_unique<sss::AtomicOutput>(jsonPath);
    jsonFile.open(jsonOutput->tempPath());
    if (!jsonFile) sss::fail(jsonPath, "cannot create the JSON report");
  }
  const sss::Stopwatch writeClock;
  sss::Json report = sss::toJson(result.report);
  report["output"] = output;
  if (result.lightmap.size > 0 && sss::lowerExtension(output) == "glb") {
    const sss::LightmappedAsset asset = sss::lightmappedAsset(
        result.lightmapSource, result.lightmap, result.baked, result.partMaterials, report.dump());
    if (!quiet)
      for (const std::string& note : sss::droppedSurfaceNotes(asset))
        sss::warn(output + ": " + note);
    sss::writeLightmappedGlb(output, asset);
  } else if (result.lightmap.size > 0) {
    report["texture"]["exitance_output"] = exitanceMapPath(output);
    writeLightmaps(output, result.lightmap);
  } else {
    sss::writeBakedMesh(output, result.baked, report.dump());
  }
  if (!jsonOutput) return;
  report["stages"]["write_s"] = writeClock.seconds();
  report["stages"]["tool_total_s"] = toolClock.seconds();
  jsonFile << report.dump(2) << "\n";
  jsonFile.close();
  if (!jsonFile) sss::fail(jsonPath, "cannot write the JSON report");
  jsonOutput->commit();
}

// --relightable [ORDER]: the order (kDefaultRelightOrder without one).
int relightOrderFrom(const std::string& text) {
  int order = sss::kDefaultRelightOrder;
  if (!text.empty()) {
    const auto r = std::from_chars(text.data(), text.data() + text.size(), order);
    if (r.ec != std::errc() || r.ptr != text.data() + text.size())
      throw sss::UsageError("--relightable " + sss::escapeControl(text) +
                            ": the SH order must be a whole number");
  }
  try {
    sss::checkRelightOrder(order);
  } catch (const sss::Error& e) {
    throw sss::UsageError(e.what());  // a nonsense option, like the others' checks
  }
  return order;
}

// The baked mesh of each input in a batch folder: DIR/<stem> + this.
constexpr const char* kBatchMeshSuffix = ".ply";

// Several meshes (or -o DIR/): the environment loaded once, each mesh baked into
// DIR/<stem>.ply (and its report into the --json folder); a bad mesh is reported and skipped.
int bakeBatch(const std::vector<std::string>& meshes, const std::string& outDir,
              const std::string& jsonDir, const sss::BakeSettings& s) {
  if (!sss::namesFolder(outDir)) {
    throw sss::UsageError("-o " + outDir + ": with several meshes, -o names a folder (DIR/)");
  }
  if (!jsonDir.empty() && !sss::namesFolder(jsonDir)) {
    throw sss::UsageError("--json " + jsonDir +
                          ": with several meshes, --json names a folder (DIR/)");
  }
  const std::vector<sss::BatchItem> items =
      sss::planBatch(meshes, {{"-o", outDir, kBatchMeshSuffix}, {"--json", jsonDir, ".json"}},
                     {{"the environment", s.environment}});
  sss::validateBakeSettings(s);
  const sss::BakeEnvironment environment = sss::loadBakeEnvironment(s);
  return sss::runBatch(
      items,
      [&](const sss::BatchItem& item) {
        const sss::Stopwatch clock;
        sss::BakeSettings one = s;
        one.meshPath = item.input;
        const sss::BakeOutput result = sss::bake(one, environment);
        writeOutputs(item.outputs[0], item.outputs[1], result, clock, s.run.quiet);
        sss::info("wrote " + item.outputs[0] + " (" +
                      std::to_string(result.baked.mesh.vertexCount()) + " vertices) in " +
                      std::to_string(clock.seconds()) + " s",
                  s.run.quiet);
      },
      s.run.quiet);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Bake per-vertex subsurface scattering (irradiance E and exitance B) into a PLY."};
  sss::BakeSettings s;
  MaterialOptions material;
  std::string output, jsonPath;
  std::vector<std::string> meshes;
  app.add_option("mesh", meshes,
                 "Input mesh (PLY, OBJ, OFF, STL, OM, glTF 2.0 .gltf/.glb); several with -o DIR/ "
                 "(one process)")
      ->required();
  sss::cli::EnvironmentChoice environment;
  sss::cli::addEnvironmentChoice(app, environment);
  app.add_option("-o,--output", output,
                 "Output baked mesh: .ply or .glb (glTF 2.0 binary), or a folder DIR/ (several "
                 "meshes: DIR/<stem>.ply)")
      ->required();
  addMaterialOptions(app, material);
  addUnitOptions(app, s);
  addBakeOptions(app, s);
  cli::addParsedOption(app, "--material-map", s.materialMap, sss::parseMaterialMap,
                       "glTF material names to presets, name=preset,... or a JSON file "
                       "({\"name\": \"preset\"}); parts not named take -m's material");
  std::string relightable;
  auto* relightOption =
      app.add_option("--relightable", relightable,
                     "Also store the SH transfer of the radiance along the normal, of order ORDER "
                     "(default 3), so that sss-relight relights the bake under other "
                     "environments")
          ->expected(0, 1)
          ->default_str("");
  app.add_option("--json", jsonPath, "Write a JSON report (a folder DIR/ with several meshes)");
  app.footer(
      "Examples:\n"
      "  sss-bake bunny.ply -e forest.exr -m marble --size-mm 150 -o bunny_baked.ply\n"
      "  sss-bake a.ply b.obj -e studio.exr -m skin1 --unit mm -o baked/  # one process\n"
      "  sss-bake asset.glb -e forest.exr -m marble --texture 512 -o asset_light.exr");

  return sss::runTool("sss-bake", app, argc, argv, [&]() -> int {
    checkUnitsGiven(meshes, s);
    s.environment = environment.source();
    if (relightOption->count() > 0) s.relightOrder = relightOrderFrom(relightable);
    if (sss::isBatch(meshes, output)) {
      if (s.texture.size > 0) throw sss::UsageError("--texture bakes one mesh at a time");
      s.material = materialFrom(material);
      return bakeBatch(meshes, output, jsonPath, s);
    }
    s.meshPath = meshes.front();
    if (s.texture.size > 0) {
      if (sss::lowerExtension(output) != "exr" && sss::lowerExtension(output) != "glb") {
        throw sss::UsageError(sss::escapeControl(output) +
                              ": with --texture the output is the lightmap, NAME.exr, or the "
                              "asset with the lightmap as its emission, NAME.glb");
      }
    } else {
      sss::checkBakedMeshPath(output);
    }
    const std::string exitanceMap =
        s.texture.size > 0 && sss::lowerExtension(output) == "exr" ? exitanceMapPath(output) : "";
    sss::checkOutputsAreNotInputs(
        {{"-o", output}, {"--json", jsonPath}, {"the exitance map", exitanceMap}},
        {{"the mesh", s.meshPath}, {"the environment", s.environment}});
    s.material = materialFrom(material);
    const sss::Stopwatch clock;
    const sss::BakeOutput result = sss::bake(s);
    writeOutputs(output, jsonPath, result, clock, s.run.quiet);
    const std::string what =
        s.texture.size > 0 ? std::to_string(s.texture.size) + "^2 texels, " +
                                 std::to_string(result.report.lightmap.coveredTexels) + " covered"
                           : std::to_string(result.baked.mesh.vertexCount()) + " vertices";
    sss::info("wrote " + output + " (" + what + ") in " + std::to_string(clock.seconds()) + " s",
              s.run.quiet);
    return 0;
  });
}

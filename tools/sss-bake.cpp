// sss-bake MESH -e ENV -m MATERIAL --mm-per-unit S -o OUT.ply [options]
// Per-vertex transmitted irradiance (with the mesh's own shadows) and subsurface exitance, written
// as a binary PLY that sss-render only has to look up. See lib/bake/bake.h for the stages.
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bake/bake.h"
#include "bake/diffusion.h"
#include "bake/finite_object_energy.h"
#include "core/atomic_output.h"
#include "core/error.h"
#include "core/timer.h"
#include "core/tool.h"
#include "material/diffusion_profile.h"
#include "material/material.h"
#include "mesh/baked_ply.h"
#include "mesh/units.h"

namespace {

// "r,g,b" or one value for all three channels.
glm::dvec3 parseRgb(const std::string& text, const std::string& option) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    try {
      std::size_t used = 0;
      values.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      sss::fail("", option + ": '" + text + "' is not a number or r,g,b triple");
    }
  }
  if (values.size() == 1) return glm::dvec3(values[0]);
  if (values.size() != 3)
    sss::fail("", option + ": expected r,g,b or one value, got '" + text + "'");
  return {values[0], values[1], values[2]};
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : "|") + n;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  return sss::runTool("sss-bake", [&]() -> int {
    CLI::App app{"Bake per-vertex subsurface scattering (irradiance E and exitance B) into a PLY."};
    sss::BakeSettings s;
    std::string output, jsonPath, materialName, sigmaA, sigmaS, albedo, mfp, unit, sky;
    std::string visibility = "rays", samples = "auto";
    double eta = 0.0, mmPerUnit = 0.0;
    bool listMaterials = false;
    std::vector<std::string> methods = sss::listDiffusionMethods();
    methods.push_back("pathtrace");

    app.add_option("mesh", s.meshPath, "Input mesh (PLY, OBJ, OFF, STL, OM)");
    app.add_option("-e,--env", s.environment,
                   "Environment: equirect, cross or cubemap-stack image");
    auto* skyOption = app.add_option("--sky", sky,
                                     "Procedural sun and sky instead of -e, optional spec "
                                     "(elevation=45,azimuth=30,turbidity=3)")
                          ->expected(0, 1)
                          ->default_str("");
    app.add_option("-o,--output", output, "Output baked PLY");
    app.add_option("-m,--material", materialName, "Measured preset (see --list-materials)");
    app.add_flag("--list-materials", listMaterials, "List the presets and exit");
    app.add_option("--sigma-a", sigmaA, "Absorption coefficient r,g,b in 1/mm");
    app.add_option("--sigma-s", sigmaS, "Reduced scattering coefficient sigma_s' r,g,b in 1/mm");
    app.add_option("--albedo", albedo, "Total diffuse reflectance r,g,b (with --mfp)");
    app.add_option("--mfp", mfp, "Diffuse mean free path r,g,b in mm (with --albedo)");
    app.add_option("--eta", eta, "Relative index of refraction (default: preset's, or 1.3)");
    app.add_option("--g", s.material.g, "Henyey-Greenstein mean cosine (--method pathtrace)");
    app.add_option("--mm-per-unit", mmPerUnit, "Millimetres per mesh unit");
    app.add_option("--unit", unit, "Mesh unit: mm, cm or m");
    app.add_option("--size-mm", s.sizeMm, "Scale the longest bounding-box side to this many mm");
    app.add_option("--visibility", visibility, "none | rays (Embree shadows)")
        ->capture_default_str();
    app.add_option("--samples", samples,
                   "Visibility rays per vertex, or auto (from --tolerance and a pilot)")
        ->capture_default_str();
    app.add_option("--seed", s.seed, "Random seed")->capture_default_str();
    app.add_option("--method", s.method, joined(methods))->capture_default_str();
    std::vector<std::string> profiles = sss::listProfiles();
    profiles.insert(profiles.begin(), "auto");
    app.add_option("--profile", s.profile,
                   joined(profiles) + " (auto: dipole with the escape energy, else burley)")
        ->capture_default_str();
    app.add_option("--energy", s.energy,
                   joined(sss::listEnergyModels()) +
                       ": escape rescales B by the object's own escape probability (random "
                       "walks), for objects small against the diffusion length")
        ->capture_default_str();
    app.add_option("--tolerance", s.tolerance, "Target relative RMS error of the exitance")
        ->capture_default_str();
    app.add_option("--walks", s.walks, "Random walks per vertex (--method pathtrace)")
        ->capture_default_str();
    app.add_option("--env-size", s.environmentFaceSize,
                   "Cubemap face size for the environment (0: from the source)")
        ->capture_default_str();
    app.add_option("--threads", s.threads, "Threads (0: all cores)")->capture_default_str();
    app.add_option("--json", jsonPath, "Write a JSON report");
    app.add_flag("-q,--quiet", s.quiet, "No progress or information on stderr");
    CLI11_PARSE(app, argc, argv);

    if (listMaterials) {
      std::printf("%-10s %-26s %-26s %s\n", "name", "sigma_a (1/mm)", "sigma_s' (1/mm)", "eta");
      for (const sss::Material& m : sss::materialPresets()) {
        std::printf("%-10s %-8.4g %-8.4g %-8.4g %-8.4g %-8.4g %-8.4g %g\n", m.name.c_str(),
                    m.sigmaA.r, m.sigmaA.g, m.sigmaA.b, m.sigmaSPrime.r, m.sigmaSPrime.g,
                    m.sigmaSPrime.b, m.eta);
      }
      return 0;
    }

    // Required inputs, each with one clear line.
    if (s.meshPath.empty()) sss::fail("", "no input mesh given");
    if (output.empty()) sss::fail("", "no output given (-o OUT.ply)");
    const bool skyGiven = skyOption->count() > 0;
    if (skyGiven == !s.environment.empty()) {
      sss::fail("", "give exactly one of -e ENV and --sky");
    }
    if (skyGiven) s.environment = sky.empty() ? "sky" : "sky:" + sky;

    const int unitSources = (mmPerUnit != 0.0) + !unit.empty() + (s.sizeMm != 0.0);
    if (unitSources == 0) {
      sss::fail("",
                "the mesh's units are missing: give --mm-per-unit S, --unit mm|cm|m or "
                "--size-mm L (translucency depends on size)");
    }
    if (unitSources > 1) sss::fail("", "give only one of --mm-per-unit, --unit and --size-mm");
    if (!unit.empty()) mmPerUnit = sss::parseUnit(unit);
    if (s.sizeMm != 0.0 && !(s.sizeMm > 0.0)) sss::fail("", "--size-mm must be positive");
    s.mmPerUnit = s.sizeMm > 0.0 ? 0.0 : sss::checkMmPerUnit(mmPerUnit);

    // Material: a preset, coefficients, or albedo + mean free path.
    const int materialSources = !materialName.empty() + (!sigmaA.empty() || !sigmaS.empty()) +
                                (!albedo.empty() || !mfp.empty());
    if (materialSources != 1) {
      sss::fail("",
                "give exactly one material: -m PRESET, --sigma-a and --sigma-s, or "
                "--albedo and --mfp (see --list-materials)");
    }
    const double g = s.material.g;
    if (!materialName.empty()) {
      s.material = sss::findMaterialPreset(materialName);
      if (eta != 0.0) s.material.eta = eta;
    } else if (!sigmaA.empty() || !sigmaS.empty()) {
      if (sigmaA.empty() || sigmaS.empty()) sss::fail("", "--sigma-a and --sigma-s go together");
      s.material.name = "custom";
      s.material.sigmaA = parseRgb(sigmaA, "--sigma-a");
      s.material.sigmaSPrime = parseRgb(sigmaS, "--sigma-s");
      s.material.eta = eta != 0.0 ? eta : 1.3;
    } else {
      if (albedo.empty() || mfp.empty()) sss::fail("", "--albedo and --mfp go together");
      s.material = sss::materialFromAlbedoMfp(parseRgb(albedo, "--albedo"), parseRgb(mfp, "--mfp"),
                                              eta != 0.0 ? eta : 1.3);
    }
    s.material.g = g;
    s.visibility = sss::parseVisibilityMode(visibility);
    if (samples != "auto") {
      std::size_t used = 0;
      int count = 0;
      try {
        count = std::stoi(samples, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != samples.size() || samples.empty()) {
        sss::fail("", "--samples: '" + samples + "' is neither auto nor an integer");
      }
      if (count < 2) sss::fail("", "--samples must be at least 2 (or auto)");
      s.samples = count;
    }

    const sss::Stopwatch clock;
    sss::BakeOutput result = sss::bake(s);

    // The report is written beside the PLY and appears only if both succeed.
    std::unique_ptr<sss::AtomicOutput> jsonOutput;
    nlohmann::ordered_json report = nlohmann::ordered_json::parse(result.reportJson);
    const sss::Stopwatch writeClock;
    std::ofstream jsonFile;
    if (!jsonPath.empty()) {
      jsonOutput = std::make_unique<sss::AtomicOutput>(jsonPath);
      jsonFile.open(jsonOutput->tempPath());
      if (!jsonFile) sss::fail(jsonPath, "cannot create the JSON report");
    }
    sss::writeBakedPly(output, result.baked);
    report["output"] = output;
    report["stages"]["write_s"] = writeClock.seconds();
    report["stages"]["tool_total_s"] = clock.seconds();
    if (jsonOutput) {
      jsonFile << report.dump(2) << "\n";
      jsonFile.close();
      if (!jsonFile) sss::fail(jsonPath, "cannot write the JSON report");
      jsonOutput->commit();
    }
    sss::info("wrote " + output + " (" + std::to_string(result.baked.mesh.vertexCount()) +
                  " vertices) in " + std::to_string(clock.seconds()) + " s",
              s.quiet);
    return 0;
  });
}

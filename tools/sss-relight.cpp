// sss-relight: a relightable bake (sss-bake --relightable) under other environments, on the CPU,
// without baking again (bake/relight.h; docs/tools/sss-relight.md).
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bake/relight.h"
#include "core/atomic_output.h"
#include "core/batch.h"
#include "core/cli.h"
#include "core/error.h"
#include "core/format.h"
#include "core/paths.h"
#include "core/timer.h"
#include "core/tool.h"
#include "envmap/environment.h"
#include "envmap/orientation_options.h"
#include "material/material.h"
#include "mesh/baked_mesh.h"
#include "mesh/triangle_mesh.h"
#include "nlohmann/json.hpp"

namespace {

struct RelightOptions {
  sss::EnvironmentOrientation orientation;
  int threads = 0;
  bool quiet = false;
};

// An environment (a file, or "sky" / "sky:<spec>") as a radiance cubemap in the bake's frame
// (--env-rotate, --env-convention).
struct NamedEnvironment {
  std::string source;
  sss::Cubemap radiance;
};

NamedEnvironment environmentOf(const std::string& source, const RelightOptions& o) {
  sss::EnvironmentOptions options;
  options.orientation = o.orientation;
  options.threads = o.threads;
  options.read.quiet = o.quiet;
  return {source, sss::loadEnvironment(source, options)};
}

// What a fresh bake would write: the mesh, material and units of the relightable bake, the relit
// exitance and radiance along the normal, a new preview; no transfer, no irradiance, no far field
// (each was the bake environment's).
struct Relit {
  sss::BakedMesh baked;
  int order = -1, compactLights = 0;
  sss::RelightSeconds seconds;
  sss::UnscatteredLightReport unscattered;  // the compact lights'
};

Relit relitMesh(const sss::BakedMesh& relightable, sss::BakedMeshRelighter& relighter,
                const NamedEnvironment& environment, const RelightOptions& o) {
  // The mesh, the material and what made it; not the relightable fields nor the light, which the
  // relight replaces (the transfer alone is (order + 1)^2 values per vertex).
  sss::BakedMesh baked;
  baked.mesh = relightable.mesh;
  baked.materialName = relightable.materialName;
  baked.sigmaA = relightable.sigmaA;
  baked.sigmaSPrime = relightable.sigmaSPrime;
  baked.eta = relightable.eta;
  baked.mmPerUnit = relightable.mmPerUnit;
  baked.extraComments = relightable.extraComments;
  baked.meshChecked = relightable.meshChecked;
  baked.unscatteredTraced = relightable.unscatteredTraced;
  const int order = relightable.relightOrder;
  sss::RelitLight relit = relighter.relight(environment.radiance);
  baked.exitance = std::move(relit.exitance);
  baked.radianceNormal = std::move(relit.radianceNormal);
  // Exit slopes without a far field are the material's and the object's (the half-space's lobe
  // and the walks', bake.cpp), not the light's: B leaves through them under any light. A traced
  // far field's were its environment's, and go with it.
  if (relightable.farExitance.empty()) baked.exitSlope = relightable.exitSlope;
  baked.extraComments.push_back(
      "relit env=" + environment.source +
      " convention=" + std::string(sss::kEquirectConventionNames.name(o.orientation.convention)) +
      " rotate_deg=" + sss::format("%g", o.orientation.rotateDeg) +
      " compact_lights=" + std::to_string(relit.compactLights));
  return {std::move(baked), order, relit.compactLights, relit.seconds,
          std::move(relit.unscattered)};
}

// The relit bake into `output`, its report into `jsonPath` (unless "").
void writeRelit(const std::string& input, const std::string& output, const std::string& jsonPath,
                const NamedEnvironment& environment, const Relit& relit, double seconds,
                const RelightOptions& o) {
  const sss::Stopwatch clock;
  const sss::BakedMesh& baked = relit.baked;
  nlohmann::json report = {{"input", input},
                           {"output", output},
                           {"environment", environment.source},
                           {"rotate_deg", o.orientation.rotateDeg},
                           {"sh_order", relit.order},
                           {"compact_lights", relit.compactLights},
                           {"unscattered",
                            {{"traced", relit.unscattered.traced},
                             {"reason", relit.unscattered.reason},
                             {"paths", relit.unscattered.paths}}},
                           {"vertices", baked.mesh.vertexCount()}};
  sss::writeBakedMesh(output, baked, report.dump());
  report["seconds"] = seconds + clock.seconds();
  // After the write: the file's embedded report stays the same from run to run.
  report["stages"] = {{"compact_lights_s", relit.seconds.compactLights},
                      {"smooth_s", relit.seconds.smooth},
                      {"compact_transport_s", relit.seconds.compactTransport},
                      {"gather_s", relit.seconds.gather},
                      {"bounces_s", relit.seconds.bounces},
                      {"unscattered_s", relit.seconds.unscattered}};
  if (!jsonPath.empty()) sss::writeFileAtomically(jsonPath, report.dump(2) + "\n");
  sss::info("wrote " + output + " (" + std::to_string(baked.mesh.vertexCount()) + " vertices) in " +
                sss::format("%.3f s", seconds + clock.seconds()),
            o.quiet);
}

// One relightable bake under each environment, into outputs[e] (and jsonPaths[e] unless ""): the
// bake read once, its rays traced once for all of them (RelightSession). Every environment is
// relit before any file is written, and a failed write takes the files written before it away:
// all of the bake's outputs or none. A report's seconds: the read and the first relight for the
// first environment, its own relight for each other, and the writes.
void relightOne(const std::string& input, const std::vector<std::string>& outputs,
                const std::vector<std::string>& jsonPaths,
                const std::vector<NamedEnvironment>& environments, const RelightOptions& o) {
  sss::Stopwatch clock;
  const sss::BakedPlyContents contents = sss::readBakedMesh(input);
  if (!contents.hasRelight)
    sss::fail(input, "not a relightable bake (no relight_order): run sss-bake --relightable");
  sss::BakedMeshRelighter relighter(input, contents.baked, {.threads = o.threads, .quiet = true},
                                    environments.size() > 1);
  std::vector<Relit> relit;
  std::vector<double> seconds;
  for (const NamedEnvironment& environment : environments) {
    relit.push_back(relitMesh(contents.baked, relighter, environment, o));
    seconds.push_back(clock.seconds());
    clock.restart();
  }
  std::size_t written = 0;
  try {
    for (; written < environments.size(); ++written)
      writeRelit(input, outputs[written], jsonPaths[written], environments[written], relit[written],
                 seconds[written], o);
  } catch (...) {
    std::error_code ignored;
    for (std::size_t e = 0; e < written; ++e) {
      std::filesystem::remove(outputs[e], ignored);
      if (!jsonPaths[e].empty()) std::filesystem::remove(jsonPaths[e], ignored);
    }
    throw;
  }
}

// Batch outputs: per environment DIR/<stem>.ply, or DIR/<stem>_<environment's stem>.ply with
// several (a UsageError when two environments share a stem).
std::vector<sss::BatchOutput> batchOutputs(const std::vector<std::string>& sources,
                                           const std::string& output, const std::string& json) {
  std::vector<sss::BatchOutput> outputs, reports;
  std::set<std::string> stems;
  for (const std::string& source : sources) {
    std::string suffix;
    if (sources.size() > 1) {
      suffix = "_" + std::filesystem::path(source).stem().string();
      if (!stems.insert(suffix).second)
        throw sss::UsageError("-e " + source + ": two environments named " + suffix.substr(1) +
                              " would write the same outputs");
    }
    outputs.push_back({"-o", output, suffix + ".ply"});
    reports.push_back({"--json", json, suffix + ".json"});
  }
  outputs.insert(outputs.end(), reports.begin(), reports.end());
  return outputs;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Relight a relightable bake (sss-bake --relightable) under other environments, without "
      "baking again: writes what a fresh bake would (exitance, radiance along the normal, "
      "preview colours). The bake itself comes from sss-bake MESH -e ENV --relightable -o "
      "NAME.ply."};
  RelightOptions o;
  std::string output, jsonPath;
  std::vector<std::string> inputs;
  app.add_option("baked", inputs, "Relightable bake, PLY or GLB; several with -o DIR/")->required();
  sss::cli::EnvironmentChoice environment;
  sss::cli::addEnvironmentChoice(app, environment, true);
  app.add_option("-o,--output", output,
                 "Output baked mesh: .ply or .glb, or a folder DIR/ (several inputs or "
                 "environments)")
      ->required();
  app.add_option("--json", jsonPath,
                 "Write a JSON report (a folder DIR/ with several inputs or environments)");
  sss::cli::addOrientationOptions(app, o.orientation);
  sss::cli::addThreadsOption(app, o.threads);
  sss::cli::addQuietFlag(app, o.quiet);
  app.footer(
      "Examples:\n"
      "  sss-relight bunny_relightable.ply -e sunset.exr --env-rotate 90 -o bunny_sunset.ply\n"
      "  sss-relight a.ply b.ply --sky elevation=10,azimuth=200 -o relit/  # one process\n"
      "  sss-relight bunny_relightable.ply -e sunset.exr -e night.exr -o relit/  # rays traced "
      "once");

  return sss::runTool("sss-relight", app, argc, argv, [&]() -> int {
    const std::vector<std::string> sources = environment.sources();
    std::vector<sss::ToolFile> shared;
    for (const std::string& source : sources) shared.push_back({"the environment", source});
    if (sss::isBatch(inputs, output) || sources.size() > 1) {
      if (!sss::namesFolder(output))
        throw sss::UsageError("-o " + output + ": with several environments, -o names a folder " +
                              "(DIR/)");
      if (!jsonPath.empty() && !sss::namesFolder(jsonPath))
        throw sss::UsageError("--json " + jsonPath +
                              ": with several inputs or environments, --json names a folder "
                              "(DIR/)");
      const std::vector<sss::BatchItem> items =
          sss::planBatch(inputs, batchOutputs(sources, output, jsonPath), shared);
      std::vector<NamedEnvironment> environments;
      for (const std::string& source : sources) environments.push_back(environmentOf(source, o));
      const std::size_t count = sources.size();
      return sss::runBatch(
          items,
          [&](const sss::BatchItem& item) {
            const std::vector<std::string> outputs(item.outputs.begin(),
                                                   item.outputs.begin() + count),
                reports(item.outputs.begin() + count, item.outputs.end());
            relightOne(item.input, outputs, reports, environments, o);
          },
          o.quiet);
    }
    sss::checkBakedMeshPath(output);
    std::vector<sss::ToolFile> inputFiles = shared;
    inputFiles.push_back({"the baked mesh", inputs.front()});
    sss::checkOutputsAreNotInputs({{"-o", output}, {"--json", jsonPath}}, inputFiles);
    relightOne(inputs.front(), {output}, {jsonPath}, {environmentOf(sources.front(), o)}, o);
    return 0;
  });
}

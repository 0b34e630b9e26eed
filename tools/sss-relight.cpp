// sss-relight: a relightable bake (sss-bake --relightable) under another environment, on the
// CPU, without baking again (bake/relight.h; docs/tools/sss-relight.md).
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
  std::string environment;  // a file, or "sky" / "sky:<spec>"
  sss::EnvironmentOrientation orientation;
  int threads = 0;
  bool quiet = false;
};

// The environment as a radiance cubemap in the bake's frame (--env-rotate, --env-convention).
sss::Cubemap environmentOf(const RelightOptions& o) {
  sss::EnvironmentOptions options;
  options.orientation = o.orientation;
  options.threads = o.threads;
  options.read.quiet = o.quiet;
  return sss::loadEnvironment(o.environment, options);
}

// What a fresh bake would write: the mesh, material and units of `input`, the relit exitance and
// radiance along the normal, a new preview; no transfer, no irradiance, no far field (each was
// the bake environment's).
struct Relit {
  sss::BakedMesh baked;
  int order = -1, compactLights = 0;
};

Relit relitMesh(const std::string& input, const sss::Cubemap& environment,
                const RelightOptions& o) {
  sss::BakedPlyContents contents = sss::readBakedMesh(input);
  if (!contents.hasRelight)
    sss::fail(input, "not a relightable bake (no relight_order): run sss-bake --relightable");
  sss::BakedMesh baked = std::move(contents.baked);
  sss::RelitLight relit =
      sss::relightBakedMesh(input, baked, environment, {.threads = o.threads, .quiet = true});
  const int order = baked.relightOrder;
  baked.exitance = std::move(relit.exitance);
  baked.radianceNormal = std::move(relit.radianceNormal);
  baked.irradiance.clear();
  baked.farExitance.clear();
  baked.farExitSlope.clear();
  baked.relightOrder = -1;
  baked.relightTransfer.clear();
  baked.radianceGain.clear();
  baked.exitancePerRadiance.clear();
  baked.escapeProbability.clear();
  baked.relightTransport.clear();
  baked.previewScale = 0.0;
  baked.extraComments.push_back(
      "relit env=" + o.environment +
      " convention=" + std::string(sss::kEquirectConventionNames.name(o.orientation.convention)) +
      " rotate_deg=" + sss::format("%g", o.orientation.rotateDeg) +
      " compact_lights=" + std::to_string(relit.compactLights));
  return {std::move(baked), order, relit.compactLights};
}

void relightOne(const std::string& input, const std::string& output, const std::string& jsonPath,
                const sss::Cubemap& environment, const RelightOptions& o) {
  const sss::Stopwatch clock;
  const Relit relit = relitMesh(input, environment, o);
  const sss::BakedMesh& baked = relit.baked;
  nlohmann::json report = {{"input", input},
                           {"output", output},
                           {"environment", o.environment},
                           {"rotate_deg", o.orientation.rotateDeg},
                           {"sh_order", relit.order},
                           {"compact_lights", relit.compactLights},
                           {"vertices", baked.mesh.vertexCount()}};
  sss::writeBakedMesh(output, baked, report.dump());
  report["seconds"] = clock.seconds();
  if (!jsonPath.empty()) sss::writeFileAtomically(jsonPath, report.dump(2) + "\n");
  sss::info("wrote " + output + " (" + std::to_string(baked.mesh.vertexCount()) + " vertices) in " +
                sss::format("%.3f s", clock.seconds()),
            o.quiet);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Relight a relightable bake (sss-bake --relightable) under another environment, without "
      "baking again: writes what a fresh bake would (exitance, radiance along the normal, "
      "preview colours). The bake itself comes from sss-bake MESH -e ENV --relightable -o "
      "NAME.ply."};
  RelightOptions o;
  std::string output, jsonPath;
  std::vector<std::string> inputs;
  app.add_option("baked", inputs, "Relightable bake, PLY or GLB; several with -o DIR/")->required();
  sss::cli::EnvironmentChoice environment;
  sss::cli::addEnvironmentChoice(app, environment);
  app.add_option("-o,--output", output,
                 "Output baked mesh: .ply or .glb, or a folder DIR/ (several inputs)")
      ->required();
  app.add_option("--json", jsonPath, "Write a JSON report (a folder DIR/ with several inputs)");
  sss::cli::addOrientationOptions(app, o.orientation);
  sss::cli::addThreadsOption(app, o.threads);
  sss::cli::addQuietFlag(app, o.quiet);
  app.footer(
      "Examples:\n"
      "  sss-relight bunny_relightable.ply -e sunset.exr --env-rotate 90 -o bunny_sunset.ply\n"
      "  sss-relight a.ply b.ply --sky elevation=10,azimuth=200 -o relit/  # one process");

  return sss::runTool("sss-relight", app, argc, argv, [&]() -> int {
    o.environment = environment.source();
    if (sss::isBatch(inputs, output)) {
      if (!jsonPath.empty() && !sss::namesFolder(jsonPath))
        throw sss::UsageError("--json " + jsonPath +
                              ": with several inputs, --json names a folder (DIR/)");
      const std::vector<sss::BatchItem> items =
          sss::planBatch(inputs, {{"-o", output, ".ply"}, {"--json", jsonPath, ".json"}},
                         {{"the environment", o.environment}});
      const sss::Cubemap light = environmentOf(o);
      return sss::runBatch(
          items,
          [&](const sss::BatchItem& item) {
            relightOne(item.input, item.outputs[0], item.outputs[1], light, o);
          },
          o.quiet);
    }
    sss::checkBakedMeshPath(output);
    sss::checkOutputsAreNotInputs(
        {{"-o", output}, {"--json", jsonPath}},
        {{"the baked mesh", inputs.front()}, {"the environment", o.environment}});
    relightOne(inputs.front(), output, jsonPath, environmentOf(o), o);
    return 0;
  });
}

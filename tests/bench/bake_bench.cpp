// The bake's speed target: the dragon with ~100K vertices (dragon_res2, scaled to 150 mm),
// marble, forest environment, 64 visibility rays per vertex (res2_rays, half-space energy as
// the paper; res2_rays_escape adds the escape energy model's walks; res2_auto is sss-bake's
// default: the 1% tolerance chooses rays, energy model, profile, method and the bounces; the
// others bake without bounces), 1% tolerance: the
// whole bake (load, environment, visibility, diffusion; not the PLY write) <= 5 s on 2 cores, peak
// memory <= 1 GB. Counters: stage seconds from the bake's report and the process's peak RSS.
// Run with --benchmark_repetitions=5 --benchmark_report_aggregates_only=true for medians.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "bake/bake.h"
#include "core/tool.h"

namespace {

const std::string kData = SSS_SOURCE_DIR "/data/cache";

// samples 0: auto (the default: as many rays as the 1% tolerance needs, see bake.h).
// bounces: sss::kAutoBounces (the default) or a count.
void BM_BakeDragon(benchmark::State& state, const char* mesh, const char* visibility, int samples,
                   const char* energy, const char* profile, int bounces) {
  const std::string meshPath = kData + "/meshes/" + mesh + ".ply";
  if (!std::filesystem::exists(meshPath)) {
    state.SkipWithError(("missing " + meshPath + ": run data/fetch.sh").c_str());
    return;
  }
  sss::BakeSettings settings;
  settings.meshPath = meshPath;
  settings.environment = kData + "/env/forest.exr";
  settings.material = sss::findMaterialPreset("marble");
  settings.sizeMm = 150.0;
  settings.visibility = sss::kVisibilityModeNames.parse(visibility);
  settings.samples = samples;
  settings.tolerance = 0.01;
  settings.energy = sss::kEnergyModelNames.parse(energy);
  settings.profile = sss::kProfileChoiceNames.parse(profile);
  settings.bounces = bounces;
  settings.run.threads = static_cast<int>(state.range(0));
  settings.run.quiet = true;
  sss::BakeReport report;
  for (auto _ : state) {
    sss::BakeOutput out = sss::bake(settings);
    report = std::move(out.report);
    benchmark::DoNotOptimize(out.baked.exitance.data());
  }
  state.counters["load_mesh_s"] = report.mesh.seconds;
  state.counters["load_environment_s"] = report.environment.seconds;
  state.counters["energy_s"] = report.energy.seconds;
  state.counters["irradiance_s"] = report.lighting.seconds;
  state.counters["exitance_s"] = report.transport.seconds;
  state.counters["total_s"] = report.totalSeconds;
  state.counters["vertices"] = static_cast<double>(report.mesh.vertices);
  if (report.lighting.mode == sss::VisibilityMode::Rays) {
    state.counters["samples"] = report.lighting.rays.samples;
  }
  state.counters["estimated_error"] = report.errors.total;
  state.SetLabel(report.energy.profileName + "/" + report.transport.methodName() + "/" +
                 sss::kEnergyModelNames.name(report.energy.plan.model));
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  state.counters["peak_rss_mb"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
}

BENCHMARK_CAPTURE(BM_BakeDragon, res2_rays, "dragon_res2", "rays", 64, "halfspace", "dipole", 0)
    ->Arg(2)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_BakeDragon, res2_rays_escape, "dragon_res2", "rays", 64, "escape", "dipole", 0)
    ->Arg(2)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_BakeDragon, res2_auto, "dragon_res2", "rays", 0, "auto", "auto",
                  sss::kAutoBounces)
    ->Arg(2)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_BakeDragon, res2_none, "dragon_res2", "none", 0, "halfspace", "dipole", 0)
    ->Arg(2)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

// Speed targets on a 1024x512 sample map (release build, 2 cores):
//   SH order 2 of the map in <= 20 ms (BM_ShOrder2FromEquirect: projection straight from the
//   equirect texels, convolution, and a 32x32-face irradiance cubemap);
//   brute-force 32x32-face irradiance cubemap in <= 0.5 s (BM_Brute32: the cut, its error check
//   against the exact sum at 256 probes, and the cubemap).
// Run with --benchmark_repetitions=5; irradiance_sweep.sh keeps the medians in CSV. "Time" is
// wall time, "CPU" the whole process's CPU time (all threads): on a shared machine wall time
// includes waiting for other processes, and CPU / 2 is what 2 idle cores would take.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "envmap/environment.h"
#include "irradiance/brute_force.h"
#include "irradiance/irradiance.h"

namespace {

using namespace sss;

const ImageRgb& sampleMap() {
  static const ImageRgb image = [] {
    const char* env = std::getenv("SSS_BENCH_ENV");
    const std::string path =
        env ? env : std::string(SSS_SOURCE_DIR) + "/data/cache/env/courtyard.exr";
    if (!std::filesystem::exists(path)) {
      std::fprintf(stderr, "%s missing: run data/fetch.sh\n", path.c_str());
      std::exit(1);
    }
    return readImage(path);
  }();
  return image;
}

const Cubemap& sampleCubemap() {
  static const Cubemap cube = cubemapFromImage(sampleMap(), EnvironmentLayout::Equirect, 0);
  return cube;
}

void BM_ShOrder2FromEquirect(benchmark::State& state) {
  const ImageRgb& image = sampleMap();
  const TransmittedCosineKernel kernel(1.0f);
  for (auto _ : state) {
    const SphericalHarmonics sh = SphericalHarmonics::projectEquirect(image, 2).convolved(kernel);
    benchmark::DoNotOptimize(sh.toCubemap(32));
  }
}
BENCHMARK(BM_ShOrder2FromEquirect)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void BM_ShOrder2FromCubemap(benchmark::State& state) {
  const Cubemap& cube = sampleCubemap();
  const TransmittedCosineKernel kernel(1.0f);
  for (auto _ : state) {
    const SphericalHarmonics sh = SphericalHarmonics::project(cube, 2).convolved(kernel);
    benchmark::DoNotOptimize(sh.toCubemap(32));
  }
}
BENCHMARK(BM_ShOrder2FromCubemap)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void BM_Brute32(benchmark::State& state) {
  const Cubemap& cube = sampleCubemap();
  BruteForceOptions o;
  o.faceSize = 32;
  o.tolerance = 0.01;
  for (auto _ : state) benchmark::DoNotOptimize(bruteForceIrradiance(cube, o));
}
BENCHMARK(BM_Brute32)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void BM_EquirectToCubemap(benchmark::State& state) {
  const ImageRgb& image = sampleMap();
  for (auto _ : state)
    benchmark::DoNotOptimize(cubemapFromImage(image, EnvironmentLayout::Equirect, 0));
}
BENCHMARK(BM_EquirectToCubemap)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void BM_ExactSumAt256Probes(benchmark::State& state) {
  const Cubemap& cube = sampleCubemap();
  const std::vector<glm::vec3> probes = fibonacciSphere(256);
  for (auto _ : state) benchmark::DoNotOptimize(irradianceAtNormals(cube, probes, 1.0f));
}
BENCHMARK(BM_ExactSumAt256Probes)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void BM_Auto(benchmark::State& state) {
  const Cubemap& cube = sampleCubemap();
  for (auto _ : state) benchmark::DoNotOptimize(computeIrradiance(cube, {}));
}
BENCHMARK(BM_Auto)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

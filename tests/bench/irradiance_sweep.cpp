// Methods x sizes on the sample HDRs: error (relative RMS against the exact sum over every texel,
// at 2000 evenly spread normals, through bilinear cubemap lookups) versus time (median of 3 runs:
// wall time, and the process's CPU time over all threads, which does not depend on what else
// the machine runs).
// Usage: irradiance_sweep OUT.csv MAP.exr...   (irradiance_sweep.sh passes the eight samples)
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/relative_rms.h"
#include "core/timer.h"
#include "envmap/environment.h"
#include "irradiance/brute_force.h"
#include "irradiance/irradiance.h"

using namespace sss;

namespace {

struct Timing {
  double wallMs, cpuMs;
};

Timing medianMs(const std::function<Cubemap()>& make, Cubemap& out, int runs = 3) {
  std::vector<double> wall, cpu;
  for (int i = 0; i < runs; ++i) {
    const Stopwatch w;
    const std::clock_t c = std::clock();
    out = make();
    cpu.push_back(1e3 * static_cast<double>(std::clock() - c) / CLOCKS_PER_SEC);
    wall.push_back(w.milliseconds());
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  return {wall[wall.size() / 2], cpu[cpu.size() / 2]};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: irradiance_sweep OUT.csv MAP.exr...\n");
    return 2;
  }
  FILE* csv = std::fopen(argv[1], "w");
  if (!csv) {
    std::fprintf(stderr, "%s: cannot write\n", argv[1]);
    return 1;
  }
  std::fprintf(csv, "env,method,parameter,face_size,wall_ms,cpu_ms,error\n");
  const std::vector<glm::vec3> probes = fibonacciSphere(2000);
  const TransmittedCosineKernel kernel(1.0f);
  for (int i = 2; i < argc; ++i) {
    const std::string name = std::filesystem::path(argv[i]).stem().string();
    const ImageRgb image = readImage(argv[i]);
    const Cubemap radiance = cubemapFromImage(image, EnvironmentLayout::Equirect, 0);
    const std::vector<glm::vec3> exact = irradianceAtNormals(radiance, probes, 1.0f);
    auto record = [&](const char* method, double parameter, Timing t, const Cubemap& e) {
      std::vector<glm::vec3> looked(probes.size());
      for (std::size_t k = 0; k < probes.size(); ++k) looked[k] = e.sample(probes[k]);
      const double error = relativeRms(looked, exact);
      std::fprintf(csv, "%s,%s,%g,%d,%.3f,%.3f,%.6g\n", name.c_str(), method, parameter, e.size(),
                   t.wallMs, t.cpuMs, error);
      std::fflush(csv);
      std::printf("%-10s %-11s %-6g face %2d  wall %8.2f ms  cpu %8.2f ms  error %.3f%%\n",
                  name.c_str(), method, parameter, e.size(), t.wallMs, t.cpuMs, 100 * error);
    };
    Cubemap e;
    for (int order : {2, 4, 6, 8}) {
      const Timing ms = medianMs(
          [&] {
            return SphericalHarmonics::project(radiance, order).convolved(kernel).toCubemap(32);
          },
          e);
      record("sh", order, ms, e);
    }
    const Timing msEq = medianMs(
        [&] {
          return SphericalHarmonics::projectEquirect(image, 2).convolved(kernel).toCubemap(32);
        },
        e);
    record("sh-equirect", 2, msEq, e);
    for (double tolerance : {0.05, 0.02, 0.01, 0.005, 0.002, 0.001}) {
      BruteForceOptions o;
      o.faceSize = 32;
      o.tolerance = tolerance;
      record("brute", tolerance, medianMs([&] { return bruteForceIrradiance(radiance, o); }, e), e);
    }
    for (int size : {8, 16, 64}) {
      BruteForceOptions o;
      o.faceSize = size;
      record("brute", 0.01, medianMs([&] { return bruteForceIrradiance(radiance, o); }, e), e);
    }
    BruteForceOptions exactOptions;
    exactOptions.faceSize = 16;
    exactOptions.tolerance = 0.0;
    record("exact", 0, medianMs([&] { return bruteForceIrradiance(radiance, exactOptions); }, e, 1),
           e);
    IrradianceOptions autoOptions;
    const Timing msAuto =
        medianMs([&] { return computeIrradiance(radiance, autoOptions).irradiance; }, e);
    record("auto", 0.01, msAuto, e);
  }
  std::fclose(csv);
  return 0;
}

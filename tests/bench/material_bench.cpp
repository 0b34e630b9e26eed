// Speed of what the bake does once per run: build a profile and fit its Gaussians (goal: the
// fit under 50 ms). Run: material_bench --benchmark_repetitions=5 --benchmark_format=csv
#include <benchmark/benchmark.h>

#include "material/diffusion_profile.h"
#include "material/gaussian_sum_fit.h"
#include "material/profile_factory.h"

namespace {

const char* kMaterials[] = {"skimmilk", "marble", "skin1", "ketchup"};
const char* kProfiles[] = {"dipole", "beam", "burley"};

void BM_MakeProfile(benchmark::State& state) {
  const sss::Material m = sss::findMaterialPreset(kMaterials[state.range(0)]);
  const char* kind = kProfiles[state.range(1)];
  for (auto _ : state) benchmark::DoNotOptimize(sss::makeProfile(kind, m));
  state.SetLabel(std::string(kind) + "/" + m.name);
}

void BM_FitGaussians(benchmark::State& state) {
  const sss::Material m = sss::findMaterialPreset(kMaterials[state.range(0)]);
  const char* kind = kProfiles[state.range(1)];
  const double tolerance = state.range(2) / 1000.0;
  const auto profile = sss::makeProfile(kind, m);
  std::size_t k = 0;
  for (auto _ : state) {
    const sss::GaussianSumFit fit = sss::fitGaussians(*profile, tolerance);
    k = fit.sum.size();
    benchmark::DoNotOptimize(fit.error);
  }
  state.counters["K"] = static_cast<double>(k);
  state.SetLabel(std::string(kind) + "/" + m.name + "/tol=" + std::to_string(tolerance));
}

}  // namespace

BENCHMARK(BM_MakeProfile)->ArgsProduct({{0, 1, 2, 3}, {0, 1, 2}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitGaussians)
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1, 2}, {5, 10, 20}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();

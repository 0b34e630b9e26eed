// Load (strict PLY reader + cleanup + topology checks) and baked-PLY write/read times on the
// sample meshes. Run: mesh_bench --benchmark_repetitions=5 --benchmark_format=csv
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "mesh/baked_ply.h"
#include "mesh/load_mesh.h"

namespace {

const char* const kMeshes[] = {"dragon_res4", "dragon_res3", "dragon_res2", "dragon"};

std::string meshPath(int i) {
  return std::string(SSS_SOURCE_DIR) + "/data/cache/meshes/" + kMeshes[i] + ".ply";
}

void BM_LoadMesh(benchmark::State& state) {
  const std::string path = meshPath(static_cast<int>(state.range(0)));
  if (!std::filesystem::exists(path)) {
    state.SkipWithError("missing sample data: run data/fetch.sh");
    return;
  }
  std::size_t vertices = 0;
  for (auto _ : state) vertices = sss::loadMesh(path).vertexCount();
  state.SetLabel(kMeshes[state.range(0)]);
  state.counters["vertices"] = static_cast<double>(vertices);
}
BENCHMARK(BM_LoadMesh)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

void BM_BakedPlyWriteRead(benchmark::State& state) {
  const std::string path = meshPath(static_cast<int>(state.range(0)));
  if (!std::filesystem::exists(path)) {
    state.SkipWithError("missing sample data: run data/fetch.sh");
    return;
  }
  sss::BakedMesh baked;
  baked.mesh = sss::loadMesh(path);
  baked.irradiance.assign(baked.mesh.vertexCount(), glm::vec3(1.0f, 0.5f, 0.25f));
  baked.exitance.assign(baked.mesh.vertexCount(), glm::vec3(0.5f, 0.25f, 0.125f));
  baked.materialName = "marble";
  const std::string out =
      (std::filesystem::temp_directory_path() / "mesh_bench_baked.ply").string();
  for (auto _ : state) {
    sss::writeBakedPly(out, baked);
    benchmark::DoNotOptimize(sss::readBakedPly(out).baked.exitance.data());
  }
  std::filesystem::remove(out);
  state.SetLabel(kMeshes[state.range(0)]);
}
BENCHMARK(BM_BakedPlyWriteRead)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

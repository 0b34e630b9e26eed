// Diffusion sums (lib/diffusion/diffusion.h): methods x tolerances on the Stanford dragon at its
// four resolutions, scaled to 150 mm, marble, lit by a directional light with a hard edge in blue
// (no visibility: the bake benchmark covers the whole pipeline). Counters per case: vertices,
// Gaussians, interactions, and the relative RMS error of B against a reference: gauss at
// tolerance 0.001 (hierarchical at 0.001 for the full dragon). Not exact: on dragon_res4 the
// vertex spacing is ~6x marble's transport mean free path, where exact's point samples and disc
// quadrature are further from the converged answer than the Gaussians' disc blur (see
// diffusion_resolution.cpp); exact appears as one more point against the same reference.
// Wall time (UseRealTime) and process CPU time (both threads) are reported.
// Environment: SSS_BENCH_NO_REFERENCE=1 skips the references (for memory measurements).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <map>
#include <string>
#include <vector>

#include "core/relative_rms.h"
#include "diffusion/diffusion.h"
#include "material/dipole_profile.h"
#include "material/material.h"
#include "mesh/load_mesh.h"
#include "mesh/triangle_mesh.h"

namespace {

using namespace sss;

struct Scene {
  std::string name;
  TriangleMesh mesh;
  std::vector<float> areas;
  std::vector<glm::vec3> irradiance;
  std::vector<glm::vec3> reference;
  std::string referenceName;
  DiffusionInput input() const { return {mesh.positions, mesh.normals, areas, irradiance}; }
};

const DipoleProfile& marble() {
  static const DipoleProfile profile(findMaterialPreset("marble"));
  return profile;
}

Scene loadScene(const std::string& name) {
  const std::string path = std::string(SSS_SOURCE_DIR) + "/data/cache/meshes/" + name + ".ply";
  if (!std::filesystem::exists(path)) {
    std::fprintf(stderr, "%s missing: run data/fetch.sh\n", path.c_str());
    std::exit(1);
  }
  Scene s;
  s.name = name;
  s.mesh = loadMesh(path);
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : s.mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const glm::vec3 extent = hi - lo;
  scalePositions(s.mesh, 150.0 / std::max({extent.x, extent.y, extent.z}));
  s.areas = vertexAreas(s.mesh);
  const glm::vec3 light = glm::normalize(glm::vec3(1, 2, 0.5));
  for (const auto& n : s.mesh.normals) {
    const float c = std::max(0.0f, glm::dot(n, light));
    s.irradiance.emplace_back(c * c * c + 0.05f, 0.5f * c + 0.02f, c > 0.5f ? 1.0f : 0.0f);
  }
  return s;
}

Scene& scene(const std::string& name) {
  static std::map<std::string, Scene> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, loadScene(name)).first;
  return it->second;
}

DiffusionResult run(const Scene& s, DiffusionMethod method, double tolerance) {
  DiffusionOptions options;
  options.method = method, options.tolerance = tolerance, options.run.quiet = true;
  return diffuse(s.input(), marble(), options);
}

const std::vector<glm::vec3>& reference(Scene& s) {
  if (s.reference.empty()) {
    const std::size_t n = s.irradiance.size();
    const DiffusionMethod method =
        n <= 120000 ? DiffusionMethod::Gauss : DiffusionMethod::Hierarchical;
    s.reference = run(s, method, 0.001).exitance;
    s.referenceName = kDiffusionMethodNames.name(method);
  }
  return s.reference;
}

void benchDiffusion(benchmark::State& state, std::string mesh, DiffusionMethod method,
                    double tolerance) {
  Scene& s = scene(mesh);
  DiffusionResult result;
  for (auto _ : state) result = run(s, method, tolerance);
  state.counters["vertices"] = static_cast<double>(s.irradiance.size());
  state.counters["gaussians"] = result.report.gaussians;
  state.counters["interactions"] = static_cast<double>(result.report.interactions);
  state.counters["ran_hierarchical"] = result.report.method == DiffusionMethod::Hierarchical;
  state.counters["estimated_error"] = result.report.estimatedError;
  if (!std::getenv("SSS_BENCH_NO_REFERENCE")) {
    state.counters["error"] = relativeRms(result.exitance, reference(s));
    state.SetLabel("ran " + std::string(kDiffusionMethodNames.name(result.report.method)) +
                   "; reference " + s.referenceName);
  }
}

}  // namespace

int main(int argc, char** argv) {
  using sss::DiffusionMethod;
  struct Case {
    const char* mesh;
    DiffusionMethod method;
    std::vector<double> tolerances;
  };
  const std::vector<double> all = {0.03, 0.01, 0.003};
  const std::vector<Case> cases = {
      {"dragon_res4", DiffusionMethod::Exact, {0.01}},
      {"dragon_res4", DiffusionMethod::Gauss, all},
      {"dragon_res4", DiffusionMethod::Incremental, all},
      {"dragon_res4", DiffusionMethod::Hierarchical, all},
      {"dragon_res4", DiffusionMethod::Auto, all},
      {"dragon_res3", DiffusionMethod::Gauss, all},
      {"dragon_res3", DiffusionMethod::Incremental, all},
      {"dragon_res3", DiffusionMethod::Hierarchical, all},
      {"dragon_res3", DiffusionMethod::Auto, all},
      {"dragon_res2", DiffusionMethod::Gauss, {0.03, 0.01}},
      {"dragon_res2", DiffusionMethod::Incremental, {0.01}},
      {"dragon_res2", DiffusionMethod::Hierarchical, all},
      {"dragon_res2", DiffusionMethod::Auto, all},
      {"dragon", DiffusionMethod::Hierarchical, {0.03, 0.01}},
      {"dragon", DiffusionMethod::Auto, {0.01}},
  };
  for (const Case& c : cases)
    for (double tol : c.tolerances) {
      char name[128];
      std::snprintf(name, sizeof name, "%s/%s/%g", c.mesh,
                    sss::kDiffusionMethodNames.name(c.method), tol);
      benchmark::RegisterBenchmark(name, benchDiffusion, std::string(c.mesh), c.method, tol)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->MeasureProcessCPUTime()
          ->Iterations(1);
    }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

// What a volumetric path tracer needs for the bake's error (docs/performance.md, "Against a path
// tracer"): the forward light tracer (lib/pathtrace/light_tracer.h: the volumetric Monte Carlo
// the accuracy studies measure the bake against, the same model of the medium and its boundary)
// on the concavity study's bunny scenes (the sample bunny at 50 mm, marble and skim milk, under
// uniform radiance 1 and forest.exr), tallying the radiance along every vertex's normal.
//
//   pathtracer_cost OUT_DIR [--paths N] [--runs R]
//
// Per scene, R alternated runs (2 threads) of:
//  - the tracer with N paths: its wall time and the per-vertex relative noise of the radiance
//    along the normal (the paths' standard errors in the studies' norm, study_support.h's
//    relativeNoise). The noise falls as 1 / sqrt(paths), so the tracer's time to a relative error
//    e is t(e) = t_N (noise_N / e)^2 (unbiased: its error is its noise);
//  - the bake as the concavity study makes it (sss-bake's pipeline at its defaults, 1 %, bounces
//    auto, 256 visibility rays), whose error against a 32M-path reference that study measured:
//    its time (the report's total).
// Medians of the times. Writes OUT_DIR/tracer.csv; tests/bench/pathtracer_cost.sh puts it beside
// the bake's measured error from concavity.csv.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "bake/bake.h"
#include "envmap/environment.h"
#include "material/material.h"
#include "mesh/triangle_mesh.h"
#include "pathtrace/light_tracer.h"
#include "study_support.h"

namespace {

using namespace sss;

struct Scene {
  std::string name, material, light;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: pathtracer_cost OUT_DIR [--paths N] [--runs R]\n");
    return 2;
  }
  const std::string outDir = argv[1];
  uint64_t paths = 2'000'000;
  int runs = 3;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--paths") paths = std::stoull(argv[i + 1]);
    if (a == "--runs") runs = std::stoi(argv[i + 1]);
  }
  const std::string data = std::string(SSS_SOURCE_DIR) + "/data/cache";
  TriangleMesh bunny = study::loadScaled(data + "/meshes/bunny.ply", 50.0);
  bunny.normals = computeVertexNormals(bunny);
  const Cubemap uniform(16, glm::vec3(1.0f));
  const Cubemap forest = loadEnvironment(data + "/env/forest.exr", {});
  std::ofstream csv(outDir + "/tracer.csv");
  csv << "scene,paths,runs,tracer_s,tracer_noise,bake_s,bounces\n";
  const std::string meshPath = outDir + "/bunny_50mm.ply";
  for (const Scene& s : {Scene{"bunny-uniform-marble", "marble", "uniform"},
                         Scene{"bunny-forest-marble", "marble", "forest"},
                         Scene{"bunny-uniform-skimmilk", "skimmilk", "uniform"},
                         Scene{"bunny-forest-skimmilk", "skimmilk", "forest"}}) {
    const HomogeneousMedium medium = homogeneousMediumOf(findMaterialPreset(s.material));
    const Material material = findMaterialPreset(s.material);
    const BakeEnvironment env{s.light == "uniform" ? uniform : forest, {}};
    std::vector<double> seconds, bakeSeconds;
    double noise = 0.0;
    int bounces = 0;
    for (int run = 0; run < runs; ++run) {
      const BakeOutput bake =
          study::bakeAtDefaults(bunny, material, env, 256, meshPath, kAutoBounces);
      bakeSeconds.push_back(bake.report.totalSeconds);
      bounces = bake.report.interreflection.bounces;
      LightTraceOptions o;
      o.paths = paths;
      o.run = {.seed = study::kReferenceSeed + uint64_t(run), .threads = 2, .quiet = true};
      const LightTraceResult r =
          lightTraceSubsurface(bunny.positions, bunny.normals, bunny.triangles,
                               DistantLight::environment(env.radiance), medium, o);
      seconds.push_back(r.seconds);
      noise = study::relativeNoise(r.radiance, r.radianceStdErr);
    }
    char line[256];
    std::snprintf(line, sizeof line, "%s,%llu,%d,%.3f,%.5f,%.3f,%d\n", s.name.c_str(),
                  (unsigned long long)paths, runs, median(seconds), noise, median(bakeSeconds),
                  bounces);
    csv << line;
    std::printf("%s", line);
    std::fflush(stdout);
  }
  return 0;
}

// The relightable bake (sss-bake --relightable, sss-relight; docs/relighting.md) against fresh
// bakes. Per scene, one relightable bake under forest.exr (order kStudyOrder: the lower orders are
// the prefixes of its transfer), then for each light a fresh bake with sss-bake's defaults and
// the relit values at each SH order: relative RMS of the radiance along the normal over the
// vertices, and the 95th percentile of the per-vertex relative error. The lights: the 8 sample
// HDRs turned by 0, 45, ..., 315 degrees about the up axis (--env-rotate), and a sun of 1
// degree from the 8 diagonal directions (half of them from below, behind the object's base).
// The fresh bakes' own noise: a second bake of the first light with another seed (row
// "seed": sh_order -1, relative_rms and p95_relative between the two). Also the costs: the plain
// and the relightable bake's times, the files' bytes, and relighting on the CPU (SH projection of
// the environment and the dot products).
//   relight_study OUT_DIR DATA_DIR [--quick] [--skip-large] [--only SCENE] [--traced-off]
// writes OUT_DIR/relight.csv and relight_cost.csv. --quick: the marble bunny alone, 2 HDRs and 2
// suns; --skip-large: without dragon_res3; --traced-off: the far field and the unscattered light
// off in every bake.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "bake/bake.h"
#include "bake/relight.h"
#include "core/relative_rms.h"
#include "core/timer.h"
#include "material/material.h"
#include "mesh/baked_ply.h"
#include "mesh/primitives.h"
#include "study_support.h"

namespace sss {
namespace {

constexpr int kStudyOrder = 6;
const char* const kHdrs[] = {"forest", "city",   "courtyard", "interior",
                             "night",  "studio", "sunrise",   "sunset"};

struct Scene {
  std::string name;
  TriangleMesh meshMm;
  std::string material;
};

// --traced-off: every bake without the stages traced per environment (far field, unscattered
// light), which a relightable bake carries as its ratio g: what is left is the stored transfer's
// own error.
bool tracedOff = false;

BakeSettings settingsFor(const std::string& meshPath, const std::string& material) {
  BakeSettings s;
  s.meshPath = meshPath;
  s.material = findMaterialPreset(material);
  s.mmPerUnit = 1.0;
  s.run.quiet = true;
  if (tracedOff) {
    s.farField = FarFieldMode::Off;
    s.unscattered = UnscatteredMode::Off;
  }
  return s;
}

struct Light {
  std::string kind;  // hdr or sun
  std::string name;  // the HDR's, or sun_<signs of x, y, z>: sun_pmm towards (+1, -1, -1)
  int rotateDeg = 0;
  BakeEnvironment environment;
};

BakeEnvironment hdr(const std::string& dataDir, const std::string& name, double rotateDeg) {
  BakeSettings s;
  s.environment = dataDir + "/env/" + name + ".exr";
  s.orientation.rotateDeg = rotateDeg;
  s.run.quiet = true;
  return loadBakeEnvironment(s);
}

std::vector<Light> lights(const std::string& dataDir, bool quick) {
  std::vector<Light> out;
  const int hdrCount = quick ? 2 : 8;
  for (int h = 0; h < hdrCount; ++h)
    for (int turn = 0; turn < 8; ++turn) {
      const double rotate = 45.0 * turn;
      if (quick && turn != 0 && turn != 2) continue;  // 0 and 90 degrees
      out.push_back({"hdr", kHdrs[h], int(rotate), hdr(dataDir, kHdrs[h], rotate)});
    }
  const int suns = quick ? 2 : 8;
  for (int k = 0; k < suns; ++k) {
    const glm::vec3 d = glm::normalize(glm::vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1));
    const std::string name =
        std::string("sun_") + (d.x > 0 ? 'p' : 'm') + (d.y > 0 ? 'p' : 'm') + (d.z > 0 ? 'p' : 'm');
    out.push_back({"sun", name, 0, {study::sunEnvironment(d, 1.0, 256), {}}});
  }
  return out;
}

// The 95th percentile of |a - b| / |b| per vertex (vector norms over the channels).
double percentile95(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  std::vector<double> e(a.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    e[i] = glm::length(a[i] - b[i]) / std::max(1e-30f, glm::length(b[i]));
  const std::size_t k = e.size() * 95 / 100;
  std::nth_element(e.begin(), e.begin() + k, e.end());
  return e[k];
}

// The transfer cut to a lower order: the first (order + 1)^2 coefficients of each vertex.
RelightTransfer truncated(const RelightTransfer& t, int order) {
  RelightTransfer out = t;
  out.order = order;
  out.relightTransfer.clear();
  const std::size_t full = std::size_t(t.order + 1) * (t.order + 1);
  const std::size_t kept = std::size_t(order + 1) * (order + 1);
  for (std::size_t v = 0; v < t.radianceGain.size(); ++v)
    for (std::size_t k = 0; k < kept; ++k)
      out.relightTransfer.push_back(t.relightTransfer[v * full + k]);
  return out;
}

BakedMesh withTransfer(BakedMesh baked, const RelightTransfer& t) {
  baked.relightOrder = t.order;
  baked.relightTransfer = t.relightTransfer;
  return baked;
}

void runScene(const Scene& scene, const std::vector<Light>& lights, const std::string& work,
              std::ofstream& csv, std::ofstream& cost) {
  const std::string meshPath = work + "/" + scene.name + ".ply";
  study::writeAsciiPly(meshPath, scene.meshMm);
  BakeSettings plain = settingsFor(meshPath, scene.material);
  BakeSettings relightable = plain;
  relightable.relightOrder = kStudyOrder;
  const BakeEnvironment& forest = lights.front().environment;
  const Stopwatch plainClock;
  const BakeOutput base = bake(plain, forest);
  const double plainSeconds = plainClock.seconds();
  const Stopwatch relightClock;
  const BakeOutput bakeOut = bake(relightable, forest);
  const double relightableSeconds = relightClock.seconds();
  const RelightTransfer full = relightTransferOf(bakeOut.baked);
  std::vector<RelightTransfer> orders;
  for (int order = 1; order <= kStudyOrder; ++order) orders.push_back(truncated(full, order));
  const RelightTransfer& order3 = orders[kDefaultRelightOrder - 1];
  writeBakedPly(work + "/plain.ply", base.baked);
  writeBakedPly(work + "/relightable.ply", withTransfer(bakeOut.baked, order3));
  const Material material = findMaterialPreset(scene.material);
  const Stopwatch relitClock;
  relight(meshPath, {scene.meshMm, material, order3}, forest.radiance, {.quiet = true});
  const double relightSeconds = relitClock.seconds();
  cost << scene.name << ',' << scene.meshMm.vertexCount() << ',' << plainSeconds << ','
       << relightableSeconds << ',' << bakeOut.report.relight.seconds << ','
       << bakeOut.report.relight.selfError << ',' << std::filesystem::file_size(work + "/plain.ply")
       << ',' << std::filesystem::file_size(work + "/relightable.ply") << ',' << relightSeconds
       << std::endl;  // a run cut short keeps its scenes' lines
  BakeSettings reseeded = plain;
  reseeded.run.seed = 2;
  const BakeOutput second = bake(reseeded, forest);
  csv << scene.name << ",seed,forest,0,-1,0,0,"
      << relativeRms(second.baked.radianceNormal, base.baked.radianceNormal) << ','
      << percentile95(second.baked.radianceNormal, base.baked.radianceNormal) << ','
      << base.report.errors.total << '\n';
  for (const Light& light : lights) {
    const BakeOutput fresh = bake(plain, light.environment);
    for (const RelightTransfer& t : orders) {
      if (t.order == 1 || t.order == 5) continue;
      const RelitLight l =
          relight(meshPath, {scene.meshMm, material, t}, light.environment.radiance, {});
      csv << scene.name << ',' << light.kind << ',' << light.name << ',' << light.rotateDeg << ','
          << t.order << ',' << l.compactLights << ',' << l.compactFluxShare << ','
          << relativeRms(l.radianceNormal, fresh.baked.radianceNormal) << ','
          << percentile95(l.radianceNormal, fresh.baked.radianceNormal) << ','
          << fresh.report.errors.total << '\n';
    }
    csv.flush();
    std::fprintf(stderr, "%s %s %d\n", scene.name.c_str(), light.name.c_str(), light.rotateDeg);
  }
}

}  // namespace
}  // namespace sss

int main(int argc, char** argv) {
  using namespace sss;
  if (argc < 3) {
    std::fprintf(stderr, "usage: relight_study OUT_DIR DATA_DIR [--quick]\n");
    return 2;
  }
  const std::string out = argv[1], data = argv[2];
  bool quick = false, skipLarge = false;
  std::string only;  // --only SCENE: that scene alone
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick")
      quick = true;
    else if (a == "--skip-large")
      skipLarge = true;
    else if (a == "--only" && i + 1 < argc)
      only = argv[++i];
    else if (a == "--traced-off")
      tracedOff = true;
    else {
      std::fprintf(stderr, "relight_study: unknown option %s\n", argv[i]);
      return 2;
    }
  }
  const std::string work =
      (std::filesystem::temp_directory_path() / ("sss-relight-study-" + std::to_string(::getpid())))
          .string();
  std::filesystem::create_directories(work);
  std::filesystem::create_directories(out);
  std::vector<Scene> scenes = {
      {"bunny-marble", study::loadScaled(data + "/meshes/bunny.ply", 50.0), "marble"}};
  if (!quick) {
    scenes.push_back({"bunny-skimmilk", scenes[0].meshMm, "skimmilk"});
    scenes.push_back({"sphere-skin1-180mm", makeIcosphere(4, 90.0f), "skin1"});
    if (!skipLarge)
      scenes.push_back({"dragon_res3-marble",
                        study::loadScaled(data + "/meshes/dragon_res3.ply", 150.0), "marble"});
  }
  if (!only.empty()) std::erase_if(scenes, [&](const Scene& scene) { return scene.name != only; });
  const std::vector<Light> all = lights(data, quick);
  std::ofstream csv(out + "/relight.csv"), cost(out + "/relight_cost.csv");
  csv << "scene,kind,light,rotate_deg,sh_order,compact_lights,compact_flux_share,relative_rms,"
         "p95_relative,fresh_predicted_error\n";
  cost << "scene,vertices,plain_bake_s,relightable_bake_s,relight_stage_s,self_relative_rms,"
          "plain_ply_bytes,relightable_ply_bytes,relight_cpu_s\n";
  for (const Scene& scene : scenes) runScene(scene, all, work, csv, cost);
  std::filesystem::remove_all(work);
  return 0;
}

// The material-interface study (docs/accuracy.md, "Several materials"): a sphere whose upper half
// is one material and lower half another, under uniform light, baked with sss-bake's defaults
// (--material-map, bake/material_parts.h) against a Monte Carlo of the two media itself.
//
//   material_interface_study OUT_DIR [--walks N]
//
// The reference (tests/support/two_media_sphere.h) walks light through both media itself and
// tallies the radiance along the normal directly, one point per ring of the UV sphere; the bake
// is the mean over that ring's vertices. The one-material spheres' references give the models'
// own error, which the mix inherits.
//
// OUT_DIR/material_interface.csv: per scene, per ring: theta, the reference's radiance along the
// normal and its standard error per channel, the bake's (mixed), and the two one-material bakes'
// (the object all of the upper or all of the lower material), with sss-bake's defaults, and the
// mixed bake with the receiver's rule and with the symmetric kernel alone.
// OUT_DIR/material_interface_summary.csv, per scene, relative RMS over the sphere's area (the
// reference's noise removed): bake_rms, the mixed bake (the border rule) against the reference;
// receiver_rule_rms and symmetric_rms, the same with the receiver's rule and the symmetric kernel
// alone (MaterialRule); the *_worst columns, the largest relative error of a ring and channel;
// homogeneous_model_rms, the one-material bakes against the one-material objects' references
// (the models' own error, which the mix inherits); interface_measured, the mixed bake's error
// beyond that (against the same difference of references): what the border adds;
// interface_predicted and predicted_total, the bake's JSON (estimated_error.model.
// material_interface, estimated_error.total).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "bake/bake.h"
#include "bake/bake_report.h"
#include "bake/bake_settings.h"
#include "bake/material_map.h"
#include "core/parallel.h"
#include "core/random.h"
#include "core/sampling.h"
#include "core/timer.h"
#include "material/material.h"
#include "optics/fresnel.h"
#include "study_support.h"
#include "support/two_media_sphere.h"

namespace sss {
namespace {

using test::ringMeans;
using test::RingReference;
using test::writeHalvesGlb;
constexpr int kRings = test::kHalvesRings;

struct Scene {
  std::string name;
  std::string upper, lower;  // material presets
  double radiusMm;
};

const Scene kScenes[] = {{"skin1_ketchup_r10", "skin1", "ketchup", 10.0},
                         {"marble_skin1_r5", "marble", "skin1", 5.0},
                         {"skimmilk_ketchup_r10", "skimmilk", "ketchup", 10.0}};

BakeOutput bakeSphere(const std::string& glb, const std::string& fallback, const std::string& map,
                      MaterialRule rule = MaterialRule::Border) {
  BakeSettings s;
  s.materialRule = rule;
  s.meshPath = glb;
  s.material = findMaterialPreset(fallback);
  if (!map.empty()) s.materialMap = parseMaterialMap(map);
  s.run.quiet = true;
  const BakeEnvironment white{Cubemap(16, glm::vec3(1.0f)), {}};
  return bake(s, white);
}

// The largest |a / ref - 1| over the rings and channels: a dim channel's error, which the
// relative RMS weights by its brightness.
double worstRing(const std::vector<glm::dvec3>& a, const std::vector<RingReference>& ref) {
  double worst = 0.0;
  for (std::size_t r = 0; r < ref.size(); ++r)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(a[r][c] / ref[r].radiance[c] - 1.0));
  return worst;
}

// Per ring: the upper half's value from `upper`, the lower's from `lower`, the equator's mean.
template <typename T>
std::vector<T> byHalf(const std::vector<T>& upper, const std::vector<T>& lower) {
  std::vector<T> out = upper;
  for (int r = kRings / 2 + 1; r <= kRings; ++r) out[r] = lower[r];
  return out;
}

}  // namespace
}  // namespace sss

int main(int argc, char** argv) {
  using namespace sss;
  const study::StudyArguments args = study::parseStudyArguments(argc, argv, 200000);
  if (args.outDir.empty()) {
    std::fprintf(stderr, "usage: material_interface_study OUT_DIR [--walks N]\n");
    return 2;
  }
  const std::string& outDir = args.outDir;
  const int walks = int(args.paths);
  std::filesystem::create_directories(outDir);
  std::ofstream rows(outDir + "/material_interface.csv");
  rows
      << "scene,ring,theta_deg,ref_r,ref_g,ref_b,ref_se_r,ref_se_g,ref_se_b,bake_r,bake_g,bake_b,"
         "upper_only_r,upper_only_g,upper_only_b,lower_only_r,lower_only_g,lower_only_b,receiver_r,"
         "receiver_g,receiver_b,symmetric_r,symmetric_g,symmetric_b\n";
  std::ofstream summary(outDir + "/material_interface_summary.csv");
  summary
      << "scene,upper,lower,radius_mm,walks,bake_rms,receiver_rule_rms,symmetric_rms,bake_worst,"
         "receiver_rule_worst,symmetric_worst,homogeneous_model_rms,"
         "interface_measured,interface_predicted,predicted_total,bake_s,reference_s\n";
  const std::string glb = outDir + "/halves.glb";
  for (const Scene& scene : kScenes) {
    writeHalvesGlb(glb, scene.radiusMm);
    const Material upper = findMaterialPreset(scene.upper), lower = findMaterialPreset(scene.lower);
    const BakeOutput mixed = bakeSphere(glb, scene.lower, "Upper=" + scene.upper);
    const std::vector<glm::dvec3> bake = ringMeans(mixed.baked);
    const std::string map = "Upper=" + scene.upper;
    const std::vector<glm::dvec3> receiver =
        ringMeans(bakeSphere(glb, scene.lower, map, MaterialRule::Receiver).baked);
    const std::vector<glm::dvec3> symmetric =
        ringMeans(bakeSphere(glb, scene.lower, map, MaterialRule::Symmetric).baked);
    const std::vector<glm::dvec3> upperOnly = ringMeans(bakeSphere(glb, scene.upper, "").baked);
    const std::vector<glm::dvec3> lowerOnly = ringMeans(bakeSphere(glb, scene.lower, "").baked);
    Stopwatch refClock;
    const std::vector<RingReference> ref =
        test::halvesReference(scene.radiusMm, upper, lower, walks);
    const double refSeconds = refClock.seconds();
    // The one-material objects' references: the bakes' own model error, which the mix inherits.
    const std::vector<RingReference> homogeneous =
        byHalf(test::halvesReference(scene.radiusMm, upper, upper, walks),
               test::halvesReference(scene.radiusMm, lower, lower, walks));
    std::vector<glm::dvec3> oneMaterial = byHalf(upperOnly, lowerOnly);
    oneMaterial[kRings / 2] = bake[kRings / 2];  // the border's blend, as the mixed bake has it
    for (int r = 0; r <= kRings; ++r) {
      char line[600];
      const RingReference& f = ref[r];
      std::snprintf(line, sizeof line,
                    "%s,%d,%.2f,%.6g,%.6g,%.6g,%.3g,%.3g,%.3g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,"
                    "%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n",
                    scene.name.c_str(), r, 180.0 * r / kRings, f.radiance.x, f.radiance.y,
                    f.radiance.z, f.stdError.x, f.stdError.y, f.stdError.z, bake[r].x, bake[r].y,
                    bake[r].z, upperOnly[r].x, upperOnly[r].y, upperOnly[r].z, lowerOnly[r].x,
                    lowerOnly[r].y, lowerOnly[r].z, receiver[r].x, receiver[r].y, receiver[r].z,
                    symmetric[r].x, symmetric[r].y, symmetric[r].z);
      rows << line;
    }
    const BakeErrorReport& e = mixed.report.errors;
    char line[400];
    std::snprintf(line, sizeof line,
                  "%s,%s,%s,%g,%d,%.4f,%.4f,%.4f,%.3f,%.3f,%.3f,%.4f,%.4f,%.4f,%.4f,%.2f,%.1f\n",
                  scene.name.c_str(), scene.upper.c_str(), scene.lower.c_str(), scene.radiusMm,
                  walks, test::ringRms(bake, ref), test::ringRms(receiver, ref),
                  test::ringRms(symmetric, ref), worstRing(bake, ref), worstRing(receiver, ref),
                  worstRing(symmetric, ref), test::ringRms(oneMaterial, homogeneous),
                  test::ringRms(bake, ref, oneMaterial, homogeneous), e.model.materialInterface,
                  e.total, mixed.report.totalSeconds, refSeconds);
    summary << line;
    std::printf("%s", line);
    std::fflush(stdout);
  }
  std::filesystem::remove(glb);
  return 0;
}

// The exit-model study (docs/accuracy.md, "The exit model at low albedo"): one-material spheres
// of radius 5, 10 and 20 mm under uniform light, baked with sss-bake's defaults, against a Monte
// Carlo that tallies the radiance leaving along the normal directly.
//
//   exit_model_study OUT_DIR [--walks N]
//
// The reference (tests/support/two_media_sphere.h, both halves one material) starts backward
// walks at a surface point along the inward normal, so that each escape is radiance leaving
// exactly along the normal (the light crossing unscattered included); it knows nothing of B or of
// an exit model. Under uniform light every point of the sphere is alike: one point, N walks per
// channel, split over streams so that it runs in parallel.
//
// OUT_DIR/exit_model.csv, per scene: the reference per channel and its standard error; ratio_*,
// the bake's radiance along the normal (area-weighted mean over the vertices) over the
// reference's; worst_bias, the largest |ratio - 1| of the three channels; rms_vertex, the relative
// RMS over vertices and channels (the reference's noise removed); exit_slope_*, the mean slope of
// the exit lobe the bake used (0: the normalized model); predicted_exit_model and
// predicted_total, the bake's JSON (estimated_error.model.exit_model, estimated_error.total);
// bake_s, the bake's time in process (2 threads on the study machine); normalized_ratio_* and
// normalized_rms_vertex, the same bake's B through the normalized exit model (the default before
// the half-space's lobe); far_ratio_*, far_rms_vertex and far_bake_s, the bake with its far field
// traced (--far-field on), whose exits measure the lobe.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "bake/bake.h"
#include "bake/bake_report.h"
#include "bake/bake_settings.h"
#include "core/parallel.h"
#include "core/random.h"
#include "core/timer.h"
#include "material/material.h"
#include "optics/exit_lobe.h"
#include "optics/fresnel.h"
#include "study_support.h"
#include "support/two_media_sphere.h"

namespace sss {
namespace {

struct Scene {
  std::string material;
  double radiusMm;
};

constexpr int kStreams = 64;

// The radiance along the normal at one point of the sphere (uniform light of radiance 1), per
// channel, with its standard error.
test::RingReference pointReference(double radiusMm, const Material& m, int walks) {
  const glm::dvec3 n(1.0, 0.0, 0.0);
  const double entry = fresnelTransmittance(1.0f, float(test::kHalvesEta));
  std::vector<glm::dvec3> escaped(kStreams, glm::dvec3(0.0));
  const int perStream = (walks + kStreams - 1) / kStreams;
  parallelFor(kStreams, defaultThreadCount(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t s = begin; s < end; ++s)
      for (int c = 0; c < 3; ++c) {
        const test::TwoMedia media = test::twoMedia(m, m, c);
        Pcg32 rng(7, s * 3 + std::uint64_t(c));
        for (int w = 0; w < perStream; ++w)
          escaped[s][c] += test::walk(n * (radiusMm * (1.0 - 1e-12)), -n, radiusMm, media, rng);
      }
  });
  glm::dvec3 sum(0.0);
  for (const glm::dvec3& e : escaped) sum += e;
  const double total = double(perStream) * kStreams;
  test::RingReference out;
  for (int c = 0; c < 3; ++c) {
    const double p = sum[c] / total;
    out.radiance[c] = entry * p;
    out.stdError[c] = entry * std::sqrt(p * (1.0 - p) / total);
  }
  return out;
}

struct Comparison {
  glm::dvec3 ratio{0.0}, meanSlope{0.0};
  double rmsVertex = 0.0;
};

// The bake's radiance along the normal with B through the normalized exit model instead of the
// bake's lobe (the unscattered light as the bake has it).
std::vector<glm::vec3> normalizedRadiance(const BakedMesh& baked) {
  std::vector<glm::vec3> out = baked.radianceNormal;
  if (baked.exitSlope.empty()) return out;
  const ExitLobe lobe(float(baked.eta));
  const glm::dvec3 normalized(normalExitRadianceScale(float(baked.eta)));
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] += glm::vec3(glm::dvec3(baked.exitance[i]) *
                        (normalized - lobe.normalRadiance(baked.exitSlope[i])));
  return out;
}

// A radiance along the normal per vertex against the one reference value of every vertex.
Comparison compare(const BakedMesh& baked, std::span<const glm::vec3> radiance,
                   const test::RingReference& ref) {
  const std::vector<float> areas = vertexAreas(baked.mesh);
  glm::dvec3 mean(0.0), slope(0.0);
  double area = 0.0, err = 0.0, norm = 0.0, noise = 0.0;
  for (std::size_t i = 0; i < areas.size(); ++i) {
    const glm::dvec3 l(radiance[i]);
    mean += double(areas[i]) * l;
    if (!baked.exitSlope.empty()) slope += double(areas[i]) * glm::dvec3(baked.exitSlope[i]);
    area += areas[i];
    for (int c = 0; c < 3; ++c) {
      err += areas[i] * std::pow(l[c] - ref.radiance[c], 2);
      noise += areas[i] * std::pow(ref.stdError[c], 2);
      norm += areas[i] * std::pow(ref.radiance[c], 2);
    }
  }
  Comparison out;
  out.ratio = mean / area / ref.radiance;
  out.meanSlope = slope / area;
  out.rmsVertex = std::sqrt(std::max(0.0, err - noise) / norm);
  return out;
}

}  // namespace
}  // namespace sss

int main(int argc, char** argv) {
  using namespace sss;
  const study::StudyArguments args = study::parseStudyArguments(argc, argv, 400000);
  if (args.outDir.empty()) {
    std::fprintf(stderr, "usage: exit_model_study OUT_DIR [--walks N]\n");
    return 2;
  }
  const std::string& outDir = args.outDir;
  const int walks = int(args.paths);
  std::filesystem::create_directories(outDir);
  std::ofstream rows(outDir + "/exit_model.csv");
  rows << "scene,material,radius_mm,walks,ref_r,ref_g,ref_b,ref_se_r,ref_se_g,ref_se_b,ratio_r,"
          "ratio_g,ratio_b,worst_bias,rms_vertex,exit_slope_r,exit_slope_g,exit_slope_b,"
          "predicted_exit_model,predicted_total,bake_s,reference_s,normalized_ratio_r,"
          "normalized_ratio_g,normalized_ratio_b,normalized_rms_vertex,far_ratio_r,far_ratio_g,"
          "far_ratio_b,far_rms_vertex,far_bake_s\n";
  const std::string glb = outDir + "/sphere.glb";
  const std::vector<Scene> scenes = {
      {"skin1", 5}, {"skin1", 10}, {"skin1", 20}, {"ketchup", 5}, {"ketchup", 10},  {"ketchup", 20},
      {"skin2", 5}, {"skin2", 10}, {"apple", 10}, {"marble", 10}, {"skimmilk", 10}, {"cream", 10}};
  for (const Scene& scene : scenes) {
    test::writeHalvesGlb(glb, scene.radiusMm);
    BakeSettings s;
    s.meshPath = glb;
    s.material = findMaterialPreset(scene.material);
    s.run.quiet = true;
    const BakeEnvironment white{Cubemap(16, glm::vec3(1.0f)), {}};
    const BakeOutput out = bake(s, white);
    s.farField = FarFieldMode::On;
    const BakeOutput traced = bake(s, white);
    const Stopwatch refClock;
    const test::RingReference ref = pointReference(scene.radiusMm, s.material, walks);
    const double refSeconds = refClock.seconds();
    const Comparison cmp = compare(out.baked, out.baked.radianceNormal, ref);
    const Comparison normalized = compare(out.baked, normalizedRadiance(out.baked), ref);
    const Comparison far = compare(traced.baked, traced.baked.radianceNormal, ref);
    const double worst = std::max(
        {std::abs(cmp.ratio.x - 1.0), std::abs(cmp.ratio.y - 1.0), std::abs(cmp.ratio.z - 1.0)});
    const BakeErrorReport& e = out.report.errors;
    char line[900];
    std::snprintf(line, sizeof line,
                  "sphere-%s-r%g,%s,%g,%d,%.5g,%.5g,%.5g,%.2g,%.2g,%.2g,%.4f,%.4f,%.4f,%.4f,%.4f,"
                  "%.3f,%.3f,%.3f,%.4f,%.4f,%.2f,%.1f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,"
                  "%.2f\n",
                  scene.material.c_str(), scene.radiusMm, scene.material.c_str(), scene.radiusMm,
                  walks, ref.radiance.x, ref.radiance.y, ref.radiance.z, ref.stdError.x,
                  ref.stdError.y, ref.stdError.z, cmp.ratio.x, cmp.ratio.y, cmp.ratio.z, worst,
                  cmp.rmsVertex, cmp.meanSlope.x, cmp.meanSlope.y, cmp.meanSlope.z,
                  e.model.exitModel, e.total, out.report.totalSeconds, refSeconds,
                  normalized.ratio.x, normalized.ratio.y, normalized.ratio.z, normalized.rmsVertex,
                  far.ratio.x, far.ratio.y, far.ratio.z, far.rmsVertex, traced.report.totalSeconds);
    rows << line;
    std::printf("%s", line);
    std::fflush(stdout);
  }
  std::filesystem::remove(glb);
  return 0;
}

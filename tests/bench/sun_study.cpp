// The sun study (docs/accuracy.md, "Under a sun: the sun study"), against the forward light
// tracer (lib/pathtrace/light_tracer.h), environments unblurred: a sphere of radius 10 mm
// (accuracy_study's `sphere`) and of radius 5 mm per material under a sun of 1 degree angular
// radius, and a 40 x 40 x 2 mm slab lit from behind at 30 degrees. Measures the bake stage by stage
// as tests/bench/accuracy_study.cpp does (visibility rays, the energy plan, the auto profile and
// diffusion method at 1 %) in several configurations (the `energy` column: energy/entry/exit):
// sss-bake's defaults (the escape energy model that `auto` picks, the directional entry, the
// far field and the unscattered light, both auto, the normalized exit model for B less the far
// field and the far field's own exit lobe for B_far: "lobe", optics/exit_lobe.h), the normalized
// exit for all of B (no lobe), the calibrated exit model (sss-render --exit-model calibrated;
// material/directional_albedo_weight.h), the hybrid (calibrated for B less the far field), the
// diffuse entry, and the half-space energy with the diffuse entry.
//
//   sun_study OUT_DIR [--paths N] [--only NAME] [--cache DIR]
//
// --cache DIR keeps each scene's two reference runs in DIR (raw floats, named by scene and path
// count) and reuses them: the bake can then be re-measured in seconds.
//
// Writes OUT_DIR/sun.csv (one row per scene and configuration) and OUT_DIR/sun_bands.csv (per
// band). Metrics, on the radiance along the normal (the bake's through its exit model), all three
// channels:
//  - bands: 8 equal-area bands of the polar angle from the sun direction (cos theta in steps of
//    0.25); each band's mean is area-weighted over its vertices;
//    band_rms = sqrt(sum_bands,c (bake - ref)^2 / sum ref^2), the reference's noise removed
//    (band_rms_raw keeps it);
//  - unlit: sum over the vertices facing away from the sun (n . s < 0) of bake / reference (area
//    weighted); for the slab, the central part (|x|, |y| < 10 mm) of the face away from the sun.
// The same metrics on the exitance B (no exit model) in the _B columns; ref_unscattered_B is the
// share of the reference's B on the unlit part that crossed without scattering, and the
// _scattered columns compare with the reference that leaves that light out (minScatteringOrder 1).
// OUT_DIR/sun_predicted.csv: sss-bake's own pipeline (lib/bake/bake.h, defaults at 1 %, 256
// rays) per scene, its JSON's predicted error (estimated_error.total; its numerical and model
// parts in the last columns) beside the relative RMS of
// its radiance along the normal over every vertex (the reference's noise removed; per vertex,
// where the band metrics above average the bake's noise away), and seed_noise, the bake's own
// noise measured as the spread between its bakes with seeds 1 and 2 (what `numerical` predicts).
// The per-vertex error is measured less the reference's own noise, which is fragile where the
// error is below that noise: the committed rows use 32M paths (--paths 32000000; at 8M, 2-6 % of
// noise per vertex, the measured errors of the 10 mm spheres move by up to 4x: docs/accuracy.md,
// "The bake's predicted error"). At the default 500K the noise is ~14 % per vertex.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "bake/bake.h"
#include "bake/bake_settings.h"
#include "bake/error_budget.h"
#include "core/error.h"
#include "core/relative_rms.h"
#include "core/timer.h"
#include "diffusion/diffusion.h"
#include "lighting/visibility.h"
#include "material/diffusion_profile.h"
#include "material/directional_albedo_weight.h"
#include "material/material.h"
#include "material/profile_factory.h"
#include "mesh/primitives.h"
#include "optics/exit_lobe.h"
#include "optics/fresnel.h"
#include "pathtrace/light_tracer.h"
#include "study_support.h"
#include "transport/far_field.h"
#include "transport/finite_object_energy.h"
#include "transport/unscattered_light.h"

namespace {

using namespace sss;
using namespace sss::study;

constexpr int kBands = 8;
constexpr double kTolerance = 0.01;  // the bake's default
constexpr int kVisibilityRays = 256;

struct Scene {
  std::string name;
  TriangleMesh mesh;
  Material material;
  glm::vec3 sun;  // towards the sun, unit
  bool slab;
};

// Which vertices a metric sums over, with their weights (areas); band b of vertex v, or -1.
struct Selection {
  std::vector<int> band;
  std::vector<char> unlit;
};

Selection selectVertices(const Scene& s, const std::vector<float>& areas) {
  Selection sel;
  const std::size_t n = s.mesh.positions.size();
  sel.band.assign(n, -1);
  sel.unlit.assign(n, 0);
  for (std::size_t v = 0; v < n; ++v) {
    const glm::vec3 p = s.mesh.positions[v], nrm = s.mesh.normals[v];
    if (s.slab) {  // the central part of the face away from the sun
      sel.unlit[v] = glm::dot(nrm, s.sun) < -0.5f && std::abs(p.x) < 10.0f &&
                     std::abs(p.y) < 10.0f && areas[v] > 0.0f;
      continue;
    }
    const double c = glm::dot(glm::normalize(p), s.sun);  // sphere about the origin
    sel.band[v] = std::min(kBands - 1, int((c + 1.0) / 2.0 * kBands));
    sel.unlit[v] = c < 0.0;
  }
  return sel;
}

struct Metrics {
  double bandRms = 0.0, bandRmsRaw = 0.0, unlitRatio = 0.0;
  std::vector<glm::dvec3> bandBake, bandRef;
};

Metrics compare(const std::vector<glm::vec3>& bake, const std::vector<glm::vec3>& ref,
                const std::vector<glm::vec3>& refSe, const std::vector<float>& areas,
                const Selection& sel) {
  Metrics m;
  m.bandBake.assign(kBands, glm::dvec3(0.0));
  m.bandRef.assign(kBands, glm::dvec3(0.0));
  std::vector<glm::dvec3> bandVar(kBands, glm::dvec3(0.0));
  std::vector<double> bandArea(kBands, 0.0);
  glm::dvec3 unlitBake(0.0), unlitRef(0.0);
  for (std::size_t v = 0; v < areas.size(); ++v) {
    const double a = areas[v];
    if (sel.unlit[v]) {
      unlitBake += a * glm::dvec3(bake[v]);
      unlitRef += a * glm::dvec3(ref[v]);
    }
    const int b = sel.band[v];
    if (b < 0) continue;
    m.bandBake[b] += a * glm::dvec3(bake[v]);
    m.bandRef[b] += a * glm::dvec3(ref[v]);
    bandVar[b] += a * a * glm::dvec3(refSe[v]) * glm::dvec3(refSe[v]);
    bandArea[b] += a;
  }
  RelativeRmsSums bands;  // pooled over bands, every band alike
  for (int b = 0; b < kBands; ++b) {
    if (!(bandArea[b] > 0.0)) continue;
    m.bandBake[b] /= bandArea[b];
    m.bandRef[b] /= bandArea[b];
    bands.add(m.bandBake[b] - m.bandRef[b], m.bandRef[b]);
    const glm::dvec3 variance = bandVar[b] / (bandArea[b] * bandArea[b]);
    bands.noise += variance.r + variance.g + variance.b;
  }
  if (bands.reference > 0.0) {
    m.bandRmsRaw = bands.ratio();
    m.bandRms = bands.noiseRemoved();
  }
  const double ub = unlitBake.x + unlitBake.y + unlitBake.z;
  const double ur = unlitRef.x + unlitRef.y + unlitRef.z;
  m.unlitRatio = ur > 0.0 ? ub / ur : 0.0;
  return m;
}

// The bake with the given energy and entry models: B per vertex and the seconds it took.
DiffusionResult bakeExitance(const Scene& s, const Cubemap& env, const std::vector<float>& areas,
                             EnergyModel model, EntryModel entryModel, FarFieldMode farMode,
                             std::string& chosen, double& seconds,
                             std::vector<glm::vec3>* farSlope = nullptr, bool lobeOfAllExits = true,
                             bool calibrateNearShare = true) {
  const Stopwatch clock;
  const DirectionalAlbedoWeight entry(s.material);
  VisibilityOptions vis;
  vis.samples = kVisibilityRays;
  if (entryModel == EntryModel::Directional) vis.entry = &entry;
  VisibilityReport visReport;
  const float eta = float(s.material.eta);
  std::vector<glm::vec3> e = transmittedIrradianceWithVisibility(
      s.mesh.positions, s.mesh.normals, s.mesh.triangles, env, eta, vis, &visReport);
  if (entryModel == EntryModel::Directional) e = std::move(visReport.entryWeighted);
  const ErrorBudget budget(kTolerance);
  EnergyOptions energyOptions;
  energyOptions.model = model;
  energyOptions.noiseBudget = budget.walkBudget();
  if (farMode != FarFieldMode::Off) energyOptions.nearWindowMm = farFieldWindowMm(s.material);
  EnergyPlan plan = planFiniteObjectEnergy(s.mesh, areas, s.material, energyOptions);
  // The far field as sss-bake runs it (bake.cpp, farFieldStage).
  FarFieldOptions farOptions;
  farOptions.mode = farMode;
  farOptions.lobeOfAllExits = lobeOfAllExits;
  farOptions.calibrateNearShare = calibrateNearShare;
  farOptions.noiseBudget = budget.walkBudget() / std::sqrt(2.0);
  const FarField far = traceFarField({s.mesh, areas, env, s.material, plan, e, farOptions});
  if (farSlope) *farSlope = far.slope;
  if (far.traced()) {
    energyOptions.noiseBudget = farOptions.noiseBudget;
    refineNearShare(plan, s.mesh, areas, s.material, energyOptions);
  }
  const std::string profileName = autoProfileName(plan.model);
  const auto profile = makeProfile(profileName, s.material);
  DiffusionOptions dopt;
  dopt.run.quiet = true;
  const double energyError =
      plan.model != EnergyModel::Escape ? 0.0
      : far.traced() ? std::hypot(plan.escape.nearErrorInB(), far.report.relativeStdError)
                     : plan.escape.relativeStdError;
  dopt.tolerance =
      budget.diffusionTolerance(plan.model == EnergyModel::Escape, energyError, std::nullopt);
  const DiffusionInput input{s.mesh.positions, s.mesh.normals, areas, e};
  DiffusionResult r = diffuseWithEnergy(input, *profile, dopt, plan, s.material, far.exitance);
  calibrateNearPart(r.exitance, {s.mesh, areas, far.exitance, far.nearExitance, far.nearVariance,
                                 far.nearFarCovariance, far.report.smoothingMm, 0});
  chosen = std::string(kEnergyModelNames.name(plan.model)) + "/" +
           (far.traced() ? "far-" + std::to_string(far.report.paths) + "/" : std::string()) +
           kEntryModelNames.name(entryModel) + "/" + profileName + "/" +
           kDiffusionMethodNames.name(r.report.method);
  seconds = clock.seconds();
  return r;
}

// The unscattered light as sss-bake adds it to the radiance along the normal (unscattered_light.h,
// auto, the budget of a 1 % bake).
void addUnscatteredLight(const Scene& s, const Cubemap& env, const std::vector<float>& areas,
                         std::vector<glm::vec3>& radiance, std::string& chosen, double& seconds) {
  UnscatteredLightOptions o;
  o.noiseBudget = ErrorBudget(kTolerance).unscatteredBudget();
  const UnscatteredLight u = traceUnscatteredLight({s.mesh, areas, env, s.material, radiance, o});
  for (std::size_t v = 0; v < u.radiance.size(); ++v) radiance[v] += u.radiance[v];
  if (u.traced()) chosen += "/unscattered-" + std::to_string(u.report.paths);
  seconds += u.report.seconds;
}

// sss-bake's pipeline on the scene: its predicted error against the measured one, per vertex.
void predictedAgainstMeasured(const Scene& s, const Cubemap& env, const LightTraceResult& ref,
                              const std::string& outDir, std::ofstream& csv) {
  // bakeAtDefaults bakes at the default tolerance, kTolerance.
  const BakeOutput out = bakeAtDefaults(s.mesh, s.material, BakeEnvironment{env, {}},
                                        kVisibilityRays, outDir + "/" + s.name + ".ply");
  const double measured =
      relativeRmsAgainst(out.baked.radianceNormal, ref.radiance, ref.radianceStdErr);
  const double predicted = out.report.errors.total;
  const BakeErrorReport& e = out.report.errors;
  // The bake's own noise, measured: the spread between two seeds, sqrt(sum (a1 - a2)^2 / 2) in
  // the same norm as the measured error (what `numerical` estimates).
  const BakeOutput other = bakeAtDefaults(s.mesh, s.material, BakeEnvironment{env, {}},
                                          kVisibilityRays, outDir + "/" + s.name + ".ply", 0, 2);
  const double seedNoise =
      seedSpread(out.baked.radianceNormal, other.baked.radianceNormal, ref.radiance);
  char line[256];
  std::snprintf(
      line, sizeof line, "%s,%s,%.5f,%.5f,%.2f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.3f,%.5f,%.5f\n",
      s.name.c_str(), s.material.name.c_str(), measured, predicted,
      predicted > 0.0 ? measured / predicted : 0.0, e.numerical, e.model.exitModel, e.model.facets,
      e.model.facetLight, e.model.farField, e.model.interreflection, out.report.totalSeconds,
      relativeNoise(ref.radiance, ref.radianceStdErr), seedNoise);
  csv << line;
  csv.flush();
  std::printf("  sss-bake defaults: per-vertex RMS %.4f, predicted %.4f (%.2fx)\n", measured,
              predicted, predicted > 0.0 ? measured / predicted : 0.0);
}

void study(const Scene& s, uint64_t paths, const std::string& cache, std::ofstream& csv,
           std::ofstream& bandsCsv, const std::string& outDir, std::ofstream& predictedCsv) {
  const Cubemap env = sunEnvironment(s.sun, 1.0, 256);
  const std::vector<float> areas = vertexAreas(s.mesh);
  const HomogeneousMedium medium = homogeneousMediumOf(s.material);
  LightTraceOptions lo;
  lo.paths = paths;
  lo.run.seed = study::kReferenceSeed;
  const std::string key = s.name + "-" + std::to_string(paths);
  const LightTraceResult ref = cachedReference(cache, key, [&] {
    return lightTraceSubsurface(s.mesh.positions, s.mesh.normals, s.mesh.triangles,
                                DistantLight::environment(env), medium, lo);
  });
  // The reference without the light that crossed unscattered (what no diffusion model produces):
  // its share of the unlit part's B, and the errors against it.
  const Selection sel = selectVertices(s, areas);
  lo.minScatteringOrder = 1;
  const LightTraceResult scattered = cachedReference(cache, key + "-scattered", [&] {
    return lightTraceSubsurface(s.mesh.positions, s.mesh.normals, s.mesh.triangles,
                                DistantLight::environment(env), medium, lo);
  });
  double all = 0.0, ms = 0.0;
  for (std::size_t v = 0; v < areas.size(); ++v) {
    if (!sel.unlit[v]) continue;
    for (int c = 0; c < 3; ++c) {
      all += areas[v] * ref.exitance[v][c];
      ms += areas[v] * scattered.exitance[v][c];
    }
  }
  const double unscatteredShare = all > 0.0 ? 1.0 - ms / all : 0.0;
  std::printf("%s: reference %llu paths, %.1f s, %.0f events/path, %llu re-entries\n",
              s.name.c_str(), (unsigned long long)paths, ref.seconds, ref.meanScatteringEvents,
              (unsigned long long)ref.reentries);
  std::fflush(stdout);
  predictedAgainstMeasured(s, env, ref, outDir, predictedCsv);
  // Radiance along the normal per unit B: the normalized exit model (the default where no far
  // field is traced), the calibrated one, or "hybrid": calibrated for the profile's part of B,
  // normalized for the escape model's excess or, with the far field, for B_far (light that
  // diffused deep; a candidate, not in the tools).
  const float eta = float(s.material.eta);
  const glm::vec3 calibrated =
      calibratedExitRadiance(DirectionalAlbedoWeight(s.material), 1.0f, eta);
  const glm::vec3 normalized(float(normalExitRadianceScale(eta)));
  // sss-bake's defaults (where the far field is traced, all of B through the exit lobe of all its
  // exits); the same without the unscattered light; B_far alone through the lobe of the far exits
  // and B - B_far through the normalized model; the normalized exit for all of B, and without the
  // far field; the calibrated exit and the hybrid instead; the diffuse entry; the half-space
  // energy with those.
  enum class Exit { Normalized, Calibrated, Hybrid, Lobe, FarLobe };
  const ExitLobe lobe(eta);
  struct Config {
    EnergyModel energy;
    EntryModel entry;
    Exit exit;
    FarFieldMode far;
    bool unscattered = true;     // with the far field: the unscattered light too
    bool calibratedNear = true;  // with the far field: its near part scaled to the traced one
  };
  constexpr FarFieldMode kAuto = FarFieldMode::Auto, kOff = FarFieldMode::Off;
  const Config configs[] = {
      {EnergyModel::Auto, EntryModel::Directional, Exit::Lobe, kAuto},
      {EnergyModel::Auto, EntryModel::Directional, Exit::Lobe, kAuto, false},
      {EnergyModel::Auto, EntryModel::Directional, Exit::Lobe, kAuto, true, false},
      {EnergyModel::Auto, EntryModel::Directional, Exit::FarLobe, kAuto},
      {EnergyModel::Auto, EntryModel::Directional, Exit::Normalized, kAuto},
      {EnergyModel::Auto, EntryModel::Directional, Exit::Normalized, kOff},
      {EnergyModel::Auto, EntryModel::Directional, Exit::Calibrated, kAuto},
      {EnergyModel::Auto, EntryModel::Directional, Exit::Calibrated, kOff},
      {EnergyModel::Auto, EntryModel::Directional, Exit::Hybrid, kAuto},
      {EnergyModel::Auto, EntryModel::Directional, Exit::Hybrid, kOff},
      {EnergyModel::Auto, EntryModel::Diffuse, Exit::Normalized, kOff},
      {EnergyModel::HalfSpace, EntryModel::Diffuse, Exit::Normalized, kOff}};
  for (const Config& config : configs) {
    const EnergyModel model = config.energy;
    std::string chosen;
    double seconds = 0.0;
    std::vector<glm::vec3> slope;
    const DiffusionResult r =
        bakeExitance(s, env, areas, model, config.entry, config.far, chosen, seconds, &slope,
                     config.exit != Exit::FarLobe, config.calibratedNear);
    const std::vector<glm::vec3>& b = r.exitance;
    std::vector<glm::vec3> l(b.size());
    const bool lobes = config.exit == Exit::Lobe || config.exit == Exit::FarLobe;
    const bool split = config.exit == Exit::Hybrid || config.exit == Exit::FarLobe;
    for (std::size_t v = 0; v < b.size(); ++v) {
      const glm::vec3 excess = split && !r.escapeExcess.empty() ? r.escapeExcess[v] : glm::vec3(0);
      const glm::vec3 farScale =
          lobes && !slope.empty() ? glm::vec3(lobe.normalRadiance(slope[v])) : normalized;
      const glm::vec3 nearScale = config.exit == Exit::Calibrated || config.exit == Exit::Hybrid
                                      ? calibrated
                                  : config.exit == Exit::Lobe ? farScale
                                                              : normalized;
      l[v] = (b[v] - excess) * nearScale + excess * farScale;
    }
    // sss-bake's defaults also add the unscattered light (auto, as bake.cpp's unscatteredStage).
    if (config.far == kAuto && config.unscattered)
      addUnscatteredLight(s, env, areas, l, chosen, seconds);
    const Metrics mL = compare(l, ref.radiance, ref.radianceStdErr, areas, sel);
    const Metrics mB = compare(b, ref.exitance, ref.exitanceStdErr, areas, sel);
    const Metrics mS = compare(l, scattered.radiance, scattered.radianceStdErr, areas, sel);
    const Metrics mSB = compare(b, scattered.exitance, scattered.exitanceStdErr, areas, sel);
    const std::string energy =
        std::string(model == EnergyModel::Auto ? "auto" : "halfspace") + "/" +
        kEntryModelNames.name(config.entry) + "/" +
        (config.exit == Exit::Normalized   ? "normalized"
         : config.exit == Exit::Calibrated ? "calibrated"
         : config.exit == Exit::Hybrid     ? "hybrid"
         : config.exit == Exit::FarLobe    ? "lobe-far-exits"
                                           : "lobe") +
        (config.far == kOff ? "/far-off" : "") +
        (config.far == kAuto && !config.unscattered ? "/no-unscattered" : "") +
        (config.far == kAuto && !config.calibratedNear ? "/near-uncalibrated" : "");
    char line[512];
    std::snprintf(line, sizeof line,
                  "%s,%s,%s,%s,%zu,%.5f,%.5f,%.4f,%.5f,%.4f,%.4f,%.5f,%.4f,%.4f,%.3f,%llu,%.1f\n",
                  s.name.c_str(), s.material.name.c_str(), energy.c_str(), chosen.c_str(),
                  s.mesh.positions.size(), mL.bandRms, mL.bandRmsRaw, mL.unlitRatio, mB.bandRms,
                  mB.unlitRatio, unscatteredShare, mS.bandRms, mS.unlitRatio, mSB.unlitRatio,
                  seconds, (unsigned long long)paths, ref.seconds + scattered.seconds);
    csv << line;
    csv.flush();
    std::printf(
        "  %-22s %-42s band rms L %.4f (raw %.4f), unlit L %.3fx; B: %.4f, %.3fx; unscattered "
        "%.3f; vs scattered-only L: %.4f, %.3fx, B %.3fx\n",
        energy.c_str(), chosen.c_str(), mL.bandRms, mL.bandRmsRaw, mL.unlitRatio, mB.bandRms,
        mB.unlitRatio, unscatteredShare, mS.bandRms, mS.unlitRatio, mSB.unlitRatio);
    std::fflush(stdout);
    if (s.slab) continue;
    for (int band = 0; band < kBands; ++band) {
      const glm::dvec3 r = mL.bandRef[band], k = mL.bandBake[band];
      std::snprintf(line, sizeof line, "%s,%s,%s,%d,%.2f,%.2f,%.5g,%.5g,%.5g,%.4f,%.4f,%.4f\n",
                    s.name.c_str(), s.material.name.c_str(), energy.c_str(), band,
                    -1.0 + 2.0 * band / kBands, -1.0 + 2.0 * (band + 1) / kBands, r.x, r.y, r.z,
                    r.x > 0 ? k.x / r.x : 0.0, r.y > 0 ? k.y / r.y : 0.0,
                    r.z > 0 ? k.z / r.z : 0.0);
      bandsCsv << line;
    }
    bandsCsv.flush();
  }
}

int run(int argc, char** argv) {
  const StudyArguments args = parseStudyArguments(argc, argv, 500000);
  if (args.outDir.empty()) {
    std::fprintf(stderr, "usage: sun_study OUT_DIR [--paths N] [--only NAME] [--cache DIR]\n");
    return 2;
  }
  const std::string& outDir = args.outDir;
  const std::string &only = args.only, &cache = args.cache;
  const uint64_t paths = args.paths;
  std::filesystem::create_directories(outDir);
  const glm::vec3 sun = glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f));
  // 30 degrees from the slab's normal: the light crossing unscattered leaves along it, outside
  // the reference's 15-degree cone about the normal (it is in B).
  const glm::vec3 behind = glm::normalize(glm::vec3(0.5f, 0.0f, -0.866f));
  std::vector<Scene> scenes;
  for (float radius : {10.0f, 5.0f})
    for (const char* m : {"marble", "skin1", "ketchup"})
      scenes.push_back({std::string(radius == 10.0f ? "sphere-sun-" : "sphere-r5-sun-") + m,
                        makeIcosphere(3, radius), findMaterialPreset(m), sun, false});
  for (const char* m : {"marble", "skin1", "ketchup"})
    scenes.push_back({std::string("slab-backlit-") + m, makeSlab(40.0f, 2.0f, 20),
                      findMaterialPreset(m), behind, true});
  std::ofstream csv(outDir + "/sun.csv");
  csv << "scene,material,energy,chosen,vertices,band_rms_L,band_rms_L_raw,unlit_ratio_L,"
         "band_rms_B,unlit_ratio_B,ref_unscattered_B,band_rms_L_scattered,unlit_ratio_L_scattered,"
         "unlit_ratio_B_scattered,bake_s,ref_paths,ref_s\n";
  std::ofstream bandsCsv(outDir + "/sun_bands.csv");
  bandsCsv << "scene,material,energy,band,cos_lo,cos_hi,ref_L_r,ref_L_g,ref_L_b,ratio_r,ratio_g,"
              "ratio_b\n";
  std::ofstream predictedCsv(outDir + "/sun_predicted.csv");
  predictedCsv << "scene,material,rms_vertex_L,predicted,measured_over_predicted,numerical,"
                  "model_exit,model_facets,model_facet_light,model_far_field,model_interreflection,"
                  "bake_s,ref_noise,"
                  "seed_noise\n";
  for (const Scene& s : scenes)
    if (only.empty() || s.name.find(only) != std::string::npos)
      study(s, paths, cache, csv, bandsCsv, outDir, predictedCsv);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sun_study: error: %s\n", e.what());
    return 1;
  }
}

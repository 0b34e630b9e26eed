// The accuracy study (docs/accuracy.md, "Under even light: the accuracy study"): every profile x
// diffusion method x tolerance against the Monte Carlo reference (lib/pathtrace), on small scenes
// where the reference is affordable, plus the half-space totals of every preset, the guard's cost
// and effect, the escape energy model (lib/transport/finite_object_energy.h) and the bake's
// automatic choice.
//
//   accuracy_study OUT_DIR [--quick] [--only NAME] [--walks N] [--entry onering|vertex]
//
// The reference is evaluated at each vertex, entering through its smooth normal (what the bake's
// per-vertex E and B assume); `--entry onering` averages over the vertex's facets instead (entry
// through the face normals: the faceted surface). On the coarse dragon the diffusion models are
// further from the latter (docs/accuracy.md, "Under even light: the accuracy study", "The
// reference's meaning on coarse meshes").
// Writes OUT_DIR/halfspace.csv, OUT_DIR/scenes.csv (see tests/bench/accuracy_study.sh, which
// draws the charts) and OUT_DIR/scenes_predicted.csv (sss-bake's predicted error against the
// measured one per scene). Data: SSS_SOURCE_DIR/data/cache (run data/fetch.sh).
//
// Error metric: radiance leaving each evaluated vertex along its normal, all three channels,
//   err = sqrt(sum (L - L_ref)^2) / sqrt(sum L_ref^2)     (normalized RMS over vertices),
// with the diffusion side's radiance from the exit model L = B F_t(1, eta) / (pi (1 - 2 C_1)).
// The reference's own noise adds sum SE^2 to the numerator's expectation; `err_L` removes it
// (sqrt(max(0, raw^2 - noise^2))), `err_L_raw` keeps it and `ref_noise` is the noise alone.
// `bias_L` = sum L / sum L_ref - 1 (the energy error); `shape_err_L` is err_L after the best
// global scale of L (what remains when the energy is right); `err_B` compares the exitance B with
// the reference's (no exit model involved). Rows: profile x method x tolerance with the half-space
// energy; "exact+escape" (the escape energy model on the exact sum; its time includes the walks);
// "bake-auto" (profile "auto": energy, profile and method as sss-bake chooses them, chosen =
// profile/method, energy in the last column; err_vs_exact against the exact sum of the profile and
// energy model it chose, with the study's own escape walks). Vertices over holes of an open mesh (>
// 1% of their reference walks lost) are left out.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "bake/bake.h"
#include "bake/bake_settings.h"
#include "bake/error_budget.h"
#include "bench/interior_segment_guard.h"
#include "core/error.h"
#include "core/relative_rms.h"
#include "core/timer.h"
#include "diffusion/diffusion.h"
#include "envmap/environment.h"
#include "lighting/visibility.h"
#include "material/diffusion_profile.h"
#include "material/directional_albedo_weight.h"
#include "material/material.h"
#include "material/profile_factory.h"
#include "mesh/load_mesh.h"
#include "mesh/primitives.h"
#include "optics/fresnel.h"
#include "pathtrace/subsurface_path_tracer.h"
#include "study_support.h"
#include "transport/far_field.h"
#include "transport/finite_object_energy.h"

namespace {

using namespace sss;
using sss::study::loadScaled;

struct Scene {
  std::string name;
  TriangleMesh mesh;  // mm
  Material material;
  std::string envName;
  const Cubemap* env;
  std::size_t evalVertices;  // evaluate this many vertices, evenly spread
};

struct Reference {
  std::vector<uint32_t> vertices;
  std::vector<glm::vec3> radiance, radianceSe, exitance, exitanceSe;
  double seconds, events;
};

// A vertex whose walks leave through holes more often than this is over an open part of the mesh.
constexpr float kMaxEscapedFraction = 0.01f;
// Budget of the escape walks for the exact + escape rows (the bake's auto sets its own).
constexpr double kStudyEscapeNoise = 0.003;

double sq(double x) {
  return x * x;
}

// Relative RMS of values against the reference over the evaluated vertices (core/relative_rms.h,
// pooled); noise: the reference's SE in the same norm.
struct ErrorPair {
  double raw, noise, corrected, bias;  // bias: sum(values) / sum(reference) - 1
  double shape;  // corrected error after the best global scale (least squares): the error
                 // that is not energy
};
ErrorPair errorPair(const std::vector<glm::vec3>& values, const std::vector<glm::vec3>& refValues,
                    const std::vector<glm::vec3>& refSe) {
  const RelativeRmsSums sums = relativeRmsSums(values, refValues, refSe);
  double sum = 0, refSum = 0, vv = 0, vr = 0;
  for (std::size_t k = 0; k < refValues.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      sum += values[k][c];
      refSum += refValues[k][c];
      vv += sq(values[k][c]);
      vr += double(values[k][c]) * refValues[k][c];
    }
  const double scale = vv > 0 ? vr / vv : 1.0;
  RelativeRmsSums shapeSums = sums;  // the same reference and noise, the scaled error
  shapeSums.error = 0.0;
  for (std::size_t k = 0; k < refValues.size(); ++k)
    for (int c = 0; c < 3; ++c) shapeSums.error += sq(scale * values[k][c] - refValues[k][c]);
  return {sums.ratio(), sums.relativeNoise(), sums.noiseRemoved(), sum / refSum - 1.0,
          shapeSums.noiseRemoved()};
}

// Half-space totals: a thick box, uniform radiance 1, the top centre vertex. The Monte Carlo
// exitance divided by the transmitted irradiance pi (1 - 2 C_1) is the true total diffuse
// reflectance the profiles' totals approximate.
void halfSpaceStudy(const std::string& outDir, int walks) {
  std::ofstream csv(outDir + "/halfspace.csv");
  csv << "material,channel,reduced_albedo,mc_all,mc_all_se,mc_multiple,mc_multiple_se,dipole,"
         "beam,burley,exit_ratio_normal,exit_ratio_all_normalized,exit_ratio_all_calibrated\n";
  const Cubemap uniform(8, glm::vec3(1.0f));
  for (const Material& m : materialPresets()) {
    const glm::dvec3 ld = m.diffuseMeanFreePath(), mfp = m.meanFreePath();
    const double lmax = std::max({ld.x, ld.y, ld.z, mfp.x, mfp.y, mfp.z});
    const float side = float(60.0 * lmax), depth = float(30.0 * lmax);
    const TriangleMesh box = makeBox(glm::vec3(side, side, depth), 2);
    uint32_t top = 0;
    for (uint32_t i = 0; i < box.positions.size(); ++i)
      if (box.normals[i].z > 0.999f && std::abs(box.positions[i].x) < 1e-3f * side &&
          std::abs(box.positions[i].y) < 1e-3f * side)
        top = i;
    PathTraceOptions options;
    options.samples = walks;
    options.vertices = {top};
    options.run.quiet = true;
    options.minScatteringOrder = 1;
    const PathTraceResult all = pathTraceSubsurface(box, uniform, m, options);
    options.minScatteringOrder = 2;
    const PathTraceResult ms = pathTraceSubsurface(box, uniform, m, options);
    const float eta = float(m.eta);
    const double et = M_PI * (1.0 - diffuseFresnelReflectance(eta));
    glm::dvec3 totals[3];
    const char* kinds[3] = {"dipole", "beam", "burley"};
    for (int k = 0; k < 3; ++k) totals[k] = makeProfile(kinds[k], m)->totalReflectance();
    const glm::vec3 calibrated = calibratedExitRadiance(DirectionalAlbedoWeight(m), 1.0f, eta);
    for (int c = 0; c < 3; ++c) {
      // Exit model check: the radiance along the normal that L = B F_t/(pi (1 - 2 C_1)) predicts
      // from the Monte Carlo B, divided into the Monte Carlo radiance: of the multiply scattered
      // light (exit_ratio_normal), and of all scattered light (what the bake's B holds) for the
      // normalized and the calibrated exit model.
      const double normalized = normalExitRadianceScale(eta);
      const double model = ms.exitance[0][c] * normalized;
      char line[512];
      std::snprintf(
          line, sizeof line, "%s,%c,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.4f,%.4f,%.4f\n",
          m.name.c_str(), "rgb"[c], m.reducedAlbedo()[c], all.exitance[0][c] / et,
          all.exitanceStdErr[0][c] / et, ms.exitance[0][c] / et, ms.exitanceStdErr[0][c] / et,
          totals[0][c], totals[1][c], totals[2][c], ms.radiance[0][c] / model,
          all.radiance[0][c] / (all.exitance[0][c] * normalized),
          all.radiance[0][c] / (all.exitance[0][c] * calibrated[c]));
      csv << line;
    }
    std::printf("halfspace %-10s done (%.1f s, %.0f events/walk)\n", m.name.c_str(),
                all.seconds + ms.seconds, all.meanScatteringEvents);
    std::fflush(stdout);
  }
}

// The bake's own choice at a tolerance (lib/bake/bake.cpp): the energy plan, the profile auto
// takes for it, and the diffusion sum's share of the tolerance (the visibility stage is fixed
// here, so its share goes to the diffusion sum).
struct AutoChoice {
  EnergyPlan plan;
  std::string profileName;
  std::unique_ptr<DiffusionProfile> profile;
  double diffusionTolerance = 0.0;
};

AutoChoice autoChoice(const TriangleMesh& mesh, const std::vector<float>& areas,
                      const Material& material, double tolerance, bool nearShare = false) {
  AutoChoice c;
  const ErrorBudget budget(tolerance);
  EnergyOptions energyOptions;
  energyOptions.noiseBudget = budget.walkBudget();
  if (nearShare) energyOptions.nearWindowMm = farFieldWindowMm(material);
  c.plan = planFiniteObjectEnergy(mesh, areas, material, energyOptions);
  c.profileName = autoProfileName(c.plan.model);
  c.profile = makeProfile(c.profileName, material);
  const bool escape = c.plan.model == EnergyModel::Escape;
  c.diffusionTolerance = budget.diffusionTolerance(
      escape, escape ? c.plan.escape.relativeStdError : 0.0, std::nullopt);
  return c;
}

// sss-bake's own pipeline (lib/bake/bake.h, defaults at 1 %, the study's visibility rays) on the
// scene: its predicted error (estimated_error.total and its parts) beside the error measured at
// the reference's vertices (radiance along the normal, the reference's noise removed; ref_noise:
// that noise, in the same norm: a measured error well below it is not resolved). These rows are
// not among those the model error's weights were fitted on (tests/bench/model_error_fit.py), and
// the backward reference, like a bake without bounces, drops the light the object sends itself.
void predictedAgainstMeasured(const Scene& scene, const Reference& ref, int visibilitySamples,
                              const std::string& outDir, std::ofstream& csv) {
  const BakeOutput out =
      study::bakeAtDefaults(scene.mesh, scene.material, BakeEnvironment{*scene.env, {}},
                            visibilitySamples, outDir + "/" + scene.name + ".ply");
  std::vector<glm::vec3> l;
  for (uint32_t v : ref.vertices) l.push_back(out.baked.radianceNormal[v]);
  const ErrorPair err = errorPair(l, ref.radiance, ref.radianceSe);
  const double measured = err.corrected;
  const BakeErrorReport& e = out.report.errors;
  char line[256];
  std::snprintf(line, sizeof line,
                "%s,%s,%s,%.5f,%.5f,%.5f,%.2f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.3f\n",
                scene.name.c_str(), scene.material.name.c_str(), scene.envName.c_str(), measured,
                err.noise, e.total, e.total > 0.0 ? measured / e.total : 0.0, e.numerical,
                e.model.exitModel, e.model.facets, e.model.facetLight, e.model.farField,
                e.model.interreflection, out.report.totalSeconds);
  csv << line;
  csv.flush();
  std::printf("%s: sss-bake defaults: RMS %.4f at the reference's vertices, predicted %.4f\n",
              scene.name.c_str(), measured, e.total);
}

void sceneStudy(const Scene& scene, int walks, int visibilitySamples, WalkEntry entry,
                std::ofstream& csv, const std::string& outDir, std::ofstream& predictedCsv) {
  const TriangleMesh& mesh = scene.mesh;
  const float eta = float(scene.material.eta);
  const std::size_t n = mesh.positions.size();
  // Reference on evenly spread vertices.
  Reference ref;
  const std::size_t m = std::min(n, scene.evalVertices);
  for (std::size_t k = 0; k < m; ++k) ref.vertices.push_back(uint32_t(k * n / m));
  PathTraceOptions options;
  options.samples = walks;
  options.vertices = ref.vertices;
  options.run.quiet = true;
  options.entry = entry;
  options.run.seed =
      study::kReferenceSeed;  // apart from the bake's visibility rays (seed 1, per vertex)
  const PathTraceResult pt = pathTraceSubsurface(mesh, *scene.env, scene.material, options);
  ref.radiance = pt.radiance;
  ref.radianceSe = pt.radianceStdErr;
  ref.exitance = pt.exitance;
  ref.exitanceSe = pt.exitanceStdErr;
  // Vertices of an open mesh with no medium behind them (their walks leave through holes) have no
  // meaningful reference: every error leaves them out.
  std::size_t kept = 0;
  for (std::size_t k = 0; k < m; ++k) {
    if (pt.escapedFraction[k] > kMaxEscapedFraction) continue;
    ref.vertices[kept] = ref.vertices[k];
    ref.radiance[kept] = ref.radiance[k];
    ref.radianceSe[kept] = ref.radianceSe[k];
    ref.exitance[kept] = ref.exitance[k];
    ref.exitanceSe[kept] = ref.exitanceSe[k];
    ++kept;
  }
  ref.vertices.resize(kept);
  for (auto* values : {&ref.radiance, &ref.radianceSe, &ref.exitance, &ref.exitanceSe})
    values->resize(kept);
  std::printf(
      "%s: %zu vertices, reference on %zu x %d walks (%zu over holes left out): %.1f s, "
      "%.0f events/walk\n",
      scene.name.c_str(), n, m, walks, m - kept, pt.seconds, pt.meanScatteringEvents);
  std::fflush(stdout);
  predictedAgainstMeasured(scene, ref, visibilitySamples, outDir, predictedCsv);

  // Transmitted irradiance with the mesh's shadows (the bake's default stage).
  // The same samples also give E_w, the irradiance weighted by the directional entry (sss-bake's
  // default; material/directional_albedo_weight.h), for the "bake-defaults" rows.
  const DirectionalAlbedoWeight weight(scene.material);
  VisibilityOptions vis;
  vis.samples = visibilitySamples;
  vis.entry = &weight;
  VisibilityReport visReport;
  const Stopwatch visClock;
  const std::vector<glm::vec3> e = transmittedIrradianceWithVisibility(
      mesh.positions, mesh.normals, mesh.triangles, *scene.env, eta, vis, &visReport);
  const double visSeconds = visClock.seconds();
  const std::vector<float> areas = vertexAreas(mesh);
  DiffusionInput input{mesh.positions, mesh.normals, areas, e};
  const glm::vec3 normalizedExit(float(normalExitRadianceScale(eta)));
  const glm::vec3 calibratedExit = calibratedExitRadiance(weight, 1.0f, eta);

  auto record = [&](const std::string& profile, const std::string& method,
                    const std::string& chosen, double tolerance, int gaussians, double seconds,
                    const std::vector<glm::vec3>& b, const std::vector<glm::vec3>* exact,
                    double droppedFraction = 0.0, const std::string& energy = "halfspace",
                    bool calibrated = false, const std::vector<glm::vec3>* hybridExcess = nullptr) {
    // hybridExcess: the calibrated exit for the profile's part of B, the normalized one for the
    // escape model's excess (a candidate, not in the tools).
    std::vector<glm::vec3> bEval, lEval;
    for (uint32_t v : ref.vertices) {
      bEval.push_back(b[v]);
      const glm::vec3 x = hybridExcess ? (*hybridExcess)[v] : glm::vec3(0.0f);
      lEval.push_back(calibrated ? (b[v] - x) * calibratedExit + x * normalizedExit
                                 : b[v] * normalizedExit);
    }
    const ErrorPair errL = errorPair(lEval, ref.radiance, ref.radianceSe);
    const ErrorPair errB = errorPair(bEval, ref.exitance, ref.exitanceSe);
    const double vsExact = exact ? relativeRms(b, *exact) : 0.0;
    char line[512];
    std::snprintf(
        line, sizeof line,
        "%s,%s,%s,%s,%s,%g,%d,%zu,%.4f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%s\n",
        scene.name.c_str(), scene.material.name.c_str(), profile.c_str(), method.c_str(),
        chosen.c_str(), tolerance, gaussians, n, visSeconds, seconds, visSeconds + seconds,
        errL.corrected, errL.raw, errL.noise, errB.corrected, vsExact, droppedFraction, errL.bias,
        errL.shape, energy.c_str());
    csv << line;
    csv.flush();
  };

  // The object's escape probability (finite_object_energy.h), walked once to a tight budget.
  EnergyOptions escapeOptions;
  escapeOptions.model = EnergyModel::Escape;
  escapeOptions.noiseBudget = kStudyEscapeNoise;
  const EnergyPlan escape = planFiniteObjectEnergy(mesh, areas, scene.material, escapeOptions);
  std::printf(
      "%s: escape probability %.3f/%.3f/%.3f (half-space %.3f/%.3f/%.3f), %d walks x %zu "
      "probes, noise %.2g%%, %.2f s\n",
      scene.name.c_str(), escape.escape.mean.x, escape.escape.mean.y, escape.escape.mean.z,
      escape.halfSpaceAlbedo.x, escape.halfSpaceAlbedo.y, escape.halfSpaceAlbedo.z, escape.walks,
      escape.escape.probes, 100.0 * escape.escape.relativeStdError, escape.seconds);

  // Each profile's exact sum with either energy model: what the bake's auto rows are checked
  // against (their error against the converged answer of the model they chose).
  std::map<std::string, std::vector<glm::vec3>> exactSums;
  for (const std::string& profileName : listProfiles()) {
    const auto profile = makeProfile(profileName, scene.material);
    DiffusionOptions dopt;
    dopt.run.quiet = true;
    dopt.method = DiffusionMethod::Exact;
    const DiffusionResult exact = diffuse(input, *profile, dopt);
    record(profileName, "exact", "exact", 0.0, 0, exact.report.totalSeconds, exact.exitance,
           &exact.exitance);
    exactSums[profileName + "/halfspace"] = exact.exitance;
    {
      const Stopwatch clock;
      const DiffusionResult b = diffuseWithEnergy(input, *profile, dopt, escape, scene.material);
      record(profileName, "exact+escape", "exact", 0.0, 0, clock.seconds() + escape.seconds,
             b.exitance, &exact.exitance, 0.0, "escape");
      exactSums[profileName + "/escape"] = b.exitance;
    }
    for (double tol : {0.1, 0.03, 0.01, 0.003}) {
      for (DiffusionMethod method : {DiffusionMethod::Gauss, DiffusionMethod::Incremental,
                                     DiffusionMethod::Hierarchical, DiffusionMethod::Auto}) {
        dopt.method = method;
        dopt.tolerance = tol;
        const DiffusionResult r = diffuse(input, *profile, dopt);
        record(profileName, kDiffusionMethodNames.name(method),
               kDiffusionMethodNames.name(r.report.method), tol, r.report.gaussians,
               r.report.totalSeconds, r.exitance, &exact.exitance);
      }
    }
    for (bool guard : {false, true}) {
      GuardedSumOptions gopt;
      gopt.guard = guard;
      const GuardedSumResult g = diffuseExactGuarded(mesh.positions, mesh.normals, areas, e,
                                                     mesh.triangles, *profile, gopt);
      record(profileName, guard ? "exact-guard" : "exact-noguard", guard ? "guard" : "noguard", 0.0,
             0, g.seconds, g.exitance, &exact.exitance,
             double(g.droppedPairs) / double(std::max<uint64_t>(g.pairs, 1)));
    }
    std::printf("%s: %s done\n", scene.name.c_str(), profileName.c_str());
    std::fflush(stdout);
  }

  // The bake's own choice (lib/bake/bake.cpp): energy model, then profile, then method, from the
  // tolerance (the visibility stage is fixed here, so its share goes to the diffusion sum).
  for (double tol : {0.1, 0.03, 0.01}) {
    const AutoChoice choice = autoChoice(mesh, areas, scene.material, tol);
    const EnergyPlan& plan = choice.plan;
    DiffusionOptions dopt;
    dopt.run.quiet = true;
    dopt.tolerance = choice.diffusionTolerance;
    const Stopwatch clock;
    const DiffusionResult r = diffuseWithEnergy(input, *choice.profile, dopt, plan, scene.material);
    const double seconds = plan.seconds + clock.seconds();
    record("auto", "bake-auto",
           choice.profileName + "/" + kDiffusionMethodNames.name(r.report.method), tol,
           r.report.gaussians, seconds, r.exitance,
           &exactSums.at(choice.profileName + "/" + kEnergyModelNames.name(plan.model)), 0.0,
           kEnergyModelNames.name(plan.model));
  }

  // sss-bake's defaults: the same choices on E_w (directional entry), radiance through the
  // normalized exit model ("bake-defaults") and through the calibrated one ("bake-calibrated").
  // err_vs_exact against the exact sum of the model chosen on E_w.
  // "bake-defaults-far": with the far field (far_field.h) as sss-bake's auto decides it.
  for (const FarFieldMode farMode : {FarFieldMode::Off, FarFieldMode::Auto}) {
    const double tol = 0.01;
    AutoChoice choice = autoChoice(mesh, areas, scene.material, tol, farMode != FarFieldMode::Off);
    EnergyPlan& plan = choice.plan;
    const DiffusionProfile& profile = *choice.profile;
    const std::string& profileName = choice.profileName;
    const DiffusionInput weighted{mesh.positions, mesh.normals, areas, visReport.entryWeighted};
    const Stopwatch farClock;
    FarFieldOptions farOptions;
    farOptions.mode = farMode;
    farOptions.noiseBudget = ErrorBudget(tol).walkBudget() / std::sqrt(2.0);
    const FarField far = traceFarField(
        {mesh, areas, *scene.env, scene.material, plan, visReport.entryWeighted, farOptions});
    if (far.traced()) {
      EnergyOptions energyOptions;
      energyOptions.noiseBudget = farOptions.noiseBudget;
      energyOptions.nearWindowMm = farFieldWindowMm(scene.material);
      refineNearShare(plan, mesh, areas, scene.material, energyOptions);
    }
    const double farSeconds = farClock.seconds();
    std::printf("%s: far field %s (%s)\n", scene.name.c_str(), far.traced() ? "traced" : "off",
                far.report.reason.c_str());
    if (farMode != FarFieldMode::Off && !far.traced()) continue;  // the same as the row before
    const std::string suffix = far.traced() ? "-far" : "";
    DiffusionOptions dopt;
    dopt.run.quiet = true;
    dopt.method = DiffusionMethod::Exact;
    const DiffusionResult exact =
        diffuseWithEnergy(weighted, profile, dopt, plan, scene.material, far.exitance);
    dopt.method = DiffusionMethod::Auto;
    dopt.tolerance = choice.diffusionTolerance;
    const Stopwatch clock;
    const DiffusionResult r =
        diffuseWithEnergy(weighted, profile, dopt, plan, scene.material, far.exitance);
    const double seconds = plan.seconds + farSeconds + clock.seconds();
    const std::string chosen = profileName + "/" + kDiffusionMethodNames.name(r.report.method);
    const std::string energy = std::string(kEnergyModelNames.name(plan.model)) + suffix;
    record("auto", "bake-defaults" + suffix, chosen, tol, r.report.gaussians, seconds, r.exitance,
           &exact.exitance, 0.0, energy + "/directional/normalized", false);
    record("auto", "bake-calibrated" + suffix, chosen, tol, r.report.gaussians, seconds, r.exitance,
           &exact.exitance, 0.0, energy + "/directional/calibrated", true);
    if (!r.escapeExcess.empty())
      record("auto", "bake-hybrid" + suffix, chosen, tol, r.report.gaussians, seconds, r.exitance,
             &exact.exitance, 0.0, energy + "/directional/hybrid", true, &r.escapeExcess);
  }
}

int run(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: accuracy_study OUT_DIR [--quick] [--only NAME] [--walks N] "
                 "[--entry onering|vertex]\n");
    return 2;
  }
  const std::string outDir = argv[1];
  bool quick = false;
  std::string only;
  int walksArg = 0;
  WalkEntry entry = WalkEntry::Vertex;
  for (int i = 2; i < argc; ++i) {
    if (std::string(argv[i]) == "--quick") quick = true;
    if (std::string(argv[i]) == "--only" && i + 1 < argc) only = argv[++i];
    if (std::string(argv[i]) == "--walks" && i + 1 < argc) walksArg = std::atoi(argv[++i]);
    if (std::string(argv[i]) == "--entry" && i + 1 < argc)
      entry = std::string(argv[++i]) == "onering" ? WalkEntry::OneRing : WalkEntry::Vertex;
  }
  std::filesystem::create_directories(outDir);
  const std::string cache = std::string(SSS_SOURCE_DIR) + "/data/cache";
  if (!std::filesystem::exists(cache + "/meshes/dragon_res4.ply"))
    fail(cache, "sample data missing: run data/fetch.sh");
  const int walks = walksArg > 0 ? walksArg : quick ? 256 : 4096;
  const std::size_t evalVertices = quick ? 48 : 96;

  if (only.empty() || only == "halfspace") halfSpaceStudy(outDir, quick ? 4000 : 40000);

  // The reference's noise grows with the environment's contrast (the walk picks one direction
  // per exit), so the scenes use forest.exr area-averaged to 4 x 4 texels per face (a blurred
  // forest: the diffusion error does not depend on sharp lighting); the strong-sun scene keeps a
  // 3-degree sun at full resolution.
  EnvironmentOptions envOptions;
  envOptions.faceSize = 4;
  const Cubemap forest = loadEnvironment(cache + "/env/forest.exr", envOptions);
  SkyParameters sun;
  sun.sunAngularRadiusDeg = 3.0f;
  const Cubemap sky = makeSky(sun, 128);
  const Material marble = findMaterialPreset("marble");
  const Material ketchup = findMaterialPreset("ketchup");
  std::vector<Scene> scenes = {
      {"sphere", makeIcosphere(3, 10.0f), marble, "forest-blur", &forest, evalVertices},
      {"slab", makeSlab(40.0f, 2.0f, 16), marble, "forest-blur", &forest, evalVertices},
      {"cube", makeBox(glm::vec3(20.0f), 8), marble, "forest-blur", &forest, evalVertices},
      {"dragon", loadScaled(cache + "/meshes/dragon_res4.ply", 150.0), marble, "forest-blur",
       &forest, evalVertices},
      {"sphere-ketchup", makeIcosphere(3, 10.0f), ketchup, "forest-blur", &forest, evalVertices},
      {"sphere-coarse", makeIcosphere(1, 10.0f), marble, "forest-blur", &forest, evalVertices},
      {"sphere-sun", makeIcosphere(3, 10.0f), marble, "sky", &sky, evalVertices},
  };
  std::ofstream csv(outDir + "/scenes.csv");
  csv << "scene,material,profile,method,chosen,tolerance,gaussians,vertices,visibility_s,"
         "diffusion_s,bake_s,err_L,err_L_raw,ref_noise,err_B,err_vs_exact,dropped_pairs,bias_L,"
         "shape_err_L,energy\n";
  std::ofstream predictedCsv(outDir + "/scenes_predicted.csv");
  predictedCsv << "scene,material,environment,rms_vertex_L,ref_noise,predicted,"
                  "measured_over_predicted,"
                  "numerical,model_exit,model_facets,model_facet_light,model_far_field,"
                  "model_interreflection,bake_s\n";
  for (const Scene& s : scenes) {
    if (!only.empty() && only != s.name) continue;
    sceneStudy(s, walks, 128, entry, csv, outDir, predictedCsv);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "accuracy_study: error: %s\n", e.what());
    return 1;
  }
}

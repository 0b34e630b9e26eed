#include "bake/bake.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <span>
#include <utility>

#include "bake/error_budget.h"
#include "core/timer.h"
#include "core/tool.h"
#include "envmap/environment.h"
#include "lighting/visibility_pilot.h"
#include "material/directional_albedo_weight.h"
#include "optics/exit_lobe.h"
#include "optics/fresnel.h"
#include "transport/interreflection.h"

namespace sss {

namespace {

LightingInput lightingInput(const BakeSettings& s, const PreparedMesh& mesh,
                            const Cubemap& radiance, const EnergyStage& energy,
                            const ErrorBudget& budget, const DirectionalAlbedoWeight& weight) {
  const bool escape = energy.report.escape();
  LightingInput in{mesh.meshMm, mesh.areasMm2, radiance, *energy.profile};
  in.eta = static_cast<float>(s.material.eta);
  if (s.entry == EntryModel::Directional && s.method != BakeMethod::PathTrace) in.entry = &weight;
  in.mode = s.visibility;
  in.samples = s.samples;
  in.visibilityBudget = budget.visibilityBudget(escape);
  in.visibilityShare = budget.visibilityShare(escape);
  in.tolerance = s.tolerance;
  in.seed = s.seed;
  in.threads = s.threads;
  in.quiet = s.quiet;
  return in;
}

// Stage 3b: the far field (far_field.h); with it, the walks' near share refined. The escape
// model's Monte Carlo keeps its share of the budget: half its variance each.
FarField farFieldStage(const BakeSettings& s, const PreparedMesh& mesh, const Cubemap& radiance,
                       const EnergyStageInput& energyIn, EnergyStage& energy,
                       const VertexLighting& lighting, const ErrorBudget& budget) {
  FarFieldOptions options;
  options.mode = s.farField;
  options.noiseBudget = budget.walkBudget() / std::sqrt(2.0);
  options.seed = s.seed;
  options.threads = s.threads;
  options.quiet = s.quiet;
  FarField far = traceFarField({mesh.meshMm, mesh.areasMm2, radiance, s.material,
                                energy.report.plan, lighting.transportIrradiance(), options});
  info("far field: " + std::string(far.traced() ? "traced" : "not traced") + " (" +
           far.report.reason + ")",
       s.quiet);
  if (far.traced()) useFarField(energy, energyIn, options.noiseBudget, far.report.relativeStdError);
  return far;
}

// What the diffusion sum may spend: only auto samples budget the rays (forced rays and the
// irradiance cubemap leave their error outside the split).
double diffusionTolerance(const BakeSettings& s, const ErrorBudget& budget,
                          const EnergyStageReport& energy, const LightingReport& lighting) {
  const bool budgetedRays = s.visibility == VisibilityMode::Rays && s.samples == 0;
  return budget.diffusionTolerance(
      energy.escape(), energy.walkError(),
      budgetedRays ? std::optional<double>(lighting.estimatedError) : std::nullopt);
}

// The path tracer's walks do not use E, so only their own error counts (and the unscattered
// light's, which is added to both). The model's error adds to either.
BakeErrorReport errorReport(const BakeReport& r, const ModelErrorReport& model, double tolerance) {
  BakeErrorReport e;
  e.exitance = r.transport.estimatedError;
  e.tolerance = tolerance;
  e.model = model;
  const UnscatteredLightReport& u = r.unscattered;
  e.unscattered = u.traced ? u.relativeStdError : u.share;
  e.exitLobe = r.farField.traced ? r.farField.lobeNoise : 0.0;
  if (r.transport.pathTrace) {
    e.numerical = std::hypot(e.exitance, e.unscattered);
  } else {
    e.visibility = r.lighting.estimatedError;
    e.energy = r.energy.walkError();
    const InterreflectionReport& ir = r.interreflection;
    e.interreflection = ir.enabled ? std::hypot(ir.gatherNoise, ir.remaining) : ir.estimatedMissing;
    e.numerical = std::hypot(ErrorBudget::total(e.visibility, e.exitance, e.energy),
                             std::hypot(e.interreflection, e.unscattered), e.exitLobe);
  }
  e.total = std::hypot(e.numerical, e.model.total);
  return e;
}

// Stage 4d: the model's own error (model_error.h), from the output's radiance; said when it is
// above the tolerance, which then bounds only the numerical part.
// With a traced far field only vertexModel (B - B_far's radiance) is the vertex model's, whose
// exit model and light across facets the model error counts (B_far's paths met the facets
// themselves); without it (empty), all of the radiance.
// interreflected: the radiance of what the bounces added to B (empty without bounces).
ModelErrorReport modelErrorStage(const BakeSettings& s, const TriangleMesh& meshMm,
                                 std::span<const glm::vec3> radianceNormal,
                                 std::span<const glm::vec3> vertexModel,
                                 std::span<const glm::vec3> interreflected, const Cubemap& radiance,
                                 const FarField& far) {
  const ModelErrorReport model = estimateModelError(
      {meshMm, radianceNormal, radiance, float(s.material.eta), exitModelSpread(s.material),
       far.traced() ? far.report.averagingBias : far.report.sensitivity, s.threads, vertexModel,
       interreflected});
  if (model.total > s.tolerance) {
    char line[300];
    std::snprintf(line, sizeof line,
                  "model error: about %.1f%% of the radiance here (exit model %.1f%%, facets "
                  "%.1f%%, light across facets %.1f%%, far field %.1f%%, interreflection "
                  "%.1f%%), beyond what --tolerance %g bounds",
                  100.0 * model.total, 100.0 * model.exitModel, 100.0 * model.facets,
                  100.0 * model.facetLight, 100.0 * model.farField, 100.0 * model.interreflection,
                  s.tolerance);
    info(line, s.quiet);
  }
  return model;
}

// The gather's options from the settings: the bounces and the pilot trace the same rays, weighted
// by the directional entry when the transport's light is.
InterreflectionOptions interreflectionOptions(const BakeSettings& s, const VertexLighting& lighting,
                                              const DirectionalAlbedoWeight& weight) {
  InterreflectionOptions options;
  options.rays = s.interreflectionRays;
  if (!lighting.entryWeighted.empty()) options.entry = &weight;
  options.seed = s.seed;
  options.threads = s.threads;
  return options;
}

// The interreflection pilot's vertices (spread over the mesh): the estimate without bounces, and
// the replica that measures the gather's noise with them.
constexpr std::size_t kPilotVertices = 1024;
constexpr uint64_t kReplicaSeedOffset = 0x9e3779b9;

// The bounces' increments are summed at most this loosely (iterateInterreflection): the loosest
// tolerance the sums' error model was fitted at (tests/bench/diffusion_sweep.sh, 0.3-3 %).
constexpr double kLoosestIncrementTolerance = 0.03;

// Stage 4b: the light the object sends to itself (interreflection.h), iterated with the transport;
// E and B become the converged ones. Returns what the bounces added to B (B - B_direct), whose
// radiance the model error counts (model_error.h).
std::vector<glm::vec3> addInterreflection(const BakeSettings& s, const PreparedMesh& mesh,
                                          const Cubemap& radiance,
                                          const TransportInput& transportIn,
                                          const DirectionalAlbedoWeight& weight,
                                          VertexLighting& lighting, VertexExitance& exitance,
                                          InterreflectionReport& report) {
  const Stopwatch clock;
  const InterreflectionOptions options = interreflectionOptions(s, lighting, weight);
  const TriangleMesh& m = mesh.meshMm;
  const InterreflectionGather gather(m.positions, m.normals, m.triangles, radiance,
                                     float(s.material.eta), options);
  // What the bounces add goes through the transport's linear part: the method the first transport
  // chose and its sums with E = 1 (transportIn.weightSums). The traced far field came from the
  // environment and carries none of the light the object sends itself: with it, the first
  // transport spread only P's near share, so the bounces go through the escape model's own
  // kernel for all of P (with their own sums), as without a far field: the near share alone
  // dropped the rest of their light (docs/physics.md, "Light the object sends itself").
  TransportInput in = transportIn;
  in.method = bakeMethodOf(exitance.report.diffusion.method);
  in.quiet = true;
  EnergyWeightSums wholeEscapeSums;
  if (!in.farExitance.empty()) {
    in.farExitance = {};
    in.farField = nullptr;
    if (in.weightSums) in.weightSums = &wholeEscapeSums;
  }
  const auto increment = [&](std::span<const glm::vec3> e, double looseness) {
    in.irradiance = e;
    in.diffusionTolerance =
        std::min(kLoosestIncrementTolerance, looseness * transportIn.diffusionTolerance);
    return transport(in).exitance;
  };
  // Auto: converged to a tenth of the tolerance, well inside the budget of B.
  const std::vector<glm::vec3>& direct = lighting.transportIrradiance();
  BounceResult r = iterateInterreflection(gather, direct, exitance.exitance, increment, s.bounces,
                                          0.1 * s.tolerance);
  // The gather's noise, from a replica of its rays with another seed at the pilot's vertices
  // (without the visibility pilot's noise model, --visibility none, no smoothing is assumed: an
  // upper estimate).
  InterreflectionOptions replicaOptions = options;
  replicaOptions.seed = options.seed + kReplicaSeedOffset;
  replicaOptions.vertices = pilotVertices(m.positions.size(), kPilotVertices);
  const InterreflectionGather replica(m.positions, m.normals, m.triangles, radiance,
                                      float(s.material.eta), replicaOptions);
  report.gatherNoise =
      predictGatherNoise(gather, replica, replicaOptions.vertices, r.exitance, r.irradiance,
                         mesh.areasMm2, lighting.report.rays.noiseModel.meanEffectiveVertices);
  // E in the output: the unweighted direct light plus what the object sent itself.
  if (!lighting.entryWeighted.empty())
    for (std::size_t i = 0; i < r.irradiance.size(); ++i)
      r.irradiance[i] += lighting.irradiance[i] - direct[i];
  lighting.irradiance = std::move(r.irradiance);
  lighting.entryWeighted.clear();
  std::vector<glm::vec3> added = r.exitance;
  for (std::size_t i = 0; i < added.size(); ++i) added[i] -= exitance.exitance[i];
  exitance.exitance = std::move(r.exitance);
  report.enabled = true;
  report.automatic = s.bounces == kAutoBounces;
  report.bounces = r.bounces;
  report.change = r.change;
  report.remaining = r.remaining;
  report.blockedFraction = gather.blockedFraction();
  report.seconds = clock.seconds();
  return added;
}

// Stage 4b without bounces (and before auto bounces): a pilot gather (about 1,000 spread
// vertices, the bounces' rays) estimates how much the light the object sends itself would add to
// B, so that the reported error counts it and a concave object is not baked dark without a word.
void estimateInterreflection(const BakeSettings& s, const PreparedMesh& mesh,
                             const Cubemap& radiance, const DiffusionProfile& profile,
                             const DirectionalAlbedoWeight& weight, const VertexLighting& lighting,
                             const VertexExitance& exitance, bool warnAboveTolerance,
                             InterreflectionReport& report) {
  const Stopwatch clock;
  const TriangleMesh& m = mesh.meshMm;
  InterreflectionOptions options = interreflectionOptions(s, lighting, weight);
  options.vertices = pilotVertices(m.positions.size(), kPilotVertices);
  const InterreflectionGather gather(m.positions, m.normals, m.triangles, radiance,
                                     float(s.material.eta), options);
  const MissingInterreflection missing = estimateMissingInterreflection(
      gather, options.vertices, exitance.exitance, lighting.transportIrradiance(), mesh.areasMm2,
      {m.positions, &profile, s.threads});
  report.estimated = true;
  report.estimatedMissing = missing.relativeRms;
  report.pilotVertices = int(options.vertices.size());
  report.blockedFraction = gather.blockedFraction();
  report.seconds = clock.seconds();
  if (warnAboveTolerance && missing.relativeRms > s.tolerance && !s.quiet) {
    char line[200];
    std::snprintf(line, sizeof line,
                  "interreflection: the light the object sends itself would change B by about "
                  "%.1f%% (%.0f%% of the rays from its surface meet it again); --bounces auto "
                  "adds it",
                  100.0 * missing.relativeRms, 100.0 * gather.blockedFraction());
    warn(line);
  }
}

// The radiance along the normal of an exitance per vertex: through the exit model sss-render uses
// by default, the normalized one (optics/fresnel.h: L = B F_t(1, eta) / (pi (1 - 2 C_1))), or
// where the far field was traced through the exit lobe its exits measured (far_field.h; slope 0
// is the normalized model).
std::vector<glm::vec3> radianceOf(std::span<const glm::vec3> exitance, const FarField& far,
                                  double eta) {
  std::vector<glm::vec3> radiance(exitance.size());
  const ExitLobe lobe{float(eta)};
  const float normalized = float(normalExitRadianceScale(float(eta)));
  for (std::size_t i = 0; i < exitance.size(); ++i)
    radiance[i] = exitance[i] * (far.traced() ? glm::vec3(lobe.normalRadiance(far.slope[i]))
                                              : glm::vec3(normalized));
  return radiance;
}

// The radiance along the normal of B, and (vertexModel) of B - B_far, the part the vertex model
// made, whose exit and light across facets the model error counts (model_error.h); empty without
// a far field.
struct RadianceAlongNormal {
  std::vector<glm::vec3> all, vertexModel;
};

RadianceAlongNormal radianceAlongNormal(std::span<const glm::vec3> exitance, const FarField& far,
                                        double eta) {
  RadianceAlongNormal r{radianceOf(exitance, far, eta), {}};
  if (!far.traced()) return r;
  std::vector<glm::vec3> vertexModel(exitance.begin(), exitance.end());
  for (std::size_t i = 0; i < vertexModel.size(); ++i) vertexModel[i] -= far.exitance[i];
  r.vertexModel = radianceOf(vertexModel, far, eta);
  return r;
}

// Stage 4c: the light that crosses the object unscattered (unscattered_light.h), beside the
// radiance along the normal that B gives.
UnscatteredLight unscatteredStage(const BakeSettings& s, const PreparedMesh& mesh,
                                  const Cubemap& radiance, std::span<const glm::vec3> scattered,
                                  const ErrorBudget& budget) {
  UnscatteredLightOptions options;
  options.mode = s.unscattered;
  options.noiseBudget = budget.unscatteredBudget();
  options.seed = s.seed;
  options.threads = s.threads;
  options.quiet = s.quiet;
  UnscatteredLight light =
      traceUnscatteredLight({mesh.meshMm, mesh.areasMm2, radiance, s.material, scattered, options});
  info("unscattered light: " + std::string(light.traced() ? "traced" : "not traced") + " (" +
           light.report.reason + ")",
       s.quiet);
  return light;
}

// Stage 5: the baked mesh in the file's units, with what made it in a comment.
BakedMesh assembleBakedMesh(TriangleMesh mesh, VertexLighting& lighting, VertexExitance& exitance,
                            std::vector<glm::vec3> radianceNormal, FarField far,
                            const BakeSettings& s, const BakeReport& r) {
  BakedMesh baked;
  baked.mesh = std::move(mesh);
  baked.irradiance = std::move(lighting.irradiance);
  baked.exitance = std::move(exitance.exitance);
  baked.radianceNormal = std::move(radianceNormal);
  baked.farExitance = std::move(far.exitance);
  baked.farExitSlope = std::move(far.slope);
  baked.materialName = s.material.name;
  baked.sigmaA = s.material.sigmaA;
  baked.sigmaSPrime = s.material.sigmaSPrime;
  baked.eta = s.material.eta;
  baked.mmPerUnit = r.mesh.mmPerUnit;
  baked.meshChecked = true;  // prepareMesh warned about its topology
  baked.unscatteredTraced = r.unscattered.traced;
  const bool rays = s.visibility == VisibilityMode::Rays;
  baked.extraComments.push_back(
      "bake method=" + r.transport.methodName() +
      (r.transport.pathTrace ? ""
                             : " profile=" + r.energy.profileName +
                                   " energy=" + kEnergyModelNames.name(r.energy.plan.model) +
                                   " far_field=" + (r.farField.traced ? "traced" : "off") +
                                   " entry=" + kEntryModelNames.name(r.lighting.entry)) +
      " unscattered=" + (r.unscattered.traced ? "traced" : "off") +
      " visibility=" + kVisibilityModeNames.name(s.visibility) + " samples=" +
      std::to_string(rays ? r.lighting.rays.samples : 0) + " seed=" + std::to_string(s.seed));
  return baked;
}

// Stages 2-5 on a prepared mesh and a loaded environment.
BakeOutput bakePrepared(const BakeSettings& s, PreparedMesh mesh, const BakeEnvironment& env,
                        const Stopwatch& clock) {
  const ErrorBudget budget(s.tolerance);
  BakeOutput out;
  BakeReport& report = out.report;
  report.material = s.material;
  report.threads = s.threads;
  report.mesh = mesh.report;
  report.environment = env.report;
  const Cubemap& radiance = env.radiance;
  const bool diffusion = s.method != BakeMethod::PathTrace;
  EnergyStageInput energyIn{mesh.meshMm,         mesh.areasMm2, s.material, s.energy,  s.profile,
                            budget.walkBudget(), diffusion,     s.seed,     s.threads, s.quiet};
  if (diffusion && s.farField != FarFieldMode::Off)
    energyIn.nearWindowMm = farFieldWindowMm(s.material);
  EnergyStage energy = planEnergy(energyIn);
  const DirectionalAlbedoWeight weight(s.material);
  VertexLighting lighting = lightVertices(lightingInput(s, mesh, radiance, energy, budget, weight));
  FarField far;
  if (diffusion) far = farFieldStage(s, mesh, radiance, energyIn, energy, lighting, budget);
  report.farField = far.report;
  TransportInput transportIn{mesh.meshMm,        mesh.areasMm2, lighting.transportIrradiance(),
                             radiance,           s.material,    *energy.profile,
                             energy.report.plan, s.method};
  transportIn.farExitance = far.exitance;
  transportIn.farField = &far;
  transportIn.diffusionTolerance = diffusionTolerance(s, budget, energy.report, lighting.report);
  transportIn.walks = s.walks;
  transportIn.seed = s.seed;
  transportIn.threads = s.threads;
  transportIn.quiet = s.quiet;
  EnergyWeightSums weightSums;  // kept for the bounces
  transportIn.weightSums = &weightSums;
  VertexExitance exitance = transport(transportIn);
  std::vector<glm::vec3> bounced;  // what the bounces added to B; empty without them
  if (diffusion && s.bounces > 0) {
    bounced = addInterreflection(s, mesh, radiance, transportIn, weight, lighting, exitance,
                                 report.interreflection);
  } else if (diffusion) {
    // Without bounces, and first with auto: the pilot's estimate. Auto bounces only when it says
    // they would change B by more than the bounces' own convergence target (a tenth of the
    // tolerance): a convex or nearly convex object costs the pilot alone.
    const bool automatic = s.bounces == kAutoBounces;
    estimateInterreflection(s, mesh, radiance, *energy.profile, weight, lighting, exitance,
                            !automatic, report.interreflection);
    report.interreflection.automatic = automatic;
    // (Bouncing builds its own gather over every vertex: the pilot's ray scene is not kept.)
    if (automatic && report.interreflection.estimatedMissing > 0.1 * s.tolerance) {
      report.interreflection = {};
      bounced = addInterreflection(s, mesh, radiance, transportIn, weight, lighting, exitance,
                                   report.interreflection);
    }
  }

  // The radiance along the normal: B's through the exit model, and the unscattered light's.
  RadianceAlongNormal normal = radianceAlongNormal(exitance.exitance, far, s.material.eta);
  std::vector<glm::vec3>& radianceNormal = normal.all;
  const UnscatteredLight unscattered = unscatteredStage(s, mesh, radiance, radianceNormal, budget);
  for (std::size_t i = 0; i < unscattered.radiance.size(); ++i)
    radianceNormal[i] += unscattered.radiance[i];
  report.unscattered = unscattered.report;

  report.energy = std::move(energy.report);
  report.lighting = std::move(lighting.report);
  report.transport = std::move(exitance.report);
  std::vector<glm::vec3> interreflected;
  if (!bounced.empty()) interreflected = radianceOf(bounced, far, s.material.eta);
  const ModelErrorReport model = modelErrorStage(s, mesh.meshMm, radianceNormal, normal.vertexModel,
                                                 interreflected, radiance, far);
  report.errors = errorReport(report, model, s.tolerance);
  out.baked = assembleBakedMesh(std::move(mesh.mesh), lighting, exitance, std::move(radianceNormal),
                                std::move(far), s, report);
  report.totalSeconds = clock.seconds();
  return out;
}

}  // namespace

BakeEnvironment loadBakeEnvironment(const BakeSettings& s) {
  const Stopwatch clock;
  EnvironmentOptions options;
  options.faceSize = s.environmentFaceSize;
  options.orientation = s.orientation;
  options.threads = s.threads;
  options.read.quiet = s.quiet;
  BakeEnvironment env;
  env.radiance = loadEnvironment(s.environment, options);
  env.report.source = s.environment;
  env.report.faceSize = env.radiance.size();
  env.report.convention = kEquirectConventionNames.name(s.orientation.convention);
  env.report.rotateDeg = s.orientation.rotateDeg;
  env.report.seconds = clock.seconds();
  return env;
}

BakeOutput bake(const BakeSettings& s) {
  const Stopwatch clock;
  validateBakeSettings(s);
  PreparedMesh mesh = prepareMesh({s.meshPath, s.mmPerUnit, s.sizeMm, s.quiet});
  const BakeEnvironment env = loadBakeEnvironment(s);
  return bakePrepared(s, std::move(mesh), env, clock);
}

BakeOutput bake(const BakeSettings& s, const BakeEnvironment& env) {
  const Stopwatch clock;
  validateBakeSettings(s);
  PreparedMesh mesh = prepareMesh({s.meshPath, s.mmPerUnit, s.sizeMm, s.quiet});
  return bakePrepared(s, std::move(mesh), env, clock);
}

}  // namespace sss

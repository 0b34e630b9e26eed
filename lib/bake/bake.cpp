#include "bake/bake.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <utility>

#include "bake/error_budget.h"
#include "bake/material_parts.h"
#include "core/format.h"
#include "core/noise_shrinkage.h"
#include "core/relative_rms.h"
#include "core/timer.h"
#include "core/tool.h"
#include "envmap/environment.h"
#include "lighting/visibility_pilot.h"
#include "material/directional_albedo_weight.h"
#include "optics/exit_lobe.h"
#include "optics/fresnel.h"
#include "raytrace/triangle_scene.h"
#include "transport/interreflection.h"

namespace sss {

namespace {

// What every stage reads and none changes: the settings, the mesh in mm, the environment, the
// tolerance's split (error_budget.h) and the directional entry's weight.
struct BakeScene {
  const BakeSettings& settings;
  const PreparedMesh& mesh;
  const Cubemap& radiance;
  const ErrorBudget budget;
  const DirectionalAlbedoWeight entryWeight;
  // The mesh's ray scene (TriangleSceneOptions::surfaceRays), one BVH for every stage that traces
  // the mesh's surface rays: the visibility, the interreflection pilot, the bounces' gather and its
  // replica, the relightable transfer. Null where none runs (the volumetric path tracer).
  const TriangleScene* rays;
  bool diffusion() const { return settings.method != BakeMethod::PathTrace; }
};

// Stage 2b: the ray scene, for a diffusion sum (its stages 3, 7 and 10b trace the mesh).
std::unique_ptr<const TriangleScene> rayScene(const BakeSettings& s, const PreparedMesh& mesh) {
  if (s.method == BakeMethod::PathTrace) return nullptr;
  return std::make_unique<const TriangleScene>(mesh.meshMm.positions, mesh.meshMm.triangles,
                                               TriangleSceneOptions::surfaceRays(s.run.threads));
}

// Stage 2's input: the walks only for a diffusion sum; with a far field, they also measure the
// near share within its window.
EnergyStageInput energyInput(const BakeScene& scene) {
  const BakeSettings& s = scene.settings;
  const bool farField = scene.diffusion() && s.farField != FarFieldMode::Off;
  return {.meshMm = scene.mesh.meshMm,
          .areasMm2 = scene.mesh.areasMm2,
          .material = s.material,
          .energy = s.energy,
          .profile = s.profile,
          .walkBudget = scene.budget.walkBudget(),
          .runWalks = scene.diffusion(),
          .run = s.run,
          .nearWindowMm = farField ? farFieldWindowMm(s.material) : glm::dvec3(0.0)};
}

// Stage 3's input: E weighted by the directional entry only for a diffusion sum.
LightingInput lightingInput(const BakeScene& scene, const EnergyStage& energy) {
  const BakeSettings& s = scene.settings;
  const bool escape = energy.report.escape();
  const bool directional = s.entry == EntryModel::Directional && scene.diffusion();
  return {.meshMm = scene.mesh.meshMm,
          .areasMm2 = scene.mesh.areasMm2,
          .radiance = scene.radiance,
          .profile = *energy.profile,
          .eta = static_cast<float>(s.material.eta),
          .entry = directional ? &scene.entryWeight : nullptr,
          .mode = s.visibility,
          .samples = s.samples,
          .visibilityBudget = scene.budget.visibilityBudget(escape),
          .visibilityShare = scene.budget.visibilityShare(escape),
          .tolerance = s.tolerance,
          // The bounces' gather takes the visibility's cosine rays (interreflection.h) up to its
          // own count; above, it traces its own (more would grow its hits and their memory).
          .keepCosineHitsUpTo = s.bounces != 0 ? gatherRaysOf(s) : 0,
          .run = s.run,
          .rayScene = scene.rays};
}

// The far field and the escape walks' refinement share the walks' budget: half its variance each.
double farFieldBudget(const BakeScene& scene) {
  return scene.budget.walkBudget() / std::sqrt(2.0);
}

// "<stage>: traced (why)" or "not traced (why)" on stderr, unless quiet.
void sayWhetherTraced(const char* stage, const TracedStageReport& report, bool quiet) {
  info(std::string(stage) + ": " + (report.traced ? "traced" : "not traced") + " (" +
           report.reason + ")",
       quiet);
}

// Stage 4: the far field (far_field.h), for a diffusion sum.
FarField farFieldStage(const BakeScene& scene, const EnergyStage& energy,
                       const VertexLighting& lighting) {
  if (!scene.diffusion()) return {};
  const BakeSettings& s = scene.settings;
  FarField far = traceFarField(
      {.meshMm = scene.mesh.meshMm,
       .areasMm2 = scene.mesh.areasMm2,
       .radiance = scene.radiance,
       .material = s.material,
       .energy = energy.report.plan,
       .irradiance = lighting.transportIrradiance(),
       .options = {.mode = s.farField, .noiseBudget = farFieldBudget(scene), .run = s.run}});
  sayWhetherTraced("far field", far.report, s.run.quiet);
  return far;
}

// Stage 5: with a traced far field the profile spreads the walks' near share, refined to its
// budget (plan_energy.h); otherwise the plan as it is.
EnergyStageReport energyForTransport(const BakeScene& scene, const EnergyStageInput& energyIn,
                                     const EnergyStage& energy, const FarField& far) {
  if (!far.traced()) return energy.report;
  return energyWithFarField(energyIn, energy.report, farFieldBudget(scene),
                            far.report.relativeStdError);
}

// What the diffusion sum may spend: only auto samples budget the rays (forced rays and the
// irradiance cubemap leave their error outside the split).
double diffusionTolerance(const BakeScene& scene, const EnergyStageReport& energy,
                          const LightingReport& lighting) {
  const BakeSettings& s = scene.settings;
  const bool budgetedRays = s.visibility == VisibilityMode::Rays && s.samples == 0;
  return scene.budget.diffusionTolerance(
      energy.escape(), energy.walkError(),
      budgetedRays ? std::optional<double>(lighting.estimatedError) : std::nullopt);
}

// Stage 6's input. weightSums: the energy model's sums with E = 1, kept for the bounces;
// meshCache: the diffusion sums' octree of the mesh, kept for every later transport on it (the
// bounces, the symmetric change, the relightable transfer), which copy this input.
TransportInput transportInput(const BakeScene& scene, const EnergyStage& energy,
                              const EnergyStageReport& energyReport, const VertexLighting& lighting,
                              const FarField& far, EnergyWeightSums& weightSums,
                              DiffusionMeshCache& meshCache) {
  const BakeSettings& s = scene.settings;
  return {.meshMm = scene.mesh.meshMm,
          .areasMm2 = scene.mesh.areasMm2,
          .irradiance = lighting.transportIrradiance(),
          .radiance = scene.radiance,
          .material = s.material,
          .profile = *energy.profile,
          .energy = energyReport.plan,
          .method = s.method,
          .diffusionTolerance = diffusionTolerance(scene, energyReport, lighting.report),
          .walks = s.walks,
          .run = s.run,
          .farField = &far,
          .weightSums = &weightSums,
          .diffusionMeshCache = &meshCache};
}

// The gather's options from the settings: the bounces and the pilot trace the same rays, weighted
// by the directional entry when the transport's light is.
InterreflectionOptions interreflectionOptions(const BakeScene& scene,
                                              const VertexLighting& lighting) {
  const BakeSettings& s = scene.settings;
  return {.rays = gatherRaysWith(s, lighting.cosineHits.perVertex),
          .entry = lighting.entryWeighted.empty() ? nullptr : &scene.entryWeight,
          .run = s.run,
          .visibilityCosineRays = lighting.cosineHits.perVertex,
          .scene = scene.rays};
}

// The interreflection pilot's vertices (spread over the mesh): the estimate without bounces, and
// the replica that measures the gather's noise with them.
constexpr std::size_t kPilotVertices = 1024;
constexpr uint64_t kReplicaSeedOffset = 0x9e3779b9;

// What the light the object sends itself makes of the direct light (interreflection.h): E and B
// with it, and what it added to B; the vectors are empty where no bounce was done.
struct Interreflection {
  std::vector<glm::vec3> irradiance;  // E with the bounces' light (unweighted), for the output
  std::vector<glm::vec3> exitance;    // B with it
  std::vector<glm::vec3> added;       // B - B_direct, whose radiance the model error counts
  InterreflectionReport report;
  // The gather's rays, kept for the relightable stage (which relights under the same environment
  // with the same rays), else null.
  std::shared_ptr<InterreflectionGather> gather;
};

// Stage 7 with bounces: the gather iterated with the transport (iterateInterreflection) until
// converged or the requested bounces are done, and the gather's noise from a replica of its rays
// with another seed at the pilot's vertices (without the visibility pilot's noise model,
// --visibility none, no smoothing is assumed: an upper estimate).
Interreflection bounce(const BakeScene& scene, const TransportInput& transportIn,
                       const VertexLighting& lighting, const VertexExitance& direct) {
  const Stopwatch clock;
  const BakeSettings& s = scene.settings;
  const TriangleMesh& m = scene.mesh.meshMm;
  InterreflectionOptions options = interreflectionOptions(scene, lighting);
  // One ray set, both uses: the visibility's cosine rays that met the object, not traced again.
  if (lighting.cosineHits.perVertex > 0) options.traced = &lighting.cosineHits;
  // A relightable bake stores which rays met the object, so that a relight traces those only.
  options.keepFrontHits = s.relightOrder >= 0;
  const float eta = float(s.material.eta);
  const auto kept = std::make_shared<InterreflectionGather>(m.positions, m.normals, m.triangles,
                                                            scene.radiance, eta, options);
  const InterreflectionGather& gather = *kept;
  EnergyWeightSums wholeEscapeSums;
  const TransportInput linear = linearTransportInput(transportIn, direct, wholeEscapeSums);
  TransportInput in = linear;
  const auto increment = [&](std::span<const glm::vec3> e, double looseness) {
    const IncrementSums sums =
        incrementSums(linear.method, transportIn.diffusionTolerance, looseness);
    in.irradiance = e;
    in.method = sums.method;
    in.diffusionTolerance = sums.tolerance;
    return transport(in).exitance;
  };
  // Auto: converged to a tenth of the tolerance, well inside the budget of B.
  const std::vector<glm::vec3>& directLight = lighting.transportIrradiance();
  // Auto ends the series with its geometric tail: fewer bounces for the same error.
  const bool automatic = s.bounces == kAutoBounces;
  BounceResult r = iterateInterreflection(gather, directLight, direct.exitance, increment,
                                          s.bounces, 0.1 * s.tolerance,
                                          automatic ? BounceTail::Geometric : BounceTail::None);
  // The replica: the same rays with another seed, traced for it.
  InterreflectionOptions replicaOptions = options;
  replicaOptions.traced = nullptr;
  replicaOptions.run.seed = options.run.seed + kReplicaSeedOffset;
  replicaOptions.vertices = pilotVertices(m.positions.size(), kPilotVertices);
  replicaOptions.mirroredLightsOf = &gather;
  const InterreflectionGather replica(m.positions, m.normals, m.triangles, scene.radiance, eta,
                                      replicaOptions);
  Interreflection out;
  InterreflectionReport& report = out.report;
  report.gatherNoise = predictGatherNoise(gather, replica, replicaOptions.vertices, r.exitance,
                                          r.irradiance, scene.mesh.areasMm2,
                                          lighting.report.rays.noiseModel.meanEffectiveVertices);
  // E in the output: the unweighted direct light plus what the object sent itself.
  if (!lighting.entryWeighted.empty())
    for (std::size_t i = 0; i < r.irradiance.size(); ++i)
      r.irradiance[i] += lighting.irradiance[i] - directLight[i];
  out.added = r.exitance;
  for (std::size_t i = 0; i < out.added.size(); ++i) out.added[i] -= direct.exitance[i];
  out.irradiance = std::move(r.irradiance);
  out.exitance = std::move(r.exitance);
  report.enabled = true;
  report.automatic = automatic;
  report.bounces = r.bounces;
  report.tail = r.tail;
  report.gatherRays = gather.rays();
  report.reusedRays = gather.visibilityCosineRays();
  report.change = r.change;
  report.remaining = r.remaining;
  report.blockedFraction = gather.blockedFraction();
  report.seconds = clock.seconds();
  if (s.relightOrder >= 0) out.gather = kept;
  return out;
}

// Stage 7 without bounces (and before auto bounces): a pilot gather (about 1,000 spread
// vertices, the bounces' rays) estimates how much the light the object sends itself would add to
// B, so that the reported error counts it and a concave object is not baked dark without a word.
InterreflectionReport estimateInterreflection(const BakeScene& scene,
                                              const DiffusionProfile& profile,
                                              const VertexLighting& lighting,
                                              const VertexExitance& direct,
                                              bool warnAboveTolerance) {
  const Stopwatch clock;
  const BakeSettings& s = scene.settings;
  const TriangleMesh& m = scene.mesh.meshMm;
  InterreflectionOptions options = interreflectionOptions(scene, lighting);
  options.vertices = pilotVertices(m.positions.size(), kPilotVertices);
  options.traceMirroredLights = false;
  const InterreflectionGather gather(m.positions, m.normals, m.triangles, scene.radiance,
                                     float(s.material.eta), options);
  const MissingInterreflection missing = estimateMissingInterreflection(
      gather, options.vertices, direct.exitance, lighting.transportIrradiance(),
      scene.mesh.areasMm2, {m.positions, &profile, s.run.threads});
  InterreflectionReport report;
  report.estimated = true;
  report.estimatedMissing = missing.relativeRms;
  report.pilotVertices = int(options.vertices.size());
  report.blockedFraction = gather.blockedFraction();
  report.seconds = clock.seconds();
  if (warnAboveTolerance && missing.relativeRms > s.tolerance && !s.run.quiet) {
    char line[200];
    std::snprintf(line, sizeof line,
                  "interreflection: the light the object sends itself would change B by about "
                  "%.1f%% (%.0f%% of the rays from its surface meet it again); --bounces auto "
                  "adds it",
                  100.0 * missing.relativeRms, 100.0 * gather.blockedFraction());
    warn(line);
  }
  return report;
}

// Stage 7: bounces when asked; otherwise, and first with auto, the pilot's estimate. Auto bounces
// only when it says they would change B by more than the bounces' own convergence target (a
// tenth of the tolerance): a convex or nearly convex object costs the pilot alone. (Bouncing
// builds its own gather over every vertex: the pilot's ray scene is not kept.)
Interreflection interreflectionStage(const BakeScene& scene, const EnergyStage& energy,
                                     const TransportInput& transportIn,
                                     const VertexLighting& lighting, const VertexExitance& direct) {
  const BakeSettings& s = scene.settings;
  if (!scene.diffusion()) return {};
  if (s.bounces > 0) return bounce(scene, transportIn, lighting, direct);
  const bool automatic = s.bounces == kAutoBounces;
  Interreflection estimate;
  estimate.report = estimateInterreflection(scene, *energy.profile, lighting, direct, !automatic);
  estimate.report.automatic = automatic;
  if (automatic && estimate.report.estimatedMissing > 0.1 * s.tolerance)
    return bounce(scene, transportIn, lighting, direct);
  return estimate;
}

// Stage 7's named step: E and B as the output holds them, with the bounces' light where it was
// added (their vectors are moved, not copied).
struct BakedLight {
  std::vector<glm::vec3> irradiance, exitance;
};

BakedLight combineInterreflection(VertexLighting& lighting, VertexExitance& direct,
                                  Interreflection& bounced) {
  if (bounced.exitance.empty()) return {std::move(lighting.irradiance), std::move(direct.exitance)};
  return {std::move(bounced.irradiance), std::move(bounced.exitance)};
}

// Stage 5b: the exit lobe B leaves through (optics/exit_lobe.h), the one sss-render draws by
// default. Where the far field was traced, the lobe its exits measured (far_field.h). Else, per
// channel where the half-space sends more than kHalfSpaceLobeMinChange more or less along the
// normal than the normalized model says (low albedo), the lobe of this object's escape walks
// (halfSpaceOrWalksSlope); 0 (the normalized model) elsewhere. Why: at low albedo much of the
// light comes back before it diffuses, and the interior radiance at the boundary is not
// isotropic: on skin1 spheres of 5-20 mm under uniform light the normalized model is 2-4 / 6-7 /
// 8-9 % (R / G / B) too bright along the normal (docs/accuracy.md, "The exit model at low
// albedo"). Why not at high albedo: there the half-space's 1-2 % is within what finite objects
// differ from it (on the 50 mm marble and skim-milk bunny the half-space's exit is 0.1-0.3
// points further from the reference than the normalized model: light diffusing out of a small
// object leaves more along the normal than a half-space's), and the walks' slope is too noisy to
// tell (docs/physics.md, "The half-space's exit lobe"). The path tracer measures its own
// radiance: no lobe.
constexpr double kHalfSpaceLobeMinChange = 0.02;

struct ExitLobeStage {
  std::vector<glm::vec3> slope;  // per vertex; empty: the normalized model
  ExitLobeReport report;
};

// One channel's slope: the half-space's, k_h, whose radiance along the normal is w(1) times the
// normalized model's (material/directional_albedo_weight.h, the half-space Monte Carlo), moved
// towards the slope of the escape walks' exits, k_w (their mean internal cosine over the surface,
// pathtrace/escape_probability.h), by shrunkByNoise(k_w - k_h): the walks know the object's
// shape (a sphere a few mean free paths across sends more along the normal than a half-space),
// the table knows the half-space without noise. `variance` gets the noise passed on.
// The departure is shrunk as by shrunkByNoise with kWalkLobeSignificance times its noise's
// variance, so that one at 2 standard errors keeps half: the half-space's lobe is right on a
// large object, and a departure within the walks' noise would only add it (two seeds of a
// 180 mm skin1 sphere differ by 1.9 %, by 2.3 % with the plain shrinkage, by 1.5 % with the
// normalized model; tests/bench/results/relight).
constexpr double kWalkLobeSignificance = 4.0;

double halfSpaceOrWalksSlope(const ExitLobe& lobe, float halfSpaceRatio, const EscapeResult& walks,
                             int c, double& variance) {
  const double halfSpace = lobe.slopeForNormalRatio(halfSpaceRatio);
  variance = 0.0;
  if (walks.walks == 0) return halfSpace;
  const double m = walks.exitCosine[c], dk = lobe.slopeDerivative(m);
  const double v = dk * dk * walks.exitCosineVariance[c], departure = lobe.slopeFor(m) - halfSpace;
  const double significant = kWalkLobeSignificance * v;
  variance = std::pow(shrunkByNoiseSlope(departure, significant), 2) * v;
  return std::clamp(halfSpace + shrunkByNoise(departure, significant), ExitLobe::kMinSlope,
                    ExitLobe::kMaxSlope);
}

// The report's noise is relative RMS over channels weighted like the radiance's (relative_rms.h):
// each channel's by its share of the light, P E summed over the surface (B under the escape model,
// before the transport has made it).
ExitLobeStage exitLobeStage(const BakeScene& scene, const EnergyStageReport& energy,
                            const VertexLighting& lighting, const FarField& far) {
  if (far.traced())
    return {far.slope, {"far field", far.report.meanExitSlope, far.report.lobeNoise}};
  if (!scene.diffusion()) return {};
  const ExitLobe lobe{float(scene.settings.material.eta)};
  const glm::vec3 halfSpace = scene.entryWeight.at(1.0f);  // w(1): per unit normalized radiance
  glm::vec3 slope(0.0f);
  glm::dvec3 light(0.0);
  const std::vector<glm::vec3>& irradiance = lighting.transportIrradiance();
  for (std::size_t i = 0; i < irradiance.size(); ++i)
    light += double(scene.mesh.areasMm2[i]) * glm::dvec3(irradiance[i]);
  light *= energy.plan.escape.walks > 0 ? energy.plan.escape.mean : energy.plan.halfSpaceAlbedo;
  double noise2 = 0.0;
  for (int c = 0; c < 3; ++c) {
    if (!(std::abs(halfSpace[c] - 1.0f) > kHalfSpaceLobeMinChange)) continue;
    double variance = 0.0;
    slope[c] = float(halfSpaceOrWalksSlope(lobe, halfSpace[c], energy.plan.escape, c, variance));
    // The radiance along the normal, (1 + k) A_0 / (A_0 + k A_1) of the normalized model's: its
    // relative change per unit k is (A_0 - A_1) / ((1 + k) (A_0 + k A_1)).
    const double a0 = lobe.moment(0), a1 = lobe.moment(1), k = slope[c];
    noise2 += variance * std::pow((a0 - a1) / ((1.0 + k) * (a0 + k * a1)) * light[c], 2);
  }
  noise2 /= std::max(glm::dot(light, light), 1e-300);
  if (slope == glm::vec3(0.0f)) return {};
  return {std::vector<glm::vec3>(scene.mesh.meshMm.positions.size(), slope),
          {"half-space", glm::dvec3(slope), std::sqrt(noise2)}};
}

// The radiance along the normal of an exitance per vertex, through the exit lobe of `slopes`
// (ExitLobeStage; empty: the normalized model, optics/fresnel.h: L = B F_t(1, eta) /
// (pi (1 - 2 C_1))).
std::vector<glm::vec3> radianceOf(std::span<const glm::vec3> exitance,
                                  std::span<const glm::vec3> slopes, double eta) {
  std::vector<glm::vec3> radiance(exitance.size());
  const ExitLobe lobe{float(eta)};
  const float normalized = float(normalExitRadianceScale(float(eta)));
  for (std::size_t i = 0; i < exitance.size(); ++i)
    radiance[i] = exitance[i] * (slopes.empty() ? glm::vec3(normalized)
                                                : glm::vec3(lobe.normalRadiance(slopes[i])));
  return radiance;
}

// The radiance along the normal of B, and (vertexModel) of B - B_far, the part the vertex model
// made, whose exit and light across facets the model error counts (model_error.h); empty without
// a far field.
struct RadianceAlongNormal {
  std::vector<glm::vec3> all, vertexModel;
};

RadianceAlongNormal radianceAlongNormal(std::span<const glm::vec3> exitance, const FarField& far,
                                        std::span<const glm::vec3> slopes, double eta) {
  RadianceAlongNormal r{radianceOf(exitance, slopes, eta), {}};
  if (!far.traced()) return r;
  std::vector<glm::vec3> vertexModel(exitance.begin(), exitance.end());
  for (std::size_t i = 0; i < vertexModel.size(); ++i) vertexModel[i] -= far.exitance[i];
  r.vertexModel = radianceOf(vertexModel, slopes, eta);
  return r;
}

// Stage 9: the light that crosses the object unscattered (unscattered_light.h), beside the
// radiance along the normal that B gives.
UnscatteredLight unscatteredStage(const BakeScene& scene, std::span<const glm::vec3> scattered) {
  const BakeSettings& s = scene.settings;
  UnscatteredLight light = traceUnscatteredLight(
      {.meshMm = scene.mesh.meshMm,
       .areasMm2 = scene.mesh.areasMm2,
       .radiance = scene.radiance,
       .material = s.material,
       .scatteredRadiance = scattered,
       .options = {
           .mode = s.unscattered, .noiseBudget = scene.budget.unscatteredBudget(), .run = s.run}});
  sayWhetherTraced("unscattered light", light.report, s.run.quiet);
  return light;
}

// The radiance along the normal in the output: B's and the unscattered light's.
std::vector<glm::vec3> withUnscattered(std::vector<glm::vec3> scattered,
                                       const UnscatteredLight& unscattered) {
  for (std::size_t i = 0; i < unscattered.radiance.size(); ++i)
    scattered[i] += unscattered.radiance[i];
  return scattered;
}

// Stage 10: the model's own error (model_error.h), from the output's radiance; said when it is
// above the tolerance, which then bounds only the numerical part.
// With a traced far field only vertexModel (B - B_far's radiance) is the vertex model's, whose
// exit model and light across facets the model error counts (B_far's paths met the facets
// themselves); without it (empty), all of the radiance.
// interreflected: the radiance of what the bounces added to B (empty without bounces).
ModelErrorReport modelErrorStage(const BakeScene& scene, std::span<const glm::vec3> radianceNormal,
                                 std::span<const glm::vec3> vertexModel,
                                 std::span<const glm::vec3> interreflected, const FarField& far) {
  const BakeSettings& s = scene.settings;
  const ModelErrorReport model = estimateModelError(
      {.mesh = scene.mesh.meshMm,
       .radianceAlongNormal = radianceNormal,
       .radiance = scene.radiance,
       .eta = float(s.material.eta),
       .exitModelSpread = exitModelSpread(s.material),
       .farFieldError = far.traced() ? far.report.averagingBias : far.report.sensitivity,
       .threads = s.run.threads,
       .vertexModelRadiance = vertexModel,
       .interreflectedRadiance = interreflected});
  return model;
}

// Stage 11: the predicted errors. The path tracer's walks do not use E, so only their own error
// counts (and the unscattered light's, which is added to both). The model's error adds to either.
BakeErrorReport errorReport(const BakeReport& r, const ModelErrorReport& model, double tolerance) {
  BakeErrorReport e;
  e.exitance = r.transport.estimatedError;
  e.tolerance = tolerance;
  e.model = model;
  const UnscatteredLightReport& u = r.unscattered;
  e.unscattered = u.traced ? u.relativeStdError : u.share;
  e.exitLobe = r.exitLobe.noise;
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

// Stage 10b (--relightable): the SH transfer of B through the transport the bounces use, and
// the ratios that make the radiance along the normal of it (relight.h; g from the bake's own E
// through the same transport and bounces); then the bake relit under its own environment,
// against itself.
RelightTransfer relightStage(const BakeScene& scene, const TransportInput& transportIn,
                             const VertexLighting& lighting, const VertexExitance& direct,
                             const Interreflection& bounced, const BakedLight& light,
                             std::span<const glm::vec3> scatteredRadiance,
                             std::span<const glm::vec3> radianceNormal, bool unscatteredTraced) {
  const InterreflectionReport& bounces = bounced.report;
  const BakeSettings& s = scene.settings;
  if (s.relightOrder < 0 || !scene.diffusion()) return {};
  EnergyWeightSums wholeEscapeSums;
  const TransportInput linear = linearTransportInput(transportIn, direct, wholeEscapeSums);
  RelightTransfer t =
      relightTransfer({.meshMm = scene.mesh.meshMm,
                       .transport = linear,
                       .entry = lighting.entryWeighted.empty() ? nullptr : &scene.entryWeight,
                       .order = s.relightOrder,
                       .rays = kRelightRays,
                       .bounces = bounces.enabled ? bounces.bounces : 0,
                       .bounceTail = bounces.enabled && bounces.tail,
                       .gatherRays = bounces.enabled ? bounces.gatherRays : gatherRaysOf(s),
                       .gatherVisibilityRays = bounces.enabled ? bounces.reusedRays : 0,
                       .gatherFrontHits = bounced.gather ? bounced.gather->frontHits()
                                                         : std::span<const uint16_t>(),
                       .exitance = light.exitance,
                       .radianceNormal = scatteredRadiance,
                       .unscattered = unscatteredTraced,
                       .run = s.run,
                       .scene = scene.rays});
  const Stopwatch clock;
  OwnEnvironmentRelight ownRelight = relightOwnEnvironment(
      s.meshPath, {scene.mesh.meshMm, s.material, t}, scene.radiance,
      lighting.transportIrradiance(), scatteredRadiance, s.run, bounced.gather, scene.rays);
  t.radianceGain = std::move(ownRelight.radianceGain);
  const RelitLight& own = ownRelight.relit;
  t.report.selfError = relativeRms(own.radianceNormal, radianceNormal);
  t.report.compactLights = own.compactLights;
  t.report.compactFluxShare = own.compactFluxShare;
  t.report.seconds += clock.seconds();
  info("relightable transfer (order " + std::to_string(t.order) +
           "): " + format("%.3f s", t.report.seconds) + ", relit under its own environment " +
           percent(t.report.selfError) + " RMS from the bake",
       s.run.quiet);
  return t;
}

// A bake whose predicted error is above --tolerance says so, whichever part is above it (the
// tolerance bounds the numerical part; the model's error is what the models leave, which more
// rays cannot remove), and writes its output; the JSON's estimated_error.tolerance_met says it
// too. A warning, not progress, but like the mesh's warnings it obeys --quiet.
void warnAboveTolerance(const BakeErrorReport& e, bool quiet) {
  if (e.total <= e.tolerance || quiet) return;
  const ModelErrorReport& m = e.model;
  char line[400];
  std::snprintf(line, sizeof line,
                "the estimated error, %.1f%% of the radiance along the normal, is above "
                "--tolerance %g%%: numerical %.1f%%, model %.1f%% (exit model %.1f%%, facets "
                "%.1f%%, light across facets %.1f%%, far field %.1f%%, interreflection %.1f%%",
                100.0 * e.total, 100.0 * e.tolerance, 100.0 * e.numerical, 100.0 * m.total,
                100.0 * m.exitModel, 100.0 * m.facets, 100.0 * m.facetLight, 100.0 * m.farField,
                100.0 * m.interreflection);
  const std::string borders =
      m.materialInterface > 0.0
          ? format(", borders between materials %.1f%%)", 100.0 * m.materialInterface)
          : std::string(")");
  warn(line + borders);
}

// Stage 12: the baked mesh in the file's units, with what made it in a comment.
BakedMesh assembleBakedMesh(TriangleMesh mesh, BakedLight light,
                            std::vector<glm::vec3> radianceNormal, FarField far,
                            ExitLobeStage exitLobe, RelightTransfer relight, const BakeSettings& s,
                            const BakeReport& r) {
  BakedMesh baked;
  baked.mesh = std::move(mesh);
  baked.irradiance = std::move(light.irradiance);
  baked.exitance = std::move(light.exitance);
  baked.radianceNormal = std::move(radianceNormal);
  baked.farExitance = std::move(far.exitance);
  baked.exitSlope = std::move(exitLobe.slope);
  baked.materialName = s.material.name;
  baked.sigmaA = s.material.sigmaA;
  baked.sigmaSPrime = s.material.sigmaSPrime;
  baked.eta = s.material.eta;
  baked.mmPerUnit = r.mesh.mmPerUnit;
  baked.meshChecked = true;  // prepareMesh warned about its topology
  baked.unscatteredTraced = r.unscattered.traced;
  baked.relightOrder = relight.order;
  baked.relightTransfer = std::move(relight.relightTransfer);
  baked.radianceGain = std::move(relight.radianceGain);
  baked.exitancePerRadiance = std::move(relight.exitancePerRadiance);
  baked.escapeProbability = std::move(relight.escapeProbability);
  baked.gatherFrontHits = std::move(relight.gatherFrontHits);
  baked.relightTransport = std::move(relight.relightTransport);
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
      std::to_string(rays ? r.lighting.rays.samples : 0) + " seed=" + std::to_string(s.run.seed));
  return baked;
}

// Stage 1: the mesh, validated and cleaned, in mm.
PreparedMesh prepareMeshStage(const BakeSettings& s) {
  return prepareMesh(
      {.path = s.meshPath, .mmPerUnit = s.mmPerUnit, .sizeMm = s.sizeMm, .quiet = s.run.quiet});
}

// The settings with another material (a part's, material_map.h).
BakeSettings withMaterial(const BakeSettings& s, const Material& material) {
  BakeSettings out = s;
  out.material = material;
  return out;
}

// The materials the mesh's parts bake with (material_map.h): -m's unless the material map gives
// parts others. Several bake whole each (material_parts.h), which the path tracer (one
// homogeneous medium) and a relightable bake (one material's transfer) do not.
PartMaterials partMaterialsStage(const BakeSettings& s, const PreparedMesh& mesh) {
  PartMaterials m = materialsForParts(s.meshPath, s.materialMap, mesh.parts, s.material);
  if (!m.single()) {
    const std::string several =
        "the material map gives the parts " + std::to_string(m.materials.size()) + " materials";
    if (s.method == BakeMethod::PathTrace)
      fail(s.meshPath, several + ", and --method pathtrace traces one homogeneous medium");
    if (s.relightOrder >= 0)
      fail(s.meshPath, several + ", and --relightable stores one material's transfer");
  }
  for (const Material& material : m.materials)
    if (material.name != s.material.name) validateBakeSettings(withMaterial(s, material));
  return m;
}

// With several materials, this material's part of the symmetric kernel's change from the
// receiver's rule (material_parts.h): (T(s E) - s T(E)) / 2 for the vertices' share s of the
// material and its transport T (the bounces' linear transport: the traced far field keeps the
// receiver's rule), in B and in the radiance along the normal.
struct SymmetricChange {
  std::vector<glm::vec3> exitance, radiance;
};

SymmetricChange symmetricChange(const BakeScene& scene, const TransportInput& transportIn,
                                const VertexExitance& direct, std::span<const glm::vec3> slopes,
                                std::span<const float> share) {
  if (share.empty() || !scene.diffusion()) return {};
  EnergyWeightSums sums;
  TransportInput in = linearTransportInput(transportIn, direct, sums);
  const std::span<const glm::vec3> all = transportIn.irradiance;
  std::vector<glm::vec3> entering(all.begin(), all.end());
  for (std::size_t i = 0; i < entering.size(); ++i) entering[i] *= share[i];
  const std::vector<glm::vec3> received = transport(in).exitance;
  in.irradiance = entering;
  std::vector<glm::vec3> change = transport(in).exitance;
  for (std::size_t i = 0; i < change.size(); ++i)
    change[i] = 0.5f * (change[i] - share[i] * received[i]);
  std::vector<glm::vec3> radiance = radianceOf(change, slopes, scene.settings.material.eta);
  return {std::move(change), std::move(radiance)};
}

// Stages 2-12 (bake.h) on a prepared mesh and a loaded environment; share (several materials):
// each vertex's share of this material, for symmetricChange.
BakeOutput bakePrepared(const BakeSettings& s, PreparedMesh mesh, const BakeEnvironment& env,
                        const Stopwatch& clock, std::span<const float> share = {}) {
  const Stopwatch rayClock;
  const std::unique_ptr<const TriangleScene> rays = rayScene(s, mesh);
  const double raySceneSeconds = rayClock.seconds();
  const BakeScene scene{
      s,         mesh, env.radiance, ErrorBudget(s.tolerance), DirectionalAlbedoWeight(s.material),
      rays.get()};
  const EnergyStageInput energyIn = energyInput(scene);
  const EnergyStage energy = planEnergy(energyIn);
  VertexLighting lighting = lightVertices(lightingInput(scene, energy));
  FarField far = farFieldStage(scene, energy, lighting);
  EnergyStageReport energyReport = energyForTransport(scene, energyIn, energy, far);
  EnergyWeightSums weightSums;
  DiffusionMeshCache meshCache;
  const TransportInput transportIn =
      transportInput(scene, energy, energyReport, lighting, far, weightSums, meshCache);
  ExitLobeStage exitLobe = exitLobeStage(scene, energyReport, lighting, far);
  VertexExitance direct = transport(transportIn);
  Interreflection bounced = interreflectionStage(scene, energy, transportIn, lighting, direct);
  SymmetricChange symmetric = symmetricChange(scene, transportIn, direct, exitLobe.slope, share);
  BakedLight light = combineInterreflection(lighting, direct, bounced);
  const RadianceAlongNormal normal =
      radianceAlongNormal(light.exitance, far, exitLobe.slope, s.material.eta);
  const UnscatteredLight unscattered = unscatteredStage(scene, normal.all);
  std::vector<glm::vec3> radianceNormal = withUnscattered(normal.all, unscattered);
  const std::vector<glm::vec3> interreflected =
      bounced.added.empty() ? std::vector<glm::vec3>{}
                            : radianceOf(bounced.added, exitLobe.slope, s.material.eta);
  const ModelErrorReport model =
      modelErrorStage(scene, radianceNormal, normal.vertexModel, interreflected, far);
  RelightTransfer relight = relightStage(scene, transportIn, lighting, direct, bounced, light,
                                         normal.all, radianceNormal, unscattered.traced());

  BakeOutput out;
  BakeReport& report = out.report;
  report.material = s.material;
  report.threads = s.run.threads;
  report.raySceneSeconds = raySceneSeconds;
  report.mesh = mesh.report;
  report.environment = env.report;
  report.energy = std::move(energyReport);
  report.lighting = std::move(lighting.report);
  report.farField = far.report;
  report.exitLobe = exitLobe.report;
  report.transport = std::move(direct.report);
  report.interreflection = bounced.report;
  report.unscattered = unscattered.report;
  report.errors = errorReport(report, model, s.tolerance);
  if (share.empty()) warnAboveTolerance(report.errors, s.run.quiet);  // else the mix warns
  report.relight = relight.report;
  out.baked = assembleBakedMesh(std::move(mesh.mesh), std::move(light), std::move(radianceNormal),
                                std::move(far), std::move(exitLobe), std::move(relight), s, report);
  out.symmetricChange = std::move(symmetric.exitance);
  out.symmetricChangeRadiance = std::move(symmetric.radiance);
  report.totalSeconds = clock.seconds();
  return out;
}

// With several materials, the report of each material's bake (MaterialBakeReport).
MaterialBakeReport materialBakeReport(const BakeReport& r, const PartMaterials& materials,
                                      const MeshParts& parts, std::size_t m, double areaShare) {
  MaterialBakeReport out{.material = r.material,
                         .parts = {},
                         .areaShare = areaShare,
                         .method = r.transport.methodName(),
                         .errors = r.errors,
                         .seconds = r.totalSeconds};
  for (std::size_t p = 0; p < parts.parts.size(); ++p) {
    const std::string& key = parts.parts[p].material;
    if (materials.partMaterial[p] == m &&
        std::find(out.parts.begin(), out.parts.end(), key) == out.parts.end())
      out.parts.push_back(key);
  }
  return out;
}

// Several materials: each one's share of each vertex and of the surface.
struct MaterialShares {
  std::vector<std::vector<float>> vertex;  // per material, per vertex (vertexMaterialShares)
  std::vector<double> surface;             // per material
  std::size_t largest = 0;                 // the material with the largest surface share
};

MaterialShares materialShares(const PartMaterials& materials, const PreparedMesh& mesh) {
  MaterialShares out;
  out.vertex = vertexMaterialShares(mesh.meshMm, mesh.parts.trianglePart, materials.partMaterial,
                                    materials.materials.size());
  out.surface = areaShares(out.vertex, mesh.areasMm2);
  out.largest = std::max_element(out.surface.begin(), out.surface.end()) - out.surface.begin();
  return out;
}

// Stages 2-12 once per material, the object all of it, with the symmetric change unless the
// receiver's rule alone is asked for.
std::vector<BakeOutput> bakeEachMaterial(const BakeSettings& s, const PartMaterials& materials,
                                         const PreparedMesh& mesh, const MaterialShares& shares,
                                         const BakeEnvironment& env) {
  std::vector<BakeOutput> bakes;
  const bool symmetric = s.materialRule != MaterialRule::Receiver;
  for (std::size_t m = 0; m < materials.materials.size(); ++m) {
    const Material& material = materials.materials[m];
    info("material " + std::to_string(m + 1) + " of " + std::to_string(materials.materials.size()) +
             ": " + material.name + " (" + percent(shares.surface[m]) + " of the surface)",
         s.run.quiet);
    bakes.push_back(bakePrepared(withMaterial(s, material), mesh, env, Stopwatch(),
                                 symmetric ? shares.vertex[m] : std::span<const float>()));
  }
  return bakes;
}

// The error near the borders (materialInterfaceError) from the materials' own bakes.
double borderError(const std::vector<BakeOutput>& bakes, const PartMaterials& materials,
                   const PreparedMesh& mesh, const MaterialShares& shares) {
  std::vector<std::span<const glm::vec3>> radiance;
  std::vector<glm::dvec3> sigmaTr;
  for (std::size_t m = 0; m < bakes.size(); ++m) {
    radiance.push_back(bakes[m].baked.radianceNormal);
    sigmaTr.push_back(materials.materials[m].sigmaTr());
  }
  return materialInterfaceError(mesh.meshMm, mesh.areasMm2, shares.vertex, radiance, sigmaTr);
}

// The materials' bakes mixed (material_parts.h): the light per vertex by the rule, the report the
// largest material's with the errors mixed and the border's added, each material's own beside.
BakeOutput mixMaterialBakes(std::vector<BakeOutput> bakes, const BakeSettings& s,
                            const PartMaterials& materials, const PreparedMesh& mesh,
                            const MaterialShares& shares) {
  const double border = borderError(bakes, materials, mesh, shares);
  std::vector<BakedMesh> baked;
  std::vector<BakeErrorReport> errors;
  std::vector<MaterialBakeReport> reports;
  std::vector<std::vector<glm::vec3>> changes, radianceChanges;
  for (std::size_t m = 0; m < bakes.size(); ++m) {
    BakeOutput& one = bakes[m];
    reports.push_back(materialBakeReport(one.report, materials, mesh.parts, m, shares.surface[m]));
    errors.push_back(one.report.errors);
    baked.push_back(std::move(one.baked));
    changes.push_back(std::move(one.symmetricChange));
    radianceChanges.push_back(std::move(one.symmetricChangeRadiance));
  }
  BakeOutput out = std::move(bakes[shares.largest]);
  out.baked = mixBakedMeshes(std::move(baked), shares.vertex, shares.largest);
  applySymmetricChange(out.baked, changes, radianceChanges, s.materialRule);
  std::string partMaterials = "bake part_materials=";
  for (const MaterialBakeReport& r : reports)
    for (const std::string& key : r.parts)
      partMaterials += (partMaterials.back() == '=' ? "" : ",") + key + ":" + r.material.name;
  out.baked.extraComments.push_back(partMaterials);
  BakeErrorReport& e = out.report.errors = mixErrorReports(errors, shares.surface);
  e.model.materialInterface = border;
  e.model.total = std::hypot(e.model.total, border);
  e.total = std::hypot(e.numerical, e.model.total);
  warnAboveTolerance(e, s.run.quiet);
  out.report.materials = std::move(reports);
  for (const std::uint32_t m : materials.partMaterial)
    out.partMaterials.push_back(materials.materials[m]);
  return out;
}

// Stages 2-12 on one material, or once per material and mixed (material_parts.h).
BakeOutput bakeMaterials(const BakeSettings& s, const PartMaterials& materials, PreparedMesh mesh,
                         const BakeEnvironment& env, const Stopwatch& clock) {
  if (materials.single())
    return bakePrepared(withMaterial(s, materials.materials.front()), std::move(mesh), env, clock);
  const MaterialShares shares = materialShares(materials, mesh);
  BakeOutput out = mixMaterialBakes(bakeEachMaterial(s, materials, mesh, shares, env), s, materials,
                                    mesh, shares);
  out.report.totalSeconds = clock.seconds();
  return out;
}

// Stages 2-12, with the texture's 1b and 13 around them when settings ask for a lightmap.
BakeOutput bakeMesh(const BakeSettings& s, const PartMaterials& materials, PreparedMesh mesh,
                    const BakeEnvironment& env, const Stopwatch& clock) {
  if (s.texture.size == 0) return bakeMaterials(s, materials, std::move(mesh), env, clock);
  TextureMesh texture = refineForTexture(std::move(mesh), s.texture, s.run.quiet);
  BakeOutput out = bakeMaterials(s, materials, std::move(texture.mesh), env, clock);
  BakedLightmap lightmap = bakeLightmap(texture, out.baked, s.texture, s.run.quiet);
  out.lightmap = std::move(lightmap.map);
  out.lightmapSource = std::move(texture.source);
  out.report.lightmap = lightmap.report;
  out.report.totalSeconds = clock.seconds();
  return out;
}

}  // namespace

BakeEnvironment loadBakeEnvironment(const BakeSettings& s) {
  const Stopwatch clock;
  EnvironmentOptions options;
  options.faceSize = s.environmentFaceSize;
  options.orientation = s.orientation;
  options.threads = s.run.threads;
  options.read.quiet = s.run.quiet;
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
  PreparedMesh mesh = prepareMeshStage(s);
  const PartMaterials materials = partMaterialsStage(s, mesh);
  const BakeEnvironment env = loadBakeEnvironment(s);
  return bakeMesh(s, materials, std::move(mesh), env, clock);
}

BakeOutput bake(const BakeSettings& s, const BakeEnvironment& env) {
  const Stopwatch clock;
  validateBakeSettings(s);
  PreparedMesh mesh = prepareMeshStage(s);
  const PartMaterials materials = partMaterialsStage(s, mesh);
  return bakeMesh(s, materials, std::move(mesh), env, clock);
}

}  // namespace sss

#include "transport/finite_object_energy.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/error.h"
#include "core/format.h"
#include "core/timer.h"
#include "material/gaussian_profile.h"
#include "material/halfspace_albedo.h"
#include "material/material.h"
#include "material/windowed_profile.h"
#include "mesh/triangle_mesh.h"

namespace sss {

glm::dvec3 farFieldWindowMm(const Material& material) {
  return kFarFieldWindowLengths / material.sigmaTr();
}

namespace {

constexpr double kExcessDiffusionLengths = 4.0;
constexpr int kMaxRefinements = 3;

// Width (mm) of the Gaussian that spreads the excess P - R.
double escapeExcessSigmaMm(const Material& material) {
  const glm::dvec3 sigmaTr = material.sigmaTr();
  const double shortest = std::min({sigmaTr.x, sigmaTr.y, sigmaTr.z});
  return shortest > 0.0 ? kExcessDiffusionLengths / shortest : 0.0;
}

// exitance: the profile's sum B_i; rho: the same sum with E = 1; then B_i becomes
// min(P_i, R) B_i / rho_i + max(0, P_i - R) Ebar_i per channel (rho_i = 0: only the second term);
// excess gets the second term alone.
void applyEscapeEnergy(std::span<glm::vec3> exitance, std::span<const glm::vec3> rho,
                       std::span<const glm::vec3> escapeProbability,
                       const glm::dvec3& halfSpaceAlbedo,
                       std::span<const glm::vec3> averageIrradiance,
                       std::vector<glm::vec3>& excess) {
  const std::size_t n = exitance.size();
  if (rho.size() != n || escapeProbability.size() != n || averageIrradiance.size() != n)
    fail("", "energy: one rho, escape probability and average irradiance per vertex needed");
  excess.assign(n, glm::vec3(0.0f));
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double p = escapeProbability[i][c], r = halfSpaceAlbedo[c];
      const double profilePart =
          rho[i][c] > 0.0f ? exitance[i][c] * std::min(p, r) / rho[i][c] : 0.0;
      excess[i][c] = static_cast<float>(std::max(0.0, p - r) * averageIrradiance[i][c]);
      exitance[i][c] = static_cast<float>(profilePart + excess[i][c]);
    }
}

glm::dvec3 halfSpaceAlbedoOf(const Material& material) {
  glm::dvec3 halfSpace(0.0);
  const glm::dvec3 albedo = material.reducedAlbedo();
  for (int c = 0; c < 3; ++c) halfSpace[c] = halfSpaceDiffuseAlbedo(albedo[c], material.eta);
  return halfSpace;
}

// Deviation of the escape probability from the half-space albedo, relative RMS over vertices and
// channels (weighted like the error of B: a dark channel counts little), with the walks' own
// noise removed; `raw` gets it with the noise.
double deviationFromHalfSpace(const EnergyPlan& plan, double& raw) {
  double deviationSq = 0.0, albedoSq = 0.0;
  for (const glm::vec3& p : plan.escape.probability)
    for (int c = 0; c < 3; ++c) {
      deviationSq += (p[c] - plan.halfSpaceAlbedo[c]) * (p[c] - plan.halfSpaceAlbedo[c]);
      albedoSq += plan.halfSpaceAlbedo[c] * plan.halfSpaceAlbedo[c];
    }
  raw = albedoSq > 0.0 ? std::sqrt(deviationSq / albedoSq) : 0.0;
  const double noise = plan.escape.relativeStdError;
  return std::sqrt(std::max(0.0, raw * raw - noise * noise));
}

// Walks per probe for a noise `ratio` times the budget at `walks` (noise ~ walks^-1/2), capped;
// in double up to the cap, so that a tiny budget cannot overflow the count.
int walksFor(int walks, double ratio, int maxWalks) {
  return static_cast<int>(std::min(double(maxWalks), std::ceil(1.05 * walks * ratio * ratio)));
}

EscapeOptions escapeOptionsOf(const EnergyOptions& options) {
  EscapeOptions escape;
  escape.maxProbes = options.maxProbes;
  escape.run = options.run;
  escape.nearWindowMm = options.nearWindowMm;
  return escape;
}

// More walks until their noise meets the budget (noise ~ walks^-1/2): needed to apply the model,
// and to tell a real deviation from noise. The noise estimate is itself noisy: a few rounds at
// most.
void refineWalks(EscapeWalks& walks, EnergyPlan& plan, const EnergyOptions& options) {
  double raw = 0.0;
  for (int round = 0;
       round < kMaxRefinements && plan.escape.relativeStdError > options.noiseBudget &&
       plan.walks < options.maxWalks;
       ++round) {
    const double ratio = plan.escape.relativeStdError / options.noiseBudget;
    walks.add(std::max(1, walksFor(plan.walks, ratio, options.maxWalks) - plan.walks));
    plan.escape = walks.result();
    plan.walks = walks.walksPerProbe();
    plan.halfSpaceDeviation = deviationFromHalfSpace(plan, raw);
  }
}

EnergyPlan keepHalfSpace(EnergyPlan plan, const EnergyOptions& options, const char* why,
                         const Stopwatch& clock) {
  plan.reason = "escape probability within " + format("%.2g%%", 100.0 * plan.halfSpaceDeviation) +
                " of the half-space albedo (budget " +
                format("%.2g%%", 100.0 * options.noiseBudget) + ", " + why + ")";
  plan.model = EnergyModel::HalfSpace;
  plan.escape.probability.clear();
  plan.seconds = clock.seconds();
  return plan;
}

std::string escapeReason(const EnergyPlan& plan, const EnergyOptions& options) {
  std::string reason =
      std::string(options.model == EnergyModel::Auto ? "finite object" : "requested") +
      ": escape probability " + format("%.2g%%", 100.0 * plan.halfSpaceDeviation) +
      " from the half-space albedo (mean " + format("%.3f", plan.escape.mean.x) + "/" +
      format("%.3f", plan.escape.mean.y) + "/" + format("%.3f", plan.escape.mean.z) +
      "), walk noise " + format("%.2g%%", 100.0 * plan.escape.relativeStdError);
  if (plan.escape.relativeStdError > options.noiseBudget) {
    reason += "; " + std::to_string(plan.walks) + " walks per probe" +
              (plan.walks >= options.maxWalks ? " (the cap)" : "") + ", over the " +
              format("%.2g%%", 100.0 * options.noiseBudget) + " budget";
  }
  return reason;
}

}  // namespace

std::vector<glm::vec3> gaussianAverageIrradiance(const DiffusionInput& input, double sigmaMm,
                                                 const DiffusionOptions& options,
                                                 std::vector<glm::vec3>* weights) {
  const std::size_t n = input.positions.size();
  if (!(sigmaMm > 0.0)) {  // no absorption: one average over the whole surface
    glm::dvec3 sum(0.0);
    double area = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      sum += glm::dvec3(input.irradiance[i]) * double(input.areas[i]);
      area += input.areas[i];
    }
    return std::vector<glm::vec3>(n, area > 0.0 ? glm::vec3(sum / area) : glm::vec3(0.0f));
  }
  DiffusionOptions average = options;
  average.weightSums = true;
  average.run.quiet = true;
  if (weights) average.knownWeightSums = *weights;
  DiffusionResult r = diffuse(input, GaussianProfile(sigmaMm * sigmaMm), average);
  if (weights && weights->empty()) *weights = r.weightSums;
  std::vector<glm::vec3> out(n, glm::vec3(0.0f));
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      if (r.weightSums[i][c] > 0.0f) out[i][c] = r.exitance[i][c] / r.weightSums[i][c];
  return out;
}

EnergyPlan planFiniteObjectEnergy(const TriangleMesh& meshMm, std::span<const float> areas,
                                  const Material& material, const EnergyOptions& options) {
  const Stopwatch clock;
  EnergyPlan plan;
  plan.halfSpaceAlbedo = halfSpaceAlbedoOf(material);
  if (options.model == EnergyModel::HalfSpace) {
    plan.reason = "requested";
    return plan;
  }
  if (!(options.noiseBudget > 0.0)) fail("", "energy: the noise budget must be positive");

  EscapeWalks walks(meshMm, areas, material, escapeOptionsOf(options));
  walks.add(std::min(options.firstWalks, options.maxWalks));
  plan.escape = walks.result();
  plan.walks = walks.walksPerProbe();
  double raw = 0.0;
  plan.halfSpaceDeviation = deviationFromHalfSpace(plan, raw);
  // Even with their noise the walks' deviation is within the budget: nothing to correct.
  if (options.model == EnergyModel::Auto && raw <= options.noiseBudget)
    return keepHalfSpace(std::move(plan), options, "first walks", clock);
  refineWalks(walks, plan, options);
  if (options.model == EnergyModel::Auto && plan.halfSpaceDeviation <= options.noiseBudget)
    return keepHalfSpace(std::move(plan), options, "noise removed", clock);
  plan.model = EnergyModel::Escape;
  plan.reason = escapeReason(plan, options);
  plan.seconds = clock.seconds();
  return plan;
}

void refineNearShare(EnergyPlan& plan, const TriangleMesh& meshMm, std::span<const float> areas,
                     const Material& material, const EnergyOptions& options) {
  // Its noise as it weighs in B: on a thin part under a sun most of B is the far field's, and the
  // near share's own relative noise overstates it.
  const double error = plan.escape.nearErrorInB();
  if (plan.model != EnergyModel::Escape || plan.walks >= options.maxWalks ||
      !(error > options.noiseBudget))
    return;
  const Stopwatch clock;
  EscapeWalks walks(meshMm, areas, material, escapeOptionsOf(options));
  walks.add(std::max(plan.walks + 1,
                     walksFor(plan.walks, error / options.noiseBudget, options.maxWalks)));
  const double seconds = plan.seconds;
  plan.escape = walks.result();
  plan.walks = walks.walksPerProbe();
  plan.reason += "; " + std::to_string(plan.walks) + " walks per probe for the near share";
  plan.seconds = seconds + clock.seconds();
}

namespace {

// diffuse() with rho (DiffusionOptions::weightSums), taken from `known` when it is filled, and
// left there when it is empty.
DiffusionResult diffuseWithWeightSums(const DiffusionInput& input, const DiffusionProfile& profile,
                                      DiffusionOptions options, std::vector<glm::vec3>* known) {
  options.weightSums = true;
  if (known) options.knownWeightSums = *known;
  DiffusionResult result = diffuse(input, profile, options);
  if (known && known->empty()) *known = result.weightSums;
  return result;
}

// The far field's B: P_near / rho_near times the windowed profile's sum, plus the traced far field.
DiffusionResult diffuseNearAndFar(const DiffusionInput& input, const DiffusionProfile& profile,
                                  const DiffusionOptions& options, const EnergyPlan& plan,
                                  const Material& material, std::span<const glm::vec3> farExitance,
                                  EnergyWeightSums* weights) {
  const std::size_t n = input.positions.size();
  if (farExitance.size() != n || plan.escape.nearProbability.size() != n)
    fail("", "energy: one far-field exitance and near share per vertex needed");
  DiffusionResult result =
      diffuseWithWeightSums(input, WindowedProfile(profile, farFieldWindowMm(material)), options,
                            weights ? &weights->profile : nullptr);
  result.escapeExcess.assign(farExitance.begin(), farExitance.end());
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double rho = result.weightSums[i][c];
      const double near =
          rho > 0.0 ? result.exitance[i][c] * plan.escape.nearProbability[i][c] / rho : 0.0;
      result.exitance[i][c] = static_cast<float>(near + farExitance[i][c]);
    }
  return result;
}

}  // namespace

DiffusionResult diffuseWithEnergy(const DiffusionInput& input, const DiffusionProfile& profile,
                                  DiffusionOptions options, const EnergyPlan& plan,
                                  const Material& material, std::span<const glm::vec3> farExitance,
                                  EnergyWeightSums* weights) {
  if (plan.model != EnergyModel::Escape) return diffuse(input, profile, options);
  if (!farExitance.empty())
    return diffuseNearAndFar(input, profile, options, plan, material, farExitance, weights);
  DiffusionResult result =
      diffuseWithWeightSums(input, profile, options, weights ? &weights->profile : nullptr);
  options.method = result.report.method;
  applyEscapeEnergy(result.exitance, result.weightSums, plan.escape.probability,
                    plan.halfSpaceAlbedo,
                    gaussianAverageIrradiance(input, escapeExcessSigmaMm(material), options,
                                              weights ? &weights->average : nullptr),
                    result.escapeExcess);
  return result;
}

std::string autoProfileName(EnergyModel model) {
  return model == EnergyModel::Escape ? "dipole" : "burley";
}

}  // namespace sss

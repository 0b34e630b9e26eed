#include "bake/finite_object_energy.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/timer.h"
#include "material/halfspace_albedo.h"
#include "material/material.h"
#include "mesh/triangle_mesh.h"

namespace sss {

std::string toString(EnergyModel model) {
  switch (model) {
    case EnergyModel::Auto:
      return "auto";
    case EnergyModel::HalfSpace:
      return "halfspace";
    case EnergyModel::Escape:
      return "escape";
  }
  return "?";
}

std::vector<std::string> listEnergyModels() {
  return {"auto", "halfspace", "escape"};
}

EnergyModel parseEnergyModel(const std::string& name) {
  for (EnergyModel m : {EnergyModel::Auto, EnergyModel::HalfSpace, EnergyModel::Escape})
    if (toString(m) == name) return m;
  fail("", "unknown energy model '" + name + "' (use auto, halfspace or escape)");
}

EnergyPlan planFiniteObjectEnergy(const TriangleMesh& meshMm, std::span<const float> areas,
                                  const Material& material, const EnergyOptions& options) {
  const Stopwatch clock;
  EnergyPlan plan;
  const glm::dvec3 albedo = material.reducedAlbedo();
  for (int c = 0; c < 3; ++c)
    plan.halfSpaceAlbedo[c] = halfSpaceDiffuseAlbedo(albedo[c], material.eta);
  if (options.model == EnergyModel::HalfSpace) {
    plan.reason = "requested";
    return plan;
  }
  if (!(options.noiseBudget > 0.0)) fail("", "energy: the noise budget must be positive");

  EscapeOptions escape;
  escape.walks = std::min(options.firstWalks, options.maxWalks);
  escape.maxProbes = options.maxProbes;
  escape.seed = options.seed;
  escape.threads = options.threads;
  plan.escape = estimateEscapeProbability(meshMm, areas, material, escape);
  plan.walks = escape.walks;

  // Deviation from the half-space albedo, relative RMS over vertices and channels (weighted like
  // the error of B: a dark channel counts little), the walks' own noise removed.
  double deviationSq = 0.0, albedoSq = 0.0;
  for (const glm::vec3& p : plan.escape.probability)
    for (int c = 0; c < 3; ++c) {
      deviationSq += (p[c] - plan.halfSpaceAlbedo[c]) * (p[c] - plan.halfSpaceAlbedo[c]);
      albedoSq += plan.halfSpaceAlbedo[c] * plan.halfSpaceAlbedo[c];
    }
  const double raw = albedoSq > 0.0 ? std::sqrt(deviationSq / albedoSq) : 0.0;
  const double noise = plan.escape.relativeStdError;
  plan.halfSpaceDeviation = std::sqrt(std::max(0.0, raw * raw - noise * noise));

  char text[256];
  // Auto keeps the half-space model unless the walks show a deviation above the budget by more
  // than twice their own noise (a few walks per probe estimate their variance roughly).
  if (options.model == EnergyModel::Auto && raw <= options.noiseBudget + 2.0 * noise) {
    std::snprintf(text, sizeof text,
                  "escape probability within %.2g%% of the half-space albedo (budget %.2g%%)",
                  100.0 * plan.halfSpaceDeviation, 100.0 * options.noiseBudget);
    plan.reason = text;
    plan.model = EnergyModel::HalfSpace;
    plan.escape.probability.clear();
    plan.seconds = clock.seconds();
    return plan;
  }
  plan.model = EnergyModel::Escape;
  // More walks until the noise meets the budget (noise ~ walks^-1/2).
  if (noise > options.noiseBudget && plan.walks < options.maxWalks) {
    const double needed =
        plan.walks * (noise / options.noiseBudget) * (noise / options.noiseBudget);
    escape.walks = std::min(options.maxWalks, static_cast<int>(std::ceil(needed)));
    plan.escape = estimateEscapeProbability(meshMm, areas, material, escape);
    plan.walks = escape.walks;
  }
  std::snprintf(text, sizeof text,
                "%s: escape probability %.2g%% from the half-space albedo (mean %.3f/%.3f/%.3f), "
                "walk noise %.2g%%",
                options.model == EnergyModel::Auto ? "finite object" : "requested",
                100.0 * plan.halfSpaceDeviation, plan.escape.mean.x, plan.escape.mean.y,
                plan.escape.mean.z, 100.0 * plan.escape.relativeStdError);
  plan.reason = text;
  if (plan.escape.relativeStdError > options.noiseBudget) {
    std::snprintf(text, sizeof text, "; capped at %d walks per probe, over the %.2g%% budget",
                  plan.walks, 100.0 * options.noiseBudget);
    plan.reason += text;
  }
  plan.seconds = clock.seconds();
  return plan;
}

void applyEscapeEnergy(std::span<glm::vec3> exitance, std::span<const glm::vec3> rho,
                       std::span<const glm::vec3> escapeProbability) {
  if (rho.size() != exitance.size() || escapeProbability.size() != exitance.size())
    fail("", "energy: one rho and one escape probability per vertex needed");
  for (std::size_t i = 0; i < exitance.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (rho[i][c] > 0.0f) exitance[i][c] *= escapeProbability[i][c] / rho[i][c];
}

}  // namespace sss

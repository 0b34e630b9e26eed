// Bake stage 2: the energy model of the diffusion sum (finite_object_energy.h: the escape walks
// that decide "auto" and measure the escape probability) and the profile that suits it.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "bake/bake_settings.h"
#include "core/run_context.h"
#include "material/diffusion_profile.h"
#include "transport/finite_object_energy.h"

namespace sss {

struct TriangleMesh;  // lib/mesh/triangle_mesh.h

struct EnergyStageInput {
  const TriangleMesh& meshMm;
  std::span<const float> areasMm2;
  const Material& material;
  EnergyModel energy = EnergyModel::Auto;
  ProfileChoice profile = ProfileChoice::Auto;
  double walkBudget = 0.0;  // ErrorBudget::walkBudget()
  bool runWalks = true;     // false for the path tracer, which needs no energy model
  RunContext run;
  // The far field's near window (far_field.h): the walks also measure P's near share; 0: not.
  glm::dvec3 nearWindowMm{0.0};
};

struct EnergyStageReport {
  EnergyModel requested = EnergyModel::Auto;
  EnergyPlan plan;
  double walkBudget = 0.0;
  ProfileChoice profileRequested = ProfileChoice::Auto;
  std::string profileName;
  glm::dvec3 profileTotalReflectance{0.0};
  double seconds = 0.0;
  bool escape() const { return plan.model == EnergyModel::Escape; }
  // With a traced far field (far_field.h) the profile spreads P's near share, not P, and the far
  // field's own noise adds to the walks'.
  bool farField = false;
  double farFieldError = 0.0;
  // The relative noise the escape model's Monte Carlo leaves in B (0 without it).
  double walkError() const {
    if (!escape()) return 0.0;
    return farField ? std::hypot(plan.escape.nearErrorInB(), farFieldError)
                    : plan.escape.relativeStdError;
  }
};

struct EnergyStage {
  std::unique_ptr<DiffusionProfile> profile;
  EnergyStageReport report;
};

EnergyStage planEnergy(const EnergyStageInput& in);

// With a traced far field (far_field.h) the profile spreads P's near share: the plan of `energy`
// with more walks until the near share's noise meets `budget` (finite_object_energy.h,
// refineNearShare), and the far field's noise beside the walks'.
EnergyStageReport energyWithFarField(const EnergyStageInput& in, EnergyStageReport energy,
                                     double budget, double farFieldError);

}  // namespace sss

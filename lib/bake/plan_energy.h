// Bake stage 2: the energy model of the diffusion sum (finite_object_energy.h: the escape walks
// that decide "auto" and measure the escape probability) and the profile that suits it.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "bake/bake_settings.h"
#include "bake/finite_object_energy.h"
#include "material/diffusion_profile.h"

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
  uint64_t seed = 1;
  int threads = 0;
  bool quiet = false;
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
  // The relative noise the escape walks leave in B (0 without them).
  double walkError() const { return escape() ? plan.escape.relativeStdError : 0.0; }
};

struct EnergyStage {
  std::unique_ptr<DiffusionProfile> profile;
  EnergyStageReport report;
};

EnergyStage planEnergy(const EnergyStageInput& in);

}  // namespace sss

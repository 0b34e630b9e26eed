// Energy of the diffusion sum on a finite object (`sss-bake --energy`).
//
// The profiles of lib/material describe a half-space: of the light E_j A_j that enters at x_j they
// return R_total, spread by R_d. The sum over a mesh departs from that in two ways: its weights
// rho_i = sum_j R_d(|x_i - x_j|) A_j are not R_total (a thin part sees the profile through both
// faces, a tip or a small object loses its tail), and a finite object absorbs less than a
// half-space (walks leave sooner: a marble sphere 20 mm across returns 0.96 of the light in red
// where the half-space returns 0.875). Measured against the Monte Carlo reference
// (tests/bench/accuracy_study.cpp) these energy errors are most of the classic dipole's error on
// small translucent objects.
//
// Models:
//   halfspace  B_i = sum_j R_d(r_ij) E_j A_j as the paper has it.
//   escape     B_i = P_i / rho_i * sum_j R_d(r_ij) E_j A_j, with P_i the object's own escape
//              probability near x_i (lib/pathtrace/escape_probability.h: random walks in the mesh
//              that only count how much light leaves, independent of the lighting). The profile
//              keeps the spatial shape and the walks set the amount; under uniform light
//              B_i = E P_i exactly. rho_i is the same diffusion method's sum with E = 1.
//   auto       escape when a first, cheap round of walks shows the escape probability departing
//              from the half-space albedo (lib/material/halfspace_albedo.h) by more than the noise
//              budget plus twice its own noise, else halfspace: a large object (a head in skin, a
//              marble statue) keeps the cheap half-space model.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "pathtrace/escape_probability.h"

namespace sss {

struct TriangleMesh;  // lib/mesh/triangle_mesh.h
struct Material;      // lib/material/material.h

enum class EnergyModel { Auto, HalfSpace, Escape };

// "auto", "halfspace", "escape".
std::string toString(EnergyModel model);
// Throws sss::Error naming the valid models.
EnergyModel parseEnergyModel(const std::string& name);
std::vector<std::string> listEnergyModels();

struct EnergyOptions {
  EnergyModel model = EnergyModel::Auto;
  // Allowed relative RMS error of B from the escape walks' noise: the walks per probe are raised
  // (up to maxWalks) until the estimate's relative standard error meets it.
  double noiseBudget = 0.005;
  int firstWalks = 2, maxWalks = 128;
  std::size_t maxProbes = 1024;
  uint64_t seed = 1;
  int threads = 0;
};

struct EnergyPlan {
  EnergyModel model = EnergyModel::HalfSpace;  // what to apply (never Auto)
  std::string reason;
  // Relative RMS over vertices and channels of P / R_total - 1 (noise removed): the energy error
  // the half-space model leaves on this object.
  double halfSpaceDeviation = 0.0;
  glm::dvec3 halfSpaceAlbedo{0.0};  // R_total of the material (Monte Carlo table)
  EscapeResult escape;              // the final walks (empty probability for halfspace)
  int walks = 0;                    // per probe and channel, in the final estimate
  double seconds = 0.0;
};

// Runs the escape walks needed to decide (auto) or apply (escape); none for halfspace.
// meshMm in mm, areas in mm^2 per vertex.
EnergyPlan planFiniteObjectEnergy(const TriangleMesh& meshMm, std::span<const float> areas,
                                  const Material& material, const EnergyOptions& options);

// B_i *= P_i / rho_i per channel (rho: the diffusion sum with E = 1); rho_i = 0 leaves B_i.
void applyEscapeEnergy(std::span<glm::vec3> exitance, std::span<const glm::vec3> rho,
                       std::span<const glm::vec3> escapeProbability);

}  // namespace sss

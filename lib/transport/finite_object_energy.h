// Energy of the diffusion sum on a finite object (`sss-bake --energy`).
//
// The profiles of lib/material describe a half-space: of the light E_j A_j that enters at x_j they
// return R_total, spread by R_d. The sum over a mesh departs from that in two ways: its weights
// rho_i = sum_j R_d(|x_i - x_j|) A_j are not R_total (a thin part sees the profile through both
// faces, a tip or a small object loses its tail), and a finite object absorbs less than a
// half-space (walks leave sooner: a small marble sphere returns clearly more of the light than
// the half-space albedo; docs/physics.md, "Finite objects are not half-spaces"). Measured against
// the Monte Carlo reference (tests/bench/accuracy_study.cpp) these energy errors are most of the
// classic dipole's error on small translucent objects.
//
// Models:
//   halfspace  B_i = sum_j R_d(r_ij) E_j A_j as Li & Guo have it.
//   escape     B_i = min(P_i, R) / rho_i * sum_j R_d(r_ij) E_j A_j + max(0, P_i - R) Ebar_i,
//              with P_i the object's own escape probability near x_i (lib/pathtrace/
//              escape_probability.h: random walks in the mesh that only count how much light
//              leaves, independent of the lighting), R the half-space albedo, rho_i the same
//              diffusion method's sum with E = 1, and Ebar_i the irradiance averaged by a
//              Gaussian of sigma = 4 diffusion lengths (longest channel). The profile places what
//              a half-space would return, normalized to the mesh; the excess P - R is light that a
//              half-space would absorb on long paths, and long paths leave far from where they
//              entered, hence the wide kernel (closer to the Monte Carlo reference than spreading
//              it with R_d, and insensitive to the width within a few diffusion lengths;
//              docs/physics.md, "Finite objects are not half-spaces").
//              Under uniform light B_i = E P_i exactly.
//   auto       halfspace when a first, cheap round of walks (2 per probe) puts the escape
//              probability within the noise budget of the half-space albedo
//              (lib/material/halfspace_albedo.h) even with their noise, or when, after more walks,
//              it is within the budget with the noise removed: a large object (a head in skin, a
//              marble statue) keeps the cheap half-space model. Escape otherwise.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/enum_names.h"
#include "core/run_context.h"
#include "diffusion/diffusion.h"
#include "pathtrace/escape_probability.h"

namespace sss {

struct TriangleMesh;  // lib/mesh/triangle_mesh.h
struct Material;      // lib/material/material.h

enum class EnergyModel { Auto, HalfSpace, Escape };

inline constexpr EnumNames<EnergyModel, 3> kEnergyModelNames{
    "energy model",
    {{{EnergyModel::Auto, "auto"},
      {EnergyModel::HalfSpace, "halfspace"},
      {EnergyModel::Escape, "escape"}}}};

// The near window w_c = kFarFieldWindowLengths / sigma_tr,c in mm of the far field (far_field.h):
// the light that leaves beyond it is traced, and the escape walks measure the near share within
// it.
inline constexpr double kFarFieldWindowLengths = 0.125;
glm::dvec3 farFieldWindowMm(const Material& material);

struct EnergyOptions {
  EnergyModel model = EnergyModel::Auto;
  // Allowed relative RMS error of B from the escape walks' noise: the walks per probe are raised
  // (up to maxWalks) until the estimate's relative standard error meets it.
  double noiseBudget = 0.005;
  int firstWalks = 2, maxWalks = 128;
  std::size_t maxProbes = 256;
  // The far field's near window (farFieldWindowMm): the walks also measure P's near
  // share with it (EscapeResult::nearProbability). 0: they do not.
  glm::dvec3 nearWindowMm{0.0};
  RunContext run;
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

// The sums with E = 1 the escape model divides by: rho of the profile (windowed, with a far
// field) and of the excess's Gaussian average. They depend on the mesh, the profile and the
// method, not on E, so that a transport run again on other light (the bounces of
// interreflection.h, with the method of the first) reuses them instead of summing them again.
struct EnergyWeightSums {
  std::vector<glm::vec3> profile, average;
};

// Ebar: the irradiance averaged by a normalized Gaussian of sigma mm in space,
// sum_j G(r_ij) E_j A_j / sum_j G(r_ij) A_j, by options' method, tolerance and threads (one
// average over the whole surface for sigma <= 0; 0 where the weights vanish). `weights`, when
// given: the denominators, reused when filled, else filled.
std::vector<glm::vec3> gaussianAverageIrradiance(const DiffusionInput& input, double sigmaMm,
                                                 const DiffusionOptions& options,
                                                 std::vector<glm::vec3>* weights = nullptr);

// More walks for an escape plan until the noise of P's near share meets options.noiseBudget
// (the far field, far_field.h, spreads P_near with the profile; it needs more walks than P).
// The walks repeat the plan's (each walk has its own random stream) and add to them.
void refineNearShare(EnergyPlan& plan, const TriangleMesh& meshMm, std::span<const float> areas,
                     const Material& material, const EnergyOptions& options);

// The diffusion sum (diffusion.h) with the plan's energy model: diffuse() as it is for halfspace;
// for escape B_i = min(P_i, R) / rho_i * B_i + max(0, P_i - R) * Ebar_i, with rho from the same
// method (DiffusionOptions::weightSums) and Ebar, the irradiance averaged by a Gaussian of 4 of
// the material's longest diffusion lengths, by the method diffuse() chose. With a traced far field
// (farExitance per vertex, far_field.h): B_i = P_near,i / rho_near,i sum_j R_d W E_j A_j + B_far,i,
// the profile windowed (material/windowed_profile.h); escapeExcess is then B_far. `weights`, when
// given: rho and Ebar's denominators, reused when filled, else filled (EnergyWeightSums).
DiffusionResult diffuseWithEnergy(const DiffusionInput& input, const DiffusionProfile& profile,
                                  DiffusionOptions options, const EnergyPlan& plan,
                                  const Material& material,
                                  std::span<const glm::vec3> farExitance = {},
                                  EnergyWeightSums* weights = nullptr);

// The profile `--profile auto` takes for the energy model in use: dipole with escape (its shape is
// the closest to the Monte Carlo reference once the energy is right), burley with halfspace (its
// total is calibrated).
std::string autoProfileName(EnergyModel model);

}  // namespace sss

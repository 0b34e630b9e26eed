// Bake stage 3b: the far field of the escape energy model, traced from the environment
// (`sss-bake --far-field`; issue 11, part 2).
//
// Why: the profiles are half-space models of light that enters diffusely. On a small object under
// a sun the light that leaves far from where it entered (through a sphere to its unlit half,
// through a thin part to the side away from the light) is neither: collimated light penetrates
// deeper than diffuse light, and the object's shape, not a half-space, decides where it comes
// out. No geometry-blind kernel gets it right on every material, and a gather from the escape
// walks (their exits weighted by E there, by reciprocity), which enter diffusely, misses the depth
// on skin and ketchup (README, "Under a sun", has both measured). Light paths from the environment
// carry both.
//
// Model: B_i = P_near,i / rho_near,i sum_j R_d(r_ij) W(r_ij) E_j A_j + B_far,i, with
//  - W(d) = exp(-d^2 / (2 w_c^2)) a window of w_c = kFarFieldWindowLengths / sigma_tr,c
//    (material/windowed_profile.h): the profile keeps the light that leaves near where it
//    entered, where it is accurate and noise-free;
//  - P_near,i the escape walks' weights times W of their exit distance (escape_probability.h):
//    what of P leaves near, so that under uniform light B = E P as before;
//  - B_far the light tracer's exits weighted by 1 - W(d) (pathtrace/light_tracer.h: paths from
//    the environment's importance distribution, refracted in, random walks, stopped at their first
//    exit, light scattered at least once), averaged over the surface by a Gaussian of sigma = the
//    longest channel's window (at least one mean edge) among vertices that face the same way
//    (surface_average.h):
//    what leaves far. Light that crosses unscattered leaves collimated, which no exit model of B
//    describes; it stays out (issue 11, part 5).
// Near part: the same paths' exits within the window calibrate the first term per vertex
// (calibrateNearPart, below): the escape walks' P_near is a diffuse entry's, and under a sun the
// near share follows the incidence.
// Exit lobe: where the far field is traced, all of B leaves through the exit lobe of
// optics/exit_lobe.h, whose slope k per vertex and channel comes from the flux-weighted mean
// internal cosine of all the traced exits, near and far (averaged like B_far but over
// kLobeSmoothing times the width, since the slope amplifies that mean's noise), shrunk towards 0
// by its noise from the batches' spread (ExitLobe::shrunkSlopeFor). Not B_far alone through a lobe
// of the far exits and B - B_far through the normalized model: the window splits the exits by
// angle too. Light that leaves within a fraction of a mean free path of where it entered went
// nearly straight back, so at low albedo under a high sun the near exits crowd the normal and the
// far ones avoid it (a half-space at a' = 0.68 under normal incidence: along the normal 1.7-2.0x
// the normalized model's radiance per unit B near, 0.70x far, 0.95x for all exits), which neither
// the normalized model nor a linear lobe of the far exits follows; all exits together are smooth in
// angle (README, "Under a sun", has the study).
// Cost and noise: a pilot round of paths estimates the smoothed far field's relative noise
// (propagated from the tracer's batch standard errors through the smoothing weights); the paths
// then grow as noise^-2 to the budget, capped by a path count and by work (scattering events, as
// the escape walks counted them: a high-albedo material affords fewer paths).
//
// Auto: traced when the energy model is escape (a half-space does not need it) and the irradiance
// varies on the diffusion length's scale: the share of B the far field can move,
// s = |(P - P_near) (E - Ebar)| / |P E| over vertices and channels (Ebar: E averaged by a
// Gaussian of the longest diffusion length), exceeds the noise budget; and the paths it needs
// stay under the caps (a large object needs many: its far field stays the escape model's kernel,
// finite_object_energy.h; a first check from the surface's count of smoothing kernels skips it
// before any tracing), or, past them, the noise left at the caps is below the kernel's model
// error it removes (a measured share of s), and it traces to the cap. Under uniform light s = 0.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/enum_names.h"
#include "core/run_context.h"
#include "transport/traced_stage.h"

namespace sss {

class Cubemap;        // envmap/cubemap.h
struct TriangleMesh;  // mesh/triangle_mesh.h
struct Material;      // material/material.h
struct EnergyPlan;    // bake/finite_object_energy.h

using FarFieldMode = TracedMode;

inline constexpr EnumNames<FarFieldMode, 3> kFarFieldModeNames{
    "far field",
    {{{FarFieldMode::Auto, "auto"}, {FarFieldMode::Off, "off"}, {FarFieldMode::On, "on"}}}};

struct FarFieldOptions {
  FarFieldMode mode = FarFieldMode::Auto;
  double noiseBudget = 0.005;  // relative RMS noise the traced far field may leave in B
  uint64_t pilotPaths = 1 << 13;
  uint64_t maxPaths = 1 << 23;
  // Cap on the tracing's work, in scattering events plus a few rays per path (auto skips what
  // would exceed it; on traces up to it).
  double maxWork = 5e7;
  RunContext run;
  // The exit lobe from all exits (above); false: from the far exits alone (the study's comparison).
  bool lobeOfAllExits = true;
  // With lobeOfAllExits: the near part of B scaled to the traced near exits (calibrateNearPart,
  // below); false: the escape walks' near share as it is (the study's comparison).
  bool calibrateNearShare = true;
};

// relativeStdError: of B, from the far field's noise.
struct FarFieldReport : TracedStageReport {
  double sensitivity = 0.0;  // the share of B the far field can move (auto's test)
  glm::dvec3 windowMm{0.0};
  double smoothingMm = 0.0;
  // The bias its surface averaging S leaves in B, estimated as S(B_far) - B_far (S applied once
  // more: to leading order what S did to the exits), relative RMS over vertices and channels like
  // relativeStdError (the model error's far-field term where it is traced, model_error.h).
  double averagingBias = 0.0;
  // The noise the slopes leave in the radiance along the normal (their mean cosines' through
  // ExitLobe::shrunkSlopeFor), relative RMS like relativeStdError: beside it in the bake's
  // numerical error (the paths are sized by B's noise).
  double lobeNoise = 0.0;
  // The exit lobe's slope averaged over the surface, weighted by B_far times the area: 0 for
  // light that left as diffusion does, below 0 for light that leaves towards grazing angles.
  glm::dvec3 meanExitSlope{0.0};
};

struct FarField {
  std::vector<glm::vec3> exitance;  // B_far per vertex; empty when not traced
  // The exit lobe's slope k per vertex and channel (optics/exit_lobe.h): the radiance B leaves
  // with, from the traced exits' mean internal cosine; empty when not traced.
  std::vector<glm::vec3> slope;
  // With FarFieldOptions::calibrateNearShare: per vertex and channel the traced exits within
  // the near window (all exits less the far ones), averaged like B_far, that mean's variance and
  // its covariance with B_far from the batches; empty otherwise (calibrateNearPart).
  std::vector<glm::vec3> nearExitance, nearVariance, nearFarCovariance;
  FarFieldReport report;
  bool traced() const { return report.traced; }
};

struct FarFieldInput {
  const TriangleMesh& meshMm;
  std::span<const float> areasMm2;
  const Cubemap& radiance;
  const Material& material;
  const EnergyPlan& energy;
  std::span<const glm::vec3> irradiance;  // E per vertex as the transport sums it (auto's test)
  FarFieldOptions options;
};

// Throws Error on bad options; never traces for the half-space energy model.
FarField traceFarField(const FarFieldInput& in);

// The near part of B, B - B_far from the windowed profile (finite_object_energy.h,
// diffuseWithEnergy), scaled per vertex and channel to the traced near exits: by S(near traced) /
// S(H(B - B_far)), S the far field's averaging and H the hat-function average
// (mesh/triangle_mesh.h: what the tracer's barycentric tally makes of the point values, which
// matters on a coarse mesh; not at folds), shrunk towards 1 by the ratio's noise as the exit
// lobe's slope is (1 + d d^2 / (d^2 + var), d the ratio less 1). Why: the escape walks enter
// diffusely, and the share of light that leaves within the window follows the incidence under a
// sun (at low albedo light that enters straight down comes straight back, at grazing incidence it
// drifts sideways: a half-space at a' = 0.68 keeps 1.13x the diffuse near share at normal
// incidence, 0.81x grazing). Nothing when traced is empty.
// Returns the noise the scale adds to B_far's in B (the traced near exits' batch variance through
// the shrinkage, and their covariance with B_far: the same paths), relative RMS over vertices and
// channels, area-weighted; 0 when nothing is done.
struct NearCalibration {
  const TriangleMesh& meshMm;
  std::span<const float> areasMm2;
  // FarField's exitance, nearExitance, nearVariance and nearFarCovariance.
  std::span<const glm::vec3> farExitance, traced, variance, covariance;
  double smoothingMm = 0.0;  // FarFieldReport::smoothingMm
  int threads = 0;
};
double calibrateNearPart(std::span<glm::vec3> exitance, const NearCalibration& near);

}  // namespace sss

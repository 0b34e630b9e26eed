// Bake stage 3b: the far field of the escape energy model, traced from the environment
// (`sss-bake --far-field`). The profiles are half-space models of light that enters diffusely. On
// a small object under uneven light, the light that leaves far from where it entered (through a
// sphere to its unlit half, through a thin part) is neither: collimated light goes deeper, and the
// object's shape decides where it comes out. Light paths from the environment carry both. The
// model: docs/physics.md, "The far field: light that leaves far from where it entered" and "The
// far field's exit lobe"; the alternatives measured (geometry-blind kernels, a gather from the
// escape walks): docs/physics.md, "Alternatives measured and not used"; the sun study:
// docs/accuracy.md, "Under a sun".
//
// Model: B_i = P_near,i / rho_near,i sum_j R_d(r_ij) W(r_ij) E_j A_j + B_far,i, with
//  - W(d) = exp(-d^2 / (2 w_c^2)), w_c = kFarFieldWindowLengths / sigma_tr,c in mm
//    (material/windowed_profile.h): the profile keeps the light that leaves near where it
//    entered, where it is accurate and noise-free;
//  - P_near,i the escape walks' weights times W of their exit distance (escape_probability.h),
//    so that under uniform light B = E P;
//  - B_far the light tracer's first exits of light scattered at least once, weighted by 1 - W(d)
//    (pathtrace/light_tracer.h), averaged over the surface among vertices that face the same way
//    by a Gaussian of the longest channel's window, at least one mean edge (surface_average.h).
//    Unscattered light leaves collimated, which no exit model of B describes: unscattered_light.h.
// Notes:
//  - The same paths' exits within the window calibrate the near part per vertex
//    (calibrateNearPart): the walks' P_near is a diffuse entry's, and under a sun the near share
//    follows the incidence.
//  - All of B leaves through one exit lobe (optics/exit_lobe.h) per vertex and channel, from the
//    flux-weighted mean internal cosine of all the traced exits, averaged over kLobeSmoothing
//    times B_far's width and shrunk towards 0 by its noise (ExitLobe::shrunkSlopeFor). One lobe for
//    all exits: the window splits the exits by angle too, and only all of them are smooth in angle.
//  - Cost: a pilot round estimates the smoothed far field's relative noise from the tracer's
//    batches; the paths grow as noise^-2 to the budget, capped by a path count and by work
//    (scattering events: a high-albedo material affords fewer paths).
//  - Auto: traced with the escape energy model when s = |(P - P_near) (E - Ebar)| / |P E| (Ebar: E
//    averaged over the longest diffusion length), the share of B it can move, exceeds the noise
//    budget and the paths fit the caps; past the caps, traced to the cap when the noise left there
//    is below the model error it removes (a measured share of s). A first check from the surface's
//    count of smoothing kernels skips large objects before any tracing: they keep the escape
//    model's kernel (finite_object_energy.h). Under uniform light s = 0.
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
struct EnergyPlan;    // transport/finite_object_energy.h

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
// diffusely, and under a sun the share of light that leaves within the window follows the
// incidence (docs/physics.md, "The far field: light that leaves far from where it entered").
// Nothing when traced is empty.
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

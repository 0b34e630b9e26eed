// Bake stage 4c: the light that crosses the object without scattering (`sss-bake --unscattered`).
//
// Why: a thin or small part of a low-density material (ketchup's red, sigma_t 0.24 /mm; skim milk)
// lets part of the light through in straight lines: refracted in, attenuated by e^(-sigma_t d),
// refracted out. No diffusion profile or exit model of B produces it, and it leaves collimated, so
// it is not a diffuse exitance. On small ketchup spheres under a sun it is a large share of the
// unlit half's light (docs/physics.md, "Light that crosses without scattering").
//
// Model: geometric optics, traced from the environment (pathtrace/light_tracer.h with
// unscatteredOnly: directions from the environment's importance distribution, so a sun is found
// by every path; exact Fresnel refraction and internal reflection; each straight flight weighted
// by its transmittance). Each exit within coneHalfAngleDeg of a vertex normal is tallied as the
// radiance along that normal, L_u (the light tracer's cone estimator: the cosine-weighted mean
// radiance over the cone, as the reference measures it; a sun's image focused by a sphere is a
// caustic that only such a mean resolves). L_u is added to the baked radiance along the normal;
// B stays the scattered light, the light the exit models spread over directions.
//
// Cost and noise: a pilot round measures L_u's share of the radiance along the normal,
// s = sqrt(max(0, sum A |L_u|^2 - sum A var(L_u)) / sum A |L_s + L_u|^2) (area-weighted over
// vertices and channels, its own noise removed), and its relative noise; paths then grow as
// noise^-2 to the budget in rounds, each round's noise (from all its paths) setting the next, up to
// a cap. A path is a few rays, no scattering events.
//
// Auto: traced when s exceeds the noise budget (what tracing would leave); a dense material
// (marble: sigma_t ~2.2 /mm) or a large object finds almost nothing in the pilot and costs only it.
// Then kept only where its noise is below s: traced, the error it leaves is its noise, left out,
// s. Auto traces no further round once the noise is not below s, or is more than twice what
// paths^-1/2 predicted (heavy-tailed tallies: a sun through thin parts onto a few small vertices).
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

using UnscatteredMode = TracedMode;

inline constexpr EnumNames<UnscatteredMode, 3> kUnscatteredModeNames{
    "unscattered light",
    {{{UnscatteredMode::Auto, "auto"},
      {UnscatteredMode::Off, "off"},
      {UnscatteredMode::On, "on"}}}};

struct UnscatteredLightOptions {
  UnscatteredMode mode = UnscatteredMode::Auto;
  double noiseBudget = 0.003;  // relative RMS noise it may leave in the radiance along the normal
  uint64_t pilotPaths = 1 << 15;
  uint64_t maxPaths = 1 << 23;
  double coneHalfAngleDeg = 15.0;
  RunContext run;
};

// relativeStdError: of the radiance along the normal, from L_u's noise.
struct UnscatteredLightReport : TracedStageReport {
  double share = 0.0;  // of the radiance along the normal (relative RMS), from all its paths
};

struct UnscatteredLight {
  std::vector<glm::vec3> radiance;  // L_u along each vertex normal; empty when not traced
  UnscatteredLightReport report;
  bool traced() const { return report.traced; }
};

struct UnscatteredLightInput {
  const TriangleMesh& meshMm;
  std::span<const float> areasMm2;
  const Cubemap& radiance;
  const Material& material;
  // The bake's radiance along the normal from B (the scattered light): what the share compares to.
  std::span<const glm::vec3> scatteredRadiance;
  UnscatteredLightOptions options;
};

// Throws Error on bad options.
UnscatteredLight traceUnscatteredLight(const UnscatteredLightInput& in);

}  // namespace sss

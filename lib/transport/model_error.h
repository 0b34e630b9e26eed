// The model's own error, beside the numerical error the tolerance controls (error_budget.h): what
// no number of rays or walks removes, estimated from five approximations of the per-vertex model
// and sized on the accuracy studies (docs/accuracy.md, "The bake's predicted error"):
//  - exitModel: the exit model's spread. The radiance along the normal per unit B is the
//    normalized model's (isotropic interior radiance at the boundary, optics/fresnel.h) or the
//    calibrated one's (the half-space Monte Carlo's, material/directional_albedo_weight.h); the
//    truth on an object lies around them, so their difference |c - 1| per channel (c = calibrated
//    / normalized) sizes this error. It grows as the reduced albedo falls (skin, ketchup).
//  - facets: a vertex stands for the facets around it, which tilt from its normal by theta
//    (1 - cos theta, area-weighted over its faces): the light they send differs from the smooth
//    surface's by that order (edges of a box: 0.29; a 642-vertex sphere: 0.004).
//  - facetLight: the light those facets receive differs from what the vertex normal receives,
//    |E(n_f) - E(n)| area-weighted over the faces, relative to max(E(n), mean E(n_f)), per
//    channel, with E the environment's transmitted irradiance without shadows: nothing under
//    even light, most at a crease facing a sun. At a crease the bake takes the facets' mean
//    (facet_light.h), so what this sizes there is the light's spread over the facets, which one
//    value per vertex cannot hold (B changes across the vertex's triangles, not linearly).
//  These two count only the radiance the vertex model makes (E at the vertex, B through
//  an exit model): a traced far field's light paths met the facets themselves.
//  - interreflection: with bounces, the light the object sent itself is modelled more coarsely
//    than the environment's (interreflection.h): it leaves each hit point through the normalized
//    exit model at whatever angle the ray came, from B interpolated over the hit triangle, with
//    the mirrored sky box-filtered to ~11 degrees, and the escape model's geometry-blind kernel
//    spreads it (a traced far field holds only the environment's light). Its error scales with
//    the share of the radiance those bounces carry (L of B - B_direct against L).
//  - farField: where the far field (far_field.h) was not traced, the escape model's excess is
//    spread by a geometry-blind kernel (docs/physics.md, "Alternatives measured and not used");
//    its error scales with the share of B the far field would move (its sensitivity, auto's test).
//    Where it was traced, the bias of its surface averaging (FarFieldReport::averagingBias),
//    largest where B changes fastest over the averaging's width (a sphere's terminator).
// All but the far field are per vertex and channel, weighted by L^2 (the studies' metric:
// relative RMS of the radiance along the normal over vertices and channels); the five add in
// quadrature with the weights below.
#pragma once

#include <span>

#include <glm/vec3.hpp>

#include "envmap/cubemap.h"
#include "material/material.h"
#include "mesh/triangle_mesh.h"

namespace sss {

// Fitted on the 25 rows of tests/bench/sun_study.cpp and concavity_study.cpp (the worst ratio
// of measured to predicted total error, minimized, the exit term's weight held: tests/bench/
// model_error_fit.py --exit 0.35, results in tests/bench/results/accuracy/model_error.csv).
inline constexpr double kExitModelWeight = 0.35;
inline constexpr double kInterreflectionWeight = 0.325;
inline constexpr double kFacetWeight = 0.075;
inline constexpr double kFacetLightWeight = 0.275;
inline constexpr double kFarFieldWeight = 0.175;

struct ModelErrorReport {
  double exitModel = 0.0;        // weighted, relative RMS of the radiance along the normal
  double facets = 0.0;           // likewise
  double facetLight = 0.0;       // likewise
  double farField = 0.0;         // of B, so of the radiance along the normal alike
  double interreflection = 0.0;  // weighted, relative RMS of the radiance along the normal
  // An object of several materials (bake/material_parts.h): the light its rule misplaces near
  // the borders between them, relative RMS of the radiance along the normal; 0 for one.
  double materialInterface = 0.0;
  double total = 0.0;  // the parts above in quadrature
  double seconds = 0.0;
};

struct ModelErrorInput {
  const TriangleMesh& mesh;                        // positions, normals, triangles (any unit)
  std::span<const glm::vec3> radianceAlongNormal;  // L per vertex (the output's)
  const Cubemap& radiance;                         // the environment
  float eta = 1.3f;                                // the surface's relative index
  glm::vec3 exitModelSpread{0.0f};                 // |c - 1| per channel (above)
  // The far field's sensitivity where it was not traced, its averaging bias where it was.
  double farFieldError = 0.0;
  int threads = 0;
  // The part of L the vertex model makes (B less a traced far field, whose light paths met the
  // facets themselves); empty: all of L.
  std::span<const glm::vec3> vertexModelRadiance{};
  // The part of L the bounces added (the radiance of B - B_direct); empty: no bounces.
  std::span<const glm::vec3> interreflectedRadiance{};
};

ModelErrorReport estimateModelError(const ModelErrorInput& in);

// The exit model's spread |calibrated / normalized - 1| per channel for a material's reduced
// albedo and eta.
glm::vec3 exitModelSpread(const Material& material);

}  // namespace sss

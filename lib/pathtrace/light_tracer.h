// Forward light tracing: the volumetric reference that resolves directional light (a sun) and
// light the object sends to itself (docs/accuracy.md, "Forward light tracer").
//
// Why: the backward tracer (subsurface_path_tracer.h) starts at a vertex and finds a small sun
// only when a walk happens to leave towards it (27 % noise per vertex under a 3-degree sun), and,
// like the bake, treats a ray that meets the object again as dark. Light paths start at the
// light instead, so every path carries the sun's power, and they are followed wherever they go.
//
// Model: the same as the backward tracer's (one medium walk, medium_walk.h): a smooth dielectric
// boundary of relative index eta (exact Fresnel, total internal reflection) around a homogeneous
// medium; the triangles' face normals at every boundary interaction.
//
// Estimator, one path:
//  - a direction w towards the light from the light's distribution (an environment by
//    EnvironmentSampler's importance sampling, texel luminance x solid angle, so a sun is found by
//    almost every path; or an analytic disc light: a cone of directions of uniform radiance, or a
//    collimated beam), weight L(w) / p(w);
//  - a start point uniform on a disc of radius R perpendicular to w, outside the object's
//    bounding sphere (radius R), moving along -w: the path carries the power
//    Phi = L(w) / p(w) * pi R^2 / N (N paths);
//  - at the surface from outside: specular reflection with probability F_r (not tallied, followed),
//    else refraction in and a medium walk to the exit; the exit is tallied, then the exit ray is
//    followed outside: if it meets the object again it is reflected or refracted again (light
//    the object sends to itself), up to maxSurfaceInteractions;
//  - tally: an exit at a point of triangle (a, b, c) with barycentric weights l_k adds
//    Phi l_k / A_k to the exitance B of vertex k (A_k its area, one third of its triangles': the
//    hat functions' integrals, so a uniform exitance is returned exactly), and, when the exit
//    direction lies within coneHalfAngle of vertex k's normal, Phi l_k / (P_k Omega_p) to its
//    radiance along the normal, Omega_p = pi sin^2(cone) the cone's projected solid angle and P_k
//    the vertex's area projected along its normal (projectedVertexAreas: sum over its facets f of
//    A_f / 3 (n_f . n_k)): the cosine-weighted mean radiance over the cone of the faceted surface
//    as a viewer down the normal sees it. For a cone about n_k, the integral over it of
//    (n_f . w) dw is (n_f . n_k) Omega_p, so facets of uniform radiance L give L exactly however
//    they tilt; dividing by A_k instead would give L times the facets' mean cosine (0.79 on an
//    icosahedron, 0.90 at the bunny's 25-degree ridges). Its bias is the curvature of the exit
//    radiance's angular distribution over the cone, (1 - cos(cone)) / 2 of its slope in mu (about
//    0.5 % for an isotropic interior at the default 15 degrees, the cone refracted to ~11 degrees
//    inside).
//
// Standard errors: the paths are cut into `batches` equal batches; the estimates are the batch
// means' mean and their standard error over the batches. Deterministic for a seed whatever the
// thread count: path i draws from Pcg32(seed, i), each batch is summed by one thread in path order
// and the batches are combined in order.
//
// Units: millimetres and per-millimetre coefficients; B in the light's radiance times steradians
// (the backward tracer's and the bake's units), radiance in the light's radiance.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/run_context.h"
#include "envmap/cubemap.h"
#include "pathtrace/subsurface_path_tracer.h"  // HomogeneousMedium

namespace sss {

class EnvironmentSampler;  // lib/envmap/environment_sampler.h

// A distant light: directions towards it and their weight L / pdf.
class DistantLight {
 public:
  // The environment (kept by reference), importance sampled. Throws Error if it is black.
  static DistantLight environment(const Cubemap& radiance);
  // A disc of uniform radiance around `towardsLight` (unit), angular radius in radians; the
  // irradiance it gives a surface facing it is irradiance = L * 2 pi (1 - cos(radius)).
  // angularRadius = 0: a collimated beam of that irradiance.
  static DistantLight disc(const glm::vec3& towardsLight, double angularRadius,
                           const glm::vec3& irradiance);

  struct Sample {
    glm::vec3 direction;  // unit, towards the light
    glm::dvec3 weight;    // L(direction) / pdf(direction): an irradiance
  };
  Sample sample(double u1, double u2) const;

  DistantLight(DistantLight&&) noexcept;
  DistantLight& operator=(DistantLight&&) noexcept;
  ~DistantLight();

 private:
  DistantLight() = default;
  std::unique_ptr<EnvironmentSampler> environment_;
  glm::vec3 axis_{0.0f, 0.0f, 1.0f};
  double cosRadius_ = 1.0;
  glm::dvec3 irradiance_{0.0};
};

struct LightTraceOptions {
  uint64_t paths = 1 << 20;
  int batches = 32;  // for the standard errors; at least 2
  RunContext run;
  double coneHalfAngleDeg = 15.0;  // radiance along the normal: exits within this cone
  // Count light scattered at least this often in all: 0 (default) counts everything, 1 leaves
  // out unscattered transmission (the backward tracer's default).
  int minScatteringOrder = 0;
  // Only the light that is never scattered, in expectation (medium_walk.h: each flight weighted by
  // its transmittance instead of sampled): the unscattered part of the count above at a fraction
  // of its cost and noise (sss-bake's unscattered light, lib/transport/unscattered_light.h).
  bool unscatteredOnly = false;
  // The far field beside a windowed profile (lib/transport/far_field.h): when > 0 (mm, per
  // channel), an exit at distance d from where its path last entered counts with the weight 1 -
  // exp(-d^2 / (2 w^2)).
  glm::dvec3 nearWindowMm{0.0};
  // Stop a path at its first exit (the far field leaves the light the object sends to itself to
  // the interreflection stage); false follows it, as the reference does.
  bool stopAtFirstExit = false;
  uint64_t firstPath = 0;     // paths [firstPath, firstPath + paths): rounds that add up
  bool tallyRadiance = true;  // false: B only (the radiance and its error stay 0)
  // Also return each batch's B (LightTraceResult::batchExitance): the far field averages it over
  // the surface per batch, so that its noise counts the paths that neighbouring vertices share.
  bool keepBatches = false;
  // Also tally B times the internal cosine of each exit (LightTraceResult::exitCosine: the far
  // field's exit lobe, optics/exit_lobe.h).
  bool tallyExitCosine = false;
  // The exit cosine's tally over every exit, not windowed by nearWindowMm (with its own exitance,
  // LightTraceResult::cosineExitance): the lobe of all the light that leaves, near and far.
  bool exitCosineOfAllExits = false;
  int maxSurfaceInteractions = 64;    // reflections and refractions at the surface, per path
  int maxScatteringEvents = 1 << 20;  // per medium walk (safety cap; counted)
};

struct LightTraceResult {
  // Per vertex.
  std::vector<glm::vec3> exitance, exitanceStdErr;    // B
  std::vector<glm::vec3> radiance, radianceStdErr;    // along the vertex normal
  std::vector<std::vector<glm::vec3>> batchExitance;  // per batch, with keepBatches
  // With tallyExitCosine: B weighted by the cosine inside the medium of each exit (the cosine of
  // the refracted exit direction with the face normal, taken back through Snell's law), so that
  // exitCosine / exitance is the exits' flux-weighted mean internal cosine.
  std::vector<glm::vec3> exitCosine;
  std::vector<std::vector<glm::vec3>> batchExitCosine;  // per batch, with keepBatches too
  // The exitance that exitCosine is weighted over: B, or with exitCosineOfAllExits the exits'
  // unwindowed B.
  std::vector<glm::vec3> cosineExitance;
  std::vector<std::vector<glm::vec3>> batchCosineExitance;  // per batch, with keepBatches too
  // Power bookkeeping per channel (summed over all paths, divided by the path count: the same
  // units as B times mm^2).
  glm::dvec3 sourcePower{0.0};   // leaving the source disc
  glm::dvec3 hitPower{0.0};      // reaching the object the first time
  glm::dvec3 enteredPower{0.0};  // refracted into the medium (every entry, re-entries included)
  glm::dvec3 exitedPower{0.0};   // refracted out (every exit; the tallies' total when counted)
  glm::dvec3 escapedPower{0.0};  // leaving towards infinity (specular reflections included)
  uint64_t paths = 0;
  uint64_t reentries = 0;  // exits that met the object again and entered it
  uint64_t truncatedWalks = 0, lostWalks = 0, truncatedPaths = 0;
  double meanScatteringEvents = 0.0;  // per path
  double seconds = 0.0;
};

// meshMm: positions in mm, unit vertex normals pointing out, closed and consistently oriented.
// Throws Error on an empty mesh, a bad medium (as pathTraceSubsurface) or bad options.
LightTraceResult lightTraceSubsurface(const std::vector<glm::vec3>& positionsMm,
                                      const std::vector<glm::vec3>& normals,
                                      const std::vector<glm::uvec3>& triangles,
                                      const DistantLight& light, const HomogeneousMedium& medium,
                                      const LightTraceOptions& options);

}  // namespace sss

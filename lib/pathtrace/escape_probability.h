// Escape probability of the light that enters a finite object: of the light the surface lets in
// diffusely at a point, the fraction that leaves the medium again through the surface after at
// least one scattering, instead of being absorbed. Energy for the diffusion profiles on real
// meshes (lib/transport/finite_object_energy.h, energy "escape").
//
// Why: a half-space profile returns R_total of the light that enters (the rest is absorbed on
// long paths deep in the medium). A finite object has no depth to lose it in: a small sphere
// returns more (walks leave sooner, so absorb less; by the mean path length invariance, Blanco &
// Fournier 2003, a body's mean path length is 4V/S, finite where the half-space's is not), a thin
// slab returns light through both faces (measured: docs/physics.md, "Finite objects are not
// half-spaces"). The profiles' shape still says where light leaves; this measures how much.
//
// Estimator: analog random walks per channel at probe vertices (all vertices, or an even stride
// of them). Each walk enters at a uniform point of the vertex's triangles (area-weighted: the
// surface the vertex stands for; a vertex of a coarse convex mesh is a cone's apex, where walks
// leave too easily) through the face, with the diffusely transmitted direction distribution
// (outside direction cosine-weighted, accepted with probability F_t, refracted in). It flies with
// sigma_s (Henyey-Greenstein g), the first flight forced to scatter before the far side (weight
// 1 - exp(-sigma_s t_far): unscattered transmission is not diffusion's light), carries absorption
// as the weight exp(-sigma_a l) of its path length l (no Russian roulette: the weight stays in
// [0, 1]), reflects or leaves at the boundary with the exact Fresnel probability and scores its
// weight when it leaves. Walks lost through holes of an open mesh are left out (the mesh says
// nothing about the medium behind a hole); where no walk nearby stayed inside (an open sheet) P
// is the half-space albedo. On a thick box it reproduces the half-space albedo table
// (lib/material/halfspace_albedo.h; tests/pathtrace/escape_probability_test.cpp). The probe
// estimates are smoothed over the surface with a Gaussian of sigma = smoothing x the channel's
// diffusion length 1/sigma_tr,c (at least twice the probe spacing), weights G(|x - x_p|) A_p: P
// follows the object's shape, which varies slowly on that scale (the accuracy study,
// tests/bench/accuracy_study.cpp, compares widths), and the wide kernel averages many walks. The
// near share varies on the near window's scale and is smoothed over two windows (same floor).
// Deterministic for any thread count: each walk draws from its own Pcg32 stream (vertex, channel,
// walk index).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/run_context.h"

namespace sss {

struct TriangleMesh;  // lib/mesh/triangle_mesh.h
struct Material;      // lib/material/material.h

struct EscapeOptions {
  int walks = 16;                // per probe vertex and channel
  std::size_t maxProbes = 2048;  // probe vertices (an even stride when the mesh has more)
  double smoothing = 2.0;        // Gaussian sigma in each channel's diffusion length
  // When > 0 (mm, per channel): also the near share of P, the walks' weights times
  // W(d) = exp(-d^2 / (2 w^2)) of their exit's distance d from the entry
  // (lib/transport/far_field.h).
  glm::dvec3 nearWindowMm{0.0};
  RunContext run;
};

struct EscapeResult {
  std::vector<glm::vec3> probability;  // smoothed escape probability per vertex
  glm::dvec3 mean{0.0};                // area-weighted mean over the surface
  // Relative standard error of `probability` (RMS over vertices and channels), from the probes'
  // sample variances propagated through the smoothing weights.
  double relativeStdError = 0.0;
  std::size_t probes = 0;
  uint64_t walks = 0;
  uint64_t lostWalks = 0;  // left through holes in an open mesh (left out)
  double meanScatteringEvents = 0.0;
  glm::dvec3 smoothingSigmaMm{0.0};  // P's, per channel
  double seconds = 0.0;
  // With a near window: P's near share per vertex (smoothed over two windows) and its relative
  // standard error (as relativeStdError); empty and 0 without.
  std::vector<glm::vec3> nearProbability;
  double nearRelativeStdError = 0.0;
  // |P_near| / |P| (area-weighted RMS over vertices and channels): what the near share's noise
  // weighs in B, the rest being the far field's (transport/far_field.h); 0 without a window.
  double nearShare = 0.0;
  // The exit lobe of the walks' light (optics/exit_lobe.h): the flux-weighted mean internal
  // cosine of every walk's exit, over the whole surface, per channel, and its variance (the
  // bake's exit lobe, bake.cpp: how far this object's exits are from a half-space's).
  glm::dvec3 exitCosine{0.0}, exitCosineVariance{0.0};
  // The near share's noise relative to B: its own relative noise times its weight in B.
  double nearErrorInB() const { return nearRelativeStdError * nearShare; }
};

// Walks added in rounds: walk s of vertex v in channel c always draws from its own stream, so a
// round of m walks per probe and then one of n give the result of one round of m + n (the bake's
// planner looks at a cheap first round before deciding how many more it needs). Holds the mesh
// and areas by reference.
class EscapeWalks {
 public:
  // options.walks is not used here. Throws Error as estimateEscapeProbability does.
  EscapeWalks(const TriangleMesh& meshMm, std::span<const float> areas, const Material& material,
              const EscapeOptions& options);
  ~EscapeWalks();
  EscapeWalks(const EscapeWalks&) = delete;
  EscapeWalks& operator=(const EscapeWalks&) = delete;

  void add(int walksPerProbe);  // per probe and channel; throws Error below 1
  int walksPerProbe() const;    // so far
  EscapeResult result() const;  // smoothed, from every walk so far; seconds: all rounds

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// One round of options.walks. meshMm: positions in mm, consistently wound triangles (outward
// normals); areas: mm^2 per vertex (vertexAreas).
// Throws Error on an empty mesh, mismatched areas, an invalid material, |g| >= 1 or walks < 1.
EscapeResult estimateEscapeProbability(const TriangleMesh& meshMm, std::span<const float> areas,
                                       const Material& material, const EscapeOptions& options);

}  // namespace sss

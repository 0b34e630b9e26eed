// Monte Carlo volumetric reference for subsurface scattering (`sss-bake --method pathtrace`).
//
// Model: the mesh is a smooth dielectric boundary (relative index eta, exact Fresnel of
// lib/optics/fresnel.h) around a homogeneous medium with sigma_a and sigma_s = sigma_s' / (1 - g)
// (isotropic phase function for g = 0, Henyey-Greenstein otherwise), lit by a radiance cubemap.
// Light that leaves the medium sees the environment only where the mesh does not occlude it
// (the bake's visibility: no interreflection between parts of the surface).
//
// Estimator: backward (adjoint) random walks, one family per vertex x_o:
//  - exitance B(x_o) = integral over the outside hemisphere of L_o(x_o, w) cos dw: the outside
//    direction w is cosine-sampled, so each walk carries pi; it refracts inward through the
//    vertex normal with the Fresnel transmittance F_t (the specular surface reflection is not
//    part of B);
//  - radiance L_o(x_o, w_v) along a fixed outside direction w_v (the normal, or towards a
//    viewer), with weight F_t(w_v); no specular reflection either.
//
// Faceted meshes: the vertex normal's hemisphere is the smooth surface's, but near a vertex the
// mesh is its 1-ring of flat triangles, which cuts off grazing inward directions (a walk would
// leave through a neighbouring triangle before its first scattering: a fraction of about the
// squared sine of the facet angle, PathTraceResult::redrawnDirections counts them). Such
// exitance directions are redrawn, i.e. B averages over the directions the facets let in;
// radiance directions are fixed and not redrawn.
//
// Inside, free flights are sampled by one channel ("hero", chosen uniformly per walk) and the
// three channels are combined by spectral MIS (one-sample balance heuristic over the channels'
// path pdfs: Wilkie et al. 2014; Miller, Georgiev & Jarosz 2019), so RGB media with different
// sigma_t are unbiased in every channel. Boundary distances come from Embree (rtcIntersect1) on
// the triangles; at the boundary the walk reflects with probability F_r (total internal
// reflection included) or refracts out and adds the environment's radiance along the refracted
// direction if it is unoccluded (rtcOccluded1). The eta^2 radiance scaling of entry and exit
// cancels along a path. Russian roulette on the MIS-weighted throughput ends long walks without
// bias. Before the run, a pilot estimates the walk length and warns when it is long.
//
// Units: positions in millimetres, coefficients per millimetre. B has the units of the
// environment's radiance times steradians (W/m^2 for W/(m^2 sr)): the same as the diffusion
// methods' exitance_r/g/b (B = sum_i R_d E_i A_i with E the Fresnel-transmitted irradiance),
// so the two compare vertex by vertex. The diffusion side's radiance is the exit model
// L_o = B F_t(mu_o, eta) / (pi (1 - 2 C_1(eta))) (lib/optics/fresnel.h); `radiance` here is the
// transport truth it is judged against.
//
// Determinism: each vertex draws from Pcg32(seed, vertex index) and is computed by one thread, so
// results are identical for any thread count.
//
// Use from sss-bake (`--method pathtrace`):
//   material.g = g;  // --g: Henyey-Greenstein; the walk uses sigma_s = sigma_s' / (1 - g)
//   PathTraceOptions opt; opt.samples = N; opt.seed = seed; opt.threads = threads;
//   opt.quiet = quiet;
//   PathTraceResult r = pathTraceSubsurface(meshMm, radianceCubemap, material, opt);
//   // r.exitance -> exitance_r/g/b; r.exitanceStdErr and r.warnings -> --json and stderr.
// The irradiance to store alongside (irradiance_r/g/b) stays the visibility step's E.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/run_context.h"
#include "envmap/cubemap.h"

namespace sss {

struct TriangleMesh;  // lib/mesh/triangle_mesh.h
struct Material;      // lib/material/material.h

// Where the radiance estimate looks from.
enum class RadianceDirection {
  Normal,       // along each vertex normal
  TowardsPoint  // towards PathTraceOptions::viewPoint (vertices facing away get 0)
};

// Where a vertex's walks enter the medium.
enum class WalkEntry {
  Vertex,  // at the vertex, through its (smooth) normal: the value at that point
  // At uniform points of its triangles (area-weighted), through their face normals: the mean over
  // the surface the vertex stands for. On a coarse mesh a vertex is the apex of a cone of facets
  // (or the bottom of a pit), which a smooth-surface model does not describe.
  OneRing
};

struct PathTraceOptions {
  int samples = 256;  // walks per vertex and per estimate (exitance, radiance)
  // Only these vertices (indices into the mesh), in this order; the result arrays then hold one
  // entry per listed vertex. Empty: every vertex. A vertex's value does not depend on the list.
  std::vector<uint32_t> vertices;
  RunContext run{.quiet = false};
  bool estimateExitance = true;
  bool estimateRadiance = true;
  RadianceDirection radianceDirection = RadianceDirection::Normal;
  glm::vec3 viewPoint = glm::vec3(0.0f);  // mm, for RadianceDirection::TowardsPoint
  bool occlusion = true;                  // the mesh shadows the environment at exit points
  WalkEntry entry = WalkEntry::Vertex;
  // Count light scattered at least this often: 1 (default) leaves out unscattered transmission,
  // 2 also single scattering (which the diffusion models lack), 0 counts everything.
  int minScatteringOrder = 1;
  int maxScatteringEvents = 1 << 20;  // safety cap; walks that reach it are counted
};

struct PathTraceResult {
  // Per vertex (or per listed vertex); empty when not estimated.
  std::vector<glm::vec3> exitance, exitanceStdErr;  // B and its standard error
  std::vector<glm::vec3> radiance, radianceStdErr;  // L_o and its standard error
  // Per vertex: the fraction of its walks lost through holes (no boundary ahead). Where it is
  // not ~0 the open mesh has no medium behind the vertex and its values mean little.
  std::vector<float> escapedFraction;
  double meanScatteringEvents = 0.0;  // per walk, all vertices
  double meanBoundaryHits = 0.0;      // per walk (internal reflections + the exit)
  uint64_t walks = 0;
  uint64_t truncatedWalks = 0;     // hit maxScatteringEvents
  uint64_t escapedWalks = 0;       // lost through a hole of an open mesh (no boundary ahead)
  uint64_t redrawnDirections = 0;  // exitance directions cut off by the faceted 1-ring
  double seconds = 0.0;
  std::vector<std::string> warnings;  // also printed (unless quiet) as "warning: ..." lines
};

// Estimates per-vertex exitance and radiance. meshMm: positions in millimetres, unit vertex
// normals pointing out, closed and consistently oriented for meaningful results. The material's
// g (Henyey-Greenstein mean cosine) sets the phase function and sigma_s = sigma_s' / (1 - g).
// Throws Error on an empty mesh, an invalid material (validateMaterial) or |g| >= 1.
PathTraceResult pathTraceSubsurface(const TriangleMesh& meshMm, const Cubemap& radiance,
                                    const Material& material, const PathTraceOptions& options);

// The same on plain arrays: sigmaS is the real (not reduced) scattering coefficient.
struct HomogeneousMedium {
  glm::dvec3 sigmaA{0.0}, sigmaS{0.0};  // mm^-1
  double eta = 1.0;                     // medium index relative to outside, >= 1
  double g = 0.0;                       // Henyey-Greenstein mean cosine, |g| < 1
};
// Throws Error unless |g| < 1, the coefficients are finite and non-negative with some
// extinction, and eta >= 1.
void validateHomogeneousMedium(const HomogeneousMedium& medium);
// The medium of a material: its sigma_a, the real sigma_s = sigma_s' / (1 - g), eta and g.
HomogeneousMedium homogeneousMediumOf(const Material& material);
PathTraceResult pathTraceSubsurface(const std::vector<glm::vec3>& positionsMm,
                                    const std::vector<glm::vec3>& normals,
                                    const std::vector<glm::uvec3>& triangles,
                                    const Cubemap& radiance, const HomogeneousMedium& medium,
                                    const PathTraceOptions& options);

}  // namespace sss

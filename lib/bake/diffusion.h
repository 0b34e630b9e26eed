// The diffusion sums of Li & Guo Eq. 7: the exitance at every vertex from the transmitted
// irradiance at all vertices,
//
//   B(x_o) = sum_i R_d(|x_i - x_o|) E(x_i) A_i,
//
// with positions in mm, A_i the area a vertex stands for (mm^2, one third of its triangles:
// Li & Guo's M) and R_d a diffusion profile (lib/material) or its sum of normalized Gaussians
// G(v, r) = exp(-r^2 / 2v) / (2 pi v) (Li & Guo Eq. 9 drops the 1/v; corrected here).
//
// Methods:
//   exact         every pair with the profile itself, O(N^2): the reference
//                 (exact_diffusion_sum.h).
//   gauss         the Gaussian fit, every pair closer than a cutoff radius per Gaussian (energy
//                 beyond r_c of a 2D Gaussian is exp(-r_c^2 / 2v)), over an octree
//                 (octree_gaussian_sum.h, diffusion_octree.h).
//   incremental   Li & Guo Eq. 11: pass k convolves pass k-1 with G(v_k - v_(k-1)); exact on
//                 a plane, approximate on a discrete curved surface (incremental_diffusion.h;
//                 measured in the README).
//   hierarchical  Jensen & Buhler 2002: octree clusters (area-weighted irradiance sums, centroid,
//                 spread) replace far groups of points when the cluster is small against the
//                 narrowest Gaussian that still reaches it; for wide (translucent) kernels.
//   auto          the cheapest of exact, gauss and hierarchical that meets the tolerance, from
//                 cost estimates (diffusion.cpp).
// Error budget of the Gaussian methods: the fit gets half the tolerance, truncation a quarter,
// clusters about a sixth.
// Stability: the self term integrates the profile over the vertex's disc of area A_i, and each
// source point is a disc (per-axis variance rho^2 / 4), so meshes coarser than the mean free path
// stay finite and close to the continuous answer.
// Determinism: every vertex sums its terms in a fixed order: identical for any thread count.
#pragma once

#include <cstddef>
#include <glm/vec3.hpp>
#include <span>
#include <string>
#include <vector>

#include "core/enum_names.h"

namespace sss {

class DiffusionProfile;  // material/diffusion_profile.h

enum class DiffusionMethod { Auto, Exact, Gauss, Incremental, Hierarchical };

inline constexpr EnumNames<DiffusionMethod, 5> kDiffusionMethodNames{
    "diffusion method",
    {{{DiffusionMethod::Auto, "auto"},
      {DiffusionMethod::Exact, "exact"},
      {DiffusionMethod::Gauss, "gauss"},
      {DiffusionMethod::Incremental, "incremental"},
      {DiffusionMethod::Hierarchical, "hierarchical"}}}};

// Plain per-vertex arrays, all of the same length (checked).
struct DiffusionInput {
  std::span<const glm::vec3> positions;   // mm
  std::span<const glm::vec3> normals;     // unit length
  std::span<const float> areas;           // mm^2 (Li & Guo's M)
  std::span<const glm::vec3> irradiance;  // transmitted irradiance E per vertex
};

struct DiffusionOptions {
  DiffusionMethod method = DiffusionMethod::Auto;
  double tolerance = 0.01;  // target relative RMS error of B (the fit gets part of it)
  int maxGaussians = 16;    // upper bound on K for fitGaussians (at most 16)
  int threads = 0;          // <= 0: all cores
  bool quiet = false;       // no progress bar on stderr
  // Also return rho_o = sum_i R_d(r_oi) A_i, the sum with E = 1 (finite_object_energy.h): fused
  // into the exact sum, a second pass of the same method otherwise.
  bool weightSums = false;
  // rho when it is already known (same mesh, profile and method: it does not depend on E), one
  // per vertex: returned as it is instead of the second pass. Empty: computed.
  std::span<const glm::vec3> knownWeightSums;
};

struct DiffusionReport {
  DiffusionMethod method = DiffusionMethod::Exact;  // the one that ran (never Auto)
  std::string reason;                               // why (auto: the estimates that decided)
  int gaussians = 0;                                // K of the fit; 0 for exact
  double fitError = 0;                              // fit error reported by fitGaussians
  std::vector<double> variances;                    // mm^2, one per Gaussian
  std::vector<double> cutoffs;  // mm, one per Gaussian (gauss, incremental, hierarchical)
  double clusterTheta = 0;      // hierarchical: cluster radius / Gaussian sigma bound
  // Model of the method's relative RMS error of B (fit + truncation + clusters) against the
  // converged sum on the same mesh; not the mesh's own discretization error (see README).
  double estimatedError = 0;
  std::size_t interactions = 0;  // terms: (receiver, source) pairs x K Gaussians (exact: x 1)
  double fitSeconds = 0, indexSeconds = 0, sumSeconds = 0, totalSeconds = 0;
};

struct DiffusionResult {
  std::vector<glm::vec3> exitance;    // B per vertex, same units as E
  std::vector<glm::vec3> weightSums;  // rho per vertex when DiffusionOptions::weightSums
  // The escape energy model's excess term per vertex, max(0, P - R) Ebar (finite_object_energy.h):
  // the part of B that diffused beyond what a half-space returns. Empty for other models.
  std::vector<glm::vec3> escapeExcess;
  DiffusionReport report;
};

// Throws sss::Error on mismatched array lengths, non-finite input or negative areas.
DiffusionResult diffuse(const DiffusionInput& input, const DiffusionProfile& profile,
                        const DiffusionOptions& options = {});

}  // namespace sss

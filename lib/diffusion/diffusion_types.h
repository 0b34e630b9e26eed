// The types of the diffusion sums (diffusion.h): what they take (positions, normals, areas, E),
// how (method, tolerance) and what they give (B, the weight sums, the report). Shared by the
// dispatcher and each method, so that neither includes the other.
#pragma once

#include <cstddef>
#include <glm/vec3.hpp>
#include <span>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "core/run_context.h"

namespace sss {

class DiffusionProfile;    // material/diffusion_profile.h
class DiffusionMeshCache;  // diffusion.h

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
  double tolerance = 0.01;         // target relative RMS error of B (the fit gets part of it)
  int maxGaussians = 16;           // upper bound on K for fitGaussians (at most 16)
  RunContext run{.quiet = false};  // the seed is unused: the sums are exact arithmetic
  // Also return rho_o = sum_i R_d(r_oi) A_i, the sum with E = 1 (finite_object_energy.h): fused
  // into the exact sum, a second pass of the same method otherwise.
  bool weightSums = false;
  // rho when it is already known (same mesh, profile and method: it does not depend on E), one
  // per vertex: returned as it is instead of the second pass. Empty: computed.
  std::span<const glm::vec3> knownWeightSums;
  // Keeps what the sums build from the mesh alone for the next call on the same mesh (null: built
  // each call); the result is the same either way. Not kept.
  DiffusionMeshCache* meshCache = nullptr;
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
  // converged sum on the same mesh; not the mesh's own discretization error (docs/accuracy.md,
  // "Resolution").
  double estimatedError = 0;
  // Terms: (receiver, source) pairs x the Gaussians reaching the source (exact: x 1).
  std::size_t interactions = 0;
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

}  // namespace sss

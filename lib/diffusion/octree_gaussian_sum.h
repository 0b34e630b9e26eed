// The sum of a Gaussian mixture over the diffusion octree, shared by the gauss, hierarchical and
// incremental methods (diffusion.h). Private to lib/diffusion.
//
// Receiver groups (diffusion_octree.h) are the unit of work: for each group one octree traversal
// collects an interaction list (source points, or clusters for the hierarchical method) with a
// conservative box-to-box distance, and every receiver of the group then sums the whole list in a
// fixed order with SIMD-friendly loops over structure-of-arrays floats. A source item j with mass
// m_j = E_j A_j (a cluster: the sums over its points) and spread c_j contributes
//
//   m_j sum_k w_k G(v_k + c_j, |x_o - x_j|),
//
// i.e. each source is a small disc (per-axis variance c_j = A_j / 4 pi for a vertex: a disc of
// radius rho has variance rho^2 / 4) convolved with the Gaussian (G(v1) * G(v2) = G(v1 + v2)), and
// a cluster adds its in-plane second moment about its centroid (the isotropic part of the
// second-order Taylor term; the first-order term vanishes at the centroid). The receiver's own
// term is the closed-form integral over its disc of area A_o:
//   E_o sum_k w_k (1 - exp(-rho^2 / 2 v_k)),  rho^2 = A_o / pi.
// Sampling the narrow Gaussians at points instead would put 1 / (2 pi v) A_o, far above 1, on a
// vertex coarser than sqrt(v): the blow-up this avoids.
//
// Cutoffs: Gaussian k is dropped beyond r_k where, in every channel, its weight times the tail
// energy exp(-r_k^2 / 2 v_k) is below tailBudget / K of the channel's total reflectance; so
// truncation loses at most tailBudget of B. An item (point or cluster) is summed with the
// Gaussians from the first whose cutoff reaches its box from the group's box on: the narrower
// ones' terms are within that budget, and for a cluster they would be worse than dropped (its
// Gaussian blob puts mass past its box, into a narrow Gaussian's reach). The list is ordered by
// that first Gaussian and each SIMD block of it is summed from its first item's Gaussian on; on
// the 150 mm marble dragon this halves the terms of the hierarchical sum (docs/performance.md).
//
// Clusters (theta > 0; Jensen & Buhler 2002's octree of clusters, with a width-based test in
// place of their solid angle): a node of radius R at box distance d from the group is used as one
// cluster when R <= theta sigma_k, sigma_k the narrowest Gaussian whose cutoff reaches d. The
// neglected (anisotropic, fourth-order) terms are relative O((R / sigma)^2 (d / sigma)^2) per
// cluster, and summed over the kernel's support they are O(theta^2) of B.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "diffusion/diffusion_octree.h"

namespace sss {

class Progress;      // core/progress.h
struct GaussianSum;  // material/gaussian_sum_fit.h

inline constexpr int kMaxKernelGaussians = 16;

// A Gaussian mixture sum_k w_k G(v_k, r) in the octree sum's float form, with each Gaussian's
// cutoff radius r_k and r_k^2 / v_k (a Gaussian blurred to variance v reaches r_k^2 v / v_k).
struct GaussianMixtureKernel {
  int count = 0;
  std::array<float, kMaxKernelGaussians> variance{}, sigma{}, cutoff{}, cutoffSquaredPerVariance{};
  std::array<glm::vec3, kMaxKernelGaussians> weight{};
  float maxCutoff = 0;
};

// The float kernel of a Gaussian sum (at most kMaxKernelGaussians terms), with cutoffs so that
// truncation loses at most tailBudget of B.
GaussianMixtureKernel makeGaussianMixtureKernel(const GaussianSum& sum, double tailBudget);

struct OctreeSumStatistics {
  std::atomic<std::size_t> interactions{0};  // (receiver, item) pairs x the Gaussians reaching it
};

// B in Morton order: the sum over sources of mass[j] sum_k w_k G(v_k + c_j, d) with the disc self
// term, mass[j] = irradiance[j] area[j] (irradiance in Morton order). theta = 0: every point
// within the cutoffs (gauss); theta > 0: clusters (hierarchical), built here unless `clusters`
// already holds them for this irradiance. Adds the terms it summed to stats.
std::vector<glm::vec3> sumGaussianMixtureOverOctree(const DiffusionOctree& tree,
                                                    const std::vector<glm::vec3>& irradiance,
                                                    const GaussianMixtureKernel& kernel,
                                                    double theta, int threads, Progress* progress,
                                                    OctreeSumStatistics& stats,
                                                    std::vector<ClusterMoments> clusters = {});

// Dry run of the traversal on every `stride`-th group: the estimated number of terms of
// sumGaussianMixtureOverOctree for the whole mesh ((receiver, item) pairs times the Gaussians that
// reach the item, padding included).
double estimateInteractionTerms(const DiffusionOctree& tree, const GaussianMixtureKernel& kernel,
                                double theta, const std::vector<ClusterMoments>& clusters,
                                std::size_t stride, int threads);

}  // namespace sss

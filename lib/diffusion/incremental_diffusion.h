// The incremental method (diffusion.h's `incremental`), Li & Guo Eq. 11: pass 0 is E; pass k =
// G(v_k - v_(k-1)) convolved with pass k-1, as a sum over vertices with the same disc terms as
// the other Gaussian methods (octree_gaussian_sum.h); B = sum_k w_k pass_k.
//
// On a plane this is exact since Gaussians compose; on a discrete curved surface it is not: each
// pass re-samples the field at the vertices, and wherever more surface lies within reach than on
// a plane (concave and thin parts, distances measured through the object) the pass gains a little
// that the next pass multiplies again. Steps narrower than two vertex spacings (v_k - v_(k-1) < 4
// mean vertex areas) are also badly normalized by the discrete sum, so those passes start from E
// with the whole v_k instead. It costs less than gauss (one Gaussian per pass; with a geometric
// variance ladder v_k - v_(k-1) is most of v_k, so the support per pass barely shrinks) and more
// than hierarchical, and its error is not bounded by the tolerance: auto never picks it (the
// errors measured on the dragon and spheres: docs/physics.md, "Where we correct the paper").
// Private to lib/diffusion.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "diffusion/octree_gaussian_sum.h"

namespace sss {

// B in Morton order from the irradiance in Morton order, for the fitted Gaussian sum `fit` whose
// float form is `kernel`; each pass's cutoff keeps its truncation within tailBudget / K of B.
// Writes the pass cutoffs (mm) to `cutoffs` (one per Gaussian) and adds its terms to stats.
std::vector<glm::vec3> incrementalDiffusionSum(
    const DiffusionOctree& tree, const std::vector<glm::vec3>& irradiance, const GaussianSum& fit,
    const GaussianMixtureKernel& kernel, double tailBudget, int threads, bool quiet,
    OctreeSumStatistics& stats, std::vector<double>& cutoffs);

}  // namespace sss

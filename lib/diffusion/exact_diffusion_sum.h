// The exact diffusion sum (diffusion.h's `exact`, the reference): every pair with the profile's
// own R_d in double precision, O(N^2). The self term is DiffusionProfile::integrateDisc(rho_o),
// rho_o^2 = A_o / pi; sources closer than four disc radii are averaged over their disc in their
// tangent plane (a 32-point quadrature), farther ones are point samples. So it approximates the
// same continuous surface integral as the Gaussian methods' disc blur (octree_gaussian_sum.h).
// Private to lib/diffusion.
#pragma once

#include <cstddef>

#include "diffusion/diffusion_types.h"

namespace sss {

// B (and rho when options.weightSums) per vertex, in input order; report.interactions = N^2, the
// other report fields are left to the caller. Input validated by the caller.
DiffusionResult exactDiffusionSum(const DiffusionInput& input, const DiffusionProfile& profile,
                                  const DiffusionOptions& options);

}  // namespace sss

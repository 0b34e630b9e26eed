#include "diffusion/incremental_diffusion.h"

#include "core/progress.h"
#include "material/gaussian_sum_fit.h"

namespace sss {

namespace {

// A step variance below this many mean vertex areas (sigma < 2 spacings) is not resolved by the
// discrete sum; measured on spheres, planes and the dragon (tests/bench/diffusion_sweep.sh).
constexpr double kIncrementalMinStep = 4;

double meanArea(const MortonSortedPoints& points) {
  double mean = 0;
  for (std::size_t j = 0; j < points.size(); ++j) mean += points.area[j];
  return mean / static_cast<double>(points.size());
}

}  // namespace

std::vector<glm::vec3> incrementalDiffusionSum(
    const DiffusionOctree& tree, const std::vector<glm::vec3>& irradiance, const GaussianSum& fit,
    const GaussianMixtureKernel& kernel, double tailBudget, int threads, bool quiet,
    OctreeSumStatistics& stats, std::vector<double>& cutoffs) {
  const std::size_t n = tree.points.size();
  Progress progress("diffusion (incremental)", tree.groups.size() * kernel.count, quiet);
  std::vector<glm::vec3> pass = irradiance;
  std::vector<glm::vec3> sum(n, glm::vec3(0));
  const double minStep = kIncrementalMinStep * meanArea(tree.points);
  double previous = 0;
  for (int k = 0; k < kernel.count; ++k) {
    // Re-convolving is only as good as the discrete sum's normalization: a step narrower than
    // the vertex spacing starts from E with the whole variance instead.
    const bool resolved = fit.variances[k] - previous >= minStep;
    GaussianSum step;
    step.variances = {resolved ? fit.variances[k] - previous : fit.variances[k]};
    step.weights = {glm::dvec3(1)};
    previous = fit.variances[k];
    const GaussianMixtureKernel stepKernel =
        makeGaussianMixtureKernel(step, tailBudget / kernel.count);
    // The pass's mass is the previous pass's field: the octree sum multiplies it by the area.
    pass = sumGaussianMixtureOverOctree(tree, resolved ? pass : irradiance, stepKernel, 0, threads,
                                        &progress, stats);
    cutoffs[k] = stepKernel.cutoff[0];
    for (std::size_t j = 0; j < n; ++j) sum[j] += kernel.weight[k] * pass[j];
  }
  progress.finish();
  return sum;
}

}  // namespace sss

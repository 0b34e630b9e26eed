// diffuse(): input checks, the Gaussian fit shared by the fast methods, the automatic choice of
// method from cost estimates, and the order changes between the input and the octree's Morton
// order. The sums themselves: exact_diffusion_sum.cpp, octree_gaussian_sum.cpp (gauss,
// hierarchical) and incremental_diffusion.cpp.
#include "diffusion/diffusion.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <utility>

#include "core/error.h"
#include "core/format.h"
#include "core/progress.h"
#include "core/timer.h"
#include "diffusion/diffusion_octree.h"
#include "diffusion/exact_diffusion_sum.h"
#include "diffusion/incremental_diffusion.h"
#include "diffusion/octree_gaussian_sum.h"
#include "material/diffusion_profile.h"
#include "material/gaussian_sum_fit.h"

namespace sss {

namespace {

// Hierarchical: theta = kThetaScale sqrt(tolerance) gives kClusterError theta^2 ~ tolerance / 6.
constexpr double kThetaScale = 12.0;
// Hierarchical: relative RMS error of B from clusters ~ kClusterError theta^2, fitted on the
// 150 mm dragon (23K vertices) and 20 mm / 80 mm spheres, marble and skimmilk
// (tests/bench/diffusion_sweep.sh).
constexpr double kClusterError = 0.0011;
// The auto method's cost model. CPU seconds per unit of work, measured on the development machine
// (Xeon, AVX-512, GCC 12); only their ratio matters.
constexpr double kCpuSecondsPerGaussTerm = 0.5e-9;  // one (receiver, item, Gaussian) term
constexpr double kCpuSecondsPerExactPair = 70e-9;   // one dipole pair (3 channels, double)
constexpr double kCpuSecondsFitFloor = 0.03;        // about what fitGaussians takes
// Auto: sampled receiver groups for the cost estimate of the octree sums.
constexpr std::size_t kCostSampleGroups = 200;

std::string threeDigits(double v) {
  return format("%.3g", v);
}

void validateInput(const DiffusionInput& in) {
  const std::size_t n = in.positions.size();
  if (in.normals.size() != n || in.areas.size() != n || in.irradiance.size() != n) {
    std::ostringstream msg;
    msg << "diffusion input: array lengths differ (positions " << n << ", normals "
        << in.normals.size() << ", areas " << in.areas.size() << ", irradiance "
        << in.irradiance.size() << ")";
    throw Error(msg.str());
  }
  if (n > 0xffffffffu) throw Error("diffusion input: more than 2^32 vertices");
  std::size_t badPos = 0, badArea = 0, badE = 0, first = n;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 p = in.positions[i], e = in.irradiance[i];
    const bool bp = !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z);
    const bool ba = !std::isfinite(in.areas[i]) || in.areas[i] < 0;
    const bool be = !std::isfinite(e.x) || !std::isfinite(e.y) || !std::isfinite(e.z) || e.x < 0 ||
                    e.y < 0 || e.z < 0;
    badPos += bp, badArea += ba, badE += be;
    if ((bp || ba || be) && first == n) first = i;
  }
  if (badPos + badArea + badE > 0) {
    std::ostringstream msg;
    msg << "diffusion input: " << badPos << " non-finite positions, " << badArea
        << " negative or non-finite areas, " << badE
        << " negative or non-finite irradiance values (first at vertex " << first << ")";
    throw Error(msg.str());
  }
}

// The exact method with its report: `reason` why it ran, times from `total`'s start.
DiffusionResult diffuseExact(const DiffusionInput& input, const DiffusionProfile& profile,
                             const DiffusionOptions& options, std::string reason,
                             const Stopwatch& total) {
  const Stopwatch sum;
  DiffusionResult result = exactDiffusionSum(input, profile, options);
  result.report.method = DiffusionMethod::Exact;
  result.report.reason = std::move(reason);
  result.report.sumSeconds = sum.seconds();
  result.report.totalSeconds = total.seconds();
  return result;
}

// What the fast methods share: the fit, its float kernel, the octree.
struct GaussianSetup {
  GaussianSumFit fit;
  GaussianMixtureKernel kernel;
  double theta = 0;  // the hierarchical method's cluster size bound (octree_gaussian_sum.h)
  std::shared_ptr<const DiffusionOctree> tree;
};

// The fit (half the tolerance), the kernel (truncation: a quarter) and the octree; fills the
// report's fit fields, fitSeconds and indexSeconds.
GaussianSetup prepareGaussianSums(const DiffusionInput& input, const DiffusionProfile& profile,
                                  const DiffusionOptions& options, DiffusionReport& report) {
  const double tol = options.tolerance;
  GaussianSetup setup;
  Stopwatch stage;
  const int maxGaussians = std::min(options.maxGaussians, kMaxKernelGaussians);
  setup.fit = options.meshCache ? options.meshCache->fit(profile, 0.5 * tol, maxGaussians)
                                : fitGaussians(profile, 0.5 * tol, maxGaussians);
  report.fitSeconds = stage.seconds();
  setup.kernel = makeGaussianMixtureKernel(setup.fit.sum, 0.25 * tol);
  setup.theta = kThetaScale * std::sqrt(tol);
  report.gaussians = setup.kernel.count;
  report.fitError = setup.fit.error;
  report.variances = setup.fit.sum.variances;
  for (int k = 0; k < setup.kernel.count; ++k) report.cutoffs.push_back(setup.kernel.cutoff[k]);
  stage.restart();
  setup.tree = options.meshCache ? options.meshCache->octree(input)
                                 : std::make_shared<const DiffusionOctree>(buildDiffusionOctree(
                                       input.positions, input.normals, input.areas));
  report.indexSeconds = stage.seconds();
  return setup;
}

struct MethodChoice {
  DiffusionMethod method = DiffusionMethod::Exact;
  std::string reason;
  double seconds = 0;                    // spent estimating
  std::vector<ClusterMoments> clusters;  // of E, for the hierarchical sum to reuse
};

// Auto: exact, gauss or hierarchical, whichever the cost model expects to be the cheapest (gauss
// unless clearly slower: it has no cluster error). Costs: exact from N^2; gauss and hierarchical
// from a dry-run traversal of about kCostSampleGroups groups.
MethodChoice chooseMethod(const DiffusionInput& input, const GaussianSetup& setup, double exactCost,
                          int threads) {
  const Stopwatch clock;
  const DiffusionOctree& tree = *setup.tree;
  const std::size_t n = input.positions.size();
  const std::size_t stride = std::max<std::size_t>(1, tree.groups.size() / kCostSampleGroups);
  std::vector<glm::vec3> mass(n);
  for (std::size_t k = 0; k < n; ++k)
    mass[k] = input.irradiance[tree.points.original[k]] * tree.points.area[k];
  MethodChoice choice;
  choice.clusters = buildClusterMoments(tree, mass, threads);
  const GaussianMixtureKernel& kernel = setup.kernel;
  const double gaussCost =
      kCpuSecondsPerGaussTerm *
      estimateInteractionTerms(tree, kernel, 0, choice.clusters, stride, threads);
  const double hierCost =
      kCpuSecondsPerGaussTerm *
      estimateInteractionTerms(tree, kernel, setup.theta, choice.clusters, stride, threads);
  choice.seconds = clock.seconds();
  if (exactCost <= std::min(gaussCost, hierCost)) {
    choice.method = DiffusionMethod::Exact;
  } else if (gaussCost <= 1.2 * hierCost) {
    choice.method = DiffusionMethod::Gauss;
  } else {
    choice.method = DiffusionMethod::Hierarchical;
  }
  choice.reason = "estimated CPU seconds: exact " + threeDigits(exactCost) + ", gauss " +
                  threeDigits(gaussCost) + ", hierarchical " + threeDigits(hierCost) +
                  "; incremental is not considered: its error on curved surfaces is not bounded";
  return choice;
}

// B in Morton order by a fast method; fills the report's sum fields and error estimate.
std::vector<glm::vec3> sumInMortonOrder(const DiffusionInput& input, const GaussianSetup& setup,
                                        DiffusionMethod method, const DiffusionOptions& options,
                                        std::vector<ClusterMoments> clusters,
                                        DiffusionReport& report) {
  const DiffusionOctree& tree = *setup.tree;
  const std::size_t n = input.positions.size();
  const double tol = options.tolerance;
  std::vector<glm::vec3> irradiance(n);
  for (std::size_t k = 0; k < n; ++k) irradiance[k] = input.irradiance[tree.points.original[k]];
  OctreeSumStatistics stats;
  std::vector<glm::vec3> sorted;
  const Stopwatch clock;
  if (method == DiffusionMethod::Incremental) {
    sorted = incrementalDiffusionSum(tree, irradiance, setup.fit.sum, setup.kernel, 0.25 * tol,
                                     options.run.threads, options.run.quiet, stats, report.cutoffs);
  } else {
    const double useTheta = method == DiffusionMethod::Hierarchical ? setup.theta : 0;
    report.clusterTheta = useTheta;
    Progress progress(std::string("diffusion (") + kDiffusionMethodNames.name(method) + ")",
                      tree.groups.size(), options.run.quiet);
    sorted =
        sumGaussianMixtureOverOctree(tree, irradiance, setup.kernel, useTheta, options.run.threads,
                                     &progress, stats, std::move(clusters));
    progress.finish();
  }
  report.sumSeconds = clock.seconds();
  report.interactions = stats.interactions;
  // Error model: the fit's profile error, the truncation bound, the calibrated cluster term.
  report.estimatedError =
      setup.fit.error + 0.25 * tol + kClusterError * report.clusterTheta * report.clusterTheta;
  if (method == DiffusionMethod::Incremental)
    report.reason = "estimatedError leaves out Eq. 11's composition error on curved surfaces";
  return sorted;
}

// rho: the same method's sum with E = 1.
std::vector<glm::vec3> unitWeightSums(const DiffusionInput& input, const DiffusionProfile& profile,
                                      const DiffusionOptions& options, DiffusionMethod method) {
  const std::vector<glm::vec3> ones(input.positions.size(), glm::vec3(1.0f));
  DiffusionOptions unitOptions = options;
  unitOptions.method = method;
  unitOptions.weightSums = false;
  unitOptions.run.quiet = true;
  return diffuse({input.positions, input.normals, input.areas, ones}, profile, unitOptions)
      .exitance;
}

}  // namespace

DiffusionMeshCache::DiffusionMeshCache() = default;
DiffusionMeshCache::~DiffusionMeshCache() = default;

std::shared_ptr<const DiffusionOctree> DiffusionMeshCache::octree(const DiffusionInput& input) {
  const auto same = [](const auto& kept, const auto& given) {
    return std::equal(kept.begin(), kept.end(), given.begin(), given.end());
  };
  if (!octree_ || !same(positions_, input.positions) || !same(normals_, input.normals) ||
      !same(areas_, input.areas)) {
    octree_ = std::make_shared<const DiffusionOctree>(
        buildDiffusionOctree(input.positions, input.normals, input.areas));
    positions_.assign(input.positions.begin(), input.positions.end());
    normals_.assign(input.normals.begin(), input.normals.end());
    areas_.assign(input.areas.begin(), input.areas.end());
  }
  return octree_;
}

namespace {

// R_d at radii from 1/256 mm to 256 mm and the total reflectance: what tells two profiles of one
// name apart (their parameters change every one of these values).
std::vector<double> profileFingerprint(const DiffusionProfile& profile) {
  std::vector<double> values;
  const auto add = [&](glm::dvec3 v) { values.insert(values.end(), {v.x, v.y, v.z}); };
  for (int k = -8; k <= 8; ++k) add(profile.evaluate(std::ldexp(1.0, k)));
  add(profile.totalReflectance());
  return values;
}

}  // namespace

GaussianSumFit DiffusionMeshCache::fit(const DiffusionProfile& profile, double tolerance,
                                       int maxGaussians) {
  const std::vector<double> values = profileFingerprint(profile);
  const std::string name = profile.name();
  for (const KeptFit& kept : fits_)
    if (kept.tolerance == tolerance && kept.maxGaussians == maxGaussians &&
        kept.profileName == name && kept.profileValues == values)
      return kept.fit;
  fits_.push_back(
      {values, name, tolerance, maxGaussians, fitGaussians(profile, tolerance, maxGaussians)});
  return fits_.back().fit;
}

DiffusionResult diffuse(const DiffusionInput& input, const DiffusionProfile& profile,
                        const DiffusionOptions& options) {
  const Stopwatch total;
  validateInput(input);
  if (!(options.tolerance > 0 && options.tolerance < 1))
    throw Error("diffusion: tolerance must be in (0, 1), got " + threeDigits(options.tolerance));
  const std::size_t n = input.positions.size();
  const double exactCost = kCpuSecondsPerExactPair * static_cast<double>(n) * n;
  if (options.method == DiffusionMethod::Auto && exactCost <= kCpuSecondsFitFloor) {
    return diffuseExact(input, profile, options,
                        "estimated CPU seconds: exact " + threeDigits(exactCost) +
                            ", less than a Gaussian fit takes",
                        total);
  }
  if (options.method == DiffusionMethod::Exact || n == 0)
    return diffuseExact(input, profile, options, "", total);

  DiffusionResult result;
  DiffusionReport& report = result.report;
  const GaussianSetup setup = prepareGaussianSums(input, profile, options, report);
  DiffusionMethod method = options.method;
  std::vector<ClusterMoments> autoClusters;  // reused by the hierarchical sum
  if (method == DiffusionMethod::Auto) {
    MethodChoice choice = chooseMethod(input, setup, exactCost, options.run.threads);
    report.indexSeconds += choice.seconds;
    if (choice.method == DiffusionMethod::Exact) {
      DiffusionResult exact = diffuseExact(input, profile, options, choice.reason, total);
      exact.report.indexSeconds = report.indexSeconds;
      exact.report.totalSeconds = total.seconds();
      return exact;
    }
    method = choice.method;
    report.reason = std::move(choice.reason);
    autoClusters = std::move(choice.clusters);
  }
  report.method = method;
  const std::vector<glm::vec3> sorted =
      sumInMortonOrder(input, setup, method, options, std::move(autoClusters), report);
  result.exitance.resize(n);
  for (std::size_t k = 0; k < n; ++k) result.exitance[setup.tree->points.original[k]] = sorted[k];
  if (options.weightSums && options.knownWeightSums.size() == n)
    result.weightSums.assign(options.knownWeightSums.begin(), options.knownWeightSums.end());
  else if (options.weightSums)
    result.weightSums = unitWeightSums(input, profile, options, method);
  report.totalSeconds = total.seconds();
  return result;
}

}  // namespace sss

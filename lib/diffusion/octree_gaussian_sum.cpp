#include "diffusion/octree_gaussian_sum.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <span>

#include "core/parallel.h"
#include "core/progress.h"
#include "material/gaussian_sum_fit.h"

namespace sss {

namespace {

constexpr int kLanes = 16;  // SIMD block (2 AVX2 / 1 AVX-512 / 4 SSE registers)
constexpr float kLog2e = std::numbers::log2e_v<float>;
constexpr float kInv2Pi = 0.5f * std::numbers::inv_pi_v<float>;

// GCC keeps a branch for the clamp below unless FP exceptions may be ignored (we never test
// them), which blocks vectorization; per-function so no build flag is needed.
#if defined(__GNUC__) && !defined(__clang__)
#define SSS_VECTORIZABLE_FP __attribute__((optimize("no-trapping-math")))
#else
#define SSS_VECTORIZABLE_FP
#endif

// exp2 for x <= 0 in float, branch-free so that the loops below vectorize: Cody-Waite split
// into 2^i 2^f, f in [-0.5, 0.5], and 2^f by its degree-5 minimax polynomial for relative error
// (Remez; 7.7e-8 in exact arithmetic, below 2.4e-7 in float over [-126, 0]).
SSS_VECTORIZABLE_FP inline float exp2Negative(float x) {
  x = x < -126.0f ? -126.0f : x;
  const int i = static_cast<int>(x - 0.5f);  // round to nearest for x <= 0
  const float f = x - static_cast<float>(i);
  float p = 1.327793890e-3f;
  p = p * f + 9.675757641e-3f;
  p = p * f + 5.550709598e-2f;
  p = p * f + 2.402211434e-1f;
  p = p * f + 6.931469682e-1f;
  p = p * f + 1.000000073f;
  std::int32_t bits = (i + 127) << 23;
  float scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return p * scale;
}

// The Gaussians an item of spread c at box distance^2 d2 from the receiver group needs: those
// from the first that reaches it on. Gaussian k reaches as far as its cutoff widened by the
// item's disc, r_k^2 (1 + c / v_k) (the blurred Gaussian G(v_k + c) has the tail of G(v_k) at
// r sqrt(1 + c / v_k); on a coarse mesh the discs are far wider than the narrow Gaussians). Beyond
// it a Gaussian adds less than its share of the truncation budget (makeGaussianMixtureKernel).
// Only a leading run of Gaussians is skipped, so a ladder whose cutoffs are not increasing loses
// none it needs.
int firstGaussianReaching(const GaussianMixtureKernel& kernel, float d2, float spread) {
  int k = 0;
  while (k < kernel.count - 1 &&
         kernel.cutoffSquaredPerVariance[k] * (kernel.variance[k] + spread) <= d2)
    ++k;
  return k;
}

// The (item, Gaussian) terms one receiver sums over a list whose items number inBand[b] with first
// Gaussian b, laid out as InteractionList::arrange lays them: in that order, in blocks of kLanes,
// each block from the first Gaussian of its first item on.
std::size_t termsPerReceiver(std::span<const std::size_t> inBand, int gaussians) {
  std::size_t terms = 0, before = 0;  // before: the items of the bands before
  for (int band = 0; band < gaussians; ++band) {
    const std::size_t firstBlock = (before + kLanes - 1) / kLanes;
    before += inBand[band];
    const std::size_t endBlock = (before + kLanes - 1) / kLanes;
    terms += (endBlock - firstBlock) * kLanes * static_cast<std::size_t>(gaussians - band);
  }
  return terms;
}

// Interaction list of one receiver group, structure of arrays, its items in the order of their
// first Gaussian (firstGaussianReaching; stable, so the group's own points come first, item r
// being receiver r, for the self term), padded to kLanes with zero mass. Each block of kLanes
// items is summed from the first Gaussian of its first item on (the others in the block are
// reached by more Gaussians than they need: a few terms more, within the budget either way).
struct InteractionList {
  struct Item {
    float x, y, z, spread;
    glm::vec3 mass;
    int band;  // its first Gaussian
  };
  std::vector<Item> staged;  // as collected
  std::vector<float> x, y, z, spread, mr, mg, mb;
  std::vector<std::uint8_t> blockBand;  // per block of kLanes items: its first Gaussian
  std::array<std::size_t, kMaxKernelGaussians> inBand{};  // items per first Gaussian
  // Per Gaussian k and item j (index k * padded + j): exponent factor -log2(e) / 2 / (v_k + c_j)
  // and the channel coefficients w_k m_j / (2 pi (v_k + c_j)).
  std::vector<float> expo, cr, cg, cb;
  std::size_t size() const { return x.size(); }
  void stage(float px, float py, float pz, float c, const glm::vec3& m, int band) {
    staged.push_back({px, py, pz, c, m, band});
  }
  // The staged items in the order of their first Gaussian, padded.
  void arrange() {
    inBand.fill(0);
    for (const Item& item : staged) ++inBand[item.band];
    std::array<std::size_t, kMaxKernelGaussians> next{};  // where each band's items go
    for (int b = 1; b < kMaxKernelGaussians; ++b) next[b] = next[b - 1] + inBand[b - 1];
    const std::size_t padded = (staged.size() + kLanes - 1) / kLanes * kLanes;
    for (auto* v : {&x, &y, &z, &spread, &mr, &mg, &mb}) v->assign(padded, 0.0f);
    blockBand.resize(padded / kLanes);
    for (const Item& item : staged) {
      const std::size_t j = next[item.band]++;
      x[j] = item.x, y[j] = item.y, z[j] = item.z, spread[j] = item.spread;
      mr[j] = item.mass.x, mg[j] = item.mass.y, mb[j] = item.mass.z;
      if (j % kLanes == 0) blockBand[j / kLanes] = static_cast<std::uint8_t>(item.band);
    }
  }
};

// The sources of `group` (other than its own points): calls cluster(nodeIndex, d2) for nodes used
// as one cluster (theta > 0) and point(k, d2) for single source points, d2 their squared box
// distance from the group; nodes beyond every cutoff from the group's box, and with `clusters`
// those of zero mass, are skipped.
template <class OnCluster, class OnPoint>
void forEachSourceOfGroup(const DiffusionOctree& tree, const OctreeNode& group,
                          const GaussianMixtureKernel& kernel, double theta,
                          const std::vector<ClusterMoments>& clusters,
                          std::vector<std::uint32_t>& stack, OnCluster&& cluster, OnPoint&& point) {
  const MortonSortedPoints& s = tree.points;
  const float maxCut2 = kernel.maxCutoff * kernel.maxCutoff;
  stack.assign(1, 0);
  while (!stack.empty()) {
    const std::uint32_t ni = stack.back();
    stack.pop_back();
    const OctreeNode& node = tree.nodes[ni];
    if (group.begin <= node.begin && node.end <= group.end) continue;  // inside the group
    // A node that holds no light sends none (the bounces' light on the convex parts, a compact
    // light's unlit side): its points are skipped with it. The masses are >= 0 per channel.
    if (!clusters.empty() && clusters[ni].mass == glm::vec3(0.0f)) continue;
    const float d2 = boxDistanceSquared(node.box, group.box);
    if (d2 >= maxCut2) continue;
    const bool containsGroup = node.begin <= group.begin && group.end <= node.end;
    if (theta > 0 && !containsGroup) {
      // The narrowest Gaussian that still reaches this node sets the allowed cluster size.
      const float d = std::sqrt(d2);
      int k = 0;
      while (k < kernel.count - 1 && kernel.cutoff[k] <= d) ++k;
      if (clusters[ni].radius <= theta * kernel.sigma[k]) {
        cluster(ni, d2);
        continue;
      }
    }
    if (node.childCount == 0) {
      for (std::uint32_t k = node.begin; k < node.end; ++k) {
        const glm::vec3 q(s.x[k], s.y[k], s.z[k]);
        const float pointD2 = boxDistanceSquared(Bounds3{q, q}, group.box);
        if (pointD2 < maxCut2) point(k, pointD2);
      }
    } else {
      for (std::uint32_t c = node.childCount; c-- > 0;) stack.push_back(node.firstChild + c);
    }
  }
}

// The sums of one group's list for each receiver: out[r] = sum_j sum_k coefficient 2^(expo d^2),
// k from the first Gaussian of item j's block on (InteractionList::blockBand).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#endif
SSS_VECTORIZABLE_FP void
sumGaussiansOverList(const float* __restrict rx, const float* __restrict ry,
                     const float* __restrict rz, std::size_t receivers, const float* __restrict x,
                     const float* __restrict y, const float* __restrict z,
                     const float* __restrict expo, const float* __restrict cr,
                     const float* __restrict cg, const float* __restrict cb,
                     const std::uint8_t* __restrict blockBand, std::size_t padded, int gaussians,
                     glm::vec3* __restrict out) {
  for (std::size_t r = 0; r < receivers; ++r) {
    float ar[kLanes] = {}, ag[kLanes] = {}, ab[kLanes] = {};
    for (std::size_t j0 = 0; j0 < padded; j0 += kLanes) {
      float d2[kLanes];
      for (int l = 0; l < kLanes; ++l) {
        const float dx = rx[r] - x[j0 + l], dy = ry[r] - y[j0 + l], dz = rz[r] - z[j0 + l];
        d2[l] = dx * dx + dy * dy + dz * dz;
      }
      for (int k = blockBand[j0 / kLanes]; k < gaussians; ++k) {
        const std::size_t o = k * padded + j0;
        for (int l = 0; l < kLanes; ++l) {
          const float g = exp2Negative(expo[o + l] * d2[l]);
          ar[l] += cr[o + l] * g, ag[l] += cg[o + l] * g, ab[l] += cb[o + l] * g;
        }
      }
    }
    glm::vec3 sum(0);
    for (int l = 0; l < kLanes; ++l) sum += glm::vec3(ar[l], ag[l], ab[l]);
    out[r] = sum;
  }
}

// Fills `items` with the group's own points first (item r is receiver r, for the self term),
// then its sources, in the order of their first Gaussian (InteractionList).
void collectInteractionList(const DiffusionOctree& tree, const OctreeNode& group,
                            const GaussianMixtureKernel& kernel, double theta,
                            const std::vector<ClusterMoments>& clusters,
                            const std::vector<glm::vec3>& mass, std::vector<std::uint32_t>& stack,
                            InteractionList& items) {
  const MortonSortedPoints& s = tree.points;
  items.staged.clear();
  for (std::uint32_t k = group.begin; k < group.end; ++k)
    items.stage(s.x[k], s.y[k], s.z[k], s.spread[k], mass[k], 0);
  forEachSourceOfGroup(
      tree, group, kernel, theta, clusters, stack,
      [&](std::uint32_t ni, float d2) {
        const ClusterMoments& c = clusters[ni];
        items.stage(c.centroid.x, c.centroid.y, c.centroid.z, c.spread, c.mass,
                    firstGaussianReaching(kernel, d2, c.spread));
      },
      [&](std::uint32_t k, float d2) {
        if (mass[k] == glm::vec3(0.0f)) return;  // no light to send
        items.stage(s.x[k], s.y[k], s.z[k], s.spread[k], mass[k],
                    firstGaussianReaching(kernel, d2, s.spread[k]));
      });
  items.arrange();
}

// The per-Gaussian exponent factors and channel coefficients of the (padded) list, where the
// kernel reads them (sumGaussiansOverList, replaceSelfTerms: the group's own points open the list
// with first Gaussian 0). The arrays are distinct, which the compiler cannot see through the
// vectors: the pointers say so, so that the loop vectorizes.
void computeListCoefficients(const GaussianMixtureKernel& kernel, InteractionList& items) {
  const int K = kernel.count;
  const std::size_t padded = items.size();
  items.expo.resize(K * padded), items.cr.resize(K * padded);
  items.cg.resize(K * padded), items.cb.resize(K * padded);
  const float* __restrict spread = items.spread.data();
  const float* __restrict mr = items.mr.data();
  const float* __restrict mg = items.mg.data();
  const float* __restrict mb = items.mb.data();
  for (int k = 0; k < K; ++k) {
    const glm::vec3 w = kernel.weight[k] * kInv2Pi;
    const float variance = kernel.variance[k];
    float* __restrict expo = items.expo.data() + k * padded;
    float* __restrict cr = items.cr.data() + k * padded;
    float* __restrict cg = items.cg.data() + k * padded;
    float* __restrict cb = items.cb.data() + k * padded;
    // The blocks summed with Gaussian k: those whose first Gaussian is k or before, a prefix of
    // the list (its items are in the order of their first Gaussian).
    const std::size_t used =
        kLanes * static_cast<std::size_t>(
                     std::upper_bound(items.blockBand.begin(), items.blockBand.end(), k) -
                     items.blockBand.begin());
    for (std::size_t j = 0; j < used; ++j) {
      const float inv = 1.0f / (variance + spread[j]);
      expo[j] = -0.5f * kLog2e * inv;
      cr[j] = w.x * inv * mr[j];
      cg[j] = w.y * inv * mg[j];
      cb[j] = w.z * inv * mb[j];
    }
  }
}

// Self term: replaces each receiver's own disc-blurred sample (item r of the list) in result by
// the integral over its disc.
void replaceSelfTerms(const MortonSortedPoints& s, const OctreeNode& group,
                      const GaussianMixtureKernel& kernel, const InteractionList& items,
                      const std::vector<glm::vec3>& irradiance, std::vector<glm::vec3>& result) {
  const std::size_t padded = items.size();
  const std::size_t receivers = group.end - group.begin;
  for (std::size_t r = 0; r < receivers; ++r) {
    const std::uint32_t k = group.begin + static_cast<std::uint32_t>(r);
    glm::vec3 sampled(0), disc(0);
    for (int q = 0; q < kernel.count; ++q) {
      const std::size_t o = q * padded + r;
      sampled += glm::vec3(items.cr[o], items.cg[o], items.cb[o]);
      const float rho2 = s.area[k] * std::numbers::inv_pi_v<float>;
      disc += kernel.weight[q] * static_cast<float>(-std::expm1(-rho2 / (2 * kernel.variance[q])));
    }
    result[k] += disc * irradiance[k] - sampled;
  }
}

}  // namespace

GaussianMixtureKernel makeGaussianMixtureKernel(const GaussianSum& sum, double tailBudget) {
  GaussianMixtureKernel kernel;
  kernel.count = static_cast<int>(sum.size());
  const glm::dvec3 total = sum.totalReflectance();
  for (int k = 0; k < kernel.count; ++k) {
    // Floor: a zero variance (a fit's spike at r = 0) would divide by zero for zero-area vertices.
    const double v = std::max(sum.variances[k], 1e-12);
    double lnRatio = 0;
    for (int c = 0; c < 3; ++c) {
      if (total[c] > 0 && sum.weights[k][c] > 0)
        lnRatio =
            std::max(lnRatio, std::log(kernel.count * sum.weights[k][c] / (tailBudget * total[c])));
    }
    kernel.variance[k] = static_cast<float>(v);
    kernel.sigma[k] = static_cast<float>(std::sqrt(v));
    kernel.cutoff[k] = static_cast<float>(std::sqrt(2 * v * lnRatio));
    kernel.cutoffSquaredPerVariance[k] = static_cast<float>(2 * lnRatio);
    kernel.weight[k] = glm::vec3(sum.weights[k]);
    kernel.maxCutoff = std::max(kernel.maxCutoff, kernel.cutoff[k]);
  }
  return kernel;
}

std::vector<glm::vec3> sumGaussianMixtureOverOctree(const DiffusionOctree& tree,
                                                    const std::vector<glm::vec3>& irradiance,
                                                    const GaussianMixtureKernel& kernel,
                                                    double theta, int threads, Progress* progress,
                                                    OctreeSumStatistics& stats,
                                                    std::vector<ClusterMoments> clusters) {
  const MortonSortedPoints& s = tree.points;
  const std::size_t n = s.size();
  std::vector<glm::vec3> mass(n);
  for (std::size_t k = 0; k < n; ++k) mass[k] = irradiance[k] * s.area[k];
  if (theta > 0 && clusters.empty()) clusters = buildClusterMoments(tree, mass, threads);
  std::vector<glm::vec3> result(n);

  parallelFor(tree.groups.size(), threads, 4, [&](std::size_t gb, std::size_t ge) {
    InteractionList items;
    std::vector<std::uint32_t> stack;
    std::size_t count = 0;
    for (std::size_t g = gb; g < ge; ++g) {
      const OctreeNode& group = tree.nodes[tree.groups[g]];
      collectInteractionList(tree, group, kernel, theta, clusters, mass, stack, items);
      computeListCoefficients(kernel, items);
      const std::size_t receivers = group.end - group.begin;
      sumGaussiansOverList(&s.x[group.begin], &s.y[group.begin], &s.z[group.begin], receivers,
                           items.x.data(), items.y.data(), items.z.data(), items.expo.data(),
                           items.cr.data(), items.cg.data(), items.cb.data(),
                           items.blockBand.data(), items.size(), kernel.count,
                           &result[group.begin]);
      replaceSelfTerms(s, group, kernel, items, irradiance, result);
      count += receivers * termsPerReceiver(items.inBand, kernel.count);
    }
    stats.interactions += count;
    if (progress) progress->advance(ge - gb);
  });
  return result;
}

double estimateInteractionTerms(const DiffusionOctree& tree, const GaussianMixtureKernel& kernel,
                                double theta, const std::vector<ClusterMoments>& clusters,
                                std::size_t stride, int threads) {
  const std::size_t samples = (tree.groups.size() + stride - 1) / stride;
  std::vector<double> groupTerms(samples);
  parallelFor(samples, threads, 1, [&](std::size_t b, std::size_t e) {
    std::vector<std::uint32_t> stack;
    for (std::size_t i = b; i < e; ++i) {
      const OctreeNode& group = tree.nodes[tree.groups[i * stride]];
      std::array<std::size_t, kMaxKernelGaussians> inBand{};
      inBand[0] = group.end - group.begin;
      forEachSourceOfGroup(
          tree, group, kernel, theta, clusters, stack,
          [&](std::uint32_t ni, float d2) {
            ++inBand[firstGaussianReaching(kernel, d2, clusters[ni].spread)];
          },
          [&](std::uint32_t k, float d2) {
            ++inBand[firstGaussianReaching(kernel, d2, tree.points.spread[k])];
          });
      groupTerms[i] = static_cast<double>(group.end - group.begin) *
                      static_cast<double>(termsPerReceiver(inBand, kernel.count));
    }
  });
  double terms = 0, sampledReceivers = 0;
  for (std::size_t i = 0; i < samples; ++i) {
    const OctreeNode& group = tree.nodes[tree.groups[i * stride]];
    terms += groupTerms[i];
    sampledReceivers += group.end - group.begin;
  }
  return sampledReceivers > 0 ? terms * static_cast<double>(tree.points.size()) / sampledReceivers
                              : 0;
}

}  // namespace sss

#include "diffusion/octree_gaussian_sum.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>

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
// into 2^i 2^f, f in [-0.5, 0.5], degree-6 Taylor polynomial (relative error < 3e-7).
SSS_VECTORIZABLE_FP inline float exp2Negative(float x) {
  x = x < -126.0f ? -126.0f : x;
  const int i = static_cast<int>(x - 0.5f);  // round to nearest for x <= 0
  const float f = x - static_cast<float>(i);
  const float l = 0.69314718f;
  float p = 1.0f / 720.0f * l;
  p = p * f + 1.0f / 120.0f;
  p = p * f * l + 1.0f / 24.0f;
  p = p * f * l + 1.0f / 6.0f;
  p = p * f * l + 0.5f;
  p = p * f * l + 1.0f;
  p = p * f * l + 1.0f;
  std::int32_t bits = (i + 127) << 23;
  float scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return p * scale;
}

// Interaction list of one receiver group, structure of arrays, padded to kLanes with zero mass.
struct InteractionList {
  std::vector<float> x, y, z, spread, mr, mg, mb;
  // Per Gaussian k and item j (index k * padded + j): exponent factor -log2(e) / 2 / (v_k + c_j)
  // and the channel coefficients w_k m_j / (2 pi (v_k + c_j)).
  std::vector<float> expo, cr, cg, cb;
  std::size_t size() const { return x.size(); }
  void clear() {
    for (auto* v : {&x, &y, &z, &spread, &mr, &mg, &mb}) v->clear();
  }
  void push(float px, float py, float pz, float c, const glm::vec3& m) {
    x.push_back(px), y.push_back(py), z.push_back(pz), spread.push_back(c);
    mr.push_back(m.x), mg.push_back(m.y), mb.push_back(m.z);
  }
};

// The sources of `group` (other than its own points): calls cluster(nodeIndex) for nodes used as
// one cluster (theta > 0) and point(k) for single source points; nodes beyond every cutoff from
// the group's box are skipped.
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
    const float d2 = boxDistanceSquared(node.box, group.box);
    if (d2 >= maxCut2) continue;
    const bool containsGroup = node.begin <= group.begin && group.end <= node.end;
    if (theta > 0 && !containsGroup) {
      // The narrowest Gaussian that still reaches this node sets the allowed cluster size.
      const float d = std::sqrt(d2);
      int k = 0;
      while (k < kernel.count - 1 && kernel.cutoff[k] <= d) ++k;
      if (clusters[ni].radius <= theta * kernel.sigma[k]) {
        cluster(ni);
        continue;
      }
    }
    if (node.childCount == 0) {
      for (std::uint32_t k = node.begin; k < node.end; ++k) {
        const glm::vec3 q(s.x[k], s.y[k], s.z[k]);
        if (boxDistanceSquared(Bounds3{q, q}, group.box) < maxCut2) point(k);
      }
    } else {
      for (std::uint32_t c = node.childCount; c-- > 0;) stack.push_back(node.firstChild + c);
    }
  }
}

// The sums of one group's list for each receiver: out[r] = sum_j sum_k coefficient 2^(expo d^2).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#endif
SSS_VECTORIZABLE_FP void
sumGaussiansOverList(const float* __restrict rx, const float* __restrict ry,
                     const float* __restrict rz, std::size_t receivers, const float* __restrict x,
                     const float* __restrict y, const float* __restrict z,
                     const float* __restrict expo, const float* __restrict cr,
                     const float* __restrict cg, const float* __restrict cb, std::size_t padded,
                     int gaussians, glm::vec3* __restrict out) {
  for (std::size_t r = 0; r < receivers; ++r) {
    float ar[kLanes] = {}, ag[kLanes] = {}, ab[kLanes] = {};
    for (std::size_t j0 = 0; j0 < padded; j0 += kLanes) {
      float d2[kLanes];
      for (int l = 0; l < kLanes; ++l) {
        const float dx = rx[r] - x[j0 + l], dy = ry[r] - y[j0 + l], dz = rz[r] - z[j0 + l];
        d2[l] = dx * dx + dy * dy + dz * dz;
      }
      for (int k = 0; k < gaussians; ++k) {
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
// then its sources, padded to kLanes; returns the number of items before padding.
std::size_t collectInteractionList(const DiffusionOctree& tree, const OctreeNode& group,
                                   const GaussianMixtureKernel& kernel, double theta,
                                   const std::vector<ClusterMoments>& clusters,
                                   const std::vector<glm::vec3>& mass,
                                   std::vector<std::uint32_t>& stack, InteractionList& items) {
  const MortonSortedPoints& s = tree.points;
  items.clear();
  for (std::uint32_t k = group.begin; k < group.end; ++k)
    items.push(s.x[k], s.y[k], s.z[k], s.spread[k], mass[k]);
  forEachSourceOfGroup(
      tree, group, kernel, theta, clusters, stack,
      [&](std::uint32_t ni) {
        const ClusterMoments& c = clusters[ni];
        items.push(c.centroid.x, c.centroid.y, c.centroid.z, c.spread, c.mass);
      },
      [&](std::uint32_t k) { items.push(s.x[k], s.y[k], s.z[k], s.spread[k], mass[k]); });
  const std::size_t used = items.size();
  const std::size_t padded = (used + kLanes - 1) / kLanes * kLanes;
  for (std::size_t j = used; j < padded; ++j) items.push(0, 0, 0, 0, glm::vec3(0));
  return used;
}

// The per-Gaussian exponent factors and channel coefficients of the (padded) list.
void computeListCoefficients(const GaussianMixtureKernel& kernel, InteractionList& items) {
  const int K = kernel.count;
  const std::size_t padded = items.size();
  items.expo.resize(K * padded), items.cr.resize(K * padded);
  items.cg.resize(K * padded), items.cb.resize(K * padded);
  for (int k = 0; k < K; ++k) {
    const glm::vec3 w = kernel.weight[k] * kInv2Pi;
    for (std::size_t j = 0; j < padded; ++j) {
      const float inv = 1.0f / (kernel.variance[k] + items.spread[j]);
      const std::size_t o = k * padded + j;
      items.expo[o] = -0.5f * kLog2e * inv;
      items.cr[o] = w.x * inv * items.mr[j];
      items.cg[o] = w.y * inv * items.mg[j];
      items.cb[o] = w.z * inv * items.mb[j];
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
      const std::size_t used =
          collectInteractionList(tree, group, kernel, theta, clusters, mass, stack, items);
      computeListCoefficients(kernel, items);
      const std::size_t receivers = group.end - group.begin;
      sumGaussiansOverList(&s.x[group.begin], &s.y[group.begin], &s.z[group.begin], receivers,
                           items.x.data(), items.y.data(), items.z.data(), items.expo.data(),
                           items.cr.data(), items.cg.data(), items.cb.data(), items.size(),
                           kernel.count, &result[group.begin]);
      replaceSelfTerms(s, group, kernel, items, irradiance, result);
      count += receivers * used * kernel.count;
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
      std::size_t items = group.end - group.begin;
      const auto count = [&](std::uint32_t) { ++items; };
      forEachSourceOfGroup(tree, group, kernel, theta, clusters, stack, count, count);
      groupTerms[i] = static_cast<double>(group.end - group.begin) *
                      static_cast<double>((items + kLanes - 1) / kLanes * kLanes);
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

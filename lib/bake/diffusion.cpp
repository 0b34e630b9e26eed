// The diffusion sums of Eq. 7 (see diffusion.h for the methods).
//
// Engine. The Gaussian methods share one engine: the vertices are sorted along a Morton curve
// into an octree (leaves <= kLeafSize points); receiver groups are the largest nodes with at
// most kGroupSize points. For each group one traversal collects an interaction list (source points,
// or clusters for the hierarchical method) with a conservative box-to-box distance, and every
// receiver of the group then sums the whole list in a fixed order with SIMD-friendly loops over
// structure-of-arrays floats. A source item j with mass m_j = E_j A_j (a cluster: the sums over its
// points) and spread c_j contributes
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
// energy exp(-r_k^2 / 2 v_k) is below (tolerance / 4) / K of the channel's total reflectance; so
// truncation loses at most tolerance / 4 of B. Points inside the widest relevant cutoff of the
// group's box are summed with every Gaussian (the extra far terms are more accurate, not less).
//
// Hierarchical criterion (Jensen & Buhler 2002's octree of clusters, with a width-based test in
// place of their solid angle): a node of radius R at box distance d from the group is used as one
// cluster when R <= theta sigma_k, sigma_k the narrowest Gaussian whose cutoff reaches d. The
// neglected (anisotropic, fourth-order) terms are relative O((R / sigma)^2 (d / sigma)^2) per
// cluster, and summed over the kernel's support they are O(theta^2) of B; theta comes from the
// tolerance with a constant measured on spheres and the dragon (tests/bench/diffusion_sweep.sh).
//
// Incremental (the paper's Eq. 11): pass 0 is E; pass k = G(v_k - v_(k-1)) convolved with pass
// k-1, as a sum over vertices with the same disc terms; B = sum_k w_k pass_k. On a plane this is
// exact since Gaussians compose; on a discrete curved surface it is not: each pass re-samples the
// field at the vertices, and wherever more surface lies within reach than on a plane (concave and
// thin parts, distances measured through the object) the pass gains a few percent that the next
// pass multiplies again. Measured with uniform E on the 150 mm dragon (23K vertices, marble):
// pure Eq. 11 is 38% above gauss at the median vertex. Steps narrower than two vertex spacings
// (v_k - v_(k-1) < 4 mean vertex areas) are also badly normalized by the discrete sum (+2.5% per
// pass on a 1 mm grid), so those passes start from E with the whole v_k instead; with that the
// dragon's median is +2.2% (p90 +7.5%) and a 2562-vertex 20 mm marble sphere is within 0.7% of
// exact, but on the 100K-vertex dragon it is still 4.4% off gauss at a 1% tolerance. It costs
// about half of gauss (one Gaussian per pass; with a geometric variance ladder v_k - v_(k-1) is
// most of v_k, so the support per pass barely shrinks) and 8x more than hierarchical, and its
// error is not bounded by the tolerance: auto never picks it.
//
// Exact: every pair with the profile's own R_d (double precision), self term
// DiffusionProfile::integrateDisc(rho_o); sources closer than four disc radii are averaged over
// their disc in their tangent plane (a 32-point quadrature), farther ones are point samples. So
// it approximates the same continuous surface integral as the Gaussian methods' disc blur.
#include "bake/diffusion.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <sstream>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/timer.h"
#include "material/diffusion_profile.h"
#include "material/gaussian_sum_fit.h"

namespace sss {

namespace {

constexpr std::size_t kLeafSize = 16;   // points per octree leaf
constexpr std::size_t kGroupSize = 64;  // receivers that share one interaction list
constexpr int kMortonBits = 21;         // per axis: 63-bit codes
constexpr int kLanes = 16;              // SIMD block (2 AVX2 / 1 AVX-512 / 4 SSE registers)
constexpr int kMaxGaussians = 16;
// Hierarchical: theta = kThetaScale sqrt(tolerance) gives kClusterError theta^2 ~ tolerance / 6.
constexpr double kThetaScale = 12.0;
// CPU seconds per unit of work, measured on the development machine (Xeon, AVX-512, GCC 12):
// the auto method's cost model only needs their ratio.
constexpr double kCpuSecondsPerGaussTerm = 0.5e-9;  // one (receiver, item, Gaussian) term
constexpr double kCpuSecondsPerExactPair = 70e-9;   // one dipole pair (3 channels, double)
constexpr double kCpuSecondsFitFloor = 0.03;        // about what fitGaussians takes
// Hierarchical: relative RMS error of B from clusters ~ kClusterError theta^2, fitted on the
// 150 mm dragon (23K vertices) and 20 mm / 80 mm spheres, marble and skimmilk.
constexpr double kClusterError = 0.0011;
// Exact method: sources closer than kNearDiscs disc radii are averaged over their disc.
constexpr double kNearDiscs = 4;
constexpr int kDiscRings = 4, kDiscAngles = 8;
// Incremental: a step variance below this many mean vertex areas (sigma < 2 spacings) is not
// resolved by the discrete sum; measured on spheres, planes and the dragon (see header comment).
constexpr double kIncrementalMinStep = 4;

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

struct Kernel {  // a Gaussian sum in the engine's float form
  int count = 0;
  std::array<float, kMaxGaussians> variance{}, sigma{}, cutoff{};
  std::array<glm::vec3, kMaxGaussians> weight{};
  float maxCutoff = 0;
};

// Vertices in Morton order, structure of arrays.
struct SortedPoints {
  std::vector<std::uint32_t> original;  // sorted index -> input index
  std::vector<float> x, y, z, area, spread;
  std::vector<glm::vec3> normal;
};

struct Node {
  std::uint32_t begin = 0, end = 0;  // range in SortedPoints
  std::uint32_t firstChild = 0, childCount = 0;
  glm::vec3 boxMin{0}, boxMax{0};
};

// Cluster moments of a node for one source field.
struct Cluster {
  glm::vec3 centroid{0};
  glm::vec3 mass{0};  // sum of E A
  float spread = 0;   // in-plane per-axis variance: second moment + mean point footprint
  float radius = 0;   // max distance from the centroid to a point
};

struct Octree {
  SortedPoints points;
  std::vector<Node> nodes;
  // Receiver groups: the largest nodes with at most kGroupSize points, in Morton order.
  std::vector<std::uint32_t> groups;
};

std::uint64_t spreadBits(std::uint64_t v) {  // 21 bits -> every third bit
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

Octree buildOctree(const DiffusionInput& in) {
  const std::size_t n = in.positions.size();
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : in.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const float extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-30f});
  const double scale = ((1u << kMortonBits) - 1) / static_cast<double>(extent);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 q = in.positions[i] - lo;
    keyed[i] = {spreadBits(static_cast<std::uint64_t>(q.x * scale)) |
                    spreadBits(static_cast<std::uint64_t>(q.y * scale)) << 1 |
                    spreadBits(static_cast<std::uint64_t>(q.z * scale)) << 2,
                static_cast<std::uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());

  Octree tree;
  SortedPoints& s = tree.points;
  s.original.resize(n);
  for (auto* v : {&s.x, &s.y, &s.z, &s.area, &s.spread}) v->resize(n);
  s.normal.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = keyed[k].second;
    s.original[k] = i;
    s.x[k] = in.positions[i].x, s.y[k] = in.positions[i].y, s.z[k] = in.positions[i].z;
    s.area[k] = in.areas[i];
    s.spread[k] = in.areas[i] / (4.0f * std::numbers::pi_v<float>);
    s.normal[k] = in.normals[i];
  }

  // Top-down split on the Morton digits; children of a node are contiguous.
  struct Pending {
    std::uint32_t node;
    int level;
  };
  tree.nodes.push_back({0, static_cast<std::uint32_t>(n), 0, 0, {}, {}});
  std::vector<Pending> stack{{0, 0}};
  while (!stack.empty()) {
    const Pending p = stack.back();
    stack.pop_back();
    Node node = tree.nodes[p.node];
    node.boxMin = glm::vec3(INFINITY), node.boxMax = glm::vec3(-INFINITY);
    for (std::uint32_t k = node.begin; k < node.end; ++k) {
      const glm::vec3 q(s.x[k], s.y[k], s.z[k]);
      node.boxMin = glm::min(node.boxMin, q), node.boxMax = glm::max(node.boxMax, q);
    }
    if (node.end - node.begin > kLeafSize && p.level < kMortonBits) {
      const int shift = 3 * (kMortonBits - 1 - p.level);
      node.firstChild = static_cast<std::uint32_t>(tree.nodes.size());
      std::uint32_t k = node.begin;
      while (k < node.end) {
        const std::uint64_t digit = keyed[k].first >> shift & 7;
        std::uint32_t e = k;
        while (e < node.end && (keyed[e].first >> shift & 7) == digit) ++e;
        tree.nodes.push_back({k, e, 0, 0, {}, {}});
        ++node.childCount;
        k = e;
      }
      for (std::uint32_t c = 0; c < node.childCount; ++c)
        stack.push_back({node.firstChild + c, p.level + 1});
    }
    tree.nodes[p.node] = node;
  }
  // Groups in Morton order (a depth-first walk), so each covers a compact patch.
  std::vector<std::uint32_t> walk{0};
  while (!walk.empty()) {
    const std::uint32_t i = walk.back();
    walk.pop_back();
    const Node& node = tree.nodes[i];
    if (node.childCount == 0 || node.end - node.begin <= kGroupSize) {
      tree.groups.push_back(i);
    } else {
      for (std::uint32_t c = node.childCount; c-- > 0;) walk.push_back(node.firstChild + c);
    }
  }
  return tree;
}

// Area-and-irradiance-weighted moments of every node for the source masses `mass` (sorted order).
std::vector<Cluster> buildClusters(const Octree& tree, const std::vector<glm::vec3>& mass,
                                   int threads) {
  const SortedPoints& s = tree.points;
  std::vector<Cluster> clusters(tree.nodes.size());
  parallelFor(tree.nodes.size(), threads, 256, [&](std::size_t nb, std::size_t ne) {
    for (std::size_t ni = nb; ni < ne; ++ni) {
      const Node& node = tree.nodes[ni];
      // Weight by luminance-like mass so the centroid is the first moment of what is summed; fall
      // back to area where the node receives no light.
      double wsum = 0, asum = 0;
      glm::dvec3 m(0), c(0), ca(0), nsum(0);
      for (std::uint32_t k = node.begin; k < node.end; ++k) {
        const glm::dvec3 q(s.x[k], s.y[k], s.z[k]);
        const double w = mass[k].x + mass[k].y + mass[k].z;
        m += glm::dvec3(mass[k]);
        wsum += w, asum += s.area[k];
        c += w * q, ca += static_cast<double>(s.area[k]) * q;
        nsum += static_cast<double>(s.area[k]) * glm::dvec3(s.normal[k]);
      }
      const bool byMass = wsum > 0;
      const double total = byMass ? wsum : asum;
      const glm::dvec3 mu = total > 0
                                ? (byMass ? c : ca) / total
                                : glm::dvec3(s.x[node.begin], s.y[node.begin], s.z[node.begin]);
      double cov[3][3] = {}, footprint = 0, radius2 = 0;
      for (std::uint32_t k = node.begin; k < node.end; ++k) {
        const glm::dvec3 d = glm::dvec3(s.x[k], s.y[k], s.z[k]) - mu;
        const double w = byMass ? mass[k].x + mass[k].y + mass[k].z : s.area[k];
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) cov[a][b] += w * d[a] * d[b];
        footprint += w * s.spread[k];
        radius2 = std::max(radius2, glm::dot(d, d));
      }
      double inPlane = 0;
      if (total > 0) {
        const double trace = (cov[0][0] + cov[1][1] + cov[2][2]) / total;
        const double nlen = glm::length(nsum);
        if (nlen > 0.5 * asum && nlen > 0) {
          // Variance per in-plane axis: remove the normal direction from the trace.
          const glm::dvec3 nn = nsum / nlen;
          double normalVar = 0;
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) normalVar += nn[a] * cov[a][b] * nn[b];
          inPlane = std::max(0.0, trace - normalVar / total) / 2;
        } else {
          inPlane = trace / 3;  // strongly curved: no dominant plane
        }
        footprint /= total;
      }
      clusters[ni] = {glm::vec3(mu), glm::vec3(m), static_cast<float>(inPlane + footprint),
                      static_cast<float>(std::sqrt(radius2))};
    }
  });
  return clusters;
}

float boxDistance2(const glm::vec3& aMin, const glm::vec3& aMax, const glm::vec3& bMin,
                   const glm::vec3& bMax) {
  const glm::vec3 gap = glm::max(glm::vec3(0), glm::max(aMin - bMax, bMin - aMax));
  return glm::dot(gap, gap);
}

// Interaction list of one receiver group, structure of arrays, padded to kLanes with zero mass.
struct ItemList {
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

struct EngineStats {
  std::atomic<std::size_t> interactions{0};
};

// Interaction list of `group` (other than its own points): calls cluster(nodeIndex) for nodes
// used as one cluster (theta > 0) and point(k) for single source points; nodes beyond every
// cutoff from the group's box are skipped.
template <class OnCluster, class OnPoint>
void traverse(const Octree& tree, const Node& group, const Kernel& kernel, double theta,
              const std::vector<Cluster>& clusters, std::vector<std::uint32_t>& stack,
              OnCluster&& cluster, OnPoint&& point) {
  const SortedPoints& s = tree.points;
  const float maxCut2 = kernel.maxCutoff * kernel.maxCutoff;
  stack.assign(1, 0);
  while (!stack.empty()) {
    const std::uint32_t ni = stack.back();
    stack.pop_back();
    const Node& node = tree.nodes[ni];
    if (group.begin <= node.begin && node.end <= group.end) continue;  // inside the group
    const float d2 = boxDistance2(node.boxMin, node.boxMax, group.boxMin, group.boxMax);
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
        if (boxDistance2(q, q, group.boxMin, group.boxMax) < maxCut2) point(k);
      }
    } else {
      for (std::uint32_t c = node.childCount; c-- > 0;) stack.push_back(node.firstChild + c);
    }
  }
}

// Sums of one group's list for each receiver: out[r] = sum_j sum_k coefficient * 2^(expo d^2).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#endif
SSS_VECTORIZABLE_FP void
sumList(const float* __restrict rx, const float* __restrict ry, const float* __restrict rz,
        std::size_t receivers, const float* __restrict x, const float* __restrict y,
        const float* __restrict z, const float* __restrict expo, const float* __restrict cr,
        const float* __restrict cg, const float* __restrict cb, std::size_t padded, int gaussians,
        glm::vec3* __restrict out) {
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

// B (sorted order) = sum over sources of mass[j] sum_k w_k G(v_k + c_j, d) with the disc self
// term; irradiance[j] = mass[j] / area[j] is what the self term needs. theta = 0: every point
// within the cutoffs (gauss); theta > 0: clusters (hierarchical), built here unless `clusters`
// already holds them for this irradiance.
std::vector<glm::vec3> runEngine(const Octree& tree, const std::vector<glm::vec3>& irradiance,
                                 const Kernel& kernel, double theta, int threads,
                                 Progress* progress, EngineStats& stats,
                                 std::vector<Cluster> clusters = {}) {
  const SortedPoints& s = tree.points;
  const std::size_t n = s.x.size();
  std::vector<glm::vec3> mass(n);
  for (std::size_t k = 0; k < n; ++k) mass[k] = irradiance[k] * s.area[k];
  if (theta > 0 && clusters.empty()) clusters = buildClusters(tree, mass, threads);
  std::vector<glm::vec3> result(n);
  const int K = kernel.count;
  constexpr float kLog2e = std::numbers::log2e_v<float>;
  constexpr float kInv2Pi = 0.5f * std::numbers::inv_pi_v<float>;

  parallelFor(tree.groups.size(), threads, 4, [&](std::size_t gb, std::size_t ge) {
    ItemList items;
    std::vector<std::uint32_t> stack;
    std::size_t count = 0;
    for (std::size_t g = gb; g < ge; ++g) {
      const Node& group = tree.nodes[tree.groups[g]];
      items.clear();
      // The group's own points first: item r is receiver r, for the self correction below.
      for (std::uint32_t k = group.begin; k < group.end; ++k)
        items.push(s.x[k], s.y[k], s.z[k], s.spread[k], mass[k]);
      traverse(
          tree, group, kernel, theta, clusters, stack,
          [&](std::uint32_t ni) {
            const Cluster& c = clusters[ni];
            items.push(c.centroid.x, c.centroid.y, c.centroid.z, c.spread, c.mass);
          },
          [&](std::uint32_t k) { items.push(s.x[k], s.y[k], s.z[k], s.spread[k], mass[k]); });
      const std::size_t used = items.size();
      const std::size_t padded = (used + kLanes - 1) / kLanes * kLanes;
      for (std::size_t j = used; j < padded; ++j) items.push(0, 0, 0, 0, glm::vec3(0));
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
      const std::size_t receivers = group.end - group.begin;
      sumList(&s.x[group.begin], &s.y[group.begin], &s.z[group.begin], receivers, items.x.data(),
              items.y.data(), items.z.data(), items.expo.data(), items.cr.data(), items.cg.data(),
              items.cb.data(), padded, K, &result[group.begin]);
      // Self term: replace the own point's disc-blurred sample by the integral over its disc.
      for (std::size_t r = 0; r < receivers; ++r) {
        const std::uint32_t k = group.begin + static_cast<std::uint32_t>(r);
        glm::vec3 sampled(0), disc(0);
        for (int q = 0; q < K; ++q) {
          const std::size_t o = q * padded + r;
          sampled += glm::vec3(items.cr[o], items.cg[o], items.cb[o]);
          const float rho2 = s.area[k] * std::numbers::inv_pi_v<float>;
          disc +=
              kernel.weight[q] * static_cast<float>(-std::expm1(-rho2 / (2 * kernel.variance[q])));
        }
        result[k] += disc * irradiance[k] - sampled;
      }
      count += receivers * used * K;
    }
    stats.interactions += count;
    if (progress) progress->advance(ge - gb);
  });
  return result;
}

// Dry run of the traversal on every `stride`-th group: estimated number of (receiver, item)
// terms for the whole mesh.
double estimateTerms(const Octree& tree, const Kernel& kernel, double theta,
                     const std::vector<Cluster>& clusters, std::size_t stride, int threads) {
  const std::size_t samples = (tree.groups.size() + stride - 1) / stride;
  std::vector<double> groupTerms(samples);
  parallelFor(samples, threads, 1, [&](std::size_t b, std::size_t e) {
    std::vector<std::uint32_t> stack;
    for (std::size_t i = b; i < e; ++i) {
      const Node& group = tree.nodes[tree.groups[i * stride]];
      std::size_t items = group.end - group.begin;
      const auto count = [&](std::uint32_t) { ++items; };
      traverse(tree, group, kernel, theta, clusters, stack, count, count);
      groupTerms[i] = static_cast<double>(group.end - group.begin) *
                      static_cast<double>((items + kLanes - 1) / kLanes * kLanes);
    }
  });
  double terms = 0, sampledReceivers = 0;
  for (std::size_t i = 0; i < samples; ++i) {
    const Node& group = tree.nodes[tree.groups[i * stride]];
    terms += groupTerms[i];
    sampledReceivers += group.end - group.begin;
  }
  return sampledReceivers > 0 ? terms * static_cast<double>(tree.points.x.size()) / sampledReceivers
                              : 0;
}

// Float kernel from a Gaussian sum; cutoffs so that truncation loses <= tailBudget of B.
Kernel makeKernel(const GaussianSum& sum, double tailBudget) {
  Kernel kernel;
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

void validate(const DiffusionInput& in) {
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

// Mean of R_d(|x_o - y|) over y in the disc of radius rho around x_i in the plane normal to n_i:
// equal-area polar midpoint rule (kDiscRings x kDiscAngles cells).
glm::dvec3 discAverage(const DiffusionProfile& profile, const glm::dvec3& xi, const glm::dvec3& ni,
                       double rho, const glm::dvec3& xo) {
  const glm::dvec3 a = std::abs(ni.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 t = glm::normalize(glm::cross(ni, a)), b = glm::cross(ni, t);
  glm::dvec3 sum(0);
  for (int ring = 0; ring < kDiscRings; ++ring) {
    const double radius = rho * std::sqrt((ring + 0.5) / kDiscRings);
    for (int k = 0; k < kDiscAngles; ++k) {
      const double phi = 2 * std::numbers::pi * (k + 0.5 * (ring & 1) + 0.25) / kDiscAngles;
      const glm::dvec3 y = xi + radius * (std::cos(phi) * t + std::sin(phi) * b);
      sum += profile.evaluate(glm::length(y - xo));
    }
  }
  return sum / static_cast<double>(kDiscRings * kDiscAngles);
}

DiffusionResult runExact(const DiffusionInput& in, const DiffusionProfile& profile,
                         const DiffusionOptions& options) {
  const std::size_t n = in.positions.size();
  DiffusionResult out;
  out.exitance.resize(n);
  if (options.weightSums) out.weightSums.resize(n);
  Progress progress("diffusion (exact)", n, options.quiet);
  parallelFor(n, options.threads, 32, [&](std::size_t b, std::size_t e) {
    for (std::size_t o = b; o < e; ++o) {
      const double rho = std::sqrt(in.areas[o] / std::numbers::pi);
      const glm::dvec3 self = profile.integrateDisc(rho);
      glm::dvec3 sum = self * glm::dvec3(in.irradiance[o]), weights = self;
      const glm::dvec3 xo(in.positions[o]);
      for (std::size_t i = 0; i < n; ++i) {
        if (i == o) continue;
        const glm::dvec3 xi(in.positions[i]);
        const double r = glm::length(xi - xo);
        const double rhoI = std::sqrt(in.areas[i] / std::numbers::pi);
        const glm::dvec3 rd = r < kNearDiscs * rhoI
                                  ? discAverage(profile, xi, glm::dvec3(in.normals[i]), rhoI, xo)
                                  : profile.evaluate(r);
        sum += rd * glm::dvec3(in.irradiance[i]) * static_cast<double>(in.areas[i]);
        weights += rd * static_cast<double>(in.areas[i]);
      }
      out.exitance[o] = glm::vec3(sum);
      if (options.weightSums) out.weightSums[o] = glm::vec3(weights);
    }
    progress.advance(e - b);
  });
  progress.finish();
  out.report.interactions = n * n;
  return out;
}

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

}  // namespace

std::string toString(DiffusionMethod method) {
  switch (method) {
    case DiffusionMethod::Auto:
      return "auto";
    case DiffusionMethod::Exact:
      return "exact";
    case DiffusionMethod::Gauss:
      return "gauss";
    case DiffusionMethod::Incremental:
      return "incremental";
    case DiffusionMethod::Hierarchical:
      return "hierarchical";
  }
  return "?";
}

std::vector<std::string> listDiffusionMethods() {
  return {"auto", "exact", "gauss", "incremental", "hierarchical"};
}

DiffusionMethod parseDiffusionMethod(const std::string& name) {
  for (auto m : {DiffusionMethod::Auto, DiffusionMethod::Exact, DiffusionMethod::Gauss,
                 DiffusionMethod::Incremental, DiffusionMethod::Hierarchical})
    if (toString(m) == name) return m;
  throw Error("unknown diffusion method '" + name +
              "' (expected auto, exact, gauss, incremental or hierarchical)");
}

DiffusionResult diffuse(const DiffusionInput& input, const DiffusionProfile& profile,
                        const DiffusionOptions& options) {
  const Stopwatch total;
  validate(input);
  if (!(options.tolerance > 0 && options.tolerance < 1))
    throw Error("diffusion: tolerance must be in (0, 1), got " + fmt(options.tolerance));
  const std::size_t n = input.positions.size();
  DiffusionMethod method = options.method;
  DiffusionResult result;
  DiffusionReport& report = result.report;

  const double exactCost = kCpuSecondsPerExactPair * static_cast<double>(n) * n;
  if (method == DiffusionMethod::Auto && exactCost <= kCpuSecondsFitFloor) {
    method = DiffusionMethod::Exact;
    report.reason =
        "estimated CPU seconds: exact " + fmt(exactCost) + ", less than a Gaussian fit takes";
  }
  if (method == DiffusionMethod::Exact || n == 0) {
    const std::string reason = report.reason;
    const Stopwatch sum;
    result = runExact(input, profile, options);
    report.method = DiffusionMethod::Exact;
    report.reason = reason;
    report.sumSeconds = sum.seconds();
    report.totalSeconds = total.seconds();
    return result;
  }

  // Error budget: the fit gets half the tolerance, truncation a quarter, clusters about a sixth
  // (kThetaScale).
  const double tol = options.tolerance;
  Stopwatch stage;
  const GaussianSumFit fit =
      fitGaussians(profile, 0.5 * tol, std::min(options.maxGaussians, kMaxGaussians));
  report.fitSeconds = stage.seconds();
  const Kernel kernel = makeKernel(fit.sum, 0.25 * tol);
  const double theta = kThetaScale * std::sqrt(tol);
  report.gaussians = kernel.count;
  report.fitError = fit.error;
  report.variances = fit.sum.variances;
  for (int k = 0; k < kernel.count; ++k) report.cutoffs.push_back(kernel.cutoff[k]);

  stage.restart();
  const Octree tree = buildOctree(input);
  report.indexSeconds = stage.seconds();

  std::vector<Cluster> autoClusters;  // reused by the hierarchical sum
  if (method == DiffusionMethod::Auto) {
    // Costs: exact from N^2; gauss and hierarchical from a dry-run traversal of ~200 groups.
    stage.restart();
    const std::size_t stride = std::max<std::size_t>(1, tree.groups.size() / 200);
    std::vector<glm::vec3> mass(n);
    for (std::size_t k = 0; k < n; ++k)
      mass[k] = input.irradiance[tree.points.original[k]] * tree.points.area[k];
    autoClusters = buildClusters(tree, mass, options.threads);
    const double gaussCost = kCpuSecondsPerGaussTerm * kernel.count *
                             estimateTerms(tree, kernel, 0, autoClusters, stride, options.threads);
    const double hierCost =
        kCpuSecondsPerGaussTerm * kernel.count *
        estimateTerms(tree, kernel, theta, autoClusters, stride, options.threads);
    report.indexSeconds += stage.seconds();
    if (exactCost <= std::min(gaussCost, hierCost)) {
      method = DiffusionMethod::Exact;
    } else if (gaussCost <= 1.2 * hierCost) {
      method = DiffusionMethod::Gauss;  // no cluster error: prefer it unless clearly slower
    } else {
      method = DiffusionMethod::Hierarchical;
    }
    report.reason = "estimated CPU seconds: exact " + fmt(exactCost) + ", gauss " + fmt(gaussCost) +
                    ", hierarchical " + fmt(hierCost) +
                    "; incremental is not considered: its error on curved surfaces is not bounded";
    if (method == DiffusionMethod::Exact) {
      DiffusionOptions exactOptions = options;
      exactOptions.method = DiffusionMethod::Exact;
      DiffusionResult exact = diffuse(input, profile, exactOptions);
      exact.report.reason = report.reason;
      exact.report.indexSeconds = report.indexSeconds;
      exact.report.totalSeconds = total.seconds();
      return exact;
    }
  }
  report.method = method;

  // Inputs in Morton order.
  std::vector<glm::vec3> irradiance(n);
  for (std::size_t k = 0; k < n; ++k) irradiance[k] = input.irradiance[tree.points.original[k]];
  EngineStats stats;
  std::vector<glm::vec3> sorted;
  stage.restart();
  if (method == DiffusionMethod::Incremental) {
    Progress progress("diffusion (incremental)", tree.groups.size() * kernel.count, options.quiet);
    std::vector<glm::vec3> pass = irradiance;
    sorted.assign(n, glm::vec3(0));
    double meanArea = 0;
    for (std::size_t j = 0; j < n; ++j) meanArea += tree.points.area[j];
    meanArea /= static_cast<double>(n);
    double previous = 0;
    for (int k = 0; k < kernel.count; ++k) {
      // Re-convolving is only as good as the discrete sum's normalization: a step narrower than
      // the vertex spacing starts from E with the whole variance instead.
      const bool resolved = fit.sum.variances[k] - previous >= kIncrementalMinStep * meanArea;
      GaussianSum step;
      step.variances = {resolved ? fit.sum.variances[k] - previous : fit.sum.variances[k]};
      step.weights = {glm::dvec3(1)};
      previous = fit.sum.variances[k];
      Kernel stepKernel = makeKernel(step, 0.25 * tol / kernel.count);
      // The pass's mass is the previous pass's field: runEngine multiplies by the area.
      pass = runEngine(tree, resolved ? pass : irradiance, stepKernel, 0, options.threads,
                       &progress, stats);
      report.cutoffs[k] = stepKernel.cutoff[0];
      for (std::size_t j = 0; j < n; ++j) sorted[j] += kernel.weight[k] * pass[j];
    }
    progress.finish();
  } else {
    const double useTheta = method == DiffusionMethod::Hierarchical ? theta : 0;
    report.clusterTheta = useTheta;
    Progress progress(std::string("diffusion (") + toString(method) + ")", tree.groups.size(),
                      options.quiet);
    sorted = runEngine(tree, irradiance, kernel, useTheta, options.threads, &progress, stats,
                       std::move(autoClusters));
    progress.finish();
  }
  report.sumSeconds = stage.seconds();
  report.interactions = stats.interactions;
  // Error model: the fit's profile error, the truncation bound, the calibrated cluster term.
  report.estimatedError =
      fit.error + 0.25 * tol + kClusterError * report.clusterTheta * report.clusterTheta;
  if (method == DiffusionMethod::Incremental)
    report.reason = "estimatedError leaves out Eq. 11's composition error on curved surfaces";
  result.exitance.resize(n);
  for (std::size_t k = 0; k < n; ++k) result.exitance[tree.points.original[k]] = sorted[k];
  if (options.weightSums) {  // the same method's sum with E = 1
    const std::vector<glm::vec3> ones(n, glm::vec3(1.0f));
    DiffusionOptions unitOptions = options;
    unitOptions.method = method;
    unitOptions.weightSums = false;
    unitOptions.quiet = true;
    result.weightSums =
        diffuse({input.positions, input.normals, input.areas, ones}, profile, unitOptions).exitance;
  }
  report.totalSeconds = total.seconds();
  return result;
}

}  // namespace sss

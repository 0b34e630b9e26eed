#include "diffusion/diffusion_octree.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "core/parallel.h"

namespace sss {

namespace {

constexpr int kMortonBits = 21;  // per axis: 63-bit codes

using MortonKeys = std::vector<std::pair<std::uint64_t, std::uint32_t>>;  // (code, input index)

std::uint64_t spreadMortonBits(std::uint64_t v) {  // 21 bits -> every third bit
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

// Morton codes of the positions over their bounding box, sorted.
MortonKeys sortedMortonKeys(std::span<const glm::vec3> positions) {
  const std::size_t n = positions.size();
  const Bounds3 bounds = boundsOf(positions);
  const float extent = std::max(bounds.longestSide(), 1e-30f);
  const double scale = ((1u << kMortonBits) - 1) / static_cast<double>(extent);
  MortonKeys keyed(n);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 q = positions[i] - bounds.lo;
    keyed[i] = {spreadMortonBits(static_cast<std::uint64_t>(q.x * scale)) |
                    spreadMortonBits(static_cast<std::uint64_t>(q.y * scale)) << 1 |
                    spreadMortonBits(static_cast<std::uint64_t>(q.z * scale)) << 2,
                static_cast<std::uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  return keyed;
}

MortonSortedPoints sortPoints(const MortonKeys& keyed, std::span<const glm::vec3> positions,
                              std::span<const glm::vec3> normals, std::span<const float> areas) {
  const std::size_t n = keyed.size();
  MortonSortedPoints s;
  s.original.resize(n);
  for (auto* v : {&s.x, &s.y, &s.z, &s.area, &s.spread}) v->resize(n);
  s.normal.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = keyed[k].second;
    s.original[k] = i;
    s.x[k] = positions[i].x, s.y[k] = positions[i].y, s.z[k] = positions[i].z;
    s.area[k] = areas[i];
    s.spread[k] = areas[i] / (4.0f * std::numbers::pi_v<float>);
    s.normal[k] = normals[i];
  }
  return s;
}

// Top-down split on the Morton digits; children of a node are contiguous.
void splitNodes(DiffusionOctree& tree, const MortonKeys& keyed) {
  const MortonSortedPoints& s = tree.points;
  struct Pending {
    std::uint32_t node;
    int level;
  };
  tree.nodes.push_back({0, static_cast<std::uint32_t>(keyed.size()), 0, 0, {}});
  std::vector<Pending> stack{{0, 0}};
  while (!stack.empty()) {
    const Pending p = stack.back();
    stack.pop_back();
    OctreeNode node = tree.nodes[p.node];
    node.box = Bounds3{};
    for (std::uint32_t k = node.begin; k < node.end; ++k) node.box.extend({s.x[k], s.y[k], s.z[k]});
    if (node.end - node.begin > kOctreeLeafSize && p.level < kMortonBits) {
      const int shift = 3 * (kMortonBits - 1 - p.level);
      node.firstChild = static_cast<std::uint32_t>(tree.nodes.size());
      std::uint32_t k = node.begin;
      while (k < node.end) {
        const std::uint64_t digit = keyed[k].first >> shift & 7;
        std::uint32_t e = k;
        while (e < node.end && (keyed[e].first >> shift & 7) == digit) ++e;
        tree.nodes.push_back({k, e, 0, 0, {}});
        ++node.childCount;
        k = e;
      }
      for (std::uint32_t c = 0; c < node.childCount; ++c)
        stack.push_back({node.firstChild + c, p.level + 1});
    }
    tree.nodes[p.node] = node;
  }
}

// Groups in Morton order (a depth-first walk), so each covers a compact patch.
void collectReceiverGroups(DiffusionOctree& tree) {
  std::vector<std::uint32_t> walk{0};
  while (!walk.empty()) {
    const std::uint32_t i = walk.back();
    walk.pop_back();
    const OctreeNode& node = tree.nodes[i];
    if (node.childCount == 0 || node.end - node.begin <= kReceiverGroupSize) {
      tree.groups.push_back(i);
    } else {
      for (std::uint32_t c = node.childCount; c-- > 0;) walk.push_back(node.firstChild + c);
    }
  }
}

// The in-plane per-axis variance of a point set from its weighted covariance `cov` (sum of
// w d d^T, total weight `total`) and area-weighted normal sum `nsum` (of area `asum`).
double inPlaneVariance(const double (&cov)[3][3], double total, const glm::dvec3& nsum,
                       double asum) {
  const double trace = (cov[0][0] + cov[1][1] + cov[2][2]) / total;
  const double nlen = glm::length(nsum);
  if (nlen > 0.5 * asum && nlen > 0) {
    // Variance per in-plane axis: remove the normal direction from the trace.
    const glm::dvec3 nn = nsum / nlen;
    double normalVar = 0;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) normalVar += nn[a] * cov[a][b] * nn[b];
    return std::max(0.0, trace - normalVar / total) / 2;
  }
  return trace / 3;  // strongly curved: no dominant plane
}

ClusterMoments clusterMomentsOf(const MortonSortedPoints& s, const OctreeNode& node,
                                const std::vector<glm::vec3>& mass) {
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
  const glm::dvec3 mu = total > 0 ? (byMass ? c : ca) / total
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
    inPlane = inPlaneVariance(cov, total, nsum, asum);
    footprint /= total;
  }
  return {glm::vec3(mu), glm::vec3(m), static_cast<float>(inPlane + footprint),
          static_cast<float>(std::sqrt(radius2))};
}

}  // namespace

DiffusionOctree buildDiffusionOctree(std::span<const glm::vec3> positions,
                                     std::span<const glm::vec3> normals,
                                     std::span<const float> areas) {
  const MortonKeys keyed = sortedMortonKeys(positions);
  DiffusionOctree tree;
  tree.points = sortPoints(keyed, positions, normals, areas);
  splitNodes(tree, keyed);
  collectReceiverGroups(tree);
  return tree;
}

std::vector<ClusterMoments> buildClusterMoments(const DiffusionOctree& tree,
                                                const std::vector<glm::vec3>& mass, int threads) {
  std::vector<ClusterMoments> clusters(tree.nodes.size());
  parallelFor(tree.nodes.size(), threads, 256, [&](std::size_t nb, std::size_t ne) {
    for (std::size_t ni = nb; ni < ne; ++ni)
      clusters[ni] = clusterMomentsOf(tree.points, tree.nodes[ni], mass);
  });
  return clusters;
}

}  // namespace sss

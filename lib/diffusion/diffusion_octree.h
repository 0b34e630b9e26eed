// The octree behind the Gaussian diffusion sums (octree_gaussian_sum.h): the vertices sorted along
// a Morton curve, nodes that own contiguous ranges of them, the receiver groups, and each node's
// cluster moments, the clusters of Jensen & Buhler 2002 ("A Rapid Hierarchical Rendering Technique
// for Translucent Materials": an octree whose nodes stand in for their points when far enough).
// Private to lib/diffusion.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "core/bounds.h"

namespace sss {

inline constexpr std::size_t kOctreeLeafSize = 16;     // points per octree leaf (at most)
inline constexpr std::size_t kReceiverGroupSize = 128;  // receivers that share one interaction list

// Vertices in Morton order, structure of arrays.
struct MortonSortedPoints {
  std::vector<std::uint32_t> original;  // sorted index -> input index
  // spread: the per-axis variance of the vertex's disc of area A, A / 4 pi (a disc of radius rho
  // has variance rho^2 / 4).
  std::vector<float> x, y, z, area, spread;
  std::vector<glm::vec3> normal;
  std::size_t size() const { return x.size(); }
};

struct OctreeNode {
  std::uint32_t begin = 0, end = 0;              // range in MortonSortedPoints
  std::uint32_t firstChild = 0, childCount = 0;  // children are contiguous in the node array
  Bounds3 box;                                   // of the node's points
};

struct DiffusionOctree {
  MortonSortedPoints points;
  std::vector<OctreeNode> nodes;  // nodes[0]: the root
  // Receiver groups: the largest nodes with at most kReceiverGroupSize points, in Morton order.
  std::vector<std::uint32_t> groups;
};

// Morton-sorts the vertices (positions in mm, unit normals, areas in mm^2; equal lengths, not
// empty) and splits nodes of more than kOctreeLeafSize points on the Morton digits.
DiffusionOctree buildDiffusionOctree(std::span<const glm::vec3> positions,
                                     std::span<const glm::vec3> normals,
                                     std::span<const float> areas);

// Moments of a node for one source field: what replaces its points when it is used as a cluster.
struct ClusterMoments {
  glm::vec3 centroid{0};
  glm::vec3 mass{0};  // sum of E A
  float spread = 0;   // in-plane per-axis variance: second moment + mean point footprint
  float radius = 0;   // max distance from the centroid to a point
};

// The moments of every node for the source masses `mass` (E A per point, in Morton order).
std::vector<ClusterMoments> buildClusterMoments(const DiffusionOctree& tree,
                                                const std::vector<glm::vec3>& mass, int threads);

// Squared distance between two boxes (0 where they overlap).
inline float boxDistanceSquared(const Bounds3& a, const Bounds3& b) {
  const glm::vec3 gap = glm::max(glm::vec3(0), glm::max(a.lo - b.hi, b.lo - a.hi));
  return glm::dot(gap, gap);
}

}  // namespace sss

// Per-vertex values averaged over the surface around each vertex, among vertices that face the
// same way (the far field's smoothing, far_field.h):
//
//   avg_i = sum_j w_ij v_j / sum_j w_ij,   w_ij = G(r_ij) A_j max(0, n_i . n_j),
//
// G a Gaussian of sigma cut at 3 sigma; the normals keep the two faces of a thin part apart.
//
// Cost: summed vertex by vertex, each vertex visits every vertex within 3 sigma, which is
// quadratic once sigma spans many edges (a small skim-milk object of many vertices:
// docs/performance.md, "What each part costs"). Where a kernel would hold more than
// kMaxDirectNeighbours vertices, the sources are gathered into clusters first: the cells of a grid
// of side sigma / 3, split by the dominant axis of the normal (6 bins), each with its area,
// area-weighted centroid, N_c = sum A_j n_j and sum A_j v_j; a cluster then weighs G(|x_i -
// centroid|) max(0, n_i . N_c), with its values at their area-weighted mean. Its error against the
// direct sum is second order in the cells' side over sigma
// (tests/transport/surface_average_test.cpp bounds it).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "mesh/vertex_grid.h"

namespace sss {

struct TriangleMesh;  // mesh/triangle_mesh.h

class SurfaceAverage {
 public:
  // Kernels expected to hold more vertices than this are summed over clusters.
  static constexpr double kMaxDirectNeighbours = 512.0;

  // mesh and areas are kept by reference. forceClusters: clusters whatever the kernel holds (for
  // the tests).
  SurfaceAverage(const TriangleMesh& mesh, std::span<const float> areas, double sigma, int threads,
                 bool forceClusters = false);

  std::vector<glm::vec3> operator()(std::span<const glm::vec3> values) const;
  // Several sets of values at once (the far field's batches): the weights are computed once for
  // all of them.
  std::vector<std::vector<glm::vec3>> operator()(
      const std::vector<std::vector<glm::vec3>>& sets) const;
  bool clustered() const { return !clusterOf_.empty(); }

 private:
  using Sets = std::vector<std::span<const glm::vec3>>;
  std::vector<std::vector<glm::vec3>> direct(const Sets& sets) const;
  std::vector<std::vector<glm::vec3>> overClusters(const Sets& sets) const;

  const TriangleMesh& mesh_;
  std::span<const float> areas_;
  double sigma_;
  int threads_;
  // Clusters (when clustered): per vertex its cluster; per cluster its centroid, N_c and area;
  // the grid over the centroids.
  std::vector<uint32_t> clusterOf_;
  std::vector<glm::vec3> centroid_, normal_;
  std::vector<double> area_;
  VertexGrid grid_;
};

}  // namespace sss

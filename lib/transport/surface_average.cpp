#include "transport/surface_average.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include <glm/geometric.hpp>

#include "core/parallel.h"
#include "mesh/triangle_mesh.h"

namespace sss {
namespace {

// Cluster side against sigma: the centroids stand in for their members to second order in the
// side over sigma.
constexpr double kClusterSidePerSigma = 1.0 / 3.0;

// 0-5: the normal's dominant axis and its sign.
int normalBin(const glm::vec3& n) {
  const glm::vec3 a = glm::abs(n);
  const int axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
  return 2 * axis + (n[axis] < 0.0f ? 1 : 0);
}

double meanVertexArea(std::span<const float> areas) {
  double total = 0.0;
  for (float a : areas) total += a;
  return areas.empty() ? 0.0 : total / double(areas.size());
}

// The cluster of every vertex: vertices sorted by (cell, normal bin), one cluster per run.
std::vector<uint32_t> clusterVertices(const TriangleMesh& mesh, double side, uint32_t& count) {
  const std::size_t n = mesh.positions.size();
  using Key = std::tuple<int64_t, int64_t, int64_t, int>;
  std::vector<std::pair<Key, uint32_t>> keyed(n);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 p = mesh.positions[i];
    keyed[i] = {{int64_t(std::floor(p.x / side)), int64_t(std::floor(p.y / side)),
                 int64_t(std::floor(p.z / side)), normalBin(mesh.normals[i])},
                uint32_t(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<uint32_t> clusterOf(n);
  count = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0 && keyed[k].first != keyed[k - 1].first) ++count;
    clusterOf[keyed[k].second] = count;
  }
  if (n > 0) ++count;
  return clusterOf;
}

}  // namespace

SurfaceAverage::SurfaceAverage(const TriangleMesh& mesh, std::span<const float> areas, double sigma,
                               int threads, bool forceClusters)
    : mesh_(mesh), areas_(areas), sigma_(sigma), threads_(threads), grid_({}, 3.0 * sigma) {
  const double perVertex = meanVertexArea(areas);
  const double neighbours = perVertex > 0.0 ? M_PI * 9.0 * sigma * sigma / perVertex : 0.0;
  if (!forceClusters && neighbours <= kMaxDirectNeighbours) {
    grid_ = VertexGrid(mesh.positions, 3.0 * sigma);
    return;
  }
  uint32_t count = 0;
  clusterOf_ = clusterVertices(mesh, kClusterSidePerSigma * sigma, count);
  std::vector<glm::dvec3> centroid(count, glm::dvec3(0.0)), normal(count, glm::dvec3(0.0));
  area_.assign(count, 0.0);
  for (std::size_t i = 0; i < clusterOf_.size(); ++i) {
    const uint32_t c = clusterOf_[i];
    const double a = areas[i];
    centroid[c] += a * glm::dvec3(mesh.positions[i]);
    normal[c] += a * glm::dvec3(mesh.normals[i]);
    area_[c] += a;
  }
  for (uint32_t c = 0; c < count; ++c) {
    centroid_.push_back(glm::vec3(area_[c] > 0.0 ? centroid[c] / area_[c] : centroid[c]));
    normal_.push_back(glm::vec3(normal[c]));
  }
  grid_ = VertexGrid(centroid_, 3.0 * sigma);
}

std::vector<glm::vec3> SurfaceAverage::operator()(std::span<const glm::vec3> values) const {
  const Sets sets{values};
  return std::move((clustered() ? overClusters(sets) : direct(sets))[0]);
}

std::vector<std::vector<glm::vec3>> SurfaceAverage::operator()(
    const std::vector<std::vector<glm::vec3>>& sets) const {
  const Sets spans(sets.begin(), sets.end());
  return clustered() ? overClusters(spans) : direct(spans);
}

namespace {

// Every set's average at vertex i from the weights visit(i, add) hands to add(w, j): sum_j w v_j
// / sum_j w per set (j a vertex or a cluster, as `values` holds them).
template <typename Visit>
std::vector<std::vector<glm::vec3>> averageSets(const std::vector<std::span<const glm::vec3>>& sets,
                                                const std::vector<std::vector<glm::dvec3>>& values,
                                                int threads, Visit&& visit) {
  const std::size_t k = sets.size(), n = k > 0 ? sets[0].size() : 0;
  std::vector<std::vector<glm::vec3>> mean;
  for (const auto& set : sets) mean.emplace_back(set.begin(), set.end());
  parallelFor(n, threads, 64, [&](std::size_t begin, std::size_t end) {
    std::vector<glm::dvec3> sum(k);
    for (std::size_t i = begin; i < end; ++i) {
      std::fill(sum.begin(), sum.end(), glm::dvec3(0.0));
      double weights = 0.0;
      visit(i, [&](double w, uint32_t j) {
        for (std::size_t b = 0; b < k; ++b) sum[b] += w * values[b][j];
        weights += w;
      });
      if (weights > 0.0)
        for (std::size_t b = 0; b < k; ++b) mean[b][i] = glm::vec3(sum[b] / weights);
    }
  });
  return mean;
}

}  // namespace

std::vector<std::vector<glm::vec3>> SurfaceAverage::direct(const Sets& sets) const {
  const double reach2 = 9.0 * sigma_ * sigma_;
  std::vector<std::vector<glm::dvec3>> values;
  for (const auto& set : sets) values.emplace_back(set.begin(), set.end());
  return averageSets(sets, values, threads_, [&](std::size_t i, auto&& add) {
    grid_.forEachNear(mesh_.positions[i], [&](uint32_t j) {
      const glm::vec3 d = mesh_.positions[j] - mesh_.positions[i];
      const double d2 = glm::dot(d, d), facing = glm::dot(mesh_.normals[i], mesh_.normals[j]);
      if (d2 > reach2 || !(facing > 0.0)) return;
      add(std::exp(-0.5 * d2 / (sigma_ * sigma_)) * areas_[j] * facing, j);
    });
  });
}

std::vector<std::vector<glm::vec3>> SurfaceAverage::overClusters(const Sets& sets) const {
  // Per cluster sum A_j v_j / area: its values at their area-weighted mean.
  std::vector<std::vector<glm::dvec3>> values;
  for (const auto& set : sets) {
    values.emplace_back(area_.size(), glm::dvec3(0.0));
    for (std::size_t i = 0; i < clusterOf_.size(); ++i)
      values.back()[clusterOf_[i]] += double(areas_[i]) * glm::dvec3(set[i]);
    for (std::size_t c = 0; c < area_.size(); ++c)
      if (area_[c] > 0.0) values.back()[c] /= area_[c];
  }
  const double reach2 = 9.0 * sigma_ * sigma_;
  return averageSets(sets, values, threads_, [&](std::size_t i, auto&& add) {
    grid_.forEachNear(mesh_.positions[i], [&](uint32_t c) {
      // sum_j A_j (n_i . n_j) = n_i . N_c over the cluster: its members' weights, exactly while
      // they all face i.
      const glm::vec3 d = centroid_[c] - mesh_.positions[i];
      const double d2 = glm::dot(d, d), facing = glm::dot(mesh_.normals[i], normal_[c]);
      if (d2 > reach2 || !(facing > 0.0) || !(area_[c] > 0.0)) return;
      add(std::exp(-0.5 * d2 / (sigma_ * sigma_)) * facing, c);
    });
  });
}

}  // namespace sss

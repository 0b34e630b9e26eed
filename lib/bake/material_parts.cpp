#include "bake/material_parts.h"

#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/error.h"

namespace sss {
namespace {

// sum_m shares[m][i] field_m[i] for every vertex i; a bake without the field adds nothing.
std::vector<glm::vec3> mixField(const std::vector<BakedMesh>& bakes,
                                const std::vector<std::vector<float>>& shares,
                                std::vector<glm::vec3> BakedMesh::*field, std::size_t vertices) {
  bool any = false;
  for (const BakedMesh& b : bakes) any = any || !(b.*field).empty();
  if (!any) return {};
  std::vector<glm::vec3> mixed(vertices, glm::vec3(0.0f));
  for (std::size_t m = 0; m < bakes.size(); ++m) {
    const std::vector<glm::vec3>& values = bakes[m].*field;
    if (values.empty()) continue;
    for (std::size_t i = 0; i < vertices; ++i) mixed[i] += shares[m][i] * values[i];
  }
  return mixed;
}

// Per vertex, the distance along the mesh's edges to the nearest vertex in `sources` (Dijkstra
// from all of them at once); infinity where none is connected.
std::vector<double> edgeDistances(const TriangleMesh& mesh, const std::vector<bool>& sources) {
  const std::size_t n = mesh.vertexCount();
  std::vector<std::vector<std::uint32_t>> neighbours(n);
  for (const glm::uvec3& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      neighbours[t[k]].push_back(t[(k + 1) % 3]);
      neighbours[t[(k + 1) % 3]].push_back(t[k]);
    }
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  for (std::size_t i = 0; i < n; ++i)
    if (sources[i]) open.push({distance[i] = 0.0, std::uint32_t(i)});
  while (!open.empty()) {
    const auto [d, i] = open.top();
    open.pop();
    if (d > distance[i]) continue;
    for (const std::uint32_t j : neighbours[i]) {
      const double through = d + glm::length(glm::dvec3(mesh.positions[i] - mesh.positions[j]));
      if (through < distance[j]) open.push({distance[j] = through, j});
    }
  }
  return distance;
}

}  // namespace

double materialInterfaceError(const TriangleMesh& meshMm, std::span<const float> vertexAreas,
                              const std::vector<std::vector<float>>& shares,
                              const std::vector<std::span<const glm::vec3>>& radiance,
                              std::span<const glm::dvec3> sigmaTr) {
  const std::size_t n = meshMm.vertexCount();
  std::vector<bool> border(n, false);
  std::vector<std::size_t> own(n, 0);  // the vertex's largest material
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t m = 0; m < shares.size(); ++m) {
      border[i] = border[i] || (shares[m][i] > 0.0f && shares[m][i] < 1.0f);
      if (shares[m][i] > shares[own[i]][i]) own[i] = m;
    }
  const std::vector<double> distance = edgeDistances(meshMm, border);
  double error = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t m = own[i];
    for (int c = 0; c < 3; ++c) {
      double difference = 0.0, mixed = 0.0;
      for (std::size_t k = 0; k < radiance.size(); ++k) {
        difference = std::max(difference, double(std::abs(radiance[k][i][c] - radiance[m][i][c])));
        mixed += shares[k][i] * radiance[k][i][c];
      }
      const double e =
          std::isinf(distance[i]) ? 0.0 : 0.5 * difference * std::exp(-sigmaTr[m][c] * distance[i]);
      error += vertexAreas[i] * e * e;
      norm += vertexAreas[i] * mixed * mixed;
    }
  }
  return norm > 0.0 ? std::sqrt(error / norm) : 0.0;
}

std::vector<std::vector<float>> vertexMaterialShares(const TriangleMesh& mesh,
                                                     std::span<const std::uint32_t> trianglePart,
                                                     std::span<const std::uint32_t> partMaterial,
                                                     std::size_t materials) {
  if (trianglePart.size() != mesh.triangles.size())
    throw Error("vertexMaterialShares: one part per triangle is needed");
  const std::size_t n = mesh.vertexCount();
  std::vector<std::vector<float>> shares(materials, std::vector<float>(n, 0.0f));
  std::vector<float> total(n, 0.0f);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    const glm::vec3 a = mesh.positions[tri.x], b = mesh.positions[tri.y], c = mesh.positions[tri.z];
    const float third = glm::length(glm::cross(b - a, c - a)) / 6.0f;
    const std::uint32_t m = partMaterial[trianglePart[t]];
    for (int k = 0; k < 3; ++k) {
      shares[m][tri[k]] += third;
      total[tri[k]] += third;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (total[i] > 0.0f) {
      for (std::vector<float>& s : shares) s[i] /= total[i];
    } else {  // a vertex of degenerate triangles only: the first material of one of them
      shares[0][i] = 1.0f;
    }
  }
  return shares;
}

BakedMesh mixBakedMeshes(std::vector<BakedMesh> bakes,
                         const std::vector<std::vector<float>>& shares, std::size_t header) {
  const std::size_t n = bakes.front().mesh.vertexCount();
  std::vector<glm::vec3> irradiance = mixField(bakes, shares, &BakedMesh::irradiance, n);
  std::vector<glm::vec3> exitance = mixField(bakes, shares, &BakedMesh::exitance, n);
  std::vector<glm::vec3> radianceNormal = mixField(bakes, shares, &BakedMesh::radianceNormal, n);
  std::vector<glm::vec3> farExitance = mixField(bakes, shares, &BakedMesh::farExitance, n);
  std::vector<glm::vec3> exitSlope = mixField(bakes, shares, &BakedMesh::exitSlope, n);
  bool unscatteredTraced = false;
  for (const BakedMesh& b : bakes) unscatteredTraced = unscatteredTraced || b.unscatteredTraced;
  BakedMesh mixed = std::move(bakes[header]);
  mixed.irradiance = std::move(irradiance);
  mixed.exitance = std::move(exitance);
  mixed.radianceNormal = std::move(radianceNormal);
  mixed.farExitance = std::move(farExitance);
  mixed.exitSlope = std::move(exitSlope);
  mixed.unscatteredTraced = unscatteredTraced;
  return mixed;
}

BakeErrorReport mixErrorReports(std::span<const BakeErrorReport> errors,
                                std::span<const double> areaShares) {
  BakeErrorReport mixed;
  mixed.tolerance = errors.front().tolerance;
  const auto mix = [&](const auto& valueOf) {
    double sum = 0.0;
    for (std::size_t m = 0; m < errors.size(); ++m)
      sum += areaShares[m] * std::pow(valueOf(errors[m]), 2);
    return std::sqrt(sum);
  };
  for (double BakeErrorReport::*f :
       {&BakeErrorReport::visibility, &BakeErrorReport::exitance, &BakeErrorReport::energy,
        &BakeErrorReport::interreflection, &BakeErrorReport::unscattered,
        &BakeErrorReport::exitLobe, &BakeErrorReport::numerical, &BakeErrorReport::total})
    mixed.*f = mix([f](const BakeErrorReport& e) { return e.*f; });
  for (double ModelErrorReport::*f :
       {&ModelErrorReport::exitModel, &ModelErrorReport::facets, &ModelErrorReport::facetLight,
        &ModelErrorReport::farField, &ModelErrorReport::interreflection, &ModelErrorReport::total})
    mixed.model.*f = mix([f](const BakeErrorReport& e) { return e.model.*f; });
  for (const BakeErrorReport& e : errors) mixed.model.seconds += e.model.seconds;
  return mixed;
}

void applySymmetricChange(BakedMesh& mixed, const std::vector<std::vector<glm::vec3>>& exitance,
                          const std::vector<std::vector<glm::vec3>>& radiance, MaterialRule rule) {
  if (rule == MaterialRule::Receiver) return;
  const float largest =
      rule == MaterialRule::Symmetric ? std::numeric_limits<float>::infinity() : 0.0f;
  const auto add = [&](std::vector<glm::vec3>& field,
                       const std::vector<std::vector<glm::vec3>>& changes) {
    for (std::size_t i = 0; i < field.size(); ++i) {
      glm::vec3 sum(0.0f);
      for (const std::vector<glm::vec3>& change : changes)
        if (!change.empty()) sum += change[i];
      field[i] += glm::min(sum, glm::vec3(largest));
    }
  };
  add(mixed.exitance, exitance);
  add(mixed.radianceNormal, radiance);
}

std::vector<double> areaShares(const std::vector<std::vector<float>>& shares,
                               std::span<const float> vertexAreas) {
  std::vector<double> out(shares.size(), 0.0);
  double total = 0.0;
  for (std::size_t i = 0; i < vertexAreas.size(); ++i) total += vertexAreas[i];
  for (std::size_t m = 0; m < shares.size(); ++m) {
    for (std::size_t i = 0; i < vertexAreas.size(); ++i) out[m] += shares[m][i] * vertexAreas[i];
    if (total > 0.0) out[m] /= total;
  }
  return out;
}

}  // namespace sss

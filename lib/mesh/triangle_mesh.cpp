#include "mesh/triangle_mesh.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>

namespace sss {

namespace {

glm::dvec3 corner(const TriangleMesh& mesh, unsigned i) {
  return glm::dvec3(mesh.positions[i]);
}

// Unnormalized normal (twice the area vector) of triangle t, in double.
glm::dvec3 areaVector(const TriangleMesh& mesh, const glm::uvec3& t) {
  const glm::dvec3 a = corner(mesh, t.x);
  return glm::cross(corner(mesh, t.y) - a, corner(mesh, t.z) - a);
}

}  // namespace

std::vector<float> vertexAreas(const TriangleMesh& mesh) {
  return vertexAreas(mesh.positions, mesh.triangles);
}

std::vector<float> vertexAreas(std::span<const glm::vec3> positions,
                               std::span<const glm::uvec3> triangles) {
  std::vector<double> sum(positions.size(), 0.0);
  for (const glm::uvec3& t : triangles) {
    const glm::dvec3 a(positions[t.x]);
    const glm::dvec3 cross =
        glm::cross(glm::dvec3(positions[t.y]) - a, glm::dvec3(positions[t.z]) - a);
    const double third = glm::length(cross) / 6.0;  // |cross| / 2 / 3
    sum[t.x] += third;
    sum[t.y] += third;
    sum[t.z] += third;
  }
  return std::vector<float>(sum.begin(), sum.end());
}

std::vector<glm::vec3> hatFunctionAverage(const TriangleMesh& mesh,
                                          std::span<const glm::vec3> values,
                                          double minFacetCosine) {
  std::vector<glm::dvec3> sum(mesh.positions.size(), glm::dvec3(0.0));
  std::vector<double> weight(mesh.positions.size(), 0.0);
  std::vector<char> folded(mesh.positions.size(), 0);
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::dvec3 a = areaVector(mesh, t);
    const double twelfth = glm::length(a) / 24.0;  // |cross| / 2 / 12
    const glm::dvec3 total =
        glm::dvec3(values[t.x]) + glm::dvec3(values[t.y]) + glm::dvec3(values[t.z]);
    bool fold = false;
    for (const unsigned v : {t.x, t.y, t.z})
      fold = fold || glm::dot(a, glm::dvec3(mesh.normals[v])) < minFacetCosine * glm::length(a);
    for (const unsigned v : {t.x, t.y, t.z}) {
      sum[v] += twelfth * (total + glm::dvec3(values[v]));
      weight[v] += 4.0 * twelfth;
      folded[v] = folded[v] || fold;
    }
  }
  std::vector<glm::vec3> out(values.begin(), values.end());
  for (std::size_t i = 0; i < out.size(); ++i)
    if (weight[i] > 0.0 && !folded[i]) out[i] = glm::vec3(sum[i] / weight[i]);
  return out;
}

std::vector<float> projectedVertexAreas(const TriangleMesh& mesh) {
  std::vector<double> sum(mesh.positions.size(), 0.0);
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::dvec3 a = areaVector(mesh, t);  // |a| = 2 x the triangle's area
    for (const unsigned v : {t.x, t.y, t.z}) {
      sum[v] += std::max(0.0, glm::dot(a, glm::dvec3(mesh.normals[v]))) / 6.0;
    }
  }
  return std::vector<float>(sum.begin(), sum.end());
}

double surfaceArea(const TriangleMesh& mesh) {
  double area = 0.0;
  for (const glm::uvec3& t : mesh.triangles) area += glm::length(areaVector(mesh, t)) / 2.0;
  return area;
}

double signedVolume(const TriangleMesh& mesh) {
  double volume = 0.0;
  for (const glm::uvec3& t : mesh.triangles) {
    volume += glm::dot(corner(mesh, t.x), glm::cross(corner(mesh, t.y), corner(mesh, t.z)));
  }
  return volume / 6.0;
}

VertexFacets vertexFacets(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                          std::span<const glm::uvec3> triangles, double smoothCosine,
                          double mergeCosine) {
  const std::size_t n = positions.size();
  // Each vertex's triangles (of any area) as (normal turned to the vertex's side, area), in
  // compressed rows; then per vertex the distinct ones merged (a vertex inside a flat region has
  // one; a box corner three).
  std::vector<uint32_t> start(n + 1, 0);
  std::vector<glm::dvec3> areaVectors(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const glm::uvec3 t = triangles[i];
    const glm::dvec3 o(positions[t.x]);
    areaVectors[i] = glm::cross(glm::dvec3(positions[t.y]) - o, glm::dvec3(positions[t.z]) - o);
    const double area = glm::length(areaVectors[i]);
    if (!(area > 0.0) || !std::isfinite(area)) continue;
    for (int k = 0; k < 3; ++k) ++start[t[k] + 1];
  }
  for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  std::vector<std::pair<glm::dvec3, double>> around(start[n]);
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const double area = glm::length(areaVectors[i]);
    if (!(area > 0.0) || !std::isfinite(area)) continue;
    const glm::dvec3 normal = areaVectors[i] / area;
    for (int k = 0; k < 3; ++k) {
      const unsigned v = triangles[i][k];
      const bool away = glm::dot(normal, glm::dvec3(normals[v])) < 0.0;
      around[fill[v]++] = {away ? -normal : normal, area};
    }
  }
  VertexFacets out;
  out.begin.reserve(n + 1);
  out.begin.push_back(0);
  for (std::size_t v = 0; v < n; ++v) {
    const auto first = around.begin() + start[v], last = around.begin() + start[v + 1];
    const glm::dvec3 normal(normals[v]);
    const bool smooth = std::all_of(
        first, last, [&](const auto& f) { return glm::dot(f.first, normal) >= smoothCosine; });
    double total = 0.0;
    for (auto f = first; f != last; ++f) total += f->second;
    if (smooth && first != last) {
      out.normals.push_back(glm::vec3(normal));
      out.shares.push_back(1.0f);
    } else {
      // Groups: a facet joins the first group whose first facet lies within acos(mergeCosine).
      std::vector<std::pair<glm::dvec3, glm::dvec3>> groups;  // (first normal, sum of area n)
      std::vector<double> areas;
      for (auto f = first; f != last; ++f) {
        std::size_t k = 0;
        while (k < groups.size() && !(glm::dot(groups[k].first, f->first) >= mergeCosine)) ++k;
        if (k == groups.size()) {
          groups.push_back({f->first, glm::dvec3(0.0)});
          areas.push_back(0.0);
        }
        groups[k].second += f->second * f->first;
        areas[k] += f->second;
      }
      for (std::size_t k = 0; k < groups.size(); ++k) {
        out.normals.push_back(glm::vec3(glm::normalize(groups[k].second)));
        out.shares.push_back(static_cast<float>(areas[k] / total));
      }
    }
    out.begin.push_back(static_cast<uint32_t>(out.normals.size()));
  }
  return out;
}

std::vector<glm::vec3> computeVertexNormals(const TriangleMesh& mesh) {
  std::vector<glm::dvec3> sum(mesh.positions.size(), glm::dvec3(0.0));
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::dvec3 n = areaVector(mesh, t);
    sum[t.x] += n;
    sum[t.y] += n;
    sum[t.z] += n;
  }
  std::vector<glm::vec3> normals(sum.size());
  for (std::size_t i = 0; i < sum.size(); ++i) {
    const double len = glm::length(sum[i]);
    normals[i] = len > 0.0 && std::isfinite(len) ? glm::vec3(sum[i] / len) : glm::vec3(0, 0, 1);
  }
  return normals;
}

void scalePositions(TriangleMesh& mesh, double scale) {
  for (glm::vec3& p : mesh.positions) p = glm::vec3(glm::dvec3(p) * scale);
}

}  // namespace sss

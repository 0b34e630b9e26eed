#include "mesh/triangle_mesh.h"

#include <algorithm>
#include <cmath>

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
  std::vector<double> sum(mesh.positions.size(), 0.0);
  for (const glm::uvec3& t : mesh.triangles) {
    const double third = glm::length(areaVector(mesh, t)) / 6.0;  // |cross| / 2 / 3
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

// Generated meshes: counts, closedness, orientation, areas and normals against closed forms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "mesh/load_mesh.h"
#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"
#include "mesh/units.h"

namespace sss {
namespace {

MeshReport topologyOf(const TriangleMesh& mesh) {
  RawMesh raw;
  raw.positions = mesh.positions;
  raw.normals = mesh.normals;
  for (const glm::uvec3& t : mesh.triangles) raw.addFace({t.x, t.y, t.z});
  MeshReport report;
  cleanMesh("generated", raw, &report);
  return report;
}

double sumOf(const std::vector<float>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0);
}

TEST(MeshIcosphere, CountsClosedOutwardAndAreaConverges) {
  const double r = 2.0;
  double previousError = 1e9;
  for (int s = 0; s <= 4; ++s) {
    const TriangleMesh m = makeIcosphere(s, static_cast<float>(r));
    EXPECT_EQ(m.vertexCount(), 10u * (1u << (2 * s)) + 2);
    EXPECT_EQ(m.triangleCount(), 20u * (1u << (2 * s)));
    const MeshReport rep = topologyOf(m);
    EXPECT_EQ(rep.boundaryEdges, 0u);
    EXPECT_EQ(rep.nonManifoldEdges + rep.nonManifoldVertices + rep.misorientedEdges, 0u);
    EXPECT_EQ(rep.components, 1u);
    EXPECT_FALSE(rep.orientationFlipped);
    EXPECT_GT(signedVolume(m), 0.0);
    // The inscribed polyhedron's area approaches 4 pi r^2 from below, monotonically.
    const double error = 4 * std::numbers::pi * r * r - surfaceArea(m);
    EXPECT_GT(error, 0.0);
    EXPECT_LT(error, previousError);
    previousError = error;
  }
  EXPECT_LT(previousError / (4 * std::numbers::pi * r * r), 2e-3);
}

TEST(MeshIcosphere, ComputedNormalsPointOutward) {
  const TriangleMesh m = makeIcosphere(3, 1.5f);
  const std::vector<glm::vec3> n = computeVertexNormals(m);
  for (std::size_t i = 0; i < n.size(); ++i) {
    EXPECT_NEAR(glm::length(n[i]), 1.0f, 1e-5f);
    EXPECT_GT(glm::dot(n[i], glm::normalize(m.positions[i])), 0.999f) << i;
  }
}

TEST(MeshVertexAreas, SumToSurfaceAreaAndAreThirds) {
  const TriangleMesh sphere = makeIcosphere(3, 1.0f);
  EXPECT_NEAR(sumOf(vertexAreas(sphere)), surfaceArea(sphere), 1e-5 * surfaceArea(sphere));

  // Grid plane of side 2 with 4 x 4 quads: interior vertices touch six triangles of area 1/8
  // each... i.e. 6 * (0.125 / 3) = 0.25 (one quad's area); corners (0,0) touch two.
  const TriangleMesh plane = makeGridPlane(4, 2.0f);
  const std::vector<float> a = vertexAreas(plane);
  EXPECT_NEAR(sumOf(a), 4.0, 1e-6);
  EXPECT_NEAR(a[6], 0.25f, 1e-6f);           // interior vertex (1, 1)
  EXPECT_NEAR(a[0], 2 * 0.125f / 3, 1e-6f);  // corner with both triangles of its quad
  EXPECT_NEAR(a[4], 0.125f / 3, 1e-6f);      // corner with one triangle
}

// hatFunctionAverage against its definition integrated numerically: integral(f l_k) /
// integral(l_k) with f the vertex values' linear interpolant, summed over barycentric grid points
// of every triangle (a midpoint rule, exact to its resolution's square).
std::vector<glm::vec3> hatAverageByQuadrature(const TriangleMesh& mesh,
                                              const std::vector<glm::vec3>& values) {
  constexpr int kSteps = 60;
  std::vector<glm::dvec3> sum(values.size(), glm::dvec3(0.0));
  std::vector<double> weight(values.size(), 0.0);
  for (const glm::uvec3& t : mesh.triangles) {
    const double area = 0.5 * glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                                     mesh.positions[t.z] - mesh.positions[t.x]));
    for (int i = 0; i < kSteps; ++i)
      for (int j = 0; i + j < kSteps; ++j)
        for (int up = 0; up < (i + j + 1 < kSteps ? 2 : 1); ++up) {
          // The centroid of one of the kSteps^2 equal sub-triangles.
          const double a = (i + (up ? 2.0 : 1.0) / 3.0) / kSteps;
          const double b = (j + (up ? 2.0 : 1.0) / 3.0) / kSteps;
          const double l[3] = {1.0 - a - b, a, b};
          const glm::dvec3 f = l[0] * glm::dvec3(values[t.x]) + l[1] * glm::dvec3(values[t.y]) +
                               l[2] * glm::dvec3(values[t.z]);
          const unsigned v[3] = {t.x, t.y, t.z};
          for (int k = 0; k < 3; ++k) {
            sum[v[k]] += l[k] * f * (area / (kSteps * kSteps));
            weight[v[k]] += l[k] * (area / (kSteps * kSteps));
          }
        }
  }
  std::vector<glm::vec3> out(values.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = glm::vec3(sum[i] / weight[i]);
  return out;
}

TEST(MeshHatFunctionAverage, MatchesItsIntegralAndKeepsFolds) {
  // On a curved surface: a 42-vertex sphere, a field varying over it. Every facet lies within
  // 30 degrees of its corners' normals, so every vertex is averaged.
  const TriangleMesh sphere = makeIcosphere(1, 10.0f);
  std::vector<glm::vec3> values;
  for (const glm::vec3& p : sphere.positions)
    values.push_back(glm::vec3(1.0f + p.z / 10.0f, p.x * p.x / 100.0f, 2.0f));
  const std::vector<glm::vec3> hat = hatFunctionAverage(sphere, values, 0.866);
  const std::vector<glm::vec3> expected = hatAverageByQuadrature(sphere, values);
  double moved = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(hat[i][c], expected[i][c], 1e-4) << i << " " << c;
    moved = std::max(moved, double(std::abs(hat[i].x - values[i].x)));
  }
  EXPECT_GT(moved, 0.05);  // the top vertex's hat reaches well down the sphere

  // A linear field on a flat grid is its own average where the one-ring is symmetric.
  const TriangleMesh plane = makeGridPlane(4, 2.0f);
  std::vector<glm::vec3> linear;
  for (const glm::vec3& p : plane.positions) linear.push_back(glm::vec3(3.0f * p.x + p.y + 1.0f));
  EXPECT_NEAR(hatFunctionAverage(plane, linear, 0.866)[12].x, linear[12].x, 1e-5);  // centre

  // At a box's folds (edge normals 45 degrees off their facets) values are kept, and so are
  // those of face vertices with a triangle at the fold; a face's centre further in is averaged.
  const TriangleMesh box = makeBox(glm::vec3(4.0f), 4);
  std::vector<glm::vec3> field;
  for (const glm::vec3& p : box.positions) field.push_back(glm::vec3(p.x * p.x + p.y));
  const std::vector<glm::vec3> boxHat = hatFunctionAverage(box, field, 0.866);
  const std::vector<glm::vec3> boxExpected = hatAverageByQuadrature(box, field);
  int kept = 0, averaged = 0;
  for (std::size_t i = 0; i < field.size(); ++i) {
    const glm::vec3 p = box.positions[i];
    const bool faceCentre = (p.x == 0.0f) + (p.y == 0.0f) + (p.z == 0.0f) == 2;
    const bool nearFold = !faceCentre;  // every other vertex of a 4 x 4 face touches an edge
    if (nearFold) {
      EXPECT_EQ(boxHat[i], field[i]) << i;
      ++kept;
    } else {
      EXPECT_NEAR(boxHat[i].x, boxExpected[i].x, 1e-4) << i;
      ++averaged;
    }
  }
  EXPECT_EQ(averaged, 6);  // the faces' centres
  EXPECT_EQ(kept, int(field.size()) - 6);
}

TEST(MeshBox, ClosedWeldedExactAreaAndVolume) {
  const glm::vec3 size(1.0f, 2.0f, 3.0f);
  const TriangleMesh box = makeBox(size, 3);
  EXPECT_EQ(box.vertexCount(), 6u * 4 + 12u * 2 + 8u);  // face interiors, edge interiors, corners
  const MeshReport rep = topologyOf(box);
  EXPECT_EQ(rep.boundaryEdges + rep.nonManifoldEdges + rep.misorientedEdges, 0u);
  EXPECT_NEAR(surfaceArea(box), 2.0 * (2 + 6 + 3), 1e-5);
  EXPECT_NEAR(sumOf(vertexAreas(box)), 22.0, 1e-4);
  EXPECT_NEAR(signedVolume(box), 6.0, 1e-5);
  for (std::size_t i = 0; i < box.vertexCount(); ++i) {
    EXPECT_GT(glm::dot(box.normals[i], box.positions[i]), 0.0f);
  }
}

// The facets around a vertex (lighting/facet_light.h takes their light): one inside a face, the two
// faces on an edge, three at a corner, with their shares of the vertex's area; a triangle wound
// the other way still faces out.
TEST(MeshVertexFacets, BoxFacesEdgesAndCornersWithTheirAreaShares) {
  TriangleMesh box = makeBox(glm::vec3(2.0f), 2);
  std::swap(box.triangles[0].y, box.triangles[0].z);  // a face of inconsistent winding
  const VertexFacets f = vertexFacets(box.positions, box.normals, box.triangles);
  ASSERT_EQ(f.begin.size(), box.vertexCount() + 1);
  const std::vector<float> areas = vertexAreas(box);
  for (std::size_t v = 0; v < box.vertexCount(); ++v) {
    const glm::vec3 p = box.positions[v];
    const int onFaces = (std::abs(p.x) == 1.0f) + (std::abs(p.y) == 1.0f) + (std::abs(p.z) == 1.0f);
    ASSERT_EQ(f.begin[v + 1] - f.begin[v], uint32_t(onFaces)) << v;
    float shares = 0.0f;
    for (uint32_t k = f.begin[v]; k < f.begin[v + 1]; ++k) {
      const glm::vec3 n = f.normals[k];
      // An axis, outwards: the face the vertex lies on.
      EXPECT_NEAR(glm::dot(n, n), 1.0f, 1e-6f);
      const int axis = std::abs(n.x) > 0.5f ? 0 : std::abs(n.y) > 0.5f ? 1 : 2;
      EXPECT_NEAR(n[axis], p[axis], 1e-6f) << v;
      shares += f.shares[k];
      // The share is that face's triangles' area at v over the vertex's: each triangle counts a
      // third of its area (vertexAreas), a unit-square quad's triangles 1/6 each.
      double onFace = 0.0;
      for (const glm::uvec3& t : box.triangles) {
        if (t.x != v && t.y != v && t.z != v) continue;
        const glm::vec3 c = glm::cross(box.positions[t.y] - box.positions[t.x],
                                       box.positions[t.z] - box.positions[t.x]);
        if (std::abs(std::abs(c[axis]) - glm::length(c)) < 1e-6f) onFace += glm::length(c) / 6.0;
      }
      EXPECT_NEAR(f.shares[k], onFace / areas[v], 1e-5) << v;
    }
    EXPECT_NEAR(shares, 1.0f, 1e-6f) << v;
  }
}

TEST(MeshSlab, ThicknessRowsAndVolume) {
  const TriangleMesh slab = makeSlab(10.0f, 1.0f, 20);  // 0.5 cells: 2 rows through z
  EXPECT_NEAR(signedVolume(slab), 100.0, 1e-3);
  EXPECT_NEAR(surfaceArea(slab), 200.0 + 40.0, 1e-3);
  EXPECT_EQ(topologyOf(slab).boundaryEdges, 0u);
  std::size_t midZ = 0;
  for (const glm::vec3& p : slab.positions) midZ += p.z == 0.0f;
  EXPECT_EQ(midZ, 80u);  // one ring of 4 * 20 vertices half way through
}

TEST(MeshUnits, ParseAndScale) {
  EXPECT_EQ(parseUnit("mm"), 1.0);
  EXPECT_EQ(parseUnit("cm"), 10.0);
  EXPECT_EQ(parseUnit("m"), 1000.0);
  EXPECT_THROW(parseUnit("inch"), Error);
  EXPECT_THROW(checkMmPerUnit(0.0), Error);
  EXPECT_THROW(checkMmPerUnit(std::nan("")), Error);
  EXPECT_EQ(checkMmPerUnit(25.4), 25.4);
  TriangleMesh m = makeIcosphere(1, 0.15f);
  scalePositions(m, 1000.0);
  EXPECT_NEAR(glm::length(m.positions[0]), 150.0f, 1e-3f);
}

}  // namespace
}  // namespace sss

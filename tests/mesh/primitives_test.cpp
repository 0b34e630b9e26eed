// Generated meshes: counts, closedness, orientation, areas and normals against closed forms.
#include <gtest/gtest.h>

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

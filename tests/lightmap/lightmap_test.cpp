// lib/lightmap: the refinement to a texture's texels (conforming, on the surface, every edge
// within its texel length), the fill (exact for a field linear on the surface), the padding, the
// seam comparison and the overlap count.
#include <cmath>
#include <map>
#include <set>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "lightmap/lightmap.h"
#include "lightmap/uv_refinement.h"
#include "mesh/primitives.h"

namespace sss {
namespace {

// A unit square in z = 0 whose texture coordinates are its (x, y) mapped onto [lo, hi]^2.
struct UvQuad {
  TriangleMesh mesh;
  std::vector<glm::vec2> uv;
};
UvQuad quad(float lo = 0.0f, float hi = 1.0f) {
  UvQuad q;
  q.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  q.mesh.normals.assign(4, glm::vec3(0, 0, 1));
  q.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  for (const glm::uvec3& t : q.mesh.triangles) {
    for (int i = 0; i < 3; ++i) {
      q.uv.push_back(lo + (hi - lo) * glm::vec2(q.mesh.positions[t[i]]));
    }
  }
  return q;
}

// A closed box whose six faces are six charts of a 3 x 2 atlas, a texel's width apart.
UvQuad atlasBox() {
  UvQuad q;
  q.mesh = makeBox(glm::vec3(2.0f), 2);
  for (const glm::uvec3& t : q.mesh.triangles) {
    const glm::vec3 a = q.mesh.positions[t[0]], b = q.mesh.positions[t[1]],
                    c = q.mesh.positions[t[2]];
    const glm::vec3 n = glm::cross(b - a, c - a);
    int axis = 0;
    for (int k = 1; k < 3; ++k) axis = std::abs(n[k]) > std::abs(n[axis]) ? k : axis;
    const int face = 2 * axis + (n[axis] > 0 ? 1 : 0);
    const glm::vec2 cell(float(face % 3) / 3.0f, float(face / 3) / 2.0f);
    for (int i = 0; i < 3; ++i) {
      const glm::vec3 p = q.mesh.positions[t[i]];
      const glm::vec2 local(0.5f * (p[(axis + 1) % 3] + 1.0f), 0.5f * (p[(axis + 2) % 3] + 1.0f));
      q.uv.push_back(cell + glm::vec2(0.02f) + local * glm::vec2(1.0f / 3.0f, 0.5f) * 0.88f);
    }
  }
  return q;
}

UvRefinement refine(const UvQuad& q, int size, double texels = 1.0) {
  return refineToTexels("test.glb", q.mesh.vertexCount(), q.mesh.triangles, q.uv, size, texels,
                        1u << 22);
}

std::map<std::pair<std::uint32_t, std::uint32_t>, int> edgeUses(const UvRefinement& r) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  for (const glm::uvec3& t : r.triangles) {
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = t[i], b = t[(i + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  return uses;
}

double area(const TriangleMesh& m) {
  double sum = 0.0;
  for (const glm::uvec3& t : m.triangles) {
    sum += 0.5 * glm::length(glm::cross(glm::dvec3(m.positions[t[1]] - m.positions[t[0]]),
                                        glm::dvec3(m.positions[t[2]] - m.positions[t[0]])));
  }
  return sum;
}

TEST(UvRefinement, EveryEdgeWithinATexelOnTheSameSurface) {
  const UvQuad q = quad();
  for (const double texels : {1.0, 2.5}) {
    const UvRefinement r = refine(q, 64, texels);
    const TriangleMesh m = refinedMesh(r, q.mesh);
    ASSERT_EQ(r.cornerTexcoords.size(), 3 * r.triangles.size());
    for (std::size_t t = 0; t < r.triangles.size(); ++t) {
      for (int i = 0; i < 3; ++i) {
        const glm::vec2 d = r.cornerTexcoords[3 * t + i] - r.cornerTexcoords[3 * t + (i + 1) % 3];
        EXPECT_LE(glm::length(d) * 64, texels + 1e-6);
        // The corner's texture coordinates are its position's (x, y), as on the square.
        const glm::vec3 p = m.positions[r.triangles[t][i]];
        EXPECT_NEAR(r.cornerTexcoords[3 * t + i].x, p.x, 1e-6);
        EXPECT_NEAR(r.cornerTexcoords[3 * t + i].y, p.y, 1e-6);
      }
      const glm::vec3 n =
          glm::cross(m.positions[r.triangles[t][1]] - m.positions[r.triangles[t][0]],
                     m.positions[r.triangles[t][2]] - m.positions[r.triangles[t][0]]);
      EXPECT_GT(n.z, 0.0f) << "winding kept";
    }
    EXPECT_NEAR(area(m), 1.0, 1e-9);
    // Longest-edge bisection keeps shapes: about 2 triangles per square of the edge length.
    const double cells = std::pow(64.0 / texels, 2);
    EXPECT_GE(double(r.triangles.size()), 2.0 * cells);
    EXPECT_LE(double(r.triangles.size()), 8.0 * cells);
  }
}

TEST(UvRefinement, AClosedMeshStaysClosedAcrossItsSeams) {
  const UvQuad box = atlasBox();
  const UvRefinement r = refine(box, 48);
  const TriangleMesh m = refinedMesh(r, box.mesh);
  const auto uses = edgeUses(r);
  for (const auto& [edge, count] : uses) EXPECT_EQ(count, 2) << edge.first << "-" << edge.second;
  // Euler: V - E + F = 2 for a sphere-like surface.
  EXPECT_EQ(long(r.vertexCount()) - long(uses.size()) + long(r.triangles.size()), 2);
  EXPECT_NEAR(area(m), 24.0, 1e-5);
  for (const glm::vec3& p : m.positions) {  // on the box's surface
    EXPECT_NEAR(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}), 1.0f, 1e-6f);
  }
  for (const glm::vec3& n : m.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
  EXPECT_GT(r.vertexCount(), 1000u);
  // Deterministic.
  const UvRefinement again = refine(box, 48);
  EXPECT_EQ(again.triangles, r.triangles);
}

TEST(UvRefinement, TexcoordsOutsideTheMapOrMissingAreErrors) {
  UvQuad q = quad();
  q.uv[4].x = 1.5f;
  try {
    refine(q, 32);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "test.glb: TEXCOORD_0 of triangle 1 is (1.500000, 1.000000), outside [0, 1]: a "
              "lightmap needs every texture coordinate in the map");
  }
  q.uv.pop_back();
  EXPECT_THROW(refine(q, 32), Error);
  const UvQuad big = quad();
  EXPECT_THROW(refineToTexels("test.glb", 4, big.mesh.triangles, big.uv, 4096, 1.0, 10000), Error);
}

TEST(Lightmap, FillIsExactForAFieldLinearOnTheSurface) {
  const UvQuad q = quad();
  const int size = 32;
  const UvRefinement r = refine(q, size);
  const TriangleMesh m = refinedMesh(r, q.mesh);
  std::vector<glm::vec3> field;
  for (const glm::vec3& p : m.positions) field.push_back({p.x, 2.0f * p.y, p.x + p.y + 1.0f});
  const std::span<const glm::vec3> fields[] = {field};
  const Lightmap map = fillLightmap(r, fields, {.size = size, .padding = 0});
  EXPECT_EQ(map.coveredTexels, std::size_t(size * size));
  EXPECT_EQ(map.overlappingTexels, 0u);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const float u = (x + 0.5f) / size, v = (y + 0.5f) / size;
      const glm::vec3 got = map.images[0][y * size + x];
      EXPECT_NEAR(got.x, u, 1e-5f);
      EXPECT_NEAR(got.y, 2.0f * v, 1e-5f);
      EXPECT_NEAR(got.z, u + v + 1.0f, 1e-5f);
    }
  }
  // The bilinear read between texel centres is the same linear field.
  EXPECT_NEAR(sampleBilinear(map.images[0], size, {0.3f, 0.6f}).z, 1.9f, 1e-5f);
}

TEST(Lightmap, PaddingFillsTheGutterAndNoMore) {
  const UvQuad q = quad(0.25f, 0.75f);  // texels 8..23 of 32
  const UvRefinement r = refine(q, 32);
  const std::vector<glm::vec3> field(r.vertexCount(), glm::vec3(2.0f, 3.0f, 4.0f));
  const std::span<const glm::vec3> fields[] = {field, field};
  const Lightmap map = fillLightmap(r, fields, {.size = 32, .padding = 2});
  EXPECT_EQ(map.coveredTexels, 16u * 16u);
  EXPECT_EQ(map.paddedTexels, 20u * 20u - 16u * 16u);
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 32; ++x) {
      const bool inGutter = x >= 6 && x < 26 && y >= 6 && y < 26;
      const glm::vec3 want = inGutter ? glm::vec3(2.0f, 3.0f, 4.0f) : glm::vec3(0.0f);
      EXPECT_EQ(map.images[1][y * 32 + x], want) << x << "," << y;
      EXPECT_EQ(map.coverage[y * 32 + x] != 0, inGutter);
    }
  }
}

TEST(Lightmap, SeamsOfASmoothFieldAgreeAndABrokenChartIsFound) {
  const UvQuad box = atlasBox();
  const int size = 96;
  const UvRefinement r = refine(box, size);
  const TriangleMesh m = refinedMesh(r, box.mesh);
  std::vector<glm::vec3> field;
  for (const glm::vec3& p : m.positions) field.push_back(glm::vec3(3.0f) + p);
  const std::span<const glm::vec3> fields[] = {field};
  Lightmap map = fillLightmap(r, fields, {.size = size, .padding = 3});
  const SeamReport smooth = compareSeams(r, map.images[0], size, 8);
  EXPECT_GT(smooth.edges, 100u);
  EXPECT_LT(smooth.relativeRms, 0.01);
  // One chart's light made 20 % brighter: its four seams disagree.
  for (int y = 0; y < size / 2; ++y) {
    for (int x = 0; x < size / 3; ++x) map.images[0][y * size + x] *= 1.2f;
  }
  const SeamReport broken = compareSeams(r, map.images[0], size, 8);
  EXPECT_GT(broken.relativeRms, 0.05);
  EXPECT_GT(broken.worstRelative, 0.15);
}

TEST(Lightmap, OverlappingChartsAreCounted) {
  UvQuad q = quad();
  // The second triangle mapped onto the first's place.
  q.uv[3] = q.uv[0];
  q.uv[4] = q.uv[1];
  q.uv[5] = q.uv[2];
  const UvRefinement r = refine(q, 32);
  const std::vector<glm::vec3> field(r.vertexCount(), glm::vec3(1.0f));
  const std::span<const glm::vec3> fields[] = {field};
  const Lightmap map = fillLightmap(r, fields, {.size = 32, .padding = 0});
  EXPECT_GT(map.overlappingTexels, 400u);
}

}  // namespace
}  // namespace sss

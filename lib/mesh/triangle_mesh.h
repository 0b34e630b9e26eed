// An indexed triangle mesh with unit per-vertex normals, and the per-vertex quantities the
// diffusion sums need (vertex areas: Li & Guo's M(x_i)).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace sss {

struct TriangleMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // one unit normal per vertex (same size as positions)
  std::vector<glm::uvec3> triangles;

  std::size_t vertexCount() const { return positions.size(); }
  std::size_t triangleCount() const { return triangles.size(); }
};

// Area of each vertex's share of the surface: one third of the areas of its adjacent triangles
// (Li & Guo's M(x_i); a correction of their unspecified "area of the vertex"). The sum equals
// surfaceArea(mesh).
std::vector<float> vertexAreas(const TriangleMesh& mesh);
std::vector<float> vertexAreas(std::span<const glm::vec3> positions,
                               std::span<const glm::uvec3> triangles);

// Each vertex's share of the surface projected onto the plane perpendicular to its normal:
// sum over its triangles of area / 3 * max(0, n_triangle . n_vertex). The area a viewer looking
// down the vertex normal sees, so radiance along the normal is flux per this area per projected
// solid angle (on a coarse mesh the facets tilt from the vertex normal: 37 degrees on an
// icosahedron, whose projected areas are 0.79 of vertexAreas).
std::vector<float> projectedVertexAreas(const TriangleMesh& mesh);

// The hat-function average of a field linear on each triangle between the given vertex values:
// per vertex k, integral(f l_k) / integral(l_k) = sum over its triangles of A_t / 12 (2 f_k + f_a +
// f_b) over A_k (the consistent mass matrix over the lumped one). What a barycentric tally
// (pathtrace/light_tracer.h) returns for that field, so that per-vertex point values compare with
// a tally on equal terms on a coarse mesh, where the hat functions span much of the object.
// Vertices with a triangle whose normal is further than acos(minFacetCosine) from one of its
// corners' normals keep their value: at a fold (a slab's rim) the field across the triangle is two
// faces' and not the interpolation of the vertex values.
std::vector<glm::vec3> hatFunctionAverage(const TriangleMesh& mesh,
                                          std::span<const glm::vec3> values, double minFacetCosine);

// The facets around each vertex: the unit normals of its triangles and their shares of its area
// (summing to 1; facets of one plane merged), vertex v's at [begin[v], begin[v + 1]). What the
// surface around a vertex faces where its one normal is an average: on a box's edge the vertex
// normal points 45 degrees from both faces, and light on the faces is not light on that normal
// (lighting/facet_light.h). A facet normal is turned to its vertex normal's side (a face of
// inconsistent winding, or normals that disagree with the winding). A vertex whose facets all lie
// within acos(smoothCosine) of its normal gets its normal as its one facet (a smooth part, where
// the two differ in second order); elsewhere a facet within acos(mergeCosine) of a group's first
// joins the group, which takes their area-weighted normal (the default merges one plane's).
struct VertexFacets {
  std::vector<uint32_t> begin;  // vertexCount + 1 offsets
  std::vector<glm::vec3> normals;
  std::vector<float> shares;
};
VertexFacets vertexFacets(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                          std::span<const glm::uvec3> triangles, double smoothCosine = 1.0,
                          double mergeCosine = 1.0 - 1e-9);

// Total triangle area, accumulated in double.
double surfaceArea(const TriangleMesh& mesh);

// Signed volume enclosed by the triangles (divergence theorem, in double): positive when a closed
// mesh's triangles wind counter-clockwise seen from outside. Meaningless for open meshes.
double signedVolume(const TriangleMesh& mesh);

// Area-weighted vertex normals (the sum of the adjacent triangles' unnormalized cross products,
// normalized). Vertices without a non-degenerate triangle get (0, 0, 1).
std::vector<glm::vec3> computeVertexNormals(const TriangleMesh& mesh);

// Multiplies every position by `scale` (normals are unchanged): e.g. to millimetres.
void scalePositions(TriangleMesh& mesh, double scale);

}  // namespace sss

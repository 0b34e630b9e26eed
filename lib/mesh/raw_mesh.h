// What a mesh reader gives (openmesh_reader.h, ply_format.h) before load_mesh.h's cleanup, and
// the report of what the file held and what the cleanup changed.
#pragma once

#include <cstddef>
#include <initializer_list>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sss {

struct MeshReport {
  std::string format;                    // "ply-ascii", "ply-binary-le", "obj", "stl", ...
  std::size_t fileVertices = 0;          // as read, before cleanup
  std::size_t fileFaces = 0;             // polygons as read
  std::size_t triangulatedPolygons = 0;  // faces with more than three corners
  std::size_t droppedDegenerate = 0;     // repeated index or zero area
  std::size_t droppedDuplicate = 0;      // same vertex set as an earlier triangle
  std::size_t droppedUnreferenced = 0;   // vertices used by no remaining triangle
  std::size_t nonManifoldEdges = 0;      // edges with more than two triangles
  std::size_t misorientedEdges = 0;      // edges whose two triangles run the same direction
  std::size_t nonManifoldVertices = 0;   // vertices whose triangles form more than one fan
  std::size_t boundaryEdges = 0;         // edges with one triangle (0: the mesh is closed)
  std::size_t components = 0;            // edge-connected components
  bool normalsComputed = false;          // the file had no usable vertex normals
  bool orientationFlipped = false;       // closed, inside out: triangles flipped
  bool normalsNegated = false;           // file normals pointed against the winding: negated
  std::vector<std::string> warnings;     // human-readable, one line each, without the file name
};

// Raw mesh data as a reader produces it, before cleanup: polygons as flat index lists.
struct RawMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;     // empty, or one per position
  std::vector<unsigned> faceCorners;  // all polygons' vertex indices, concatenated
  std::vector<unsigned> faceSizes;    // corners per polygon

  void addFace(std::initializer_list<unsigned> corners) {
    faceCorners.insert(faceCorners.end(), corners);
    faceSizes.push_back(static_cast<unsigned>(corners.size()));
  }
};
}  // namespace sss

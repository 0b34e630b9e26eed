// A strict PLY reader (ascii, binary little and big endian), private to the mesh library.
//
// Format: Greg Turk's PLY ("ply", "format ...", "comment ...", "element NAME COUNT",
// "property TYPE NAME", "property list COUNT_TYPE TYPE NAME", "end_header"). Unlike OpenMesh's
// lenient reader, every count in the header is checked against the file size before anything
// is allocated, a file that ends early or holds a malformed number is an error, and indices
// are range-checked later by cleanMesh.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "mesh/raw_mesh.h"

namespace sss::ply {

// What the reader keeps: positions, normals (when nx, ny, nz are all present), every other
// scalar vertex property as float, the faces as flat index lists, and the comments.
struct PlyMesh {
  std::string format;                 // "ply-ascii", "ply-binary-le", "ply-binary-be"
  std::vector<std::string> comments;  // text after "comment ", in file order
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;                           // empty when absent
  std::map<std::string, std::vector<float>> vertexScalars;  // other scalar vertex properties
  std::vector<std::uint32_t> faceCorners;                   // all faces' indices, concatenated
  std::vector<std::uint32_t> faceSizes;                     // corners per face
  std::vector<std::string> warnings;
};

// Reads `path`; throws Error("<path>: <problem>").
PlyMesh readPly(const std::string& path);

// Moves ply's positions, normals and faces into a RawMesh for cleanMesh, and its format and
// warnings into report (replacing its warnings).
RawMesh takeMesh(PlyMesh& ply, MeshReport& report);

}  // namespace sss::ply

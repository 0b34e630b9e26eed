// OBJ, OFF, STL and OM through OpenMesh's readers into a raw face list, private to the mesh
// library. OpenMesh's own topology is bypassed (it would split non-manifold and duplicate faces
// apart silently); the counts that the formats state are checked against what was read.
#pragma once

#include <string>
#include <vector>

#include "mesh/raw_mesh.h"

namespace sss {

// `ext`: "obj", "off", "stl" or "om". Throws Error("<path>: <problem>").
RawMesh readWithOpenMesh(const std::string& path, const std::string& ext);

}  // namespace sss

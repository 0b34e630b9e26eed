// What a mesh file's header says it holds, read before the file is: for estimating up front the
// memory that loading and baking it will take (lib/bake/prepare_mesh.cpp). Not a validator: a
// header that cannot be read, or that declares more than the file size can hold, gives
// known = false and is left to the full reader's precise error.
#pragma once

#include <cstdint>
#include <string>

namespace sss {

struct DeclaredMeshCounts {
  bool known = false;  // the format has counts in its header, and they look consistent
  std::uint64_t vertices = 0;
  std::uint64_t faces = 0;  // polygons (each gives one triangle or more)
};

// PLY ("element vertex N", "element face N"), ASCII OFF (the counts line) and binary STL (its
// triangle count, when the file size matches it); OBJ, ASCII STL and OM give known = false.
// Reads at most the first 64 KiB; never throws.
DeclaredMeshCounts declaredMeshCounts(const std::string& path);

}  // namespace sss

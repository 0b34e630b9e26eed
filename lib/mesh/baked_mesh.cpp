#include "mesh/baked_mesh.h"

#include "core/file_extension.h"
#include "core/tool.h"
#include "mesh/baked_glb.h"

namespace sss {

void checkBakedMeshPath(const std::string& path) {
  const std::string extension = lowerExtension(path);
  if (extension != "ply" && extension != "glb") {
    throw UsageError(escapeControl(path) + ": the output's extension must be .ply or .glb (" +
                     (extension.empty() ? "none" : "." + escapeControl(extension)) + " given)");
  }
}

void writeBakedMesh(const std::string& path, const BakedMesh& baked,
                    const std::string& reportJson) {
  checkBakedMeshPath(path);
  if (lowerExtension(path) == "glb") {
    writeBakedGlb(path, baked, reportJson);
  } else {
    writeBakedPly(path, baked);
  }
}

BakedPlyContents readBakedMesh(const std::string& path) {
  return lowerExtension(path) == "glb" ? readBakedGlb(path) : readBakedPly(path);
}

}  // namespace sss

#include "mesh/baked_mesh.h"

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/file_extension.h"
#include "core/tool.h"
#include "mesh/baked_glb.h"
#include "mesh/glb_chunks.h"

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

namespace {

// Whether a GLB is one sss-bake wrote (asset.extras.sss); a GLB that cannot be read is left to
// the scene reader's error.
bool isBakedGlb(const std::string& path) {
  try {
    const nlohmann::json json = nlohmann::json::parse(readGlbChunks(path).json, nullptr, false);
    const auto asset = json.is_object() ? json.find("asset") : json.end();
    if (asset == json.end() || !asset->is_object()) return false;
    const auto extras = asset->find("extras");
    return extras != asset->end() && extras->is_object() && extras->contains("sss");
  } catch (const Error&) {
    return false;
  }
}

}  // namespace

BakedPlyContents readBakedMesh(const std::string& path) {
  const std::string extension = lowerExtension(path);
  if (extension == "glb" && isBakedGlb(path)) return readBakedGlb(path);
  return readBakedPly(path);  // a PLY, or any other mesh (a glTF scene) with nothing baked
}

}  // namespace sss

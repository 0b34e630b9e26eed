// The baked-mesh formats, chosen by the output's extension: .ply (mesh/baked_ply.h, what
// sss-render reads fastest and MeshLab shows) and .glb (mesh/baked_glb.h, glTF 2.0 binary for
// engines and DCC tools). Any other extension is a usage error, found before the bake runs.
#pragma once

#include <string>

#include "mesh/baked_ply.h"

namespace sss {

// Throws UsageError (core/tool.h) when `path`'s extension names no baked-mesh writer.
void checkBakedMeshPath(const std::string& path);

// Writes `baked` in the format `path`'s extension names; `reportJson` (the bake's JSON report,
// or empty) is embedded where the format has room for it (the GLB's extras).
void writeBakedMesh(const std::string& path, const BakedMesh& baked,
                    const std::string& reportJson = "");

// Reads a baked GLB (a .glb that sss-bake wrote: asset.extras.sss) or PLY; any other mesh file,
// a glTF scene included, loads as readBakedPly does (nothing baked; a glTF's unit, metres, is
// recorded).
BakedPlyContents readBakedMesh(const std::string& path);

}  // namespace sss

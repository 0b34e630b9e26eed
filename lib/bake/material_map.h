// --material-map: a glTF's material names mapped to the bake's material presets
// (material/material.h), for assets whose parts are different materials. Given inline
// ("Skin=skin1,Teeth=marble") or as a JSON file ({"Skin": "skin1", "Teeth": "marble"}; a name
// holding ',' or '=' needs the file). A part's material key (mesh/mesh_parts.h) is the glTF
// material's name, "#<index>" when it has none, or "" for a primitive without a material; parts
// the map does not name take the bake's material (-m).
//
// Parts of different materials bake as one object (bake/material_parts.h): light crosses between
// them, each vertex taking the light its own material's transport gives.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "material/material.h"
#include "mesh/mesh_parts.h"

namespace sss {

// How light crosses between parts of different materials (bake/material_parts.h): the border
// rule (the lower of the receiver's rule and the symmetric kernel, per vertex and channel), and
// the two alone (the study's comparison).
enum class MaterialRule { Border, Symmetric, Receiver };

struct MaterialMap {
  std::vector<std::pair<std::string, Material>> entries;  // material key -> material
  bool empty() const { return entries.empty(); }
};

// Parses "name=preset,..." or, when `spec` ends in .json (any case), the JSON file it names (an
// object of names to preset names). Throws Error naming the entry or the file.
MaterialMap parseMaterialMap(const std::string& spec);

// The materials the parts of `parts` bake with, each once, in the order of first use:
// `fallback` for every part the map does not name, one material for a mesh without parts.
struct PartMaterials {
  std::vector<Material> materials;
  std::vector<std::uint32_t> partMaterial;  // per part of MeshParts::parts: into materials
  bool single() const { return materials.size() == 1; }
};

// Throws Error("<path>: ...") when the map names a material no part has (a misspelt name would
// bake the wrong material), and when the parts' materials differ in eta (the bake has no
// refraction between them).
PartMaterials materialsForParts(const std::string& path, const MaterialMap& map,
                                const MeshParts& parts, const Material& fallback);

}  // namespace sss

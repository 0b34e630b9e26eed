// --material-map: a glTF's material names mapped to the bake's material presets
// (material/material.h), for assets whose parts are different materials. Given inline
// ("Skin=skin1,Teeth=marble") or as a JSON file ({"Skin": "skin1", "Teeth": "marble"}; a name
// holding ',' or '=' needs the file). A part's material key (mesh/mesh_parts.h) is the glTF
// material's name, "#<index>" when it has none, or "" for a primitive without a material; parts
// the map does not name take the bake's material (-m).
//
// The bake transports light through one material: the diffusion profile, the escape energy and
// the far field are the object's. A map that gives the parts more than one distinct material is
// refused ("not yet supported") rather than baked as if the object were one of them; one that
// gives every part the same material bakes with it.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "material/material.h"
#include "mesh/mesh_parts.h"

namespace sss {

struct MaterialMap {
  std::vector<std::pair<std::string, Material>> entries;  // material key -> material
  bool empty() const { return entries.empty(); }
};

// Parses "name=preset,..." or, when `spec` ends in .json (any case), the JSON file it names (an
// object of names to preset names). Throws Error naming the entry or the file.
MaterialMap parseMaterialMap(const std::string& spec);

// The one material the parts of `parts` bake with: `fallback` for every part the map does not
// name. Throws Error("<path>: ...") naming the parts and materials when they are more than one,
// and when the map names a material no part has (a misspelt name would bake the wrong material).
Material materialForParts(const std::string& path, const MaterialMap& map, const MeshParts& parts,
                          const Material& fallback);

}  // namespace sss

// A glTF 2.0 document's materials (section 3.9) as mesh/surface_material.h keeps them: the
// metallic-roughness parameters the bake does not replace, the normal and occlusion maps, alpha,
// and the PNG/JPEG images their textures use (section 3.8), read from a bufferView, a data: URI
// or a file beside the asset.
// The JSON is read as strictly as the rest of the document (gltf_document.h): an index out of
// range, a value of the wrong type or out of its range (factors in [0, 1], sampler enums, alpha
// modes) is an Error naming the file. What is valid but cannot be kept is listed in the
// material's `dropped` instead: textures on TEXCOORD_1 or with KHR_texture_transform, images
// that are not PNG or JPEG or cannot be read (a missing texture does not stop a bake), and
// material extensions (the bake writes its own).
#pragma once

#include "mesh/gltf_document.h"
#include "mesh/surface_material.h"

namespace sss {

SurfaceMaterials readSurfaceMaterials(const gltf::Document& doc);

}  // namespace sss

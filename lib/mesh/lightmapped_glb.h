// A UV-lightmapped asset as glTF 2.0 binary (GLB), for engines and stock viewers (three.js,
// Babylon.js, Blender, model-viewer): the baked light is the material's emission, the surface's
// reflection is left to the viewer's own image-based lighting. Per node of the source scene (its
// name and world transform; the scene graph flattened), one mesh with one primitive per part:
//   POSITION, NORMAL  float VEC3 in the node's frame (the node scales the file's unit to metres)
//   TEXCOORD_0        float VEC2, the source's
//   indices           unsigned int
// Vertices are split where a welded vertex has several texture coordinates (a UV seam). A material
// per source material the parts use (one for parts without; the glTF 2.0 specification, Appendix
// B, and the extensions named):
//   baseColorFactor 0 (black), metallic 0: the diffuse light is all in the emission (the source's
//                     alpha and, for MASK and BLEND, its base colour texture are kept for alpha)
//   roughnessFactor   the source's (0 without a source material), with its roughness texture
//   normalTexture, occlusionTexture, alphaMode, alphaCutoff, doubleSided  the source's
//   emissiveTexture   the lightmap, 8-bit sRGB PNG (the radiance over emissiveStrength)
//   KHR_materials_emissive_strength  emissiveStrength: the lightmap's scale, in the
//                     environment's radiance units (the viewer's background is in the same units)
//   KHR_materials_clearcoat  factor coatWeight, the source's roughness and normal map: a
//                     dielectric coat (index 1.5) that reflects the environment with its weighted
//                     Fresnel factor and darkens the emission beneath it by the same
//                     (KHR_materials_clearcoat, "Emission"): the view dependence sss-render
//                     draws, (1 - F_r(mu_o)) times the radiance along the normal plus
//                     F_r(mu_o) L_env, with the weight matching the material's F_r
//   KHR_materials_specular  specularFactor 0: no second reflection from the base layer
//   KHR_materials_ior, KHR_materials_volume  the medium's index, and the diffuse light's
//                     attenuation exp(-sigma_tr d) as attenuationColor over attenuationDistance
//                     with the thickness: descriptive (no transmission extension turns them on)
// The kept textures' images are copied as the source holds them (PNG or JPEG), with their
// samplers.
// asset.extras.sss: format, position_unit "m", mm_per_unit of the source, the material, the
// emission's description and the bake's report.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "mesh/mesh_parts.h"
#include "mesh/triangle_mesh.h"

namespace sss {

// The coat's index (KHR_materials_clearcoat fixes 1.5) and its reflectance along the normal,
// ((1.5 - 1) / (1.5 + 1))^2 = 0.04; viewers use Schlick's approximation from there.
inline constexpr double kCoatIor = 1.5;
inline constexpr double kCoatNormalReflectance = 0.04;

struct LightmappedAsset {
  TriangleMesh mesh;     // welded, in the file's units
  double mmPerUnit = 0;  // the file's unit
  MeshParts parts;       // the parts, each triangle's part, TEXCOORD_0 (3 per triangle), materials
  std::string emissivePng;      // the lightmap's PNG bytes (sRGB, row 0 at v = 0)
  double emissiveStrength = 1;  // linear emission = emissiveStrength * decoded texel
  double coatWeight = 1;        // clearcoatFactor: reflectance c F_Schlick(mu_o, 1.5)
  // A medium: its name and coefficients per mm.
  struct Medium {
    std::string name;
    glm::dvec3 sigmaAPerMm{0.0}, sigmaSPrimePerMm{0.0};
  };
  Medium medium;
  // Per part (parts.parts) where the parts are of different media (a bake of several materials):
  // each one's, written in its material's KHR_materials_volume; empty: every part `medium`.
  std::vector<Medium> partMedia;
  double eta = 1.0;        // relative index, of every part
  double thicknessM = 0;   // a typical thickness of the object in metres (KHR_materials_volume)
  std::string extrasJson;  // asset.extras.sss (a JSON object)
};

// Writes the asset through writeFileAtomically. Throws Error naming `path`.
void writeLightmappedGlb(const std::string& path, const LightmappedAsset& asset);

// What the written file will not keep of the source materials the parts use, a line each:
// "material 'NAME': normalTexture (TEXCOORD_1) not kept".
std::vector<std::string> droppedSurfaceNotes(const LightmappedAsset& asset);

}  // namespace sss

// The baked mesh as glTF 2.0 binary (GLB), for engines and DCC tools that do not import our PLY
// (Unreal, Unity) or drop its float properties (Blender 3.4). One scene, one node, one mesh with
// one triangle primitive:
//   POSITION     float VEC3, metres (glTF's unit: positions * mm_per_unit / 1000)
//   NORMAL       float VEC3
//   COLOR_0      float VEC3, linear RGB in [0, 1]: the radiance along the normal that sss-render
//                shows (exit term, normalized exit model: B F_t(1, eta) / (pi (1 - 2 C_1(eta))),
//                optics/fresnel.h) times the bake's exposure (previewScaleFor: the PLY's
//                preview_scale). Values above 1 are clamped with a warning naming how many.
//   _IRRADIANCE  float VEC3, E per vertex as baked (custom attribute: leading underscore)
//   _EXITANCE    float VEC3, B per vertex as baked
//   _TRANSFER_EXPONENT, _TRANSFER_LOW_<j>, _TRANSFER_EXPONENT_HIGH, _TRANSFER_HIGH_<j>
//                a relightable bake's transfer (baked_ply.h's transfer_scale, transfer<k>,
//                transfer_scale_high): the scales as exponents in BYTE VEC4s, the steps packed
//                in normalized SHORT (bands 0-3) and BYTE (bands 4-8) VEC4s
//                (quantized_transfer.h, docs/relighting.md)
//   _RADIANCE_GAIN, _EXITANCE_PER_RADIANCE, _ESCAPE_PROBABILITY
//                float VEC3, its other values (radiance_gain, exitance_per_radiance,
//                escape_probability), with extras.sss.relight = {"order": N, "transport": "..."}
//   indices      unsigned int
// and a material whose base colour is the vertex colour (baseColorFactor 1, metallic 0) with
// KHR_materials_unlit, so that a viewer shows COLOR_0 as is. asset.extras.sss holds what the PLY
// header holds (format, mm_per_unit of the source, material, exposure, checked, unscattered,
// comments) plus the colour's scale and exit model and the bake's JSON report:
//   {"format": 1, "position_unit": "m", "mm_per_unit": 0.3,
//    "material": {"name": "marble", "sigma_a_per_mm": [..], "sigma_s_prime_per_mm": [..],
//                 "eta": 1.3},
//    "color": {"exposure": 0.8, "exit_model": "normalized", "radiance_per_exitance": 0.61,
//              "scale": 0.49, "clamped_vertices": 0},          (COLOR_0 = min(1, scale * B))
//    "checked": true, "unscattered": false, "comments": ["bake method=..."], "report": {...}}
// The layout follows the glTF 2.0 specification, section 4.4 (GLB): a 12-byte header, a JSON
// chunk padded with spaces and a BIN chunk padded with zeros, both 4-byte aligned.
#pragma once

#include <string>

#include "mesh/baked_ply.h"

namespace sss {

// Writes `baked` (checkBakedMesh) through AtomicOutput; `reportJson` (JSON text, or empty) goes
// into extras.sss.report. Warns when COLOR_0 clamps. Throws Error.
void writeBakedGlb(const std::string& path, const BakedMesh& baked,
                   const std::string& reportJson = "");

// Reads a GLB back: the attributes bit-exactly, positions in metres (baked.mmPerUnit = 1000), the
// material and flags from extras.sss when present (a GLB from elsewhere with one triangle
// primitive loads as a plain mesh). Strict: every declared length, offset and count is checked
// against the file before anything is allocated; the mesh then goes through cleanMesh like every
// other reader. Throws Error "<path>: <problem>".
BakedPlyContents readBakedGlb(const std::string& path);

}  // namespace sss

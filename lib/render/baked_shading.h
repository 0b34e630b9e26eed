// What the renderer needs from a baked mesh (sss-bake's PLY, read by mesh/baked_ply.h), computed
// before drawing: the material's shading parameters (eta, the exit model's scale, the brdf mode's
// albedo), whether to cull back faces, and the render mesh with the mode's per-vertex values.
#pragma once

#include <optional>
#include <string>

#include <glm/vec3.hpp>

#include "core/enum_names.h"
#include "mesh/baked_ply.h"
#include "render/renderer.h"

namespace sss {

// How exitance B leaves the surface as radiance (ShadingOptions::exitScale): normalized,
// L = B F_t / (pi (1 - 2 C_1)), whose flux is B (d'Eon 2012, optics/fresnel.h); jensen,
// L = B F_t / pi (Jensen et al. 2001).
enum class ExitModel { Normalized, Jensen };
inline constexpr EnumNames<ExitModel, 2> kExitModelNames{
    "exit model", {{{ExitModel::Normalized, "normalized"}, {ExitModel::Jensen, "jensen"}}}};

// Back-face culling. Auto culls only closed, consistently wound meshes: culling would punch holes
// where a scan's triangles are wound the wrong way.
enum class CullMode { Auto, Back, None };
inline constexpr EnumNames<CullMode, 3> kCullModeNames{
    "cull mode", {{{CullMode::Auto, "auto"}, {CullMode::Back, "back"}, {CullMode::None, "none"}}}};

// Used when neither the file (no material recorded) nor the caller gives a value.
inline constexpr float kFallbackEta = 1.3f;
inline constexpr float kFallbackAlbedo = 0.8f;

// What the caller asks for; an unset value comes from the bake.
struct ShadingRequest {
  ShadingMode mode = ShadingMode::Sss;
  ExitModel exitModel = ExitModel::Normalized;
  CullMode cull = CullMode::Auto;
  std::optional<float> eta;         // default: the material's, else kFallbackEta
  std::optional<glm::vec3> albedo;  // brdf; default: the material's half-space albedo
                                    // (so that B = R_d E on flat, uniformly lit regions), else
                                    // kFallbackAlbedo
};

// The material part of ShadingOptions.
struct ShadingParameters {
  float eta = kFallbackEta;
  float exitScale = 0.0f;
  glm::vec3 albedo = glm::vec3(1.0f);  // set in the brdf mode only
  bool cullBackFaces = false;
  bool etaIsFallback = false;     // sss mode, no material in the file, none asked
  bool albedoIsFallback = false;  // brdf mode, idem
};

ShadingParameters shadingFor(const BakedPlyContents& contents, const ShadingRequest& request);

// The per-vertex properties `mode` draws that the file lacks ("exitance_r, exitance_g,
// exitance_b" for sss, the irradiance ones for the irradiance view); empty when none is missing.
std::string missingBakedValues(const BakedPlyContents& contents, ShadingMode mode);

// Positions, normals, triangles, and the values `mode` draws: exitance (sss), irradiance
// (irradiance view), none otherwise.
RenderMesh renderMeshFor(const BakedMesh& baked, ShadingMode mode);

}  // namespace sss

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

// How exitance B leaves the surface as radiance (ShadingOptions::exitScale, exitWeight):
// auto (default), B through the exit lobe the bake's traced far field measured
// (optics/exit_lobe.h, the slope its light paths measured; the file's far_exit_slope), the
// normalized model where the file has no far field;
// normalized, L = B F_t / (pi (1 - 2 C_1)) for all of B, whose flux is B (d'Eon 2012,
// optics/fresnel.h); calibrated, the same times w(mu), the material's directional albedo weight
// (material/directional_albedo_weight.h: the half-space Monte Carlo's angular shape across
// albedo, flux-preserving), exact for a half-space under even light where normalized is 5-12 %
// high along the normal at alpha' <= 0.75, but further from the reference on the study's finite
// objects (docs/physics.md, "Where we correct the paper"; docs/accuracy.md, "Under a sun");
// jensen, L = B F_t / pi (Jensen et al. 2001).
enum class ExitModel { Auto, Normalized, Calibrated, Jensen };
inline constexpr EnumNames<ExitModel, 4> kExitModelNames{"exit model",
                                                         {{{ExitModel::Auto, "auto"},
                                                           {ExitModel::Normalized, "normalized"},
                                                           {ExitModel::Calibrated, "calibrated"},
                                                           {ExitModel::Jensen, "jensen"}}}};

// Back-face culling. Auto culls only closed, consistently wound meshes: culling would punch holes
// where a scan's triangles are wound the wrong way.
enum class CullMode { Auto, Back, None };
inline constexpr EnumNames<CullMode, 3> kCullModeNames{
    "cull mode", {{{CullMode::Auto, "auto"}, {CullMode::Back, "back"}, {CullMode::None, "none"}}}};

// The light that crosses the object without scattering (renderer.h, ShadingOptions::
// unscatteredSigmaT), in the sss mode on a closed mesh (culled back faces) whose file records its
// material and units (sigma_t = sigma_a + sigma_s' per mesh unit: g = 0, as the bake's light
// tracers have it). Auto: where the bake traced it (BakedMesh::unscatteredTraced; the back faces'
// pass and the per-pixel march cost 2.5x per frame on llvmpipe: docs/tools/sss-render.md,
// "Unscattered light"); on: wherever it can.
enum class UnscatteredDrawing { Auto, On, Off };
inline constexpr EnumNames<UnscatteredDrawing, 3> kUnscatteredDrawingNames{
    "unscattered light",
    {{{UnscatteredDrawing::Auto, "auto"},
      {UnscatteredDrawing::On, "on"},
      {UnscatteredDrawing::Off, "off"}}}};

// Used when neither the file (no material recorded) nor the caller gives a value.
inline constexpr float kFallbackEta = 1.3f;
inline constexpr float kFallbackAlbedo = 0.8f;

// What the caller asks for; an unset value comes from the bake.
struct ShadingRequest {
  ShadingMode mode = ShadingMode::Sss;
  ExitModel exitModel = ExitModel::Auto;
  CullMode cull = CullMode::Auto;
  UnscatteredDrawing unscattered = UnscatteredDrawing::Auto;
  std::optional<float> eta;         // default: the material's, else kFallbackEta
  std::optional<glm::vec3> albedo;  // brdf; default: the material's half-space albedo
                                    // (so that B = R_d E on flat, uniformly lit regions), else
                                    // kFallbackAlbedo
};

// The material part of ShadingOptions.
struct ShadingParameters {
  float eta = kFallbackEta;
  float exitScale = 0.0f;
  ExitWeightTable exitWeight = flatExitWeight();  // calibrated: the material's w at mu = k / 16
  bool exitLobe = false;  // auto with exit slopes in the file: B through their exit lobe
  float lobeMoment0 = 1.0f, lobeMoment1 = 0.0f;  // with exitLobe: ShadingOptions' (renderer.h)
  glm::vec3 albedo = glm::vec3(1.0f);            // set in the brdf mode only
  bool cullBackFaces = false;
  // Per mesh unit, where asked and the file has a material and units; 0: not drawn.
  glm::vec3 unscatteredSigmaT = glm::vec3(0.0f);
  bool etaIsFallback = false;     // sss mode, no material in the file, none asked
  bool albedoIsFallback = false;  // brdf mode, idem
};

ShadingParameters shadingFor(const BakedPlyContents& contents, const ShadingRequest& request);
// The calibrated exit model's weights for a baked material at eta.
ExitWeightTable exitWeightTable(const BakedMesh& baked, float eta);

// The per-vertex properties `mode` draws that the file lacks ("exitance_r, exitance_g,
// exitance_b" for sss, the irradiance ones for the irradiance view); empty when none is missing.
std::string missingBakedValues(const BakedPlyContents& contents, ShadingMode mode);

// Positions, normals, triangles, and the values `mode` draws: exitance (sss; with exitLobe, the
// exit slopes too), irradiance (irradiance view), none otherwise.
RenderMesh renderMeshFor(const BakedMesh& baked, ShadingMode mode, bool exitLobe = false);

}  // namespace sss

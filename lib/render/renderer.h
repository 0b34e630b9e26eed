// Draws a baked mesh in an environment into an offscreen framebuffer: the surface shading of
// shaders/surface.frag, the environment behind it, MSAA resolved by a blit, read back as an
// image. One vertex buffer with interleaved attributes, one index buffer (and for a relit mesh one
// storage buffer with its transfer), one draw call; nothing is uploaded per frame, so --frames
// measures the drawing alone.
#pragma once

#include <array>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/enum_names.h"
#include "render/camera.h"
#include "render/shader_sources.h"

namespace sss {

// The exit model's angular weight w_c(mu) at mu = k / 16 (shaders/surface.vert interpolates it).
inline constexpr int kExitWeightNodes = 17;
using ExitWeightTable = std::array<glm::vec3, kExitWeightNodes>;
inline ExitWeightTable flatExitWeight() {
  ExitWeightTable t;
  t.fill(glm::vec3(1.0f));
  return t;
}

class Cubemap;

// World-space triangles with unit vertex normals (CCW front faces) and one value per vertex:
// exitance B (sss), irradiance E (irradiance view); brdf and normals ignore it. exitSlopes (sss):
// the slope of the exit lobe B leaves with, which the bake's far field measured
// (optics/exit_lobe.h); empty: 0, the exit model alone.
// Relit in the vertex shader (ShadingOptions::relightCoefficients K > 0; bake/relight.h,
// RelitSplit): B = max(sum_k T_k L_k + value, 0) g b, with relightTransfer T at [vertex * K + k]
// and exitanceGain g b per vertex, L_k the renderer's smooth light (Renderer::setSmoothLight),
// and the values then the rest of B before g (the compact lights and the bounces; empty: none).
struct RenderMesh {
  std::vector<glm::vec3> positions, normals, values, exitSlopes;
  std::vector<uint32_t> indices;  // three per triangle
  std::vector<glm::vec3> relightTransfer, exitanceGain;
};

// sss: the baked exitance B through the exit model, plus Fresnel reflections; brdf: a Lambertian
// surface of the material's albedo lit by the transmitted irradiance cubemap (no transport); the
// baked irradiance E and the normals, for inspection.
enum class ShadingMode { Sss, Brdf, Irradiance, Normals };
inline constexpr EnumNames<ShadingMode, 4> kShadingModeNames{
    "shading mode",
    {{{ShadingMode::Sss, "sss"},
      {ShadingMode::Brdf, "brdf"},
      {ShadingMode::Irradiance, "irradiance"},
      {ShadingMode::Normals, "normals"}}}};
// Exact dielectric Fresnel or Schlick 1994's approximation (optics/fresnel.h).
enum class FresnelModel { Exact, Schlick };
inline constexpr EnumNames<FresnelModel, 2> kFresnelModelNames{
    "Fresnel model", {{{FresnelModel::Exact, "exact"}, {FresnelModel::Schlick, "schlick"}}}};
// Display transform after exposure: none (clamped), Reinhard et al. 2002's x / (1 + x), or the
// ACES filmic curve (Narkowicz 2015's fit; shaders/common.glsl).
enum class Tonemap { None, Reinhard, Aces };
inline constexpr EnumNames<Tonemap, 3> kTonemapNames{
    "tonemap",
    {{{Tonemap::None, "none"}, {Tonemap::Reinhard, "reinhard"}, {Tonemap::Aces, "aces"}}}};

struct ShadingOptions {
  ShadingMode mode = ShadingMode::Sss;
  FresnelModel fresnel = FresnelModel::Exact;
  float eta = 1.3f;
  // Radiance leaving at normal incidence per unit exitance, before F_t: 1 / (pi (1 - 2 C_1))
  // for the normalized exit model (exitRadianceScale), 1 / pi for Jensen et al.'s.
  float exitScale = 0.31830988f;
  // w_c(mu) at mu = k / 16 multiplying the exit term (ExitModel::Calibrated); all 1 otherwise.
  ExitWeightTable exitWeight = flatExitWeight();
  // The exit lobe's moments A_0, A_1 at eta (optics/exit_lobe.h) for a mesh with exit slopes k,
  // whose radiance is exitScale B F_t (1 + k mu_i) A_0 / (A_0 + k A_1) (exitScale that of the
  // normalized model, 1 / (pi A_0)).
  float lobeMoment0 = 1.0f, lobeMoment1 = 0.0f;
  // Set: the paper's constant mix(base, reflection, f) instead of the Fresnel-weighted sum.
  std::optional<float> reflectFactor;
  glm::vec3 albedo = glm::vec3(1.0f);  // brdf: total diffuse reflectance of the material
  float exposureEv = 0.0f;
  Tonemap tonemap = Tonemap::Aces;
  // Set: a flat background, stored as given (display values, not tonemapped); else the
  // environment.
  std::optional<glm::vec3> backgroundColor;
  // Cull back faces (closed, consistently CCW meshes); off shows both sides.
  bool cullBackFaces = true;
  // sss with culled back faces: the extinction sigma_t = sigma_a + sigma_s per mesh unit of the
  // light that crosses the object unscattered (shaders/surface.frag;
  // transport/unscattered_light.h), drawn where > 0 in some channel. A pass over the back faces'
  // depth shows where each refracted view ray leaves (shaders/surface.frag marches it).
  glm::vec3 unscatteredSigmaT = glm::vec3(0.0f);
  // sss: > 0, the SH coefficients (order + 1)^2 of a relightable bake's transfer, relit in the
  // vertex shader (RenderMesh); 0: B as given.
  int relightCoefficients = 0;
  bool drawsUnscattered() const;
  // A relit mesh: sss with relightCoefficients > 0.
  bool relights() const;
};

struct FrameOptions {
  int width = 1024, height = 1024;
  int samples = 4;      // MSAA samples; 1 = none
  bool linear = false;  // float framebuffer with linear values (.exr) instead of sRGB 8 bit
};

// Read back, top row first, RGB.
struct RenderedImage {
  int width = 0, height = 0;
  bool linear = false;
  std::vector<float> linearRgb;  // when linear
  std::vector<uint8_t> srgb8;    // otherwise
};

struct FrameTimings {
  int frames = 0;
  // Per frame: draw + resolve + glFinish, by the wall clock.
  double medianWallMs = 0, minWallMs = 0, maxWallMs = 0;
  // Per frame by GL_TIME_ELAPSED queries; not a measure of CPU work on software renderers.
  double medianGpuMs = 0;
  // All frames queued, one glFinish at the end, divided by the count.
  double pipelinedMs = 0;
  // Process CPU time (every thread) per frame over the glFinish-per-frame run: on a software
  // renderer the work itself, independent of what else the machine runs.
  double cpuMs = 0;
  double fps() const { return medianWallMs > 0 ? 1000.0 / medianWallMs : 0.0; }
};

// The bytes of a relit mesh's storage buffer (RenderMesh): per vertex g b and `coefficients`
// transfer entries, 3 floats each. A GL reads it only up to GlContext::maxVertexStorageBytes.
std::size_t relightStorageBytes(std::size_t vertices, std::size_t coefficients);

// Needs a current GL 4.5 context (GlContext) for its whole life.
class Renderer {
 public:
  // Compiles the program variant for these options; throws Error with the GLSL log.
  Renderer(const ShaderSources& shaders, const FrameOptions& frame, const ShadingOptions& shading);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  void setMesh(const RenderMesh& mesh);
  // The mesh's values replaced (RenderMesh::values: one per vertex, or empty for 0), the rest of
  // it kept: a relit mesh's rest of B under a new light.
  void setValues(const std::vector<glm::vec3>& values);
  // radiance: reflections and background; irradiance: the brdf mode's E(n) (may be null in
  // other modes). Faces are uploaded as they are (GL orientation), RGB16F with mipmaps.
  void setEnvironment(const Cubemap& radiance, const Cubemap* irradiance);
  void setCamera(const Camera& camera);
  // The smooth light's SH coefficients L_k of a relit mesh (relightCoefficients of them).
  void setSmoothLight(const std::vector<glm::vec3>& coefficients);

  // Draws one frame into the resolved framebuffer (no wait).
  void draw();
  RenderedImage readBack();
  // `warmup` untimed frames, then `frames` timed ones.
  FrameTimings timeFrames(int frames, int warmup = 3);

 private:
  void createBackDepthPass(const ShaderSources& shaders, const std::string& defines);
  void drawBackDepth();
  struct Gl;
  Gl* gl_;
  FrameOptions frame_;
  ShadingOptions shading_;
  Camera camera_;
  std::size_t indexCount_ = 0, vertexCount_ = 0;
};

}  // namespace sss

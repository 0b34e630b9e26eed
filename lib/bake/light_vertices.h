// Bake stage 3: the transmitted irradiance E per vertex (Li & Guo Eq. 6 with the exact Fresnel
// transmittance): the irradiance cubemap (lib/irradiance, Li & Guo Eq. 12) looked up at the
// vertex normal, or Embree visibility rays that add the mesh's own shadows (visibility.h), their
// count chosen from the error budget by the pilot's noise model (visibility_noise_model.h).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "bake/bake_settings.h"
#include "core/run_context.h"
#include "irradiance/irradiance.h"
#include "lighting/visibility.h"
#include "lighting/visibility_noise_model.h"

namespace sss {

class Cubemap;           // envmap/cubemap.h
class DiffusionProfile;  // material/diffusion_profile.h
struct TriangleMesh;     // mesh/triangle_mesh.h

struct LightingInput {
  const TriangleMesh& meshMm;
  std::span<const float> areasMm2;
  const Cubemap& radiance;
  const DiffusionProfile& profile;  // weights the visibility noise model
  float eta = 1.3f;
  // Rays: also E_w, the irradiance weighted by the directional entry (not owned; null: none).
  // The cubemap lookup (mode none) has no per-direction samples to weight: E_w = E there.
  const DirectionalAlbedoWeight* entry = nullptr;
  VisibilityMode mode = VisibilityMode::Rays;
  int samples = 0;                // rays per vertex; 0: auto, from visibilityBudget
  double visibilityBudget = 0.0;  // auto samples: the noise in B the rays may leave
  double visibilityShare = 0.0;   // the same as a share of the tolerance (for the report)
  double tolerance = 0.01;        // the irradiance cubemap's (mode none)
  // Rays: keep the cosine rays that meet the mesh for the bounces' gather when there are at most
  // this many per vertex (VisibilityOptions::keepCosineHitsUpTo); 0: never.
  int keepCosineHitsUpTo = 0;
  RunContext run;
  // Rays: the mesh's ray scene where the caller has one (VisibilityOptions::scene); null: built.
  const TriangleScene* rayScene = nullptr;
};

// Mode none: how the irradiance cubemap was made.
struct CubemapLightingReport {
  IrradianceMethod method = IrradianceMethod::Brute;
  int faceSize = 0;
  std::string reason;
};

// Mode rays: what the rays cost and how many were chosen.
struct RayLightingReport {
  int samples = 0;
  int samplesRequested = 0;  // 0: auto
  std::string samplesReason;
  uint64_t seed = 1;
  VisibilityReport visibility;  // rays, occlusion, timings, the pilot
  VisibilityNoiseModel noiseModel;
  double noiseModelSeconds = 0.0;
  double irradianceError = 0.0;  // predicted relative RMS noise of E itself
  double budget = 0.0;           // the visibility budget (auto), else the whole tolerance
};

struct LightingReport {
  VisibilityMode mode = VisibilityMode::Rays;
  EntryModel entry = EntryModel::Diffuse;  // what the transport's irradiance used
  // Predicted relative RMS error of B from E's error (cubemap lookup or ray noise).
  double estimatedError = 0.0;
  CubemapLightingReport cubemap;  // mode none
  RayLightingReport rays;         // mode rays
  double seconds = 0.0;
};

struct VertexLighting {
  std::vector<glm::vec3> irradiance;     // E per vertex
  std::vector<glm::vec3> entryWeighted;  // E_w per vertex (LightingInput::entry), else empty
  // What the transport sums: E_w where there is one, else E.
  const std::vector<glm::vec3>& transportIrradiance() const {
    return entryWeighted.empty() ? irradiance : entryWeighted;
  }
  CosineHits cosineHits;  // per LightingInput::keepCosineHitsUpTo, else empty
  LightingReport report;
};

VertexLighting lightVertices(const LightingInput& in);

}  // namespace sss

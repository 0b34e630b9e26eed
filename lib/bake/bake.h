// The sss-bake pipeline: mesh + environment + material -> per-vertex transmitted irradiance E
// (Eq. 6, with or without the mesh's own shadows) and exitance B (Eq. 7, a diffusion method, or
// the Monte Carlo reference), ready for writeBakedPly.
//
// Stages, each timed: load and clean the mesh (lib/mesh), scale it to millimetres, load the
// environment as a radiance cubemap (lib/envmap), the energy model (finite_object_energy.h:
// escape walks, which also settle the "auto" profile), E per vertex (visibility "none": the
// irradiance cubemap of lib/irradiance computed with the material's eta, looked up at the vertex
// normal; "rays": visibility.h), then B (lib/bake/diffusion.h with a profile of lib/material and
// the energy model, or lib/pathtrace). Every input is validated before the first expensive stage.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "bake/visibility.h"

#include "material/material.h"
#include "mesh/baked_ply.h"

namespace sss {

class DiffusionProfile;  // material/diffusion_profile.h

enum class VisibilityMode { None, Rays };
// "none" or "rays"; throws Error otherwise.
VisibilityMode parseVisibilityMode(const std::string& name);

struct BakeSettings {
  std::string meshPath;
  std::string environment;  // an environment file, or "sky" / "sky:<spec>" (loadEnvironment)
  Material material;        // validated by bake()
  double mmPerUnit = 0.0;   // millimetres per mesh unit (> 0), unless sizeMm > 0
  double sizeMm = 0.0;      // > 0: scale so that the longest bounding-box side is this long
  VisibilityMode visibility = VisibilityMode::Rays;
  int samples = 0;              // visibility rays per vertex; 0: auto (chooseVisibilitySamples)
  uint64_t seed = 1;            // visibility rays and Monte Carlo walks
  std::string method = "auto";  // a diffusion method (diffusion.h) or "pathtrace"
  // listProfiles() or "auto" (dipole with the escape energy model, else burley); unused by
  // pathtrace.
  std::string profile = "auto";
  std::string energy = "auto";  // listEnergyModels() (finite_object_energy.h); unused by pathtrace
  // Relative RMS of B (diffusion methods). With auto samples and visibility rays the budget is
  // split in quadrature: visibility noise may take 0.9 of it, the diffusion sum gets the rest.
  double tolerance = 0.01;
  int walks = 256;              // pathtrace: random walks per vertex
  int environmentFaceSize = 0;  // 0: from the source resolution
  int threads = 0;              // <= 0: all cores
  bool quiet = false;           // no progress bars or info lines
};

// Visibility noise in B ("auto" samples). The pilot (visibility.h) gives, at a subset of vertices
// o, E_o and the variance of an m-ray estimate per channel at two ray counts. Vertices'
// estimates are independent (per-vertex seeds), so the diffusion sum B_o = sum_i w_oi E_i
// (w_oi = R_d(r_oi) A_i; the self term the profile integrated over the vertex's disc) has
// Var(B_o) = sum_i w_oi^2 Var(E_i); assuming the variance is locally uniform that is
// Var(E_o) sum_i w_oi^2, with B_o ~ E_o sum_i w_oi: the noise of E divided by the effective
// number of vertices under the kernel, N_eff = (sum w)^2 / sum w^2. The relative error of B
// (sqrt(sum |dB|^2 / sum |B|^2) over vertices and channels, the error the benchmarks measure)
// at n rays is sqrt(variance * (fineRays / n)^rate), the rate (1 = plain Monte Carlo, up to 1.5
// for stratified sampling of discontinuities) fitted between the pilot's two levels. The weight
// sums run over all mesh vertices within the profile's 99.9% radius of each pilot vertex.
struct VisibilityNoiseModel {
  int fineRays = 1;
  double variance = 0.0;               // relative variance of B at fineRays rays per vertex
  double rate = 1.0;                   // variance ~ n^-rate
  double meanEffectiveVertices = 0.0;  // mean over pilot vertices of N_eff
  double errorAt(int samples) const {
    return std::sqrt(variance * std::pow(static_cast<double>(fineRays) / samples, rate));
  }
};
VisibilityNoiseModel visibilityNoiseModel(const VisibilityPilot& pilot,
                                          std::span<const glm::vec3> positionsMm,
                                          std::span<const float> areasMm2,
                                          const DiffusionProfile& profile);

// Rays per vertex: the smallest multiple of kAutoSampleStep in [kMinAutoSamples,
// kMaxAutoSamples] whose predicted error meets `budget` (the largest if none does).
inline constexpr int kMinAutoSamples = 16, kMaxAutoSamples = 1024, kAutoSampleStep = 16;
int chooseVisibilitySamples(const VisibilityNoiseModel& model, double budget);

struct BakeOutput {
  BakedMesh baked;         // positions in the mesh's own units, mmPerUnit recorded
  std::string reportJson;  // counts, units, material, profile fit, method, stage times, errors
};

// Runs every stage. Warnings (mesh cleanup, long walks) go to stderr through warn(); errors throw
// sss::Error naming the file and the problem. Writes nothing.
BakeOutput bake(const BakeSettings& settings);

}  // namespace sss

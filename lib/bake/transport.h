// Bake stage 4: the exitance B per vertex from E: a diffusion sum of Li & Guo Eq. 7
// (diffusion.h) with the energy model of finite_object_energy.h, or the volumetric Monte Carlo
// reference (lib/pathtrace/subsurface_path_tracer.h), which needs neither E nor a profile.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "bake/bake_settings.h"
#include "core/run_context.h"
#include "diffusion/diffusion.h"
#include "transport/finite_object_energy.h"

namespace sss {

struct FarField;  // transport/far_field.h

class Cubemap;           // envmap/cubemap.h
class DiffusionProfile;  // material/diffusion_profile.h
struct TriangleMesh;     // mesh/triangle_mesh.h

struct TransportInput {
  const TriangleMesh& meshMm;
  std::span<const float> areasMm2;
  std::span<const glm::vec3> irradiance;  // E per vertex (diffusion)
  const Cubemap& radiance;                // the environment (path tracer)
  const Material& material;
  const DiffusionProfile& profile;
  const EnergyPlan& energy;
  BakeMethod method = BakeMethod::Auto;
  double diffusionTolerance = 0.01;  // ErrorBudget::diffusionTolerance
  int walks = 256;                   // path tracer: walks per vertex
  RunContext run;
  // The far field (far_field.h), or null: where traced, B_far is added to B and its traced near
  // exits calibrate B's near part (calibrateNearPart).
  const FarField* farField = nullptr;
  // The energy model's sums with E = 1 (finite_object_energy.h), filled by a first transport and
  // reused by later ones on other light with the same method (the bounces); null: not kept.
  EnergyWeightSums* weightSums = nullptr;
  // The diffusion sums' octree of this mesh, kept for the next transport on it (diffusion.h);
  // null: built each time.
  DiffusionMeshCache* diffusionMeshCache = nullptr;
};

struct PathTraceStageReport {
  int walks = 0;
  double g = 0.0;
  double meanScatteringEvents = 0.0;
  uint64_t truncatedWalks = 0, escapedWalks = 0;
  std::vector<std::string> warnings;
};

struct TransportReport {
  BakeMethod requested = BakeMethod::Auto;
  bool pathTrace = false;
  DiffusionReport diffusion;  // diffusion methods
  double diffusionTolerance = 0.0;
  PathTraceStageReport pathTracer;  // pathTrace
  // The near part's calibration's noise (far_field.h, calibrateNearPart), relative RMS of B; 0
  // where the far field is not traced.
  double nearPartNoise = 0.0;
  // The method's own relative RMS error of B: the diffusion's and nearPartNoise in quadrature.
  double estimatedError = 0.0;
  double seconds = 0.0;
  // The name of the method that ran ("hierarchical", "pathtrace", ...).
  std::string methodName() const;
};

struct VertexExitance {
  std::vector<glm::vec3> exitance;  // B per vertex
  TransportReport report;
};

VertexExitance transport(const TransportInput& in);

// The transport of light that did not come from the environment's traced far field (the bounces,
// a relightable bake's basis lights): the method the first transport (`direct`) chose, quiet. The
// traced far field carries none of that light: with it, the first transport spread only P's near
// share, so this one goes through the escape model's own kernel for all of P, with its own sums
// (wholeEscapeSums; docs/physics.md, "Light the object sends itself").
TransportInput linearTransportInput(const TransportInput& transportIn, const VertexExitance& direct,
                                    EnergyWeightSums& wholeEscapeSums);

// How the bounces' increments (interreflection.h's BounceTransport) are summed: `looseness` times
// the direct light's tolerance, at most the loosest the sums' error model was fitted at
// (tests/bench/diffusion_sweep.sh, 0.3-3 %), and, where the direct light took the Gaussian sum
// over every pair, by the cheapest method that meets that tolerance (auto: the hierarchical sum's
// clusters grow with it; on a small mesh under a wide profile it halves a bounce's cost). The
// energy model's sums with E = 1 stay the direct light's, the more precise.
struct IncrementSums {
  BakeMethod method = BakeMethod::Auto;
  double tolerance = 0.0;
};
IncrementSums incrementSums(BakeMethod direct, double directTolerance, double looseness);

}  // namespace sss

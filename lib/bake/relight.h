// Relightable bakes (sss-bake --relightable, sss-relight; docs/relighting.md).
//
// Every stage of the bake is linear in the environment's radiance. A relightable bake splits the
// light as real-time practice does (envmap/compact_lights.h): the smooth part goes through a
// stored spherical-harmonic transfer (Sloan, Kautz & Snyder 2002), the compact bright sources (a
// sun, lamps) are directional lights whose shadows are traced and whose light is spread by the
// bake's own transport at relight time. Per vertex and channel:
//
//   B_direct = sum_k T_k L_k + transport(E_compact),
//   B = B_direct and the bake's bounces on it (interreflection.h),
//   L_n = g B + L_u(compact lights),   B_out = b g B,
//
// T_k (k = l (l + 1) + m, l <= order) the exitance B of SH basis function k through the bake's
// linear transport (to the precision the files store: mesh/quantized_transfer.h), L_k the SH
// coefficients of the environment without its compact lights, E_compact their transmitted
// irradiance with shadows, g the bake's own ratio of its radiance along the normal to its B, and b
// its B / L_n. T is built from what is linear and light-independent in the pipeline:
//   1. the transmitted-cosine transfer with the mesh's shadows and the directional entry
//      (lighting/visibility_transfer.h), one irradiance per basis function;
//   2. each through the bake's transport (the diffusion sum of Li & Guo Eq. 7 with the energy
//      model; transport.h, linearTransportInput), split into its positive and negative parts, as
//      the sums take light >= 0.
// g carries the exit model and what the traced far field changes, in the proportion the bake's
// own environment gave them: the bake's radiance along the normal of its scattered light over its
// own light through the same transport and bounces (relightOwnEnvironment). That is the
// approximation that docs/relighting.md measures. The light that crosses without scattering
// leaves collimated, along the light's own direction, so no ratio carries it to another light:
// where the bake traced it, a relight traces it again for the compact lights
// (transport/unscattered_light.h, the same auto) and adds it to L_n. The transport is stored as a
// key (method, tolerance, profile, energy model, half-space albedo, entry, bounces, gather rays)
// and the escape probability per vertex, so that sss-relight rebuilds it.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "bake/transport.h"
#include "core/run_context.h"
#include "envmap/compact_lights.h"
#include "irradiance/spherical_harmonics.h"
#include "material/material.h"
#include "mesh/baked_ply.h"
#include "mesh/triangle_mesh.h"
#include "transport/unscattered_light.h"

namespace sss {

class Cubemap;                  // envmap/cubemap.h
class InterreflectionGather;    // transport/interreflection.h
class TriangleScene;            // raytrace/triangle_scene.h
class DirectionalAlbedoWeight;  // material/directional_albedo_weight.h

// --relightable's order when none is given, and the rays per vertex of its transfer.
inline constexpr int kDefaultRelightOrder = 3;
inline constexpr int kRelightRays = 64;

struct RelightInput {
  const TriangleMesh& meshMm;
  const TransportInput& transport;                 // linearTransportInput of the bake's transport
  const DirectionalAlbedoWeight* entry = nullptr;  // the transport's, null for diffuse entry
  int order = kDefaultRelightOrder;
  int rays = kRelightRays;
  int bounces = 0;               // the bake's (interreflection.h), done again at relight time
  bool bounceTail = false;       // the bake ended its bounces with their geometric tail
  int gatherRays = 64;           // the bounces' gather rays per vertex
  int gatherVisibilityRays = 0;  // of them, the visibility's cosine set (InterreflectionOptions)
  // Which of the gather's rays met the front of a surface (InterreflectionGather::frontHits),
  // stored so that a relight traces those only; empty: none stored (a relight traces them all).
  std::span<const uint16_t> gatherFrontHits{};
  std::span<const glm::vec3> exitance;  // the bake's B (with its bounces)
  // Its radiance along the normal, of the scattered light (without the unscattered light, which a
  // relight traces again: `unscattered`).
  std::span<const glm::vec3> radianceNormal;
  // The bake traced the light that crosses without scattering (unscattered_light.h): the key
  // says so, and a relight traces it for the compact lights.
  bool unscattered = false;
  RunContext run{};
  const TriangleScene* scene = nullptr;  // the bake's ray scene of the mesh, else null: built
};

struct RelightReport {
  int order = -1;  // -1: not relightable
  int coefficients = 0;
  int rays = 0;
  double blockedFraction = 0.0;
  // Relative RMS of the radiance along the normal, relit under the bake's own environment
  // against the bake: what the split light and g cost there.
  double selfError = 0.0;
  int compactLights = 0;          // in the bake's own environment
  double compactFluxShare = 0.0;  // their share of its irradiance
  double transferSeconds = 0.0, transportSeconds = 0.0, seconds = 0.0;
};

// What the bake stores (BakedMesh's relight fields, the same names).
struct RelightTransfer {
  int order = -1;
  std::vector<glm::vec3> relightTransfer;  // T at [vertex * coefficients + k], per channel
  std::vector<glm::vec3> radianceGain, exitancePerRadiance, escapeProbability;
  std::vector<uint16_t> gatherFrontHits;  // RelightInput::gatherFrontHits
  std::string relightTransport;
  RelightReport report;
};

RelightTransfer relightTransfer(const RelightInput& in);

// A relightable bake (mesh in mm) with its material, as relight() reads it.
struct RelightableMesh {
  const TriangleMesh& meshMm;
  const Material& material;
  const RelightTransfer& transfer;
};

// Where one relight's time went, in seconds: finding the compact lights, the smooth rest through
// the transfer (its SH projection included), the compact lights' shadows and transport, the
// bounces' gather rays (traced by a session's first relight; their sky swapped after), the
// bounces' transports and the compact lights' unscattered light.
struct RelightSeconds {
  double compactLights = 0.0, smooth = 0.0, compactTransport = 0.0, gather = 0.0, bounces = 0.0,
         unscattered = 0.0;
};

struct RelitLight {
  std::vector<glm::vec3> radianceNormal, exitance;
  int compactLights = 0;
  double compactFluxShare = 0.0;
  RelightSeconds seconds;
  // The compact lights' unscattered light: whether auto traced it, why, and its paths (requested
  // Off where the bake did not trace that light or there is no compact light).
  UnscatteredLightReport unscattered;
};

// The relight split for a renderer that sums the smooth part itself (sss-render, in its vertex
// shader): per vertex and channel, relight()'s exitance is
//   max(sum_k T_k L_k + rest, 0) g b,
// L_k the smooth light's SH coefficients (`smoothLight`, at the transfer's order), rest the B
// before g of the compact lights and the bounces (`restExitance`; empty where there are neither:
// no per-vertex work is done here then).
struct RelitSplit {
  SphericalHarmonics smoothLight;
  std::vector<glm::vec3> restExitance;
  int compactLights = 0;
  double compactFluxShare = 0.0;
  RelightSeconds seconds;
};

// The bake under `environment` (a radiance cubemap in the mesh's frame): compact lights split
// off, the rest through the transfer. Throws Error naming `path` on a transport key it cannot
// read.
RelitLight relight(const std::string& path, const RelightableMesh& bake, const Cubemap& environment,
                   const RunContext& run);

// relight() under any number of environments (a light turntable; one bake, N environments): what
// does not depend on the light is built once (the transport key parsed, the profile and its
// weight sums, the compact lights' shadow rays, the bounces' gather rays, whose mirrored sky is
// swapped for each environment). Each relight is relight()'s under the same environment, bit for
// bit. Throws Error naming `path` on a transport key it cannot read. Keeps references to `bake`'s
// mesh, material and transfer.
class RelightSession {
 public:
  // reusable false: for one environment (the gather keeps no mirror directions: less memory).
  RelightSession(const std::string& path, const RelightableMesh& bake, const RunContext& run,
                 bool reusable = true);
  ~RelightSession();
  RelitLight relight(const Cubemap& environment);
  // relight() as its parts (RelitSplit), equal to it up to float rounding.
  RelitSplit relightSplit(const Cubemap& environment);

  class Context;  // relight.cpp

 private:
  const RelightableMesh bake_;
  std::unique_ptr<Context> context_;
};

// The bake relit under its own environment, and g (step 4 of the file's comment) for it: the
// bake's radiance along the normal over its own light through the stored transport and bounces
// (E as the bake's rays measured it, not through the SH transfer, so that g holds the exit model
// and the traced stages but not the transfer's truncation). `bake.transfer`'s radianceGain is
// not read. One transport and one gather serve both: `gather`, when given, is the bake's own
// (traced under `environment` with the stored transport's rays and entry), else one is traced;
// `rays`, when given, the bake's ray scene of the mesh (TriangleSceneOptions::surfaceRays).
struct OwnEnvironmentRelight {
  std::vector<glm::vec3> radianceGain;
  RelitLight relit;  // with that g
};
OwnEnvironmentRelight relightOwnEnvironment(const std::string& path, const RelightableMesh& bake,
                                            const Cubemap& environment,
                                            std::span<const glm::vec3> ownIrradiance,
                                            std::span<const glm::vec3> radianceNormal,
                                            const RunContext& run,
                                            std::shared_ptr<InterreflectionGather> gather = {},
                                            const TriangleScene* rays = nullptr);

// sum_k T_k L_k per vertex over the bands both have (B of the smooth light, before g).
std::vector<glm::vec3> transferredExitance(std::span<const glm::vec3> transfer, int order,
                                           const SphericalHarmonics& light);

// Throws Error naming `path` unless `baked` is a plain bake or a relightable one whose transport
// key parses (what relight() checks first; the readers check the rest).
void checkRelightTransport(const std::string& path, const BakedMesh& baked);

// A relightable bake as a file holds it (its units and material comments), relit under any
// number of environments: a RelightSession on its mesh in mm. Throws Error naming `path` without
// a material or on a transport key it cannot read. Copies what it needs of `baked`.
class BakedMeshRelighter {
 public:
  BakedMeshRelighter(const std::string& path, const BakedMesh& baked, const RunContext& run,
                     bool reusable = true);
  RelitLight relight(const Cubemap& environment) { return session_.relight(environment); }
  RelitSplit relightSplit(const Cubemap& environment) { return session_.relightSplit(environment); }
  const RelightTransfer& transfer() const { return transfer_; }

 private:
  TriangleMesh meshMm_;
  Material material_;
  RelightTransfer transfer_;
  RelightableMesh bake_;
  RelightSession session_;
};

// BakedMeshRelighter for one environment.
RelitLight relightBakedMesh(const std::string& path, const BakedMesh& baked,
                            const Cubemap& environment, const RunContext& run);

// A relightable BakedMesh's fields as relight() takes them (copies).
RelightTransfer relightTransferOf(const BakedMesh& baked);

}  // namespace sss

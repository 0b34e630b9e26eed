// Interreflection: the light the object sends to itself (`sss-bake --bounces`). The visibility
// stage (visibility.h) counts a direction the mesh blocks as dark, as Li & Guo's Eq. 6 does (the
// paper names the limitation: "it cannot express inter-object reflection"), which leaves
// concavities 13-29 % dark under uniform light. The model and its measurements: docs/physics.md,
// "Light the object sends itself"; docs/tools/sss-bake.md, "Bounces and interreflection".
//
// Each vertex's facets sample their directions again (cosine-weighted about the facets' normals,
// stratified, Pcg32(seed, vertex): the light the facets take in, facet_light.h). A ray that meets
// the object brings back the radiance leaving the hit point towards the vertex,
//   L_hit = B F_t(mu_h, eta) / (pi (1 - 2 C_1(eta))) + F_r(mu_h) L_env(r),
// B interpolated over the hit triangle's vertices through the normalized exit model
// (optics/fresnel.h), mu_h the cosine between the way back and the hit's interpolated normal, r
// the mirror direction at the hit, L_env the environment without its compact lights, box-filtered
// to texels of ~11 degrees (interreflection.cpp). The compact lights (a sun, lamps), which a
// mirror direction would find only by chance, are traced from the lights instead
// (mirrored_lights.h) and added per vertex. The vertex's transmitted irradiance gains
//   E_ir = integral over blocked w of factor(w) L_hit(w) dw  ~  1 / N sum_k factor / pdf L_hit,k,
// factor = sum_f share_f F_t(mu_f) mu_f, N rays from the facets' cosine lobes (unblocked ones add
// nothing: the visibility stage has them). The hits are traced once; each bounce is a gather over
// them, so B -> E_ir is linear and cheap, and the bake iterates E = E_direct + E_ir(B),
// B = transport(E) until B stops changing. Closed, non-absorbing objects under uniform radiance 1
// (the white furnace) then send radiance 1 everywhere, concavities included
// (tests/transport/interreflection_test.cpp).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/run_context.h"
#include "envmap/cubemap.h"
#include "lighting/cosine_hits.h"
#include "material/directional_albedo_weight.h"
#include "transport/mirrored_lights.h"

namespace sss {

class DiffusionProfile;  // material/diffusion_profile.h
class InterreflectionGather;
class TriangleScene;  // raytrace/triangle_scene.h

struct InterreflectionOptions {
  int rays = 64;  // cosine-distributed rays per vertex (>= 1)
  // The directional entry (material/directional_albedo_weight.h): the light arriving at a vertex
  // is weighted as the transport's direct light is. Null: diffuse entry. Not kept.
  const DirectionalAlbedoWeight* entry = nullptr;
  RunContext run;  // quiet: unused
  // Only these vertices trace rays (a pilot, estimateMissingInterreflection); the others gather
  // nothing. Empty: every vertex.
  std::vector<uint32_t> vertices{};
  // Keep each hit's mirror direction, so that setSky can put another environment in the mirrored
  // sky (the rays do not depend on the light: one gather serves every environment a relightable
  // bake is relit under). 24 bytes more per hit.
  bool keepMirrors = false;
  // One ray set, both uses: the first `visibilityCosineRays` rays per vertex are the visibility's
  // cosine samples (the same stratified set, seeded as visibility_vertex_estimator.cpp seeds it,
  // so that the set is a function of the mesh, the seed and the count), the rest of
  // max(rays, visibilityCosineRays) a set of its own. `traced`: those samples' hits kept by the
  // visibility pass (lighting/cosine_hits.h; perVertex must equal visibilityCosineRays; not
  // kept), taken instead of tracing them again. A relight, which has no visibility pass, traces
  // the same set itself.
  int visibilityCosineRays = 0;
  const CosineHits* traced = nullptr;
  // Which of each vertex's rays met the front of a surface (InterreflectionGather::frontHits of
  // a gather with the same mesh, seed and ray counts): only those are traced (the others meet
  // nothing, or a back face, and bring no light), for a relight of a bake that stored them.
  // Empty: every ray. Not kept.
  std::span<const uint16_t> frontHits{};
  bool keepFrontHits = false;  // record them (frontHits())
  // The environment's compact lights (envmap/compact_lights.h) in the mirrored sky traced from
  // the lights (mirrored_lights.h; this many paths per mesh vertex for lights that hold all of the
  // environment's flux, times the square of their share, at least one) and left out of the sky
  // the hits look up; false (a pilot: its thousand vertices would pay for the whole surface's
  // paths), looked up with the rest of the sky.
  bool traceMirroredLights = true;
  int mirroredLightPaths = kMirroredLightPathsPerVertex;
  // Take that gather's images of the compact lights (built under the same sky) instead of tracing
  // them: a replica of the rays (predictGatherNoise), whose difference is then the rays' noise
  // alone. Not kept.
  const InterreflectionGather* mirroredLightsOf = nullptr;
  // The mesh's ray scene (TriangleSceneOptions::surfaceRays over the gather's positions and
  // triangles) where the caller has one; null: built by the gather. Not owned.
  const TriangleScene* scene = nullptr;
};

// The 16-bit words of one vertex's front-hit bits for `rays` rays per vertex
// (InterreflectionGather::frontHits): whole groups of four (64 rays), as a glTF VEC4 of
// UNSIGNED_SHORT holds them.
inline std::size_t frontHitWords(int rays) {
  return 4 * ((std::size_t(std::max(rays, 0)) + 63) / 64);
}

class InterreflectionGather {
 public:
  // Positions in mm, unit vertex normals pointing out. Keeps no reference to its arguments.
  InterreflectionGather(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                        std::span<const glm::uvec3> triangles, const Cubemap& radiance, float eta,
                        const InterreflectionOptions& options);

  // E_ir per vertex for the exitance B per vertex (one per mesh vertex). With `variance`, also
  // each vertex's Monte Carlo variance of E_ir (from its rays' spread, rays that met nothing
  // counting 0; an upper bound, the rays being stratified).
  // `mirrored` false: without the Fresnel-reflected sky, which does not depend on B (the linear
  // part, for the bounces' increments).
  std::vector<glm::vec3> gather(std::span<const glm::vec3> exitance,
                                std::vector<glm::vec3>* variance = nullptr,
                                bool mirrored = true) const;
  // Of the rays traced, the fraction that met the object.
  double blockedFraction() const { return blockedFraction_; }
  int rays() const { return rays_; }  // per vertex, the visibility's set included
  int visibilityCosineRays() const { return visibilityCosineRays_; }
  // The compact lights' mirror images' variance per vertex (their paths' noise), empty where none
  // were traced.
  std::span<const glm::vec3> mirroredLightVariance() const { return mirroredLights_.variance; }
  // With InterreflectionOptions::keepFrontHits: per vertex frontHitWords(rays()) words, bit j
  // (bit j % 16 of word j / 16) set where its ray j (the visibility's cosine set first) met the
  // front of a surface. Empty otherwise.
  std::span<const uint16_t> frontHits() const { return frontHits_; }
  // The mirrored sky of `radiance` instead of the one built with: the same values as a gather
  // built under `radiance`. Needs InterreflectionOptions::keepMirrors. `scene`: the mesh's ray
  // scene for the compact lights' mirror images, where the caller has one (else built).
  void setSky(const Cubemap& radiance, const TriangleScene* scene = nullptr);

 private:
  struct Hit {
    glm::uvec3 vertices;
    glm::vec3 barycentric;
    glm::vec3 exitWeight;  // pi / N F_t(mu) w(mu) F_t(mu_h) / (pi (1 - 2 C_1))
    glm::vec3 reflection;  // pi / N F_t(mu) w(mu) F_r(mu_h) L_env(r)
    bool sameRay;          // the mirror bounce of the hit before it: one ray's light with it
  };
  struct Mirror {
    glm::vec3 direction;  // of the mirror bounce at the hit
    glm::vec3 weight;     // pi / N F_t(mu) w(mu) F_r(mu_h), 0 where the mirror meets the object
  };
  // The hits traced per chunk of `grain` vertices (chunk c: vertices[c * grain] on, each vertex's
  // hits together, hitCount[v] of them) into hits_, mirrors_ and offsets_, vertex by vertex.
  void layOutPerVertex(std::span<const uint32_t> vertices, std::size_t grain,
                       std::span<const uint32_t> hitCount, std::vector<std::vector<Hit>> chunkHits,
                       std::vector<std::vector<Mirror>> chunkMirrors);

  int rays_ = 0;
  int threads_ = 0;  // for gather (InterreflectionOptions::run)
  int visibilityCosineRays_ = 0;
  std::vector<uint32_t> offsets_;  // hits of vertex v: [offsets_[v], offsets_[v + 1])
  std::vector<Hit> hits_;
  std::vector<Mirror> mirrors_;  // per hit, with keepMirrors
  std::vector<uint16_t> frontHits_;
  double blockedFraction_ = 0.0;
  // The compact lights' mirror images per vertex (empty: none traced), and, with keepMirrors,
  // what setSky needs to trace them again.
  MirroredLights mirroredLights_;
  struct MirroredLightsSetup {
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::uvec3> triangles;
    float eta = 1.3f;
    DirectionalAlbedoWeight entry;
    int pathsPerVertex = 0;  // InterreflectionOptions::mirroredLightPaths; 0: none traced
    RunContext run;
  };
  MirroredLightsSetup mirroredSetup_;
  static MirroredLightsSetup mirroredLightsSetup(const InterreflectionOptions& options, float eta,
                                                 std::span<const glm::vec3> positions,
                                                 std::span<const glm::vec3> normals,
                                                 std::span<const glm::uvec3> triangles);
  // The sky the hits look up, and mirroredLights_ traced, for `radiance`.
  // `scene`: of the positions and triangles, or null (built if there are lights to trace);
  // `same`: a gather whose images to take instead (InterreflectionOptions::mirroredLightsOf).
  Cubemap mirrorSkyFor(const Cubemap& radiance, const TriangleScene* scene,
                       const InterreflectionGather* same, std::span<const glm::vec3> positions,
                       std::span<const glm::vec3> normals, std::span<const glm::uvec3> triangles);
};

struct BounceResult {
  std::vector<glm::vec3> irradiance;  // E_direct + E_ir of the last bounce (and the tail)
  std::vector<glm::vec3> exitance;    // B = transport(irradiance)
  int bounces = 0;                    // gathers done
  double change = 0.0;                // relative RMS change of B at the last bounce
  // What the bounces not done would still add, relative RMS against B. Without a tail: the last
  // change times rho / (1 - rho), the series' ratio rho estimated by one more gather (no
  // transport) as |gather(dB_k)| / |dE_k|, capped at 0.95. With the geometric tail: its error
  // (bounceTail).
  double remaining = 0.0;
  bool tail = false;  // the geometric tail was added
};

// What follows the last bounce done. None: nothing (B holds the bounces done). Geometric: the
// rest of the series as a geometric one (bounceTail), so that the bounces can stop once the
// series' ratios have settled rather than once its terms are small.
enum class BounceTail { None, Geometric };

// The geometric tail of the bounces' series (Aitken's extrapolation of a power iteration): once
// the increments dB_k shrink by a steady ratio rho per bounce, the bounces still to come add
// dB_k rho / (1 - rho), and their light dE_k rho / (1 - rho). rho is taken per vertex and channel,
// the ratio of the last two increments (capped at 0.95): a concavity's light decays by its own
// ratio (how much of its sky the object fills there, and the albedo per channel), and one ratio
// for the whole object leaves the deep ones short. The error returned is how much the tail moves
// between the ratios of the last two pairs of increments (`earlier`, dB_(k-2), empty where there
// is none: then the whole tail), as its sum of squares over vertices and channels (against B's,
// a relative RMS as relative_rms.h pools it): small once the ratios have settled.
struct GeometricTail {
  std::vector<glm::vec3> exitance, irradiance;  // what the tail adds to B and E
  double squaredError = 0.0;
};
GeometricTail bounceTail(std::span<const glm::vec3> earlier, std::span<const glm::vec3> previous,
                         std::span<const glm::vec3> last, std::span<const glm::vec3> lastLight);

// Without bounces, how much the light the object sends itself would change B, estimated at the
// traced vertices of a pilot gather (InterreflectionOptions::vertices) from one gather of the
// bake's B. The first bounce adds dE_v = gather(B)_v; B answers E through the transport, whose
// energy ratio over the object is k = sum B A / sum E A (per channel: what leaves per what
// enters), so dB_v ~ k dE'_v, dE' the light as the transport spreads it: with a profile
// (TransportSmoothing) dE averaged over the pilot's vertices with the weights of the diffusion
// sum (Li & Guo Eq. 7), R_d(r_vu) a_u, a_u the vertex's area scaled so that the pilot's vertices
// stand for the whole surface, and for the vertex itself the profile integrated over its a_v;
// without one, dE itself (a local transport: an upper estimate where dE varies within a
// diffusion length, most in a material whose diffusion length is a concavity's size, as skim
// milk's in the concavity study's pit). Each later bounce sends back
// about the same share again, q = sum k dE / sum B over the traced vertices, so the bounces add
// dB / (1 - q) (q capped at 0.9). The rays' own noise is taken out of the RMS (a sun found by a
// mirror direction by chance). Weighting q by where the light is added (the pit's own gain)
// overestimates the studies' rows, with the spreading or without; the measured agreement:
// docs/accuracy.md, "Concavities: the box with a pit and the bunny".
struct MissingInterreflection {
  double relativeRms = 0.0;  // of the added B against B, over traced vertices and channels
  double gain = 0.0;         // q: the first bounce's mean relative gain
  double firstBounce = 0.0;  // the first bounce's alone (relativeRms = firstBounce / (1 - q))
};
struct TransportSmoothing {
  std::span<const glm::vec3> positionsMm;  // every mesh vertex's
  const DiffusionProfile* profile = nullptr;
  int threads = 0;  // <= 0: all cores
};
MissingInterreflection estimateMissingInterreflection(const InterreflectionGather& gather,
                                                      std::span<const uint32_t> vertices,
                                                      std::span<const glm::vec3> exitance,
                                                      std::span<const glm::vec3> irradiance,
                                                      std::span<const float> areas,
                                                      const TransportSmoothing& smoothing = {});

// With bounces, the noise the gather's rays leave in B, as a relative RMS over vertices and
// channels. The hits are traced once, so one draw of noise serves every bounce. Its variance per
// vertex is measured, as the visibility pilot's is (visibility.h), from a replica: the same rays
// with another seed at some vertices (`vertices`; the rays are stratified, so the variance of one
// estimate from its rays' spread would be an upper bound, 1.4-3.5x too high on the studies'
// scenes), Var = |E_ir - E_ir'|^2 / 2 at the converged B. Then through the transport: its energy
// ratio k = sum B A / sum E A per channel, and its smoothing over effectiveVertices vertices (the
// visibility noise model's N_eff, visibility_noise_model.h). Not amplified by the later bounces as
// the light is: each vertex gathers over many hit points, which averages the noise out. Measured
// against the spread over seeds: docs/tools/sss-bake.md, "Bounces and interreflection".
double predictGatherNoise(const InterreflectionGather& gather, const InterreflectionGather& replica,
                          std::span<const uint32_t> vertices, std::span<const glm::vec3> exitance,
                          std::span<const glm::vec3> irradiance, std::span<const float> areas,
                          double effectiveVertices);

// The transport's part that is linear in E (B = transport(E) less its constant terms, the traced
// far field): what the bounces' light adds to B, from that light and a looseness >= 1, how many
// times the transport's own relative error the sum may have (iterateInterreflection).
using BounceTransport =
    std::function<std::vector<glm::vec3>(std::span<const glm::vec3>, double looseness)>;

// B_0 = `initial` (the transport of E_direct, which the bake has); then B_k = B_(k-1) + dB_k with
// dE_1 = gather(B_0), dE_k = gather(dB_(k-1)) without the mirrored sky, dB_k = increment(dE_k):
// the same B_k = transport(E_direct + gather(B_(k-1))) as iterating the whole transport, for
// maxBounces bounces, or (maxBounces <= 0: auto) until the relative RMS change of B is below
// tolerance (at most 64 bounces). Summing only what each bounce adds leaves out what does not
// change: the direct light's sums, and the far field, which is traced from the environment. And
// the increments, small against B, need less precision: bounce k (from 1) allows a looseness of
// 2^-(k+1) / s_k, s_k the relative RMS of dE_k against E_direct (at least 1), so that their errors
// add up to at most half of the transport's own, even all in one direction.
// With BounceTail::Geometric, from the second bounce on, the tail is added after the last bounce:
// auto stops once the tail's error is below tolerance (relative RMS against B) or the change is.
BounceResult iterateInterreflection(const InterreflectionGather& gather,
                                    std::span<const glm::vec3> direct,
                                    std::vector<glm::vec3> initial,
                                    const BounceTransport& increment, int maxBounces,
                                    double tolerance, BounceTail tail = BounceTail::None);

}  // namespace sss

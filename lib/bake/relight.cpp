#include "bake/relight.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>

#include <glm/common.hpp>
#include <glm/vector_relational.hpp>

#include "core/error.h"
#include "core/format.h"
#include "core/relative_rms.h"
#include "core/timer.h"
#include "core/tool.h"
#include "lighting/visibility_transfer.h"
#include "material/directional_albedo_weight.h"
#include "material/material.h"
#include "material/profile_factory.h"
#include "mesh/quantized_transfer.h"
#include "mesh/triangle_mesh.h"
#include "optics/fresnel.h"
#include "raytrace/triangle_scene.h"
#include "transport/interreflection.h"
#include "transport/unscattered_light.h"

namespace sss {

namespace {

// B of light of either sign (an SH basis function, or SH light ringing below zero) through a
// transport that takes light >= 0: the transport of its positive part less that of its negative
// part (the second only where there is one).
template <class NonNegativeTransport>
std::vector<glm::vec3> transportOfEitherSign(std::span<const glm::vec3> irradiance,
                                             NonNegativeTransport&& nonNegative) {
  std::vector<glm::vec3> positive(irradiance.size()), negative(irradiance.size());
  bool anyNegative = false;
  for (std::size_t v = 0; v < irradiance.size(); ++v) {
    positive[v] = glm::max(irradiance[v], glm::vec3(0.0f));
    negative[v] = glm::max(-irradiance[v], glm::vec3(0.0f));
    anyNegative = anyNegative || negative[v] != glm::vec3(0.0f);
  }
  std::vector<glm::vec3> b = nonNegative(std::span<const glm::vec3>(positive));
  if (anyNegative) {
    const std::vector<glm::vec3> minus = nonNegative(std::span<const glm::vec3>(negative));
    for (std::size_t v = 0; v < b.size(); ++v) b[v] -= minus[v];
  }
  return b;
}

// Step 2: B per basis function through the bake's transport, at [vertex * count + k]. A basis
// function's light takes both signs where the sums take light >= 0: each band's functions go
// through the transport with the band's envelope added (per vertex and channel the largest |E_k|
// of the band), whose own transport is then taken away. The transport is linear (Eq. 7 and the
// energy model), so this is its transport of E_k: (order + 1)^2 + order transports where the
// positive and negative parts of each function took 2 (order + 1)^2 - 1, and a band's errors
// stay on the scale of its own light.
std::vector<glm::vec3> transportedTransfer(const VisibilityTransfer& transfer,
                                           const TransportInput& transportIn) {
  const std::size_t n = transfer.coefficients.size() / transfer.count;
  std::vector<glm::vec3> out(transfer.coefficients.size()), basis(n);
  TransportInput in = transportIn;
  DiffusionMeshCache meshCache;  // one octree for every basis function, unless the input has one
  if (!in.diffusionMeshCache) in.diffusionMeshCache = &meshCache;
  const auto nonNegative = [&](std::span<const glm::vec3> e) {
    in.irradiance = e;
    return transport(in).exitance;
  };
  for (int band = 0; band * band < transfer.count; ++band) {
    const int first = band * band, end = std::min((band + 1) * (band + 1), transfer.count);
    std::vector<glm::vec3> envelope(n, glm::vec3(0.0f));
    bool anyNegative = false;
    for (std::size_t v = 0; v < n; ++v)
      for (int k = first; k < end; ++k) {
        const glm::vec3 e = transfer.at(v)[k];
        envelope[v] = glm::max(envelope[v], glm::abs(e));
        anyNegative = anyNegative || glm::any(glm::lessThan(e, glm::vec3(0.0f)));
      }
    std::vector<glm::vec3> offset;  // B of the envelope, where it was added
    if (anyNegative) offset = nonNegative(envelope);
    for (int k = first; k < end; ++k) {
      for (std::size_t v = 0; v < n; ++v)
        basis[v] = transfer.at(v)[k] + (anyNegative ? envelope[v] : glm::vec3(0.0f));
      std::vector<glm::vec3> b = nonNegative(basis);
      for (std::size_t v = 0; v < n; ++v)
        out[v * transfer.count + k] = anyNegative ? b[v] - offset[v] : b[v];
    }
  }
  return out;
}

// numerator / denominator per vertex and channel, or `fallback` where the denominator is no light
// at all (below 1e-9 of its channel's mean).
std::vector<glm::vec3> ratios(std::span<const glm::vec3> numerator,
                              std::span<const glm::vec3> denominator, float fallback) {
  const glm::vec3 mean = std::accumulate(denominator.begin(), denominator.end(), glm::vec3(0.0f)) /
                         float(std::max<std::size_t>(denominator.size(), 1));
  std::vector<glm::vec3> out(numerator.size());
  for (std::size_t i = 0; i < out.size(); ++i)
    for (int c = 0; c < 3; ++c)
      out[i][c] =
          denominator[i][c] > 1e-9f * mean[c] ? numerator[i][c] / denominator[i][c] : fallback;
  return out;
}

// The paths a relight's unscattered light of the compact lights may take (the bake's cap is 32x
// this): on the skim-milk bunny under sunrise.exr turned by 135 or 270 degrees the relight is as
// far from a fresh bake at 262K paths as at 8.4M (16.4 / 14.0 % against 16.2 / 14.0 %), in 0.2 s
// instead of 1.6-1.9 s.
constexpr uint64_t kRelightUnscatteredPaths = 1 << 18;

// The transport as one word: method,tolerance,profile,energy,R_r,R_g,R_b,entry,bounces,rays
// (shortest round-trip numbers; entry: directional or diffuse; bounces: the bake's count, 0 for
// none, followed by '+' where the bake added their geometric tail; rays: the gather's per vertex,
// followed by ':N' where the first N are the visibility's cosine set), and ",unscattered" where
// g and b hold the scattered light alone and a relight traces the unscattered light
// (RelightInput::unscattered; a bake of an earlier build put it in g).
std::string transportKey(const TransportInput& in, bool directionalEntry, int bounces,
                         bool bounceTail, int gatherRays, int gatherVisibilityRays,
                         bool unscattered) {
  const glm::dvec3 r = in.energy.halfSpaceAlbedo;
  std::string visibilitySet;
  if (gatherVisibilityRays > 0) visibilitySet = ':' + std::to_string(gatherVisibilityRays);
  return std::string(kDiffusionMethodNames.name(diffusionMethodOf(in.method))) + "," +
         shortestDecimal(in.diffusionTolerance) + "," + in.profile.name() + "," +
         kEnergyModelNames.name(in.energy.model) + "," + shortestDecimal(r.x) + "," +
         shortestDecimal(r.y) + "," + shortestDecimal(r.z) + "," +
         kEntryModelNames.name(directionalEntry ? EntryModel::Directional : EntryModel::Diffuse) +
         "," + std::to_string(bounces) + (bounceTail ? "+" : "") + "," +
         std::to_string(gatherRays) + visibilitySet + (unscattered ? ",unscattered" : "");
}

}  // namespace

// Named, not anonymous: RelightSession::Context, declared in the header, holds these (GCC's
// -Wsubobject-linkage, where this file is compiled inside another, as in a unity build).
namespace stored_relight {

struct StoredTransport {
  DiffusionMethod method = DiffusionMethod::Auto;
  double tolerance = 0.01;
  std::string profile;
  EnergyModel energy = EnergyModel::HalfSpace;
  glm::dvec3 albedo{0.0};
  EntryModel entry = EntryModel::Directional;
  int bounces = 0, gatherRays = 64, gatherVisibilityRays = 0;
  bool bounceTail = false;
  bool unscattered = false;  // transportKey's last field
};

StoredTransport parseTransportKey(const std::string& path, const std::string& key,
                                  std::size_t escapeProbabilities) {
  std::vector<std::string> f;
  for (std::size_t begin = 0;;) {
    const std::size_t comma = key.find(',', begin);
    f.push_back(key.substr(begin, comma - begin));
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  const auto real = [&](const std::string& text) {
    double x = 0.0;
    if (!parseDecimal(text, x) || x < 0) fail(path, "bad relight_transport '" + key + "'");
    return x;
  };
  const auto named = [&](const auto& names, const std::string& text) {
    const auto value = names.find(text);
    if (!value) fail(path, "bad relight_transport '" + key + "'");
    return *value;
  };
  StoredTransport t;
  t.unscattered = f.size() == 11 && f[10] == "unscattered";
  if (f.size() != 10 && !t.unscattered) fail(path, "bad relight_transport '" + key + "'");
  t.method = named(kDiffusionMethodNames, f[0]);
  t.tolerance = real(f[1]);
  t.profile = f[2];
  t.energy = named(kEnergyModelNames, f[3]);
  t.albedo = {real(f[4]), real(f[5]), real(f[6])};
  t.entry = named(kEntryModelNames, f[7]);
  t.bounceTail = f[8].size() > 1 && f[8].back() == '+';
  if (t.bounceTail) f[8].pop_back();
  const std::size_t colon = f[9].find(':');
  const double visibilityRays = colon == std::string::npos ? 0.0 : real(f[9].substr(colon + 1));
  if (colon != std::string::npos) f[9].resize(colon);
  const double bounces = real(f[8]), rays = real(f[9]);
  if (visibilityRays != std::floor(visibilityRays) || visibilityRays > 4096)
    fail(path, "bad relight_transport '" + key + "'");
  t.gatherVisibilityRays = int(visibilityRays);
  if (bounces != std::floor(bounces) || bounces > 64 || rays != std::floor(rays) || rays < 1 ||
      rays > 4096)
    fail(path, "bad relight_transport '" + key + "'");
  t.bounces = int(bounces);
  t.gatherRays = int(rays);
  if (!(t.tolerance > 0.0 && t.tolerance < 1.0) || t.energy == EnergyModel::Auto ||
      t.method == DiffusionMethod::Auto)
    fail(path, "bad relight_transport '" + key + "'");
  if (t.energy == EnergyModel::Escape && escapeProbabilities == 0)
    fail(path, "relight_transport says escape without escape_probability_r/g/b");
  return t;
}

// Stored front hits (RelightInput::gatherFrontHits) fit the stored gather: its words per vertex
// for its rays, and bounces to use them.
void checkGatherFrontHits(const std::string& path, std::span<const uint16_t> frontHits,
                          std::size_t vertices, const StoredTransport& t) {
  if (frontHits.empty()) return;
  const std::size_t words = frontHitWords(t.gatherRays);
  if (t.bounces <= 0 || frontHits.size() != vertices * words)
    fail(path,
         "gather_hits: " + std::to_string(frontHits.size() / std::max<std::size_t>(vertices, 1)) +
             " words per vertex where relight_transport's " + std::to_string(t.bounces) +
             " bounces of " + std::to_string(t.gatherRays) + " gather rays need " +
             (t.bounces > 0 ? std::to_string(words) : std::string("none")));
}

// The bake's linear transport, rebuilt from what the file stores.
class StoredTransportRun {
 public:
  StoredTransportRun(const RelightableMesh& bake, const StoredTransport& t, const RunContext& run)
      : bake_(bake),
        stored_(t),
        profile_(makeProfile(t.profile, bake.material)),
        areas_(vertexAreas(bake.meshMm)),
        run_(run) {
    plan_.model = t.energy;
    plan_.halfSpaceAlbedo = t.albedo;
    plan_.escape.probability = bake.transfer.escapeProbability;
    run_.quiet = true;
  }
  // B of E through the transport; E of either sign (SH light rings below zero). (`environment`:
  // TransportInput's, which the diffusion sums do not read.)
  std::vector<glm::vec3> operator()(std::span<const glm::vec3> irradiance,
                                    const Cubemap& environment) {
    return eitherSign(irradiance, environment, {bakeMethodOf(stored_.method), stored_.tolerance});
  }
  // A bounce's increment, summed as the bake summed it (incrementSums).
  std::vector<glm::vec3> increment(std::span<const glm::vec3> irradiance,
                                   const Cubemap& environment, double looseness) {
    return eitherSign(irradiance, environment,
                      incrementSums(bakeMethodOf(stored_.method), stored_.tolerance, looseness));
  }

 private:
  std::vector<glm::vec3> eitherSign(std::span<const glm::vec3> irradiance,
                                    const Cubemap& environment, const IncrementSums& sums) {
    return transportOfEitherSign(irradiance, [&](std::span<const glm::vec3> e) {
      return nonNegative(e, environment, sums);
    });
  }
  std::vector<glm::vec3> nonNegative(std::span<const glm::vec3> irradiance,
                                     const Cubemap& environment, const IncrementSums& sums) {
    TransportInput in{.meshMm = bake_.meshMm,
                      .areasMm2 = areas_,
                      .irradiance = irradiance,
                      .radiance = environment,
                      .material = bake_.material,
                      .profile = *profile_,
                      .energy = plan_,
                      .method = sums.method,
                      .diffusionTolerance = sums.tolerance,
                      .run = run_,
                      .weightSums = &sums_,
                      .diffusionMeshCache = &meshCache_};
    return transport(in).exitance;
  }

  const RelightableMesh& bake_;
  const StoredTransport& stored_;
  std::unique_ptr<DiffusionProfile> profile_;
  std::vector<float> areas_;
  EnergyPlan plan_;
  EnergyWeightSums sums_;
  DiffusionMeshCache meshCache_;  // one octree for every transport of the session
  RunContext run_;
};

}  // namespace stored_relight

using stored_relight::parseTransportKey, stored_relight::StoredTransport,
    stored_relight::StoredTransportRun;

RelightTransfer relightTransfer(const RelightInput& in) {
  const Stopwatch clock;
  RelightTransfer out;
  RelightReport& report = out.report;
  const TriangleMesh& m = in.meshMm;
  const float eta = float(in.transport.material.eta);
  const VisibilityTransfer transfer = visibilityTransfer(
      m.positions, m.normals, m.triangles, eta,
      {.order = in.order, .rays = in.rays, .entry = in.entry, .run = in.run, .scene = in.scene});
  report.transferSeconds = clock.seconds();
  // As the files store it, so that the bake relit here is the bake relit from its file.
  out.relightTransfer =
      storedTransfer("", transportedTransfer(transfer, in.transport), std::size_t(transfer.count));
  report.transportSeconds = clock.seconds() - report.transferSeconds;
  const float exitScale = float(normalExitRadianceScale(eta));
  out.order = in.order;
  out.exitancePerRadiance = ratios(in.exitance, in.radianceNormal, 1.0f / exitScale);
  if (in.transport.energy.model == EnergyModel::Escape)
    out.escapeProbability = in.transport.energy.escape.probability;
  if (in.bounces > 0)
    out.gatherFrontHits.assign(in.gatherFrontHits.begin(), in.gatherFrontHits.end());
  out.relightTransport = transportKey(in.transport, in.entry != nullptr, in.bounces, in.bounceTail,
                                      in.gatherRays, in.gatherVisibilityRays, in.unscattered);
  report.order = in.order;
  report.coefficients = transfer.count;
  report.rays = in.rays;
  report.blockedFraction = transfer.blockedFraction;
  report.seconds = clock.seconds();
  return out;
}

std::vector<glm::vec3> transferredExitance(std::span<const glm::vec3> transfer, int order,
                                           const SphericalHarmonics& light) {
  const std::size_t count = std::size_t(order + 1) * std::size_t(order + 1);
  const std::size_t used = std::min<std::size_t>(count, light.coefficientCount());
  std::vector<glm::vec3> out(count == 0 ? 0 : transfer.size() / count, glm::vec3(0.0f));
  for (std::size_t v = 0; v < out.size(); ++v)
    for (std::size_t k = 0; k < used; ++k) out[v] += transfer[v * count + k] * light[int(k)];
  return out;
}

// What relighting builds once for any number of environments: the key parsed, the entry weight,
// the transport with its sums, the mesh's ray scene (one for the compact lights' shadows and the
// bounces' gather) and the gather (both built when first needed, or the bake's own; the gather's
// mirrored sky swapped for each environment).
class RelightSession::Context {
 public:
  // rays: the mesh's ray scene where the caller has one (not owned); null: built when first
  // needed.
  Context(const std::string& path, const RelightableMesh& bake, const RunContext& run,
          bool reusable, const TriangleScene* rays = nullptr)
      : givenRays_(rays),
        bake_(bake),
        run_(run),
        reusable_(reusable),
        stored_(parseTransportKey(path, bake.transfer.relightTransport,
                                  bake.transfer.escapeProbability.size())),
        weight_(bake.material),
        entry_(stored_.entry == EntryModel::Directional ? &weight_ : nullptr),
        transportRun_(bake_, stored_, run),
        shadows_(bake.meshMm.positions, bake.meshMm.normals, bake.meshMm.triangles,
                 float(bake.material.eta), entry_, run) {
    checkGatherFrontHits(path, bake.transfer.gatherFrontHits, bake.meshMm.positions.size(),
                         stored_);
  }

  // Rays already traced under the current environment, with the stored transport's options.
  void useGather(std::shared_ptr<InterreflectionGather> gather) { gather_ = std::move(gather); }

  // The environment the next calls relight under (the gather's mirrored sky follows it).
  void lightWith(const Cubemap& environment) {
    environment_ = &environment;
    if (gather_) gather_->setSky(environment);
  }

  // B of E through the stored transport (E of either sign).
  std::vector<glm::vec3> transport(std::span<const glm::vec3> irradiance) {
    return transportRun_(irradiance, *environment_);
  }

  // The bake's bounces (interreflection.h) on a direct B: the gather under the environment, its
  // increments through the stored transport, the bake's own count of bounces (none: B as it is).
  // The gather's share of E sets only the increments' precision: E is estimated as B / R.
  std::vector<glm::vec3> bounced(std::vector<glm::vec3> direct) {
    if (stored_.bounces <= 0) return direct;
    std::vector<glm::vec3> light(direct.size());
    const glm::vec3 albedo = glm::max(glm::vec3(stored_.albedo), glm::vec3(1e-6f));
    for (std::size_t v = 0; v < light.size(); ++v) light[v] = direct[v] / albedo;
    const auto increment = [&](std::span<const glm::vec3> e, double looseness) {
      return transportRun_.increment(e, *environment_, looseness);
    };
    return iterateInterreflection(gather(), light, std::move(direct), increment, stored_.bounces,
                                  0.0,
                                  stored_.bounceTail ? BounceTail::Geometric : BounceTail::None)
        .exitance;
  }

  // B of the environment before g: its compact lights with their shadows and its smooth rest
  // through the transfer, then the bounces; each stage's time into `seconds`.
  std::vector<glm::vec3> relitExitance(CompactLightSplit& split, RelightSeconds& seconds) {
    return withCompactLightsAndBounces(smoothExitance(smoothLight(split, seconds), seconds), split,
                                       seconds);
  }

  // The compact lights' light that crosses without scattering, along each vertex normal, where
  // the bake traced it (the key's last field; else empty), as the bake's auto decides it
  // against `scatteredRadiance`; its time into `seconds`.
  UnscatteredLight unscattered(const CompactLightSplit& split,
                               std::span<const glm::vec3> scatteredRadiance,
                               RelightSeconds& seconds) {
    if (!stored_.unscattered || split.lights.empty()) {
      UnscatteredLight none;
      none.report.requested = UnscatteredMode::Off;
      none.report.reason = stored_.unscattered ? "no compact light" : "not traced by the bake";
      return none;
    }
    Stopwatch clock;
    const Cubemap& all = *environment_;
    Cubemap lights(all.size());
    forEachTexel(all.size(), [&](int f, int x, int y) {
      lights.at(f, x, y) = glm::max(all.at(f, x, y) - split.rest.at(f, x, y), glm::vec3(0.0f));
    });
    if (areas_.empty()) areas_ = vertexAreas(bake_.meshMm);
    UnscatteredLight u =
        traceUnscatteredLight({.meshMm = bake_.meshMm,
                               .areasMm2 = areas_,
                               .radiance = lights,
                               .material = bake_.material,
                               .scatteredRadiance = scatteredRadiance,
                               .options = {.maxPaths = kRelightUnscatteredPaths, .run = run_}});
    seconds.unscattered = clock.lap();
    return u;
  }

  // The split for a renderer that sums the smooth part itself: its SH light, and B before g less
  // that part (the compact lights and the bounces; empty where there is neither).
  RelitSplit relitSplit(CompactLightSplit& split, RelightSeconds& seconds) {
    RelitSplit out;
    out.smoothLight = smoothLight(split, seconds);
    if (split.lights.empty() && stored_.bounces <= 0) return out;
    const std::vector<glm::vec3> smooth = smoothExitance(out.smoothLight, seconds);
    out.restExitance = withCompactLightsAndBounces(smooth, split, seconds);
    for (std::size_t v = 0; v < smooth.size(); ++v) out.restExitance[v] -= smooth[v];
    return out;
  }

 private:
  // The compact lights split off the environment (`split`), and the SH projection of its rest.
  SphericalHarmonics smoothLight(CompactLightSplit& split, RelightSeconds& seconds) {
    Stopwatch clock;
    split = splitCompactLights(*environment_);
    seconds.compactLights = clock.lap();
    SphericalHarmonics sh =
        SphericalHarmonics::project(split.rest, bake_.transfer.order, run_.threads);
    seconds.smooth = clock.lap();
    return sh;
  }

  // B of the smooth light `sh` through the transfer; its time added to the smooth part's.
  std::vector<glm::vec3> smoothExitance(const SphericalHarmonics& sh, RelightSeconds& seconds) {
    Stopwatch clock;
    std::vector<glm::vec3> b =
        transferredExitance(bake_.transfer.relightTransfer, bake_.transfer.order, sh);
    seconds.smooth += clock.lap();
    return b;
  }

  // b (the smooth light's B) with the compact lights' B through the transport, then the bounces.
  std::vector<glm::vec3> withCompactLightsAndBounces(std::vector<glm::vec3> b,
                                                     const CompactLightSplit& split,
                                                     RelightSeconds& seconds) {
    Stopwatch clock;
    if (!split.lights.empty()) {
      const std::vector<glm::vec3> compact = transport(shadows_.irradiance(split.lights, rays()));
      for (std::size_t v = 0; v < b.size(); ++v) b[v] += compact[v];
    }
    seconds.compactTransport = clock.lap();
    if (stored_.bounces > 0) gather();
    seconds.gather = clock.lap();
    std::vector<glm::vec3> out = bounced(std::move(b));
    seconds.bounces = clock.lap();
    return out;
  }

  // The mesh's ray scene, for the compact lights' shadows and the gather: one BVH for both.
  const TriangleScene& rays() {
    if (givenRays_) return *givenRays_;
    if (!ownRays_)
      ownRays_ = std::make_unique<TriangleScene>(bake_.meshMm.positions, bake_.meshMm.triangles,
                                                 TriangleSceneOptions::surfaceRays(run_.threads));
    return *ownRays_;
  }

  const InterreflectionGather& gather() {
    if (!gather_) {
      const TriangleMesh& m = bake_.meshMm;
      gather_ = std::make_shared<InterreflectionGather>(
          m.positions, m.normals, m.triangles, *environment_, float(bake_.material.eta),
          InterreflectionOptions{.rays = stored_.gatherRays,
                                 .entry = entry_,
                                 .run = run_,
                                 .keepMirrors = reusable_,
                                 .visibilityCosineRays = stored_.gatherVisibilityRays,
                                 .frontHits = bake_.transfer.gatherFrontHits,
                                 .scene = &rays()});
    }
    return *gather_;
  }

  const TriangleScene* givenRays_;
  std::unique_ptr<TriangleScene> ownRays_;
  std::vector<float> areas_;    // mm^2 per vertex, for the unscattered light
  const RelightableMesh bake_;  // references to the caller's mesh, material and transfer
  RunContext run_;
  bool reusable_;
  StoredTransport stored_;
  DirectionalAlbedoWeight weight_;
  const DirectionalAlbedoWeight* entry_;
  StoredTransportRun transportRun_;
  DirectionalShadows shadows_;
  std::shared_ptr<InterreflectionGather> gather_;
  const Cubemap* environment_ = nullptr;
};

namespace {

// The radiance along the normal (B times g, light below zero none: the SH light's ringing where
// the bake is dark) and B of it (times b).
RelitLight withGain(std::vector<glm::vec3> exitance, std::span<const glm::vec3> gain,
                    std::span<const glm::vec3> exitancePerRadiance,
                    const CompactLightSplit& split) {
  RelitLight out;
  out.radianceNormal = std::move(exitance);
  out.exitance.resize(out.radianceNormal.size());
  for (std::size_t v = 0; v < out.radianceNormal.size(); ++v) {
    out.radianceNormal[v] = glm::max(out.radianceNormal[v], glm::vec3(0.0f)) * gain[v];
    out.exitance[v] = out.radianceNormal[v] * exitancePerRadiance[v];
  }
  out.compactLights = int(split.lights.size());
  out.compactFluxShare = split.fluxShare;
  return out;
}

// `relit` with the unscattered light along the normal added (empty: none), not to B, and its
// report.
void addUnscattered(RelitLight& relit, UnscatteredLight unscattered) {
  for (std::size_t v = 0; v < unscattered.radiance.size(); ++v)
    relit.radianceNormal[v] += unscattered.radiance[v];
  relit.unscattered = std::move(unscattered.report);
}

}  // namespace

RelightSession::RelightSession(const std::string& path, const RelightableMesh& bake,
                               const RunContext& run, bool reusable)
    : bake_(bake), context_(std::make_unique<Context>(path, bake, run, reusable)) {}

RelightSession::~RelightSession() = default;

RelitLight RelightSession::relight(const Cubemap& environment) {
  context_->lightWith(environment);
  CompactLightSplit split;
  RelightSeconds seconds;
  std::vector<glm::vec3> b = context_->relitExitance(split, seconds);
  RelitLight out = withGain(std::move(b), bake_.transfer.radianceGain,
                            bake_.transfer.exitancePerRadiance, split);
  addUnscattered(out, context_->unscattered(split, out.radianceNormal, seconds));
  out.seconds = seconds;
  return out;
}

RelitSplit RelightSession::relightSplit(const Cubemap& environment) {
  context_->lightWith(environment);
  CompactLightSplit split;
  RelightSeconds seconds;
  RelitSplit out = context_->relitSplit(split, seconds);
  out.seconds = seconds;
  out.compactLights = int(split.lights.size());
  out.compactFluxShare = split.fluxShare;
  return out;
}

RelitLight relight(const std::string& path, const RelightableMesh& bake, const Cubemap& environment,
                   const RunContext& run) {
  return RelightSession(path, bake, run, false).relight(environment);
}

OwnEnvironmentRelight relightOwnEnvironment(const std::string& path, const RelightableMesh& bake,
                                            const Cubemap& environment,
                                            std::span<const glm::vec3> ownIrradiance,
                                            std::span<const glm::vec3> radianceNormal,
                                            const RunContext& run,
                                            std::shared_ptr<InterreflectionGather> gather,
                                            const TriangleScene* rays) {
  RelightSession::Context c(path, bake, run, false, rays);
  c.lightWith(environment);
  if (gather) c.useGather(std::move(gather));
  OwnEnvironmentRelight out;
  out.radianceGain = ratios(radianceNormal, c.bounced(c.transport(ownIrradiance)),
                            float(normalExitRadianceScale(float(bake.material.eta))));
  CompactLightSplit split;
  RelightSeconds seconds;
  std::vector<glm::vec3> b = c.relitExitance(split, seconds);
  out.relit = withGain(std::move(b), out.radianceGain, bake.transfer.exitancePerRadiance, split);
  addUnscattered(out.relit, c.unscattered(split, out.relit.radianceNormal, seconds));
  out.relit.seconds = seconds;
  return out;
}

void checkRelightTransport(const std::string& path, const BakedMesh& baked) {
  if (baked.relightOrder < 0) return;
  const StoredTransport t =
      parseTransportKey(path, baked.relightTransport, baked.escapeProbability.size());
  checkGatherFrontHits(path, baked.gatherFrontHits, baked.mesh.positions.size(), t);
}

namespace {

const BakedMesh& withMaterial(const std::string& path, const BakedMesh& baked) {
  if (baked.materialName.empty()) fail(path, "relightable bake without its material comments");
  return baked;
}

TriangleMesh meshInMm(const BakedMesh& baked) {
  TriangleMesh m = baked.mesh;
  scalePositions(m, baked.mmPerUnit);
  return m;
}

}  // namespace

BakedMeshRelighter::BakedMeshRelighter(const std::string& path, const BakedMesh& baked,
                                       const RunContext& run, bool reusable)
    : meshMm_(meshInMm(withMaterial(path, baked))),
      material_{.name = baked.materialName,
                .sigmaA = baked.sigmaA,
                .sigmaSPrime = baked.sigmaSPrime,
                .eta = baked.eta},
      transfer_(relightTransferOf(baked)),
      bake_{meshMm_, material_, transfer_},
      session_(path, bake_, run, reusable) {}

RelitLight relightBakedMesh(const std::string& path, const BakedMesh& baked,
                            const Cubemap& environment, const RunContext& run) {
  return BakedMeshRelighter(path, baked, run, false).relight(environment);
}

RelightTransfer relightTransferOf(const BakedMesh& baked) {
  RelightTransfer t;
  t.order = baked.relightOrder;
  t.relightTransfer = baked.relightTransfer;
  t.radianceGain = baked.radianceGain;
  t.exitancePerRadiance = baked.exitancePerRadiance;
  t.escapeProbability = baked.escapeProbability;
  t.gatherFrontHits = baked.gatherFrontHits;
  t.relightTransport = baked.relightTransport;
  return t;
}

}  // namespace sss

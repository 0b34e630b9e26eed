#include "bake/relight.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <memory>
#include <numeric>

#include "core/error.h"
#include "core/format.h"
#include "core/relative_rms.h"
#include "core/timer.h"
#include "core/tool.h"
#include "lighting/visibility_transfer.h"
#include "material/directional_albedo_weight.h"
#include "material/material.h"
#include "material/profile_factory.h"
#include "mesh/triangle_mesh.h"
#include "optics/fresnel.h"
#include "transport/interreflection.h"

namespace sss {

namespace {

// Basis function k's irradiance per vertex, split into its parts >= 0: E = positive - negative.
struct SignedIrradiance {
  std::vector<glm::vec3> positive, negative;
  bool anyNegative = false;
};

SignedIrradiance basisIrradiance(const VisibilityTransfer& transfer, int k) {
  const std::size_t n = transfer.coefficients.size() / transfer.count;
  SignedIrradiance e{std::vector<glm::vec3>(n), std::vector<glm::vec3>(n)};
  for (std::size_t v = 0; v < n; ++v) {
    const glm::vec3 t = transfer.at(v)[k];
    e.positive[v] = glm::max(t, glm::vec3(0.0f));
    e.negative[v] = glm::max(-t, glm::vec3(0.0f));
    e.anyNegative = e.anyNegative || e.negative[v] != glm::vec3(0.0f);
  }
  return e;
}

// Step 2: B per basis function through the bake's transport, at [vertex * count + k].
std::vector<glm::vec3> transportedTransfer(const VisibilityTransfer& transfer,
                                           const TransportInput& transportIn) {
  const std::size_t n = transfer.coefficients.size() / transfer.count;
  std::vector<glm::vec3> out(transfer.coefficients.size());
  TransportInput in = transportIn;
  for (int k = 0; k < transfer.count; ++k) {
    const SignedIrradiance e = basisIrradiance(transfer, k);
    in.irradiance = e.positive;
    std::vector<glm::vec3> b = transport(in).exitance;
    if (e.anyNegative) {
      in.irradiance = e.negative;
      const std::vector<glm::vec3> minus = transport(in).exitance;
      for (std::size_t v = 0; v < n; ++v) b[v] -= minus[v];
    }
    for (std::size_t v = 0; v < n; ++v) out[v * transfer.count + k] = b[v];
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

// The transport as one word: method,tolerance,profile,energy,R_r,R_g,R_b,entry,bounces,rays
// (shortest round-trip numbers; entry: directional or diffuse; bounces: the bake's count, 0 for
// none; rays: the gather's per vertex).
std::string number(double x) {
  char buffer[32];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, r.ptr);
}

std::string transportKey(const TransportInput& in, bool directionalEntry, int bounces,
                         int gatherRays) {
  const glm::dvec3 r = in.energy.halfSpaceAlbedo;
  return std::string(kDiffusionMethodNames.name(diffusionMethodOf(in.method))) + "," +
         number(in.diffusionTolerance) + "," + in.profile.name() + "," +
         kEnergyModelNames.name(in.energy.model) + "," + number(r.x) + "," + number(r.y) + "," +
         number(r.z) + "," +
         kEntryModelNames.name(directionalEntry ? EntryModel::Directional : EntryModel::Diffuse) +
         "," + std::to_string(bounces) + "," + std::to_string(gatherRays);
}

struct StoredTransport {
  DiffusionMethod method = DiffusionMethod::Auto;
  double tolerance = 0.01;
  std::string profile;
  EnergyModel energy = EnergyModel::HalfSpace;
  glm::dvec3 albedo{0.0};
  EntryModel entry = EntryModel::Directional;
  int bounces = 0, gatherRays = 64;
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
    const auto r = std::from_chars(text.data(), text.data() + text.size(), x);
    if (r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(x) || x < 0)
      fail(path, "bad relight_transport '" + key + "'");
    return x;
  };
  if (f.size() != 10) fail(path, "bad relight_transport '" + key + "'");
  StoredTransport t;
  t.method = kDiffusionMethodNames.parse(f[0]);
  t.tolerance = real(f[1]);
  t.profile = f[2];
  t.energy = kEnergyModelNames.parse(f[3]);
  t.albedo = {real(f[4]), real(f[5]), real(f[6])};
  t.entry = kEntryModelNames.parse(f[7]);
  const double bounces = real(f[8]), rays = real(f[9]);
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

// The bake's linear transport, rebuilt from what the file stores.
class StoredTransportRun {
 public:
  StoredTransportRun(const RelightableMesh& bake, const StoredTransport& t,
                     const Cubemap& environment, const RunContext& run)
      : bake_(bake),
        stored_(t),
        environment_(environment),
        profile_(makeProfile(t.profile, bake.material)),
        areas_(vertexAreas(bake.meshMm)),
        run_(run) {
    plan_.model = t.energy;
    plan_.halfSpaceAlbedo = t.albedo;
    plan_.escape.probability = bake.transfer.escapeProbability;
    run_.quiet = true;
  }
  // B of E through the transport, its sums within `looseness` times the bake's tolerance; E of
  // either sign (SH light rings below zero), as the transport of its parts.
  std::vector<glm::vec3> operator()(std::span<const glm::vec3> irradiance, double looseness = 1.0) {
    std::vector<glm::vec3> positive(irradiance.size()), negative(irradiance.size());
    bool anyNegative = false;
    for (std::size_t v = 0; v < irradiance.size(); ++v) {
      positive[v] = glm::max(irradiance[v], glm::vec3(0.0f));
      negative[v] = glm::max(-irradiance[v], glm::vec3(0.0f));
      anyNegative = anyNegative || negative[v] != glm::vec3(0.0f);
    }
    std::vector<glm::vec3> b = nonNegative(positive, looseness);
    if (anyNegative) {
      const std::vector<glm::vec3> minus = nonNegative(negative, looseness);
      for (std::size_t v = 0; v < b.size(); ++v) b[v] -= minus[v];
    }
    return b;
  }

 private:
  std::vector<glm::vec3> nonNegative(std::span<const glm::vec3> irradiance, double looseness) {
    TransportInput in{.meshMm = bake_.meshMm,
                      .areasMm2 = areas_,
                      .irradiance = irradiance,
                      .radiance = environment_,
                      .material = bake_.material,
                      .profile = *profile_,
                      .energy = plan_,
                      .method = bakeMethodOf(stored_.method),
                      .diffusionTolerance = std::min(0.03, looseness * stored_.tolerance),
                      .run = run_,
                      .weightSums = &sums_};
    return transport(in).exitance;
  }

  const RelightableMesh& bake_;
  const StoredTransport& stored_;
  const Cubemap& environment_;
  std::unique_ptr<DiffusionProfile> profile_;
  std::vector<float> areas_;
  EnergyPlan plan_;
  EnergyWeightSums sums_;
  RunContext run_;
};

// The bake's bounces (interreflection.h) on the relit direct B: the gather under `environment`,
// its increments through the stored transport, the bake's own count of bounces. The gather's
// share of E sets only the increments' precision: E is estimated as B / R.
std::vector<glm::vec3> bounced(const RelightableMesh& bake, const StoredTransport& t,
                               const DirectionalAlbedoWeight* entry, const Cubemap& environment,
                               StoredTransportRun& transportRun, std::vector<glm::vec3> direct,
                               const RunContext& run) {
  const TriangleMesh& m = bake.meshMm;
  const InterreflectionGather gather(m.positions, m.normals, m.triangles, environment,
                                     float(bake.material.eta),
                                     {.rays = t.gatherRays, .entry = entry, .run = run});
  std::vector<glm::vec3> light(direct.size());
  const glm::vec3 albedo = glm::max(glm::vec3(t.albedo), glm::vec3(1e-6f));
  for (std::size_t v = 0; v < light.size(); ++v) light[v] = direct[v] / albedo;
  const auto increment = [&](std::span<const glm::vec3> e, double looseness) {
    return transportRun(e, looseness);
  };
  return iterateInterreflection(gather, light, std::move(direct), increment, t.bounces, 0.0)
      .exitance;
}

}  // namespace

RelightTransfer relightTransfer(const RelightInput& in) {
  const Stopwatch clock;
  RelightTransfer out;
  RelightReport& report = out.report;
  const TriangleMesh& m = in.meshMm;
  const VisibilityTransfer transfer =
      visibilityTransfer(m.positions, m.normals, m.triangles, in.eta,
                         {.order = in.order, .rays = in.rays, .entry = in.entry, .run = in.run});
  report.transferSeconds = clock.seconds();
  out.relightTransfer = transportedTransfer(transfer, in.transport);
  report.transportSeconds = clock.seconds() - report.transferSeconds;
  const float exitScale = float(normalExitRadianceScale(in.eta));
  out.order = in.order;
  out.exitancePerRadiance = ratios(in.exitance, in.radianceNormal, 1.0f / exitScale);
  if (in.transport.energy.model == EnergyModel::Escape)
    out.escapeProbability = in.transport.energy.escape.probability;
  out.relightTransport = transportKey(in.transport, in.entry != nullptr, in.bounces, in.gatherRays);
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

// What relight() and radianceGainOf() share: the key parsed, the entry weight and the transport.
struct RelightContext {
  RelightContext(const std::string& path, const RelightableMesh& bake, const Cubemap& environment,
                 const RunContext& run)
      : stored(parseTransportKey(path, bake.transfer.relightTransport,
                                 bake.transfer.escapeProbability.size())),
        weight(bake.material),
        entry(stored.entry == EntryModel::Directional ? &weight : nullptr),
        transportRun(bake, stored, environment, run) {}
  StoredTransport stored;
  DirectionalAlbedoWeight weight;
  const DirectionalAlbedoWeight* entry;
  StoredTransportRun transportRun;
};

RelitLight relight(const std::string& path, const RelightableMesh& bake, const Cubemap& environment,
                   const RunContext& run) {
  const RelightTransfer& t = bake.transfer;
  RelightContext c(path, bake, environment, run);
  const CompactLightSplit split = splitCompactLights(environment);
  const SphericalHarmonics sh = SphericalHarmonics::project(split.rest, t.order, run.threads);
  std::vector<glm::vec3> b = transferredExitance(t.relightTransfer, t.order, sh);
  if (!split.lights.empty()) {
    const TriangleMesh& m = bake.meshMm;
    const std::vector<glm::vec3> e = directionalIrradiance(
        m.positions, m.normals, m.triangles, float(bake.material.eta), c.entry, split.lights, run);
    const std::vector<glm::vec3> compact = c.transportRun(e);
    for (std::size_t v = 0; v < b.size(); ++v) b[v] += compact[v];
  }
  if (c.stored.bounces > 0)
    b = bounced(bake, c.stored, c.entry, environment, c.transportRun, std::move(b), run);
  RelitLight out;
  out.radianceNormal = std::move(b);
  out.exitance.resize(out.radianceNormal.size());
  for (std::size_t v = 0; v < out.radianceNormal.size(); ++v) {
    // Light below zero (the SH light's ringing where the bake is dark) is no light.
    out.radianceNormal[v] = glm::max(out.radianceNormal[v], glm::vec3(0.0f)) * t.radianceGain[v];
    out.exitance[v] = out.radianceNormal[v] * t.exitancePerRadiance[v];
  }
  out.compactLights = int(split.lights.size());
  out.compactFluxShare = split.fluxShare;
  return out;
}

std::vector<glm::vec3> radianceGainOf(const std::string& path, const RelightableMesh& bake,
                                      const Cubemap& environment,
                                      std::span<const glm::vec3> ownIrradiance,
                                      std::span<const glm::vec3> radianceNormal,
                                      const RunContext& run) {
  RelightContext c(path, bake, environment, run);
  std::vector<glm::vec3> b = c.transportRun(ownIrradiance);
  if (c.stored.bounces > 0)
    b = bounced(bake, c.stored, c.entry, environment, c.transportRun, std::move(b), run);
  return ratios(radianceNormal, b, float(normalExitRadianceScale(float(bake.material.eta))));
}

void checkRelightTransport(const std::string& path, const BakedMesh& baked) {
  if (baked.relightOrder >= 0)
    parseTransportKey(path, baked.relightTransport, baked.escapeProbability.size());
}

RelitLight relightBakedMesh(const std::string& path, const BakedMesh& baked,
                            const Cubemap& environment, const RunContext& run) {
  if (baked.materialName.empty()) fail(path, "relightable bake without its material comments");
  TriangleMesh meshMm = baked.mesh;
  scalePositions(meshMm, baked.mmPerUnit);
  const Material material{.name = baked.materialName,
                          .sigmaA = baked.sigmaA,
                          .sigmaSPrime = baked.sigmaSPrime,
                          .eta = baked.eta};
  const RelightTransfer transfer = relightTransferOf(baked);
  return relight(path, {meshMm, material, transfer}, environment, run);
}

RelightTransfer relightTransferOf(const BakedMesh& baked) {
  RelightTransfer t;
  t.order = baked.relightOrder;
  t.relightTransfer = baked.relightTransfer;
  t.radianceGain = baked.radianceGain;
  t.exitancePerRadiance = baked.exitancePerRadiance;
  t.escapeProbability = baked.escapeProbability;
  t.relightTransport = baked.relightTransport;
  return t;
}

}  // namespace sss

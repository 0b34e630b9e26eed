#include "bake/bake.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "bake/diffusion.h"
#include "bake/finite_object_energy.h"
#include "bake/visibility.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/timer.h"
#include "core/tool.h"
#include "envmap/environment.h"
#include "irradiance/irradiance.h"
#include "material/diffusion_profile.h"
#include "mesh/load_mesh.h"
#include "mesh/triangle_mesh.h"
#include "mesh/units.h"
#include "pathtrace/subsurface_path_tracer.h"

namespace sss {

namespace {

using Json = nlohmann::ordered_json;

Json toJson(const glm::dvec3& v) {
  return Json::array({v.x, v.y, v.z});
}

std::string format(const char* fmt, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, fmt, value);
  return buffer;
}

// Root mean square over vertices of |stderr| / |value| in luminance, for vertices with light.
double relativeRms(const std::vector<glm::vec3>& value, const std::vector<glm::vec3>& stdErr) {
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < value.size() && i < stdErr.size(); ++i) {
    const double y = 0.2126 * value[i].r + 0.7152 * value[i].g + 0.0722 * value[i].b;
    const double e = 0.2126 * stdErr[i].r + 0.7152 * stdErr[i].g + 0.0722 * stdErr[i].b;
    if (y > 0.0) {
      sum += (e / y) * (e / y);
      ++count;
    }
  }
  return count ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

// Share of the tolerance that visibility noise may take with auto samples; the diffusion sum gets
// what the chosen rays leave in quadrature (at least sqrt(1 - 0.9^2) = 0.44 of it), so that
// sqrt(visibility^2 + diffusion^2) <= tolerance. Rays are the expensive part: on the 100K-vertex
// dragon (marble, forest, 1%) half the budget took 416 rays and 7.9 s, 0.9 of it ~180 rays,
// while the hierarchical sum at 0.44% instead of 0.87% costs ~0.2 s more.
constexpr double kVisibilityShare = 0.9;
// With the escape energy model its walks' noise takes a share too (the three add in quadrature);
// the larger one, as a walk buys less error than a visibility ray (bunny: ~5x the cost per unit
// variance).
constexpr double kVisibilityShareWithEnergy = 0.7;  // with kEscapeNoiseShare for the walks

}  // namespace

VisibilityNoiseModel visibilityNoiseModel(const VisibilityPilot& pilot,
                                          std::span<const glm::vec3> positionsMm,
                                          std::span<const float> areasMm2,
                                          const DiffusionProfile& profile) {
  VisibilityNoiseModel model;
  if (pilot.vertices.empty() || positionsMm.empty()) return model;
  if (areasMm2.size() != positionsMm.size()) fail("", "noise model: one area per vertex required");
  const double radius = profile.radiusContaining(0.999);
  // R_d tabulated on [0, radius] (linear interpolation): the sums below evaluate it millions of
  // times. Entry 0 at half a step, for profiles singular at r = 0 (Burley).
  constexpr int kTable = 4096;
  const double step = radius / kTable;
  std::vector<glm::dvec3> table(kTable + 2);
  for (int k = 0; k < kTable + 2; ++k) table[k] = profile.evaluate(k == 0 ? 0.5 * step : k * step);

  // Vertices sorted by grid cell (cell side = radius), so a pilot vertex's neighbours are in 27
  // cells found by binary search.
  struct Cell {
    int64_t x, y, z;
    uint32_t v;
    auto key() const { return std::tie(x, y, z); }
  };
  const auto cellOf = [&](const glm::vec3& p) {
    return glm::dvec3(std::floor(p.x / radius), std::floor(p.y / radius), std::floor(p.z / radius));
  };
  std::vector<Cell> cells(positionsMm.size());
  for (std::size_t i = 0; i < positionsMm.size(); ++i) {
    const glm::dvec3 c = cellOf(positionsMm[i]);
    cells[i] = {static_cast<int64_t>(c.x), static_cast<int64_t>(c.y), static_cast<int64_t>(c.z),
                static_cast<uint32_t>(i)};
  }
  std::sort(cells.begin(), cells.end(), [](const Cell& a, const Cell& b) {
    return a.key() < b.key() || (a.key() == b.key() && a.v < b.v);
  });

  const std::size_t m = pilot.vertices.size();
  std::vector<double> coarse(m), fine(m), denominator(m), effective(m);
  parallelFor(m, 0, 16, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      const uint32_t o = pilot.vertices[k];
      const glm::vec3 po = positionsMm[o];
      const glm::dvec3 self = profile.integrateDisc(std::sqrt(areasMm2[o] / M_PI));
      glm::dvec3 w1 = self, w2 = self * self;
      const glm::dvec3 c = cellOf(po);
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dz = -1; dz <= 1; ++dz) {
            const Cell query{static_cast<int64_t>(c.x) + dx, static_cast<int64_t>(c.y) + dy,
                             static_cast<int64_t>(c.z) + dz, 0};
            auto it =
                std::lower_bound(cells.begin(), cells.end(), query,
                                 [](const Cell& a, const Cell& b) { return a.key() < b.key(); });
            for (; it != cells.end() && it->key() == query.key(); ++it) {
              if (it->v == o) continue;
              const glm::vec3 d = positionsMm[it->v] - po;
              const double r = std::sqrt(static_cast<double>(glm::dot(d, d)));
              if (r >= radius) continue;
              const double x = r / step;
              const int j = static_cast<int>(x);
              const double f = x - j;
              const glm::dvec3 w =
                  ((1.0 - f) * table[j] + f * table[j + 1]) * static_cast<double>(areasMm2[it->v]);
              w1 += w;
              w2 += w * w;
            }
          }
        }
      }
      const glm::dvec3 e(pilot.irradiance[k]);
      coarse[k] = glm::dot(glm::dvec3(pilot.coarseVariance[k]), w2);
      fine[k] = glm::dot(glm::dvec3(pilot.fineVariance[k]), w2);
      denominator[k] = glm::dot(e * w1, e * w1);
      effective[k] = w2.g > 0.0 ? w1.g * w1.g / w2.g : 1.0;
    }
  });
  double coarseSum = 0.0, fineSum = 0.0, den = 0.0, neff = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    coarseSum += coarse[k];
    fineSum += fine[k];
    den += denominator[k];
    neff += effective[k];
  }
  model.fineRays = pilot.fineRays;
  model.variance = den > 0.0 ? fineSum / den : 0.0;
  // Rate between the levels, kept within plain Monte Carlo (1) and stratified sampling of a
  // discontinuity in 2D (1.5) against the noise of the estimate.
  model.rate =
      coarseSum > 0.0 && fineSum > 0.0
          ? std::clamp(std::log(coarseSum / fineSum) /
                           std::log(static_cast<double>(pilot.fineRays) / pilot.coarseRays),
                       1.0, 1.5)
          : 1.0;
  model.meanEffectiveVertices = neff / static_cast<double>(m);
  return model;
}

int chooseVisibilitySamples(const VisibilityNoiseModel& model, double budget) {
  if (!(model.variance > 0.0)) return kMinAutoSamples;
  if (!(budget > 0.0)) return kMaxAutoSamples;
  // errorAt(n) = budget solved for n, then rounded up to whole strata of 16.
  const double exact =
      model.fineRays * std::pow(model.variance / (budget * budget), 1.0 / model.rate);
  if (!(exact < kMaxAutoSamples)) return kMaxAutoSamples;
  const int rounded = static_cast<int>(std::ceil(exact / kAutoSampleStep)) * kAutoSampleStep;
  return std::clamp(rounded, kMinAutoSamples, kMaxAutoSamples);
}

VisibilityMode parseVisibilityMode(const std::string& name) {
  if (name == "none") return VisibilityMode::None;
  if (name == "rays") return VisibilityMode::Rays;
  fail("", "unknown visibility '" + name + "' (use none or rays)");
}

BakeOutput bake(const BakeSettings& settings) {
  const Stopwatch totalClock;
  // Everything that needs no file first, so that a typo costs nothing.
  validateMaterial(settings.material, "material");
  const bool pathTrace = settings.method == "pathtrace";
  const DiffusionMethod diffusionMethod =
      pathTrace ? DiffusionMethod::Auto : parseDiffusionMethod(settings.method);
  const EnergyModel energyModel = parseEnergyModel(settings.energy);
  if (settings.profile != "auto") makeProfile(settings.profile, settings.material);  // validates
  if (settings.sizeMm > 0.0) {
    if (!std::isfinite(settings.sizeMm)) fail("", "--size-mm must be finite");
  } else {
    checkMmPerUnit(settings.mmPerUnit);
  }
  const bool autoSamples = settings.samples == 0;
  if (!autoSamples && settings.samples < 2) fail("", "--samples must be at least 2 (or auto)");
  if (pathTrace && settings.walks < 1) fail("", "--walks must be at least 1");
  if (!(settings.tolerance > 0.0 && settings.tolerance < 1.0)) {
    fail("", "--tolerance must be in (0, 1), e.g. 0.01 for 1%");
  }

  Json report;
  Json stages = Json::object();
  Stopwatch clock;

  // Mesh.
  MeshReport meshReport;
  BakedMesh baked;
  baked.mesh = loadMesh(settings.meshPath, &meshReport);
  for (const std::string& w : meshReport.warnings) warn(settings.meshPath + ": " + w);
  TriangleMesh& mesh = baked.mesh;
  glm::vec3 lo = mesh.positions[0], hi = mesh.positions[0];
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const double longest = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  double mmPerUnit = settings.mmPerUnit;
  if (settings.sizeMm > 0.0) {
    if (!(longest > 0.0)) fail(settings.meshPath, "the mesh has no extent to scale (--size-mm)");
    mmPerUnit = settings.sizeMm / longest;
  }
  const double sizeMm = longest * mmPerUnit;
  if (sizeMm < 0.01 || sizeMm > 1e6) {
    warn(settings.meshPath + ": the mesh is " + format("%g", sizeMm) +
         " mm long: check --mm-per-unit / --unit");
  }
  TriangleMesh meshMm = mesh;
  scalePositions(meshMm, mmPerUnit);
  const std::vector<float> areas = vertexAreas(meshMm);
  stages["load_mesh_s"] = clock.seconds();
  info("mesh: " + std::to_string(mesh.vertexCount()) + " vertices, " +
           std::to_string(mesh.triangleCount()) + " triangles, " + format("%.4g", sizeMm) +
           " mm long",
       settings.quiet);

  // Environment.
  clock.restart();
  EnvironmentOptions envOptions;
  envOptions.faceSize = settings.environmentFaceSize;
  const Cubemap radiance = loadEnvironment(settings.environment, envOptions);
  stages["load_environment_s"] = clock.seconds();

  // Energy model (finite_object_energy.h), then the profile that suits it.
  clock.restart();
  EnergyPlan energy;
  if (!pathTrace) {
    EnergyOptions energyOptions;
    energyOptions.model = energyModel;
    energyOptions.noiseBudget = kEscapeNoiseShare * settings.tolerance;
    energyOptions.seed = settings.seed;
    energyOptions.threads = settings.threads;
    energyOptions.quiet = settings.quiet;
    energy = planFiniteObjectEnergy(meshMm, areas, settings.material, energyOptions);
    info("energy: " + toString(energy.model) + " (" + energy.reason + ")", settings.quiet);
    if (energy.model == EnergyModel::Escape &&
        energy.escape.relativeStdError > energyOptions.noiseBudget)
      warn("energy: " + energy.reason);
  }
  const bool escapeEnergy = energy.model == EnergyModel::Escape;
  const std::string profileName =
      settings.profile != "auto" ? settings.profile : autoProfileName(energy.model);
  const auto profile = makeProfile(profileName, settings.material);
  const double visibilityShare = escapeEnergy ? kVisibilityShareWithEnergy : kVisibilityShare;
  const double energyError = escapeEnergy ? energy.escape.relativeStdError : 0.0;
  stages["energy_s"] = clock.seconds();

  // Transmitted irradiance E per vertex.
  clock.restart();
  const float eta = static_cast<float>(settings.material.eta);
  Json visibilityJson;
  double visibilityError = 0.0;  // predicted relative RMS error of B from E's error
  // Without a visibility budget to share, the escape walks' noise still takes its part.
  double diffusionTolerance =
      std::max(std::sqrt(1.0 - kEscapeNoiseShare * kEscapeNoiseShare) * settings.tolerance,
               std::sqrt(std::max(
                   0.0, settings.tolerance * settings.tolerance - energyError * energyError)));
  visibilityJson["mode"] = settings.visibility == VisibilityMode::Rays ? "rays" : "none";
  if (settings.visibility == VisibilityMode::None) {
    IrradianceOptions irradianceOptions;
    irradianceOptions.eta = eta;
    irradianceOptions.tolerance = settings.tolerance;
    irradianceOptions.threads = settings.threads;
    const IrradianceResult irradiance = computeIrradiance(radiance, irradianceOptions);
    baked.irradiance.resize(mesh.vertexCount());
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
      baked.irradiance[v] = irradiance.irradiance.sample(mesh.normals[v]);
    }
    visibilityJson["irradiance_method"] = irradianceMethodName(irradiance.method);
    visibilityJson["irradiance_face_size"] = irradiance.irradiance.size();
    visibilityJson["estimated_error"] = irradiance.estimatedError;
    visibilityJson["reason"] = irradiance.reason;
    visibilityError = irradiance.estimatedError;
  } else {
    const double budget = visibilityShare * settings.tolerance;
    VisibilityOptions visibilityOptions;
    visibilityOptions.samples = settings.samples;
    visibilityOptions.seed = settings.seed;
    visibilityOptions.threads = settings.threads;
    visibilityOptions.quiet = settings.quiet;
    visibilityOptions.pilot = VisibilityPilotOptions{};
    VisibilityNoiseModel model;
    double modelSeconds = 0.0;
    visibilityOptions.chooseSamples = [&](const VisibilityPilot& pilot) {
      const Stopwatch modelClock;
      model = visibilityNoiseModel(pilot, meshMm.positions, areas, *profile);
      modelSeconds = modelClock.seconds();
      return autoSamples ? chooseVisibilitySamples(model, budget) : settings.samples;
    };
    VisibilityReport visibilityReport;
    baked.irradiance =
        transmittedIrradianceWithVisibility(meshMm.positions, meshMm.normals, meshMm.triangles,
                                            radiance, eta, visibilityOptions, &visibilityReport);
    const int samples = visibilityReport.samples;
    visibilityError = model.errorAt(samples);
    if (autoSamples) {
      const double energyShare = escapeEnergy ? kEscapeNoiseShare : 0.0;
      diffusionTolerance =
          std::max(std::sqrt(1.0 - visibilityShare * visibilityShare - energyShare * energyShare) *
                       settings.tolerance,
                   std::sqrt(std::max(0.0, settings.tolerance * settings.tolerance -
                                               visibilityError * visibilityError -
                                               energyError * energyError)));
    }
    std::string reason;
    if (!autoSamples) {
      reason = "forced by --samples";
    } else if (visibilityError <= budget) {
      reason = "fewest rays (a multiple of " + std::to_string(kAutoSampleStep) + ", " +
               std::to_string(kMinAutoSamples) + ".." + std::to_string(kMaxAutoSamples) +
               ") whose predicted noise in B " + format("%.3g%%", 100.0 * visibilityError) +
               " meets its budget " + format("(%.3g%% of the tolerance)", 100.0 * visibilityShare) +
               "; the diffusion sum gets the rest in quadrature";
    } else {
      reason = "capped at " + std::to_string(kMaxAutoSamples) + " rays: the predicted noise in B " +
               format("%.3g%%", 100.0 * visibilityError) + " exceeds its budget " +
               format("(%.3g%% of the tolerance)", 100.0 * visibilityShare);
      warn("visibility: " + reason);
    }
    // Per-vertex noise of E from the pilot (replica spread, all channels).
    double eVariance = 0.0, eSquare = 0.0;
    const VisibilityPilot& pilot = visibilityReport.pilot;
    for (std::size_t k = 0; k < pilot.vertices.size(); ++k) {
      const glm::dvec3 var(pilot.fineVariance[k]), e(pilot.irradiance[k]);
      eVariance += (var.r + var.g + var.b) *
                   std::pow(static_cast<double>(pilot.fineRays) / samples, model.rate);
      eSquare += glm::dot(e, e);
    }
    visibilityJson["samples"] = samples;
    visibilityJson["samples_requested"] = autoSamples ? Json("auto") : Json(settings.samples);
    visibilityJson["samples_reason"] = reason;
    visibilityJson["seed"] = settings.seed;
    visibilityJson["rays"] = visibilityReport.rays;
    visibilityJson["occluded_fraction"] = visibilityReport.occludedFraction;
    // Predicted relative RMS error of B from the visibility noise (the noise model in bake.h).
    visibilityJson["estimated_error"] = visibilityError;
    visibilityJson["estimated_error_E"] = eSquare > 0.0 ? std::sqrt(eVariance / eSquare) : 0.0;
    // The per-technique bound of one estimate (ignores stratification: 2.5-4x too high).
    visibilityJson["error_bound_E"] = visibilityReport.relativeStdError;
    visibilityJson["budget"] = autoSamples ? budget : settings.tolerance;
    visibilityJson["pilot"] = {{"vertices", pilot.vertices.size()},
                               {"replicas", pilot.replicas},
                               {"rays_per_replica", {pilot.coarseRays, pilot.fineRays}},
                               {"convergence_rate", model.rate},
                               {"rays", pilot.rays},
                               {"effective_vertices", model.meanEffectiveVertices},
                               {"seconds", pilot.seconds},
                               {"noise_model_s", modelSeconds}};
    visibilityJson["bvh_build_s"] = visibilityReport.buildSeconds;
    visibilityJson["trace_s"] = visibilityReport.traceSeconds;
  }
  stages["irradiance_s"] = clock.seconds();
  info("irradiance (" + visibilityJson["mode"].get<std::string>() +
           "): " + format("%.3f s", stages["irradiance_s"].get<double>()),
       settings.quiet);

  // Exitance B per vertex.
  clock.restart();
  Json methodJson;
  if (pathTrace) {
    PathTraceOptions options;
    options.samples = settings.walks;
    options.seed = settings.seed;
    options.threads = settings.threads;
    options.quiet = settings.quiet;
    options.estimateRadiance = false;
    PathTraceResult result = pathTraceSubsurface(meshMm, radiance, settings.material, options);
    baked.exitance = std::move(result.exitance);
    methodJson["method"] = "pathtrace";
    methodJson["walks"] = settings.walks;
    methodJson["g"] = settings.material.g;
    methodJson["mean_scattering_events"] = result.meanScatteringEvents;
    methodJson["truncated_walks"] = result.truncatedWalks;
    methodJson["escaped_walks"] = result.escapedWalks;
    methodJson["estimated_error"] = relativeRms(baked.exitance, result.exitanceStdErr);
    methodJson["warnings"] = result.warnings;
  } else {
    DiffusionInput input{meshMm.positions, meshMm.normals, areas, baked.irradiance};
    DiffusionOptions options;
    options.method = diffusionMethod;
    options.tolerance = diffusionTolerance;
    options.threads = settings.threads;
    options.quiet = settings.quiet;
    DiffusionResult result = diffuseWithEnergy(input, *profile, options, energy, settings.material);
    baked.exitance = std::move(result.exitance);
    const DiffusionReport& r = result.report;
    methodJson["method"] = toString(r.method);
    methodJson["requested"] = settings.method;
    methodJson["reason"] = r.reason;
    methodJson["tolerance"] = diffusionTolerance;
    methodJson["cutoffs_mm"] = r.cutoffs;
    if (r.clusterTheta > 0) methodJson["cluster_theta"] = r.clusterTheta;
    methodJson["interactions"] = r.interactions;
    methodJson["estimated_error"] = r.estimatedError;
    methodJson["fit_s"] = r.fitSeconds;
    methodJson["index_s"] = r.indexSeconds;
    methodJson["sum_s"] = r.sumSeconds;
    Json fit;
    fit["gaussians"] = r.gaussians;
    fit["error"] = r.fitError;
    fit["variances_mm2"] = r.variances;
    methodJson["profile_fit"] = fit;
  }
  stages["exitance_s"] = clock.seconds();
  info(methodJson["method"].get<std::string>() + ": " +
           format("%.3f s", stages["exitance_s"].get<double>()),
       settings.quiet);

  baked.materialName = settings.material.name;
  baked.sigmaA = settings.material.sigmaA;
  baked.sigmaSPrime = settings.material.sigmaSPrime;
  baked.eta = settings.material.eta;
  baked.mmPerUnit = mmPerUnit;
  baked.extraComments.push_back(
      "bake method=" + methodJson["method"].get<std::string>() +
      (pathTrace ? "" : " profile=" + profileName + " energy=" + toString(energy.model)) +
      " visibility=" + visibilityJson["mode"].get<std::string>() + " samples=" +
      (settings.visibility == VisibilityMode::Rays ? visibilityJson["samples"].dump()
                                                   : std::string("0")) +
      " seed=" + std::to_string(settings.seed));

  report["mesh"] = {{"file", settings.meshPath},
                    {"format", meshReport.format},
                    {"vertices", mesh.vertexCount()},
                    {"triangles", mesh.triangleCount()},
                    {"file_vertices", meshReport.fileVertices},
                    {"file_faces", meshReport.fileFaces},
                    {"dropped_degenerate", meshReport.droppedDegenerate},
                    {"dropped_duplicate", meshReport.droppedDuplicate},
                    {"dropped_unreferenced", meshReport.droppedUnreferenced},
                    {"non_manifold_edges", meshReport.nonManifoldEdges},
                    {"non_manifold_vertices", meshReport.nonManifoldVertices},
                    {"boundary_edges", meshReport.boundaryEdges},
                    {"components", meshReport.components},
                    {"normals_computed", meshReport.normalsComputed},
                    {"orientation_flipped", meshReport.orientationFlipped},
                    {"surface_area_mm2", surfaceArea(meshMm)}};
  report["units"] = {{"mm_per_unit", mmPerUnit}, {"longest_side_mm", sizeMm}};
  report["environment"] = {{"source", settings.environment}, {"face_size", radiance.size()}};
  report["material"] = {
      {"name", settings.material.name},
      {"sigma_a_per_mm", toJson(settings.material.sigmaA)},
      {"sigma_s_prime_per_mm", toJson(settings.material.sigmaSPrime)},
      {"eta", settings.material.eta},
      {"diffuse_mean_free_path_mm", toJson(settings.material.diffuseMeanFreePath())}};
  if (!pathTrace) {
    report["profile"] = {{"name", profile->name()},
                         {"requested", settings.profile},
                         {"total_reflectance", toJson(profile->totalReflectance())}};
    Json energyJson = {{"model", toString(energy.model)},
                       {"requested", settings.energy},
                       {"reason", energy.reason},
                       {"halfspace_albedo", toJson(energy.halfSpaceAlbedo)},
                       {"seconds", energy.seconds}};
    if (energyModel != EnergyModel::HalfSpace) {
      energyJson["halfspace_deviation"] = energy.halfSpaceDeviation;
      energyJson["mean_escape_probability"] = toJson(energy.escape.mean);
      energyJson["probes"] = energy.escape.probes;
      energyJson["walks_per_probe"] = energy.walks;
      energyJson["lost_walks"] = energy.escape.lostWalks;
      energyJson["mean_scattering_events"] = energy.escape.meanScatteringEvents;
      energyJson["smoothing_sigma_mm"] = toJson(energy.escape.smoothingSigmaMm);
      energyJson["estimated_error"] = energyError;
    }
    report["energy"] = energyJson;
  }
  report["visibility"] = visibilityJson;
  report["exitance"] = methodJson;
  // Total: the visibility (or irradiance) error and the method's own, independent, in quadrature.
  // Pathtrace walks do not use E, so only their own error counts.
  const double methodError = methodJson["estimated_error"].get<double>();
  const double totalError =
      pathTrace ? methodError : std::hypot(visibilityError, methodError, energyError);
  report["estimated_error"] = {{"visibility", pathTrace ? 0.0 : visibilityError},
                               {"exitance", methodError},
                               {"energy", energyError},
                               {"total", totalError},
                               {"tolerance", settings.tolerance}};
  report["threads"] = settings.threads;
  stages["total_s"] = totalClock.seconds();
  report["stages"] = stages;
  return {std::move(baked), report.dump(2) + "\n"};
}

}  // namespace sss

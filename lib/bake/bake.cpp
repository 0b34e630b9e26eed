#include "bake/bake.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include "bake/diffusion.h"
#include "bake/visibility.h"
#include "core/error.h"
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

}  // namespace

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
  const auto profile = makeProfile(settings.profile, settings.material);
  if (settings.sizeMm > 0.0) {
    if (!std::isfinite(settings.sizeMm)) fail("", "--size-mm must be finite");
  } else {
    checkMmPerUnit(settings.mmPerUnit);
  }
  if (settings.samples < 2) fail("", "--samples must be at least 2");
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

  // Transmitted irradiance E per vertex.
  clock.restart();
  const float eta = static_cast<float>(settings.material.eta);
  Json visibilityJson;
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
  } else {
    VisibilityOptions visibilityOptions;
    visibilityOptions.samples = settings.samples;
    visibilityOptions.seed = settings.seed;
    visibilityOptions.threads = settings.threads;
    visibilityOptions.quiet = settings.quiet;
    VisibilityReport visibilityReport;
    baked.irradiance =
        transmittedIrradianceWithVisibility(meshMm.positions, meshMm.normals, meshMm.triangles,
                                            radiance, eta, visibilityOptions, &visibilityReport);
    visibilityJson["samples"] = settings.samples;
    visibilityJson["seed"] = settings.seed;
    visibilityJson["rays"] = visibilityReport.rays;
    visibilityJson["occluded_fraction"] = visibilityReport.occludedFraction;
    visibilityJson["estimated_error"] = visibilityReport.relativeStdError;
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
    options.tolerance = settings.tolerance;
    options.threads = settings.threads;
    options.quiet = settings.quiet;
    DiffusionResult result = diffuse(input, *profile, options);
    baked.exitance = std::move(result.exitance);
    const DiffusionReport& r = result.report;
    methodJson["method"] = toString(r.method);
    methodJson["requested"] = settings.method;
    methodJson["reason"] = r.reason;
    methodJson["tolerance"] = settings.tolerance;
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
  baked.extraComments.push_back("bake method=" + methodJson["method"].get<std::string>() +
                                (pathTrace ? "" : " profile=" + settings.profile) +
                                " visibility=" + visibilityJson["mode"].get<std::string>() +
                                " samples=" + std::to_string(settings.samples) +
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
                         {"total_reflectance", toJson(profile->totalReflectance())}};
  }
  report["visibility"] = visibilityJson;
  report["exitance"] = methodJson;
  report["threads"] = settings.threads;
  stages["total_s"] = totalClock.seconds();
  report["stages"] = stages;
  return {std::move(baked), report.dump(2) + "\n"};
}

}  // namespace sss

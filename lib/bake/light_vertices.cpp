#include "bake/light_vertices.h"

#include "core/format.h"
#include "core/timer.h"
#include "core/tool.h"
#include "envmap/cubemap.h"
#include "lighting/facet_light.h"
#include "mesh/triangle_mesh.h"

namespace sss {

namespace {

// E from the irradiance cubemap at each vertex's facets (their area-weighted mean, as the rays
// take it: visibility.h): no shadows.
std::vector<glm::vec3> lightFromCubemap(const LightingInput& in, LightingReport& report) {
  IrradianceOptions options;
  options.eta = in.eta;
  options.tolerance = in.tolerance;
  options.threads = in.run.threads;
  const IrradianceResult irradiance = computeIrradiance(in.radiance, options);
  const VertexFacets facets =
      lightFacets(in.meshMm.positions, in.meshMm.normals, in.meshMm.triangles);
  std::vector<glm::vec3> e(in.meshMm.vertexCount());
  for (std::size_t v = 0; v < e.size(); ++v)
    forEachLightFacet(facets, v, in.meshMm.normals[v], [&](const glm::vec3& n, float share) {
      e[v] += share * irradiance.irradiance.sample(n);
    });
  report.cubemap.method = irradiance.method;
  report.cubemap.faceSize = irradiance.irradiance.size();
  report.cubemap.reason = irradiance.reason;
  report.estimatedError = irradiance.estimatedError;
  return e;
}

// Why the rays per vertex are what they are; warns when auto hit the cap.
std::string samplesReason(const LightingInput& in, double error, double share) {
  if (in.samples != 0) return "forced by the requested sample count";
  const int cap = maxAutoSamples(in.meshMm.vertexCount());
  if (error <= in.visibilityBudget) {
    return "fewest rays (a multiple of " + std::to_string(kAutoSampleStep) + ", " +
           std::to_string(kMinAutoSamples) + ".." + std::to_string(cap) +
           ") whose predicted noise in B " + percent(error) + " meets its budget (" +
           percent(share) + " of the tolerance); the diffusion sum gets the rest in quadrature";
  }
  const std::string reason = "capped at " + std::to_string(cap) +
                             " rays: the predicted noise in B " + percent(error) +
                             " exceeds its budget (" + percent(share) + " of the tolerance)";
  warn("visibility: " + reason);
  return reason;
}

// E with the mesh's own shadows, the ray count from the pilot's noise model when auto.
std::vector<glm::vec3> lightWithRays(const LightingInput& in, LightingReport& report,
                                     std::vector<glm::vec3>& entryWeighted,
                                     CosineHits& cosineHits) {
  RayLightingReport& rays = report.rays;
  VisibilityOptions options;
  options.samples = in.samples;
  options.run = in.run;
  options.entry = in.entry;
  options.keepCosineHitsUpTo = in.keepCosineHitsUpTo;
  options.scene = in.rayScene;
  options.pilot = VisibilityPilotOptions{};
  options.chooseSamples = [&](const VisibilityPilot& pilot) {
    const Stopwatch clock;
    rays.noiseModel = visibilityNoiseModel(pilot, in.meshMm.positions, in.areasMm2, in.profile);
    rays.noiseModelSeconds = clock.seconds();
    return in.samples == 0 ? chooseVisibilitySamples(rays.noiseModel, in.visibilityBudget,
                                                     maxAutoSamples(in.meshMm.vertexCount()))
                           : in.samples;
  };
  std::vector<glm::vec3> e = transmittedIrradianceWithVisibility(
      in.meshMm.positions, in.meshMm.normals, in.meshMm.triangles, in.radiance, in.eta, options,
      &rays.visibility);
  rays.samples = rays.visibility.samples;
  rays.samplesRequested = in.samples;
  rays.seed = in.run.seed;
  report.estimatedError = rays.noiseModel.errorAt(rays.samples);
  rays.samplesReason = samplesReason(in, report.estimatedError, in.visibilityShare);
  rays.irradianceError = rays.noiseModel.irradianceErrorAt(rays.visibility.pilot, rays.samples);
  rays.budget = in.samples == 0 ? in.visibilityBudget : in.tolerance;
  entryWeighted = std::move(rays.visibility.entryWeighted);
  cosineHits = std::move(rays.visibility.cosineHits);
  rays.visibility.cosineHits = {};
  return e;
}

}  // namespace

VertexLighting lightVertices(const LightingInput& in) {
  const Stopwatch clock;
  VertexLighting out;
  out.report.mode = in.mode;
  out.irradiance = in.mode == VisibilityMode::None
                       ? lightFromCubemap(in, out.report)
                       : lightWithRays(in, out.report, out.entryWeighted, out.cosineHits);
  out.report.entry = out.entryWeighted.empty() ? EntryModel::Diffuse : EntryModel::Directional;
  out.report.seconds = clock.seconds();
  info("irradiance (" + std::string(kVisibilityModeNames.name(in.mode)) +
           "): " + format("%.3f s", out.report.seconds),
       in.run.quiet);
  return out;
}

}  // namespace sss

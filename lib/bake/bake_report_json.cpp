#include "bake/bake_report_json.h"

namespace sss {

namespace {

Json toJson(const glm::dvec3& v) {
  return Json::array({v.x, v.y, v.z});
}

Json pilotJson(const RayLightingReport& r) {
  const VisibilityPilot& pilot = r.visibility.pilot;
  return {{"vertices", pilot.vertices.size()},
          {"replicas", pilot.replicas},
          {"rays_per_replica", {pilot.coarseRays, pilot.fineRays}},
          {"convergence_rate", r.noiseModel.rate},
          {"rays", pilot.rays},
          {"effective_vertices", r.noiseModel.meanEffectiveVertices},
          {"seconds", pilot.seconds},
          {"noise_model_s", r.noiseModelSeconds}};
}

Json profileJson(const EnergyStageReport& r) {
  return {{"name", r.profileName},
          {"requested", kProfileChoiceNames.name(r.profileRequested)},
          {"total_reflectance", toJson(r.profileTotalReflectance)}};
}

Json materialJson(const Material& m) {
  return {{"name", m.name},
          {"sigma_a_per_mm", toJson(m.sigmaA)},
          {"sigma_s_prime_per_mm", toJson(m.sigmaSPrime)},
          {"eta", m.eta},
          {"diffuse_mean_free_path_mm", toJson(m.diffuseMeanFreePath())}};
}

}  // namespace

Json toJson(const MeshStageReport& r) {
  const MeshReport& m = r.load;
  Json j = {{"file", r.file},
            {"format", m.format},
            {"vertices", r.vertices},
            {"triangles", r.triangles},
            {"file_vertices", m.fileVertices},
            {"file_faces", m.fileFaces},
            {"dropped_degenerate", m.droppedDegenerate},
            {"dropped_duplicate", m.droppedDuplicate},
            {"dropped_unreferenced", m.droppedUnreferenced},
            {"non_manifold_edges", m.nonManifoldEdges},
            {"non_manifold_vertices", m.nonManifoldVertices},
            {"boundary_edges", m.boundaryEdges},
            {"components", m.components},
            {"normals_computed", m.normalsComputed},
            {"orientation_flipped", m.orientationFlipped},
            {"surface_area_mm2", r.surfaceAreaMm2}};
  if (r.parts.empty()) return j;
  // A glTF's parts, in the order its scene places them.
  Json parts = Json::array();
  for (const MeshPart& p : r.parts) {
    parts.push_back({{"node", p.node},
                     {"node_index", p.nodeIndex},
                     {"mesh", p.mesh},
                     {"mesh_index", p.meshIndex},
                     {"primitive", p.primitive},
                     {"material", p.material},
                     {"triangles", p.triangles},
                     {"texcoords", p.hasTexcoords}});
  }
  j["parts"] = parts;
  j["welded_vertices"] = r.weldedVertices;
  j["texcoords"] = r.texcoords;
  return j;
}

Json toJson(const EnergyStageReport& r) {
  const EnergyPlan& plan = r.plan;
  Json j = {{"model", kEnergyModelNames.name(plan.model)},
            {"requested", kEnergyModelNames.name(r.requested)},
            {"reason", plan.reason},
            {"halfspace_albedo", toJson(plan.halfSpaceAlbedo)},
            {"seconds", plan.seconds}};
  if (r.requested != EnergyModel::HalfSpace) {
    j["halfspace_deviation"] = plan.halfSpaceDeviation;
    j["mean_escape_probability"] = toJson(plan.escape.mean);
    j["probes"] = plan.escape.probes;
    j["walks_per_probe"] = plan.walks;
    j["lost_walks"] = plan.escape.lostWalks;
    j["mean_scattering_events"] = plan.escape.meanScatteringEvents;
    j["smoothing_sigma_mm"] = toJson(plan.escape.smoothingSigmaMm);
    j["estimated_error"] = r.walkError();
    if (r.farField) {
      j["near_share"] = plan.escape.nearShare;
      j["near_share_error"] = plan.escape.nearErrorInB();
    }
  }
  return j;
}

Json toJson(const LightingReport& r) {
  Json j;
  j["mode"] = kVisibilityModeNames.name(r.mode);
  j["entry"] = kEntryModelNames.name(r.entry);
  if (r.mode == VisibilityMode::None) {
    j["irradiance_method"] = kIrradianceMethodNames.name(r.cubemap.method);
    j["irradiance_face_size"] = r.cubemap.faceSize;
    j["estimated_error"] = r.estimatedError;
    j["reason"] = r.cubemap.reason;
    return j;
  }
  const RayLightingReport& rays = r.rays;
  j["samples"] = rays.samples;
  j["samples_requested"] = rays.samplesRequested == 0 ? Json("auto") : Json(rays.samplesRequested);
  j["samples_reason"] = rays.samplesReason;
  j["seed"] = rays.seed;
  j["rays"] = rays.visibility.rays;
  j["occluded_fraction"] = rays.visibility.occludedFraction;
  j["estimated_error"] = r.estimatedError;  // of B, from the noise model
  j["estimated_error_E"] = rays.irradianceError;
  // The per-technique bound of one estimate (ignores stratification, so it is too high).
  j["error_bound_E"] = rays.visibility.relativeStdError;
  j["budget"] = rays.budget;
  j["pilot"] = pilotJson(rays);
  j["bvh_build_s"] = rays.visibility.buildSeconds;
  j["trace_s"] = rays.visibility.traceSeconds;
  j["unoccluded_s"] = rays.visibility.unoccludedSeconds;
  return j;
}

Json toJson(const TransportReport& r) {
  Json j;
  if (r.pathTrace) {
    const PathTraceStageReport& p = r.pathTracer;
    j["method"] = r.methodName();
    j["walks"] = p.walks;
    j["g"] = p.g;
    j["mean_scattering_events"] = p.meanScatteringEvents;
    j["truncated_walks"] = p.truncatedWalks;
    j["escaped_walks"] = p.escapedWalks;
    j["estimated_error"] = r.estimatedError;
    j["warnings"] = p.warnings;
    return j;
  }
  const DiffusionReport& d = r.diffusion;
  j["method"] = r.methodName();
  j["requested"] = kBakeMethodNames.name(r.requested);
  j["reason"] = d.reason;
  j["tolerance"] = r.diffusionTolerance;
  j["cutoffs_mm"] = d.cutoffs;
  if (d.clusterTheta > 0) j["cluster_theta"] = d.clusterTheta;
  j["interactions"] = d.interactions;
  j["estimated_error"] = r.estimatedError;
  j["near_part_noise"] = r.nearPartNoise;
  j["fit_s"] = d.fitSeconds;
  j["index_s"] = d.indexSeconds;
  j["sum_s"] = d.sumSeconds;
  j["profile_fit"] = {
      {"gaussians", d.gaussians}, {"error", d.fitError}, {"variances_mm2", d.variances}};
  return j;
}

// What every traced stage reports (transport/traced_stage.h); paths and noise only when traced.
template <std::size_t N>
Json tracedStageJson(const TracedStageReport& r, const EnumNames<TracedMode, N>& modeNames) {
  return {{"requested", modeNames.name(r.requested)},
          {"traced", r.traced},
          {"reason", r.reason},
          {"seconds", r.seconds}};
}
void addTracedPaths(Json& j, const TracedStageReport& r) {
  j["paths"] = r.paths;
  j["estimated_error"] = r.relativeStdError;
}

Json toJson(const FarFieldReport& r) {
  Json j = tracedStageJson(r, kFarFieldModeNames);
  if (r.requested == FarFieldMode::Off || r.windowMm == glm::dvec3(0.0)) return j;
  j["sensitivity"] = r.sensitivity;
  j["near_window_mm"] = toJson(r.windowMm);
  if (!r.traced) return j;
  j["smoothing_sigma_mm"] = r.smoothingMm;
  addTracedPaths(j, r);
  j["averaging_bias"] = r.averagingBias;
  j["lobe_noise"] = r.lobeNoise;
  j["mean_exit_slope"] = toJson(r.meanExitSlope);
  return j;
}

Json toJson(const UnscatteredLightReport& r) {
  Json j = tracedStageJson(r, kUnscatteredModeNames);
  if (r.requested == UnscatteredMode::Off) return j;
  j["share"] = r.share;
  if (r.traced) addTracedPaths(j, r);
  return j;
}

Json toJson(const BakeErrorReport& r) {
  Json j = {{"visibility", r.visibility},
            {"exitance", r.exitance},
            {"energy", r.energy},
            {"interreflection", r.interreflection},
            {"unscattered", r.unscattered},
            {"exit_lobe", r.exitLobe},
            {"numerical", r.numerical},
            {"model",
             {{"exit_model", r.model.exitModel},
              {"facets", r.model.facets},
              {"facet_light", r.model.facetLight},
              {"far_field", r.model.farField},
              {"interreflection", r.model.interreflection},
              {"total", r.model.total},
              {"seconds", r.model.seconds}}},
            {"total", r.total},
            {"tolerance", r.tolerance},
            {"tolerance_met", r.total <= r.tolerance}};
  if (r.model.materialInterface > 0.0) j["model"]["material_interface"] = r.model.materialInterface;
  return j;
}

Json toJson(const LightmapReport& r) {
  const double texels = double(r.size) * r.size;
  return {{"size", r.size},
          {"padding_texels", r.padding},
          {"original_vertices", r.originalVertices},
          {"original_triangles", r.originalTriangles},
          {"refined_vertices", r.refinedVertices},
          {"refined_triangles", r.refinedTriangles},
          {"covered_texels", r.coveredTexels},
          {"covered_fraction", double(r.coveredTexels) / texels},
          {"padded_texels", r.paddedTexels},
          {"overlapping_texels", r.overlappingTexels},
          {"seams",
           {{"edges", r.seams.edges},
            {"relative_rms", r.seams.relativeRms},
            {"worst_relative", r.seams.worstRelative}}},
          {"refine_s", r.refineSeconds},
          {"fill_s", r.fillSeconds}};
}

Json toJson(const BakeReport& r) {
  Json j;
  j["mesh"] = toJson(r.mesh);
  j["units"] = {{"mm_per_unit", r.mesh.mmPerUnit}, {"longest_side_mm", r.mesh.longestSideMm}};
  if (r.mesh.unitFromFile) j["units"]["from_file"] = true;
  j["environment"] = {{"source", r.environment.source},
                      {"face_size", r.environment.faceSize},
                      {"convention", r.environment.convention},
                      {"rotate_deg", r.environment.rotateDeg}};
  j["material"] = materialJson(r.material);
  if (!r.materials.empty()) {
    Json materials = Json::array();
    for (const MaterialBakeReport& m : r.materials) {
      Json one = materialJson(m.material);
      one["parts"] = m.parts;
      one["area_share"] = m.areaShare;
      one["method"] = m.method;
      one["estimated_error"] = toJson(m.errors);
      one["seconds"] = m.seconds;
      materials.push_back(std::move(one));
    }
    j["part_materials"] = std::move(materials);
  }
  if (!r.transport.pathTrace) {
    j["profile"] = profileJson(r.energy);
    j["energy"] = toJson(r.energy);
    j["far_field"] = toJson(r.farField);
    j["exit_lobe"] = {{"source", r.exitLobe.source},
                      {"mean_slope", toJson(r.exitLobe.meanSlope)},
                      {"noise", r.exitLobe.noise}};
  }
  j["visibility"] = toJson(r.lighting);
  j["exitance"] = toJson(r.transport);
  j["interreflection"] = {{"enabled", r.interreflection.enabled},
                          {"bounces_requested", r.interreflection.automatic ? "auto" : "count"},
                          {"bounces", r.interreflection.bounces},
                          {"last_change", r.interreflection.change},
                          {"blocked_fraction", r.interreflection.blockedFraction},
                          {"gather_noise", r.interreflection.gatherNoise},
                          {"remaining", r.interreflection.remaining},
                          {"geometric_tail", r.interreflection.tail},
                          {"gather_rays", r.interreflection.gatherRays},
                          {"gather_rays_reused", r.interreflection.reusedRays},
                          {"seconds", r.interreflection.seconds}};
  if (r.interreflection.estimated) {
    j["interreflection"]["estimated_missing"] = r.interreflection.estimatedMissing;
    j["interreflection"]["pilot_vertices"] = r.interreflection.pilotVertices;
  }
  j["unscattered"] = toJson(r.unscattered);
  j["estimated_error"] = toJson(r.errors);
  if (r.lightmap.size > 0) j["texture"] = toJson(r.lightmap);
  if (r.relight.order >= 0)
    j["relightable"] = {{"sh_order", r.relight.order},
                        {"coefficients", r.relight.coefficients},
                        {"rays_per_vertex", r.relight.rays},
                        {"blocked_fraction", r.relight.blockedFraction},
                        {"self_relative_rms", r.relight.selfError},
                        {"transfer_s", r.relight.transferSeconds},
                        {"transport_s", r.relight.transportSeconds},
                        {"seconds", r.relight.seconds}};
  j["threads"] = r.threads;
  j["stages"] = {{"load_mesh_s", r.mesh.seconds},
                 {"load_environment_s", r.environment.seconds},
                 {"energy_s", r.energy.seconds},
                 {"ray_scene_s", r.raySceneSeconds},
                 {"irradiance_s", r.lighting.seconds},
                 {"far_field_s", r.farField.seconds},
                 {"exitance_s", r.transport.seconds},
                 {"unscattered_s", r.unscattered.seconds},
                 {"model_error_s", r.errors.model.seconds},
                 {"total_s", r.totalSeconds}};
  return j;
}

}  // namespace sss

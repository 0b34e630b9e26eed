// What a bake did, stage by stage: each stage's own report (counts, choices and why, timings),
// gathered once. bake_report_json.h turns it into the JSON of `sss-bake --json`.
#pragma once

#include <string>
#include <vector>

#include "bake/light_vertices.h"
#include "bake/plan_energy.h"
#include "bake/prepare_mesh.h"
#include "bake/relight.h"
#include "bake/texture_stage.h"
#include "bake/transport.h"
#include "material/material.h"
#include "transport/far_field.h"
#include "transport/model_error.h"
#include "transport/unscattered_light.h"

namespace sss {

struct EnvironmentStageReport {
  std::string source;              // the file, or "sky[:spec]"
  int faceSize = 0;                // of the radiance cubemap
  std::string convention = "sss";  // --env-convention (equirect sources)
  double rotateDeg = 0.0;          // --env-rotate
  double seconds = 0.0;
};

// Predicted relative RMS errors of B, independent, so they add in quadrature (error_budget.h):
// the numerical ones, which the tolerance controls, and the model's own (model_error.h).
struct BakeErrorReport {
  double visibility = 0.0;  // from E (visibility noise or the irradiance cubemap)
  double exitance = 0.0;    // the transport method's own
  double energy = 0.0;      // the escape walks' noise
  // Without bounces a model error, the light the object sends itself that they would add
  // (estimateMissingInterreflection); with them, the noise of the gather's rays
  // (predictGatherNoise) and what the bounces not done would add, in quadrature.
  double interreflection = 0.0;
  // Of the radiance along the normal: the traced unscattered light's noise, or the share of it
  // that auto found negligible and left out.
  double unscattered = 0.0;
  // Of the radiance along the normal: the exit lobe's noise (ExitLobeReport::noise).
  double exitLobe = 0.0;
  double numerical = 0.0;  // the six above in quadrature: what the tolerance bounds
  ModelErrorReport model;  // of the radiance along the normal
  double total = 0.0;      // numerical and model in quadrature
  double tolerance = 0.0;
};

// Interreflection (interreflection.h): whether it ran, how many bounces, the last change of B.
struct InterreflectionReport {
  bool enabled = false;
  bool automatic = false;        // bounces chosen by convergence
  int bounces = 0;               // gathers done
  double change = 0.0;           // relative RMS change of B at the last bounce
  double blockedFraction = 0.0;  // of the gather's rays, those that met the object
  // Without bounces: the pilot's estimate of the share of B they would add (relative RMS).
  bool estimated = false;
  double estimatedMissing = 0.0;
  int pilotVertices = 0;
  double gatherNoise = 0.0;  // with bounces: predicted relative RMS noise of B from the gather
  double remaining = 0.0;    // with bounces: what the bounces not done would add (BounceResult)
  bool tail = false;         // with bounces: their geometric tail was added (auto)
  int gatherRays = 0;        // with bounces: the gather's rays per vertex
  int reusedRays = 0;        // of them, the visibility's cosine rays (0: all traced for it)
  double seconds = 0.0;
};

// With several materials (material_parts.h), each material's own bake of the whole object.
struct MaterialBakeReport {
  Material material;
  std::vector<std::string> parts;  // the material keys of the parts it bakes (mesh_parts.h)
  double areaShare = 0.0;          // of the surface
  std::string method;              // its transport's
  BakeErrorReport errors;
  double seconds = 0.0;
};

// The exit lobe B leaves through (optics/exit_lobe.h): "far field" (its traced exits'),
// "half-space" (the half-space Monte Carlo's radiance along the normal, in the channels where it
// departs from the normalized model), or "normalized" (slope 0 everywhere).
struct ExitLobeReport {
  std::string source = "normalized";
  glm::dvec3 meanSlope{0.0};  // area-weighted (the far field's: weighted by B_far)
  double noise = 0.0;         // of the radiance along the normal, relative RMS
};

struct BakeReport {
  MeshStageReport mesh;
  EnvironmentStageReport environment;
  Material material;
  EnergyStageReport energy;  // also the profile; empty for the path tracer
  LightingReport lighting;
  FarFieldReport farField;
  ExitLobeReport exitLobe;
  TransportReport transport;
  InterreflectionReport interreflection;
  UnscatteredLightReport unscattered;
  BakeErrorReport errors;
  LightmapReport lightmap;  // size 0: no texture
  RelightReport relight;    // order -1: a plain bake
  // Several materials: each one's bake. The stages above are then those of the material with the
  // largest share of the surface, and errors the materials' mixed by their shares.
  std::vector<MaterialBakeReport> materials;
  int threads = 0;
  double raySceneSeconds = 0.0;  // the mesh's BVH, shared by the stages that trace it
  double totalSeconds = 0.0;
};

}  // namespace sss

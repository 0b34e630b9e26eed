// The sss-bake pipeline: mesh + environment + material -> per-vertex transmitted irradiance E
// (Li & Guo Eq. 6, with or without the mesh's own shadows) and exitance B (Li & Guo Eq. 7 with a
// diffusion method, or the Monte Carlo reference), ready for writeBakedPly.
//
// A sequence of stages, each with its input, its result and its report (bake_report.h):
//   1. prepare_mesh.h     load, validate and clean the mesh; scale it to millimetres
//   -. the environment    loadEnvironment (lib/envmap) into a radiance cubemap
//   2. plan_energy.h      the energy model (escape walks, finite_object_energy.h) and the profile
//   3. light_vertices.h   E per vertex: the irradiance cubemap, or visibility rays
//   3b. far_field.h       the light leaving far from where it entered, traced (escape model only)
//   4. transport.h        B per vertex: a diffusion sum, or the path tracer
//   5. assemble           the baked mesh: positions in the file's units, E, B, the material
// ErrorBudget (error_budget.h) splits the tolerance between the stages' estimates. Every setting
// is validated (validateBakeSettings) before the first expensive stage.
#pragma once

#include "bake/bake_report.h"
#include "bake/bake_settings.h"
#include "envmap/cubemap.h"
#include "mesh/baked_ply.h"

namespace sss {

struct BakeOutput {
  BakedMesh baked;  // positions in the mesh's own units, mmPerUnit recorded
  BakeReport report;
};

// Runs every stage. Warnings (mesh cleanup, long walks) go to stderr through warn(); errors throw
// sss::Error naming the file and the problem. Writes nothing.
BakeOutput bake(const BakeSettings& settings);

// The environment as the bake uses it (settings.environment, orientation, face size), loaded
// once for a batch of meshes (core/batch.h).
struct BakeEnvironment {
  Cubemap radiance;
  EnvironmentStageReport report;
};
BakeEnvironment loadBakeEnvironment(const BakeSettings& settings);
// The same bake on an environment loaded before: settings.environment is not read again.
BakeOutput bake(const BakeSettings& settings, const BakeEnvironment& environment);

}  // namespace sss

// The sss-bake pipeline: mesh + environment + material -> per-vertex transmitted irradiance E
// (Li & Guo Eq. 6, with or without the mesh's own shadows), exitance B (Li & Guo Eq. 7 with a
// diffusion method, or the Monte Carlo reference) and the radiance along the normal, ready for
// writeBakedMesh. bake() runs these stages in this order; each takes a typed input and returns
// its own result and report (bake_report.h), and none changes an earlier one's result:
//   1. prepareMesh             load, validate and clean the mesh; scale it to mm (prepare_mesh.h)
//   1a. partMaterials          the parts' materials (material_map.h); with several, stages 2-12
//                              run once per material and mixBakedMeshes mixes them per vertex
//                              (material_parts.h)
//   1b. refineForTexture       with --texture: the mesh refined to the texels (texture_stage.h)
//      loadBakeEnvironment     the environment as a radiance cubemap (below; lib/envmap)
//   2. planEnergy              the energy model (escape walks) and the profile (plan_energy.h)
//   2b. rayScene               the mesh's BVH, one for every stage below that traces the
//                              surface's rays (3, 7, 10b; bake.cpp)
//   3. lightVertices           E per vertex: the irradiance cubemap or visibility rays
//                              (light_vertices.h, lib/lighting)
//   4. traceFarField           the light leaving far from where it entered (transport/far_field.h)
//   5. energyWithFarField      with a traced far field, the walks' near share refined
//   5b. exitLobeStage          the exit lobe B leaves through: the far field's, the half-space's
//                              at low albedo, or none (the normalized model; bake.cpp)
//   6. transport               B per vertex: a diffusion sum or the path tracer (transport.h)
//   7. interreflection         the light the object sends itself, its own E, B and what it added
//                              (transport/interreflection.h), or the pilot's estimate of it
//   8. radianceAlongNormal     B's radiance along the normal through the exit lobe
//   9. traceUnscatteredLight   the light crossing the object unscattered, added to that radiance
//                              (transport/unscattered_light.h)
//  10. estimateModelError      the model's own error (transport/model_error.h)
//  10b. relightTransfer        with --relightable: the SH transfer of B and the ratios that
//                              relight the bake under other environments (relight.h)
//  11. errorReport             the predicted errors, split as ErrorBudget (error_budget.h) does
//  12. assembleBakedMesh       the baked mesh in the file's units, E and B with the bounces' light
//  13. bakeLightmap            with --texture: the refined vertices' radiance along the normal
//                              and B in the UV lightmap, padded, seams compared (texture_stage.h)
// and, when the tool writes a GLB, lightmappedAsset (texture_stage.h) puts the lightmap on the
// source mesh as its emission.
// Every setting is validated (validateBakeSettings) before the first expensive stage; the run's
// seed, threads and quietness (core/run_context.h) go to every stage whole.
#pragma once

#include "bake/bake_report.h"
#include "bake/bake_settings.h"
#include "bake/texture_stage.h"
#include "envmap/cubemap.h"
#include "mesh/baked_ply.h"

namespace sss {

struct BakeOutput {
  BakedMesh baked;               // positions in the mesh's own units, mmPerUnit recorded
  Lightmap lightmap;             // with --texture (size > 0): radiance along the normal, then B
  TextureSource lightmapSource;  // with --texture: the mesh the lightmap is drawn on
  // With several materials (material_parts.h): each part's (mesh_parts.h), else empty.
  std::vector<Material> partMaterials;
  // With several materials, one material's bake (bakeMaterials): what the symmetric kernel
  // changes from the receiver's rule in B and in the radiance along the normal
  // (material_parts.h); else empty.
  std::vector<glm::vec3> symmetricChange, symmetricChangeRadiance;
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

// The light a vertex takes in, as a linear function of the environment (a relightable bake,
// sss-bake --relightable): per vertex and channel, the spherical-harmonic coefficients of its
// transmitted-cosine transfer with the mesh's own shadows,
//
//   T_lm,c(x) = integral of Y_lm(w) V(x, w) sum_f share_f F_t(n_f . w) w_c(n_f . w) (n_f . w)+ dw,
//
// so that under any environment with SH coefficients L_lm the transmitted irradiance is
// E_c(x) = sum_lm T_lm,c(x) L_lm,c, exactly for an environment of order <= the transfer's
// (Sloan, Kautz & Snyder 2002, "Precomputed radiance transfer", with Li & Guo Eq. 6's kernel).
// The facets and the directional entry's weight w_c are the visibility rays' (facet_light.h).
//
// Split as the visibility estimator splits E: the unoccluded part in closed form (Funk-Hecke:
// T_lm = kHat_l,c Y_lm(n_f) per facet, transmitted_cosine.h), minus what the rays find blocked,
// by Monte Carlo over the facets' cosine lobes (stratified, each vertex its own rotation of one
// Hammersley set, so the result depends on the seed alone). A convex mesh is exact.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/run_context.h"
#include "envmap/compact_lights.h"
#include "mesh/triangle_mesh.h"

namespace sss {

class DirectionalAlbedoWeight;  // material/directional_albedo_weight.h
class TriangleScene;            // raytrace/triangle_scene.h

struct VisibilityTransferOptions {
  int order = 3;                                   // SH bands 0..order: (order + 1)^2 coefficients
  int rays = 64;                                   // per vertex, for the blocked part
  const DirectionalAlbedoWeight* entry = nullptr;  // null: w = 1
  RunContext run{};
  // The mesh's ray scene (TriangleSceneOptions::surfaceRays) where the caller has one; null:
  // built here. Not owned.
  const TriangleScene* scene = nullptr;
};

struct VisibilityTransfer {
  int order = -1;
  int count = 0;                        // (order + 1)^2
  std::vector<glm::vec3> coefficients;  // [vertex * count + lm], per channel
  double blockedFraction = 0.0;         // of all rays
  std::span<const glm::vec3> at(std::size_t v) const {
    return {coefficients.data() + v * count, static_cast<std::size_t>(count)};
  }
};

// Throws Error on an order outside [0, SphericalHarmonics::kMaxOrder] or rays < 1.
VisibilityTransfer visibilityTransfer(std::span<const glm::vec3> positions,
                                      std::span<const glm::vec3> normals,
                                      std::span<const glm::uvec3> triangles, float eta,
                                      const VisibilityTransferOptions& options);

// The transmitted irradiance of directional lights (envmap/compact_lights.h) per vertex, as the
// visibility rays would count a source that small: sum over lights of its irradiance times
// sum_f share_f F_t w_c (n_f . d)+, where one ray from the vertex towards it is not blocked.
std::vector<glm::vec3> directionalIrradiance(std::span<const glm::vec3> positions,
                                             std::span<const glm::vec3> normals,
                                             std::span<const glm::uvec3> triangles, float eta,
                                             const DirectionalAlbedoWeight* entry,
                                             std::span<const DirectionalLight> lights,
                                             const RunContext& run);

// directionalIrradiance for any number of sets of lights on one mesh: the facets built once, the
// shadow rays traced in the caller's scene of the mesh (TriangleSceneOptions::surfaceRays; a
// relit turntable, bake/relight.h). Keeps references to the mesh's arrays and to `entry`.
class DirectionalShadows {
 public:
  DirectionalShadows(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                     std::span<const glm::uvec3> triangles, float eta,
                     const DirectionalAlbedoWeight* entry, const RunContext& run);
  std::vector<glm::vec3> irradiance(std::span<const DirectionalLight> lights,
                                    const TriangleScene& scene) const;

 private:
  std::span<const glm::vec3> positions_, normals_;
  std::span<const glm::uvec3> triangles_;
  float eta_;
  const DirectionalAlbedoWeight* entry_;
  RunContext run_;
  VertexFacets facets_;
};

}  // namespace sss

// Interreflection (issue 11, part 3): the light the object sends to itself.
//
// The visibility stage (visibility.h) counts a direction the mesh blocks as dark, which leaves
// concavities 13-29 % dark under uniform light. Here each vertex's hemisphere is sampled again
// (cosine-weighted, stratified, Pcg32(seed, vertex)), and a ray that meets the object brings back
// the radiance leaving the hit point towards the vertex: the exit model's radiance of the exitance
// interpolated over the hit triangle's vertices, L = B F_t(mu_h, eta) / (pi (1 - 2 C_1(eta)))
// (optics/fresnel.h), plus the Fresnel-reflected environment F_r(mu_h) L_env(r), r the mirror
// direction at the hit (not traced again: one reflection). mu_h is the cosine at the hit between
// the way back to the vertex and the hit's interpolated normal. The vertex's transmitted irradiance
// gains
//   E_ir = integral over blocked w of F_t(mu) L_hit(w) cos dw  ~  pi / N sum_k F_t(mu_k) L_hit,k
// (N cosine-distributed rays; unblocked ones add nothing: the visibility stage has them). The hits
// are traced once; each bounce is a gather over them, so B -> E_ir is linear and cheap, and the
// bake iterates E = E_direct + E_ir(B), B = transport(E) until B stops changing.
//
// Closed, non-absorbing objects under uniform radiance 1 (the white furnace) then send radiance 1
// everywhere, concavities included (tests/bake/interreflection_test.cpp).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "envmap/cubemap.h"
#include "material/directional_albedo_weight.h"

namespace sss {

struct InterreflectionOptions {
  int rays = 64;  // cosine-distributed rays per vertex (>= 1)
  // The directional entry (material/directional_albedo_weight.h): the light arriving at a vertex
  // is weighted as the transport's direct light is. Null: diffuse entry. Not kept.
  const DirectionalAlbedoWeight* entry = nullptr;
  uint64_t seed = 1;
  int threads = 0;  // <= 0: all cores
};

class InterreflectionGather {
 public:
  // Positions in mm, unit vertex normals pointing out. Keeps no reference to its arguments.
  InterreflectionGather(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                        std::span<const glm::uvec3> triangles, const Cubemap& radiance, float eta,
                        const InterreflectionOptions& options);

  // E_ir per vertex for the exitance B per vertex (one per mesh vertex).
  std::vector<glm::vec3> gather(std::span<const glm::vec3> exitance) const;
  // Of the rays traced, the fraction that met the object.
  double blockedFraction() const { return blockedFraction_; }

 private:
  struct Hit {
    glm::uvec3 vertices;
    glm::vec3 barycentric;
    glm::vec3 exitWeight;  // pi / N F_t(mu) w(mu) F_t(mu_h) / (pi (1 - 2 C_1))
    glm::vec3 reflection;  // pi / N F_t(mu) w(mu) F_r(mu_h) L_env(r)
  };
  std::vector<uint32_t> offsets_;  // hits of vertex v: [offsets_[v], offsets_[v + 1])
  std::vector<Hit> hits_;
  double blockedFraction_ = 0.0;
};

struct BounceResult {
  std::vector<glm::vec3> irradiance;  // E_direct + E_ir of the last bounce
  std::vector<glm::vec3> exitance;    // B = transport(irradiance)
  int bounces = 0;                    // gathers done
  double change = 0.0;                // relative RMS change of B at the last bounce
};

// B_0 = transport(E_direct); then E_k = E_direct + gather(B_{k-1}), B_k = transport(E_k), for
// maxBounces bounces, or (maxBounces <= 0: auto) until the relative RMS change of B is below
// tolerance (at most 64 bounces).
BounceResult iterateInterreflection(
    const InterreflectionGather& gather, std::span<const glm::vec3> direct,
    const std::function<std::vector<glm::vec3>(std::span<const glm::vec3>)>& transport,
    int maxBounces, double tolerance);

}  // namespace sss

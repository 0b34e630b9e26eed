// The compact lights' mirror images on the object: a sun or a lamp reflected by the object's
// specular surface onto another part of it, traced forward from the light (the gather's mirrored
// sky, interreflection.h, without those lights).
//
// Why: the gather looks up the sky in the mirror direction at each of its hits, so a 1-degree sun
// is found only by the few mirror directions that happen to fall on it (through the sky's ~11
// degree texels): looked up so, that noise is 2.5 % of B on the marble bunny under a sky's
// sun, 1.63 % under sunrise.exr (tests/bench/results/bake/mirrored_lights_ab.csv;
// docs/tools/sss-bake.md, "Bounces and interreflection"). Traced from the light, every path carries
// it, as light tracing resolves caustics (Veach 1997, ch. 10).
//
// Model, per path: a direction within the light's cone (DirectionalLight: its irradiance at
// normal incidence and solid angle), a start uniform on a disc of the object's bounding sphere
// perpendicular to it, power Phi = E / p(light) pi R^2 / N. At the first hit (the front of a
// surface) the path reflects about the smooth normal (transport/surface_hit.h) with weight
// F_r(mu); where the reflected ray meets the front of the object again, at a point of triangle
// (a, b, c) with barycentric weights l_k, it adds Phi F_t(mu_f) w(mu_f) l_k / A_k to vertex k's
// transmitted irradiance (mu_f against the triangle's face normal, w the entry's weight, A_k a
// third of the vertex's triangles' area: the gather's facet intake in the mean), and reflects once
// more, as the gather follows a mirror ray to a second hit. Two reflections in all.
//
// Deterministic for a seed whatever the thread count: path i draws from Pcg32(seed, i) and the
// deposits are added in path order.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/run_context.h"
#include "envmap/compact_lights.h"
#include "material/directional_albedo_weight.h"

namespace sss {

class TriangleScene;  // raytrace/triangle_scene.h

// Paths per mesh vertex for lights that hold all of the environment's flux (a sun alone; the
// gather scales them by the square of the lights' share, interreflection.h): the marble bunny's
// gather noise under a sky's sun 0.70 %, and under sunrise.exr (6 per vertex) 0.70 % against
// 1.63 % looked up in the sky (mirrored_lights_ab.csv).
inline constexpr int kMirroredLightPathsPerVertex = 16;

struct MirroredLightsInput {
  std::span<const glm::vec3> positions, normals;  // mm; unit normals pointing out
  std::span<const glm::uvec3> triangles;
  const TriangleScene& scene;  // of positions and triangles
  std::span<const DirectionalLight> lights;
  float eta = 1.3f;
  const DirectionalAlbedoWeight& entry;  // w = 1: diffuse entry
  uint64_t paths = 0;                    // in all
  RunContext run;                        // seed, threads
};

// Per vertex, the transmitted irradiance (entry-weighted, as the gather's E_ir) of the lights'
// mirror images, and its variance over the paths (sum of the deposits' squares less the mean's
// square over the paths: each path is independent); all 0 without lights or paths.
struct MirroredLights {
  std::vector<glm::vec3> irradiance, variance;
};
MirroredLights traceMirroredLights(const MirroredLightsInput& in);

}  // namespace sss

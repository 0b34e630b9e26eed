// The pilot of the visibility rays (visibility.h): replicas of the per-vertex
// estimate on an evenly strided subset of vertices, at two ray counts. Private to lib/lighting.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "lighting/visibility_vertex_estimator.h"

namespace sss {

// Pilot: on an evenly strided subset of vertices, `replicas` independent estimates of E at each
// of two ray counts (the same estimator, other rotations of the point set, seeded per vertex).
// The spread between replicas measures the variance of E honestly, stratification included,
// which the per-technique variance of one estimate does not (an upper bound, several times too
// high); the two levels give the convergence rate (stratified sets beat 1/n), so the noise model
// (visibility_noise_model.h) extrapolates to n rays without overshooting.
struct VisibilityPilot {
  int replicas = 0;
  int coarseRays = 0, fineRays = 0;       // rays per replica of the two levels
  std::vector<uint32_t> vertices;         // the sampled vertex indices, ascending
  std::vector<glm::vec3> irradiance;      // per sampled vertex: mean of the fine replicas
  std::vector<glm::vec3> coarseVariance;  // per sampled vertex and channel: of one replica
  std::vector<glm::vec3> fineVariance;    // the same at fineRays
  uint64_t rays = 0;                      // occlusion rays the pilot traced
  double seconds = 0.0;
};

struct VisibilityPilotOptions {
  int coarseRays = 8, fineRays = 32;  // rays per replica, >= 2, coarse < fine
  int replicas = 4;                   // >= 2; 0: no pilot
  std::size_t maxVertices = 1024;     // subset size (all vertices if fewer)
};

// An evenly strided subset of the vertices: every stride-th, starting half a stride in, at most
// maxVertices of them (the pilots' vertices: here and the interreflection estimate's).
std::vector<uint32_t> pilotVertices(std::size_t vertexCount, std::size_t maxVertices);

// Throws Error unless options ask for at least 2 replicas of at least 2 rays and coarse < fine.
// `makeEstimator` gives each thread its estimator; the replicas' rotations come from their own
// stream family of `seed`, apart from the full pass's.
VisibilityPilot runVisibilityPilot(std::size_t vertexCount, const VisibilityPilotOptions& options,
                                   uint64_t seed, int threads,
                                   const std::function<VertexEstimator()>& makeEstimator);

}  // namespace sss

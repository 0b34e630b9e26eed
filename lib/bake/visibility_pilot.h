// The pilot of the visibility rays (VisibilityPilot, visibility.h): replicas of the per-vertex
// estimate on an evenly strided subset of vertices, at two ray counts. Private to lib/bake.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "bake/visibility.h"
#include "bake/visibility_vertex_estimator.h"

namespace sss {

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

// Importance sampling of a radiance cubemap, piecewise constant over its texels: texel
// probability proportional to luminance x solid angle, so that a small bright sun is found by
// every sample that can see it, and uniform across the chosen texel's (s, t) square. Used by the
// bake's visibility rays (lib/lighting/visibility.h) in a multiple-importance-sampling estimator.
//
// The CDF runs over the texels in Morton (Z-curve) order within each face, so that a stratum of
// u1 is a compact 2D patch of a face, not a strip of rows: stratified sample sets keep more of
// their stratification over the sphere (docs/tools/sss-bake.md, "Lighting and visibility").
// Texels are drawn by inverting the CDF through a guide table (Chen & Asau 1974: O(1) expected,
// stratification kept).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "envmap/cubemap.h"

namespace sss {

class EnvironmentSampler {
 public:
  // Keeps a reference to `radiance`. Throws Error if the cubemap is empty or black (nothing to
  // sample).
  explicit EnvironmentSampler(const Cubemap& radiance);

  struct Sample {
    glm::vec3 direction;  // unit
    float pdf;            // per steradian
    glm::vec3 radiance;   // the texel's value
  };
  // (u1, u2) in [0, 1)^2: u1 picks the texel by its cumulative distribution and, rescaled,
  // the position across it; u2 the position down it. Uniform in the texel's (s, t) square.
  Sample sample(float u1, float u2) const;
  // Density per steradian of sample() producing `direction` (unit).
  float pdf(const glm::vec3& direction) const;
  // The texel value along `direction` (not necessarily unit).
  glm::vec3 radiance(const glm::vec3& direction) const;

 private:
  std::size_t texelIndex(const glm::vec3& direction) const;

  const Cubemap* cubemap_;
  std::vector<double> cdf_;      // texelCount + 1 entries, cdf_[0] = 0, back() = 1
  std::vector<uint32_t> order_;  // CDF position -> texel index (Morton order within faces)
  std::vector<uint32_t> guide_;  // texelCount + 1 entries: CDF position of u = k / texelCount
  std::vector<float> pdfScale_;  // per texel: p_i N^2 / 4 (times |d|^3 per steradian)
};

}  // namespace sss

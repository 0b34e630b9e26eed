// Relative RMS: the project's headline error metric (docs/accuracy.md), in one place.
//
// Two different ideas share the name; they are kept apart here:
//
//  * Pooled (relativeRms, relativeRmsNoiseRemoved): the norm of the error over the norm of the
//    reference, both summed over vertices and the three RGB channels,
//        sqrt( sum_i w_i |a_i - r_i|^2 / sum_i w_i |r_i|^2 ),
//    w_i = 1 (every vertex counts alike) or the vertex's area (an integral over the surface). A
//    dark vertex or channel counts little, as it does to the eye and to the energy. This is the
//    error the benchmarks and the tolerances measure. With a noisy reference (a path-traced one),
//    the reference's own variance sum_i w_i |se_i|^2 is subtracted from the numerator.
//
//  * Per vertex (rmsOfRelativeLuminance, MeanSquare): the RMS over vertices of each vertex's own
//    relative error e_i / y_i, in luminance, over the vertices with light only. Every lit vertex
//    counts alike however dark: the relative noise a reader of one vertex sees.
//
// Sums are in double, one vertex at a time, |v|^2 as glm::dot: callers that feed a bake's
// outputs rely on this order staying fixed.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "core/error.h"
#include "core/luminance.h"

namespace sss {

// The sums behind a pooled relative RMS.
struct RelativeRmsSums {
  double error = 0.0;      // sum w |a - r|^2
  double reference = 0.0;  // sum w |r|^2
  double noise = 0.0;      // sum w |se|^2: the reference's own variance, when it has one

  void add(const glm::dvec3& difference, const glm::dvec3& ref) {
    error += glm::dot(difference, difference);
    reference += glm::dot(ref, ref);
  }
  void add(const glm::dvec3& difference, const glm::dvec3& ref, double weight) {
    error += weight * glm::dot(difference, difference);
    reference += weight * glm::dot(ref, ref);
  }

  // sqrt(error / reference); an empty or black reference gives 0 when a matches it, else inf.
  double ratio() const {
    if (reference > 0.0) return std::sqrt(error / reference);
    return error > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
  }
  // The error with the reference's noise removed, sqrt(max(0, error - noise) / reference): the
  // expected squared difference from a noisy reference is the true error's plus its variance.
  double noiseRemoved() const {
    return reference > 0.0 ? std::sqrt(std::max(0.0, error - noise) / reference) : 0.0;
  }
  // The reference's own noise in the same norm, sqrt(noise / reference): an error well below it
  // is not resolved.
  double relativeNoise() const { return reference > 0.0 ? std::sqrt(noise / reference) : 0.0; }
};

// Pooled sums of a against ref (one value per vertex in each; a mismatch is a caller's error);
// se (the reference's standard errors) adds to `noise` when given; `only` (when given) marks the
// vertices that count.
inline RelativeRmsSums relativeRmsSums(std::span<const glm::vec3> a, std::span<const glm::vec3> ref,
                                       std::span<const glm::vec3> se = {},
                                       std::span<const char> only = {}) {
  if (a.size() != ref.size() || (!se.empty() && se.size() != ref.size()) ||
      (!only.empty() && only.size() != ref.size()))
    throw Error("relative RMS: size mismatch");
  RelativeRmsSums s;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    if (!only.empty() && !only[i]) continue;
    const glm::dvec3 r(ref[i]);
    s.add(glm::dvec3(a[i]) - r, r);
    if (!se.empty()) s.noise += glm::dot(glm::dvec3(se[i]), glm::dvec3(se[i]));
  }
  return s;
}

// Pooled relative RMS of a against ref, every vertex alike: sqrt(sum |a - r|^2 / sum |r|^2).
inline double relativeRms(std::span<const glm::vec3> a, std::span<const glm::vec3> ref) {
  return relativeRmsSums(a, ref).ratio();
}

// Pooled relative RMS weighted by area: sqrt(sum A |a - r|^2 / sum A |r|^2), the surface
// integral's ratio rather than the vertices'.
inline double relativeRms(std::span<const glm::vec3> a, std::span<const glm::vec3> ref,
                          std::span<const float> areas) {
  if (a.size() != ref.size() || areas.size() != ref.size())
    throw Error("relative RMS: size mismatch");
  RelativeRmsSums s;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    const glm::dvec3 r(ref[i]);
    s.add(glm::dvec3(a[i]) - r, r, areas[i]);
  }
  return s.ratio();
}

// Pooled relative RMS of a against a noisy reference (standard errors se), the reference's noise
// removed; over the vertices `only` marks, when given.
inline double relativeRmsNoiseRemoved(std::span<const glm::vec3> a, std::span<const glm::vec3> ref,
                                      std::span<const glm::vec3> se,
                                      std::span<const char> only = {}) {
  return relativeRmsSums(a, ref, se, only).noiseRemoved();
}

// Per-vertex relative values' RMS: sqrt(mean of the squared relative values added).
struct MeanSquare {
  double sum = 0.0;
  std::size_t count = 0;
  void add(double relativeSquared) {
    sum += relativeSquared;
    ++count;
  }
  double rms() const { return count ? std::sqrt(sum / static_cast<double>(count)) : 0.0; }
};

// Per vertex: RMS over the vertices with light of |error| / |value| in luminance (error: a
// standard error, or a difference); 0 when no vertex has light.
inline double rmsOfRelativeLuminance(std::span<const glm::vec3> value,
                                     std::span<const glm::vec3> error) {
  MeanSquare m;
  for (std::size_t i = 0; i < value.size() && i < error.size(); ++i) {
    const double y = luminance(glm::dvec3(value[i]));
    const double e = luminance(glm::dvec3(error[i]));
    if (y > 0.0) m.add((e / y) * (e / y));
  }
  return m.rms();
}

}  // namespace sss

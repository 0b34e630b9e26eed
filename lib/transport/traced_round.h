// A round of light-tracer paths as the bake's traced stages keep it (far_field.h,
// unscattered_light.h): a per-vertex mean, its variance and the path count, so that a pilot round
// and the round that completes it to the budget add up as one estimate.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace sss {

struct TracedRound {
  std::vector<glm::dvec3> mean, variance;  // per vertex and channel
  uint64_t paths = 0;
  // The traced exits weighted by their internal cosine (light_tracer.h, exitCosine) and
  // unweighted (cosineExitance: all exits, or the far ones), both averaged over the exit lobe's
  // kernel (far_field.cpp), and the variance of their ratio (the mean cosine) from the batches;
  // empty where not tallied.
  std::vector<glm::dvec3> cosineMean, lobeExitance, meanCosineVariance;
  // The near exits (all less the far ones, with the exit cosine tallied over all exits), averaged
  // like mean, their variance and their covariance with mean (the same paths: a batch that sends
  // more light into a region has more of both); empty where not tallied.
  std::vector<glm::dvec3> nearMean, nearVariance, nearFarCovariance;
};

// Two independent rounds as one: means weighted by their paths, variances accordingly.
inline TracedRound combineRounds(const TracedRound& a, const TracedRound& b) {
  TracedRound out;
  out.paths = a.paths + b.paths;
  const double wa = double(a.paths) / double(out.paths), wb = 1.0 - wa;
  out.mean.reserve(a.mean.size());
  out.variance.reserve(a.mean.size());
  for (std::size_t i = 0; i < a.mean.size(); ++i) {
    out.mean.push_back(wa * a.mean[i] + wb * b.mean[i]);
    out.variance.push_back(wa * wa * a.variance[i] + wb * wb * b.variance[i]);
  }
  if (!a.nearMean.empty() && !b.nearMean.empty())
    for (std::size_t i = 0; i < a.nearMean.size(); ++i) {
      out.nearMean.push_back(wa * a.nearMean[i] + wb * b.nearMean[i]);
      out.nearVariance.push_back(wa * wa * a.nearVariance[i] + wb * wb * b.nearVariance[i]);
      out.nearFarCovariance.push_back(wa * wa * a.nearFarCovariance[i] +
                                      wb * wb * b.nearFarCovariance[i]);
    }
  if (!a.cosineMean.empty() && !b.cosineMean.empty())
    for (std::size_t i = 0; i < a.cosineMean.size(); ++i) {
      out.cosineMean.push_back(wa * a.cosineMean[i] + wb * b.cosineMean[i]);
      out.lobeExitance.push_back(wa * a.lobeExitance[i] + wb * b.lobeExitance[i]);
      out.meanCosineVariance.push_back(wa * wa * a.meanCosineVariance[i] +
                                       wb * wb * b.meanCosineVariance[i]);
    }
  return out;
}

}  // namespace sss

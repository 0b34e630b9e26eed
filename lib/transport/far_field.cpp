#include "transport/far_field.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/exponential.hpp>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/format.h"
#include "core/noise_shrinkage.h"
#include "core/parallel.h"
#include "core/timer.h"
#include "diffusion/diffusion.h"
#include "envmap/cubemap.h"
#include "material/material.h"
#include "mesh/triangle_mesh.h"
#include "optics/exit_lobe.h"
#include "pathtrace/light_tracer.h"
#include "transport/finite_object_energy.h"
#include "transport/surface_average.h"
#include "transport/traced_round.h"

namespace sss {
namespace {

// The smoothing is never narrower than a mean edge: a vertex needs its neighbours' exits (wider
// spreads the lit side into the unlit one near the terminator: docs/accuracy.md, "Under a sun").
constexpr double kSmoothingMinEdges = 1.0;
// The exit lobe's moments are averaged over this many times the far field's smoothing: the slope
// amplifies the mean cosine's noise (the mean spans only 0.78-0.85 at eta 1.3, and 0.01 more of
// it is 16 % more radiance along the normal at slope 0), while the lobe's shape changes over the
// surface (a small ketchup sphere's lit side from its unlit one) and a wider kernel blurs a thin
// part's faces into each other (docs/physics.md, "The far field's exit lobe").
constexpr double kLobeSmoothing = 3.0;
// Paths the far field needs per smoothing kernel at a 0.42 % budget, at the least (the study's
// cheapest object needs this many; docs/accuracy.md, "Under a sun"): auto skips objects that would
// exceed the cap before tracing a pilot.
constexpr double kPathsPerKernel = 2000.0;
constexpr double kRaysPerPath = 4.0;  // a path's work beside its scattering events
// The error the far field removes from B per unit of its sensitivity, where it is left out: 0.11
// on the back-lit ketchup slab (7.3 % per vertex against 3.6 % traced, at a sensitivity of 0.59;
// docs/accuracy.md, "Under a sun"), 0.5 on the skim-milk box with a pit under uniform light (3.1 %
// against 1.7 % at 0.05: there the near part's calibration removes more than the kernel's error);
// about their geometric mean. A fixed measurement, not model_error.h's fitted weight: auto's
// choices would otherwise move the rows that weight is fitted on.
constexpr double kKernelErrorPerSensitivity = 0.25;
// The near part's calibration compares the model's point values, hat-averaged, with the tracer's
// barycentric tally where a vertex's facets lie within 30 degrees of its corners' normals (a
// 42-vertex sphere's do), and the point values themselves at folds (a 2 mm slab's rim of one
// strip, 45 degrees), where the hat average puts the calibrated rim 19 % off its reference and
// the point values 12 % (docs/physics.md, "The far field: light that leaves far from where it
// entered").
constexpr double kSmoothOneRingCosine = 0.866;
// Auto leaves out meshes over this many vertices: the tracer keeps 16 batches of tallies per
// vertex (B, the exit cosine and its exitance: ~1.7 KB a vertex with their float copies), which
// the bake's memory estimate does not count.
constexpr std::size_t kMaxFarFieldVertices = 250000;

// The exit lobe's moments (far_field.h) over their wider kernel, per batch: the batches' mean of
// the cosine-weighted and of the plain exitance, and the variance of their ratio, the mean cosine
// m = C / B, from the batches' spread (delta method: var m = var(C_b - m B_b) / (K B^2)).
void addLobeMoments(const LightTraceResult& r, const SurfaceAverage& lobeAverage,
                    TracedRound& round) {
  std::vector<std::vector<glm::vec3>> sets = r.batchExitCosine;
  sets.insert(sets.end(), r.batchCosineExitance.begin(), r.batchCosineExitance.end());
  const std::vector<std::vector<glm::vec3>> averaged = lobeAverage(sets);
  const std::size_t k = r.batchExitance.size(), n = r.exitance.size();
  round.cosineMean.assign(n, glm::dvec3(0.0));
  round.lobeExitance.assign(n, glm::dvec3(0.0));
  round.meanCosineVariance.assign(n, glm::dvec3(0.0));
  for (std::size_t i = 0; i < n; ++i) {
    glm::dvec3 c(0.0), b(0.0);
    for (std::size_t j = 0; j < k; ++j) {
      c += glm::dvec3(averaged[j][i]);
      b += glm::dvec3(averaged[k + j][i]);
    }
    c /= double(k);
    b /= double(k);
    round.cosineMean[i] = c;
    round.lobeExitance[i] = b;
    for (int ch = 0; ch < 3; ++ch) {
      if (!(b[ch] > 0.0)) continue;
      const double m = c[ch] / b[ch];
      double spread = 0.0;
      for (std::size_t j = 0; j < k; ++j) {
        const double d = double(averaged[j][i][ch]) - m * double(averaged[k + j][i][ch]);
        spread += d * d;
      }
      round.meanCosineVariance[i][ch] = spread / (double(k) * double(k - 1) * b[ch] * b[ch]);
    }
  }
}

// Per vertex the covariance of two batched estimates' means (meanA, meanB: the batches' means)
// from the batches' joint spread (a's with itself: the mean's variance).
std::vector<glm::dvec3> covarianceOfMeans(const std::vector<std::vector<glm::vec3>>& a,
                                          const std::vector<std::vector<glm::vec3>>& b,
                                          std::span<const glm::dvec3> meanA,
                                          std::span<const glm::dvec3> meanB) {
  const double k = double(a.size());
  std::vector<glm::dvec3> sumProduct(meanA.size(), glm::dvec3(0.0));
  for (std::size_t j = 0; j < a.size(); ++j)
    for (std::size_t i = 0; i < meanA.size(); ++i)
      sumProduct[i] += glm::dvec3(a[j][i]) * glm::dvec3(b[j][i]);
  std::vector<glm::dvec3> covariance(meanA.size());
  for (std::size_t i = 0; i < meanA.size(); ++i)
    covariance[i] = (sumProduct[i] / k - meanA[i] * meanB[i]) / (k - 1.0);
  return covariance;
}

// Per vertex the mean of the batches' values and that mean's variance from their spread.
void meanOverBatches(const std::vector<std::vector<glm::vec3>>& batches,
                     std::vector<glm::dvec3>& mean, std::vector<glm::dvec3>& variance) {
  const std::size_t n = batches.empty() ? 0 : batches[0].size();
  const double k = double(batches.size());
  mean.assign(n, glm::dvec3(0.0));
  for (const std::vector<glm::vec3>& batch : batches)
    for (std::size_t i = 0; i < n; ++i) mean[i] += glm::dvec3(batch[i]) / k;
  variance = covarianceOfMeans(batches, batches, mean, mean);
  for (glm::dvec3& v : variance) v = glm::max(glm::dvec3(0.0), v);
}

// A round of traced paths, averaged over the surface: the mean of its batches' averages and that
// mean's variance from their spread (which counts what neighbouring vertices share: an exit is
// split between a triangle's vertices, and the averaging sums neighbours).
TracedRound traceRound(const FarFieldInput& in, const SurfaceAverage& average,
                       const SurfaceAverage& lobeAverage, uint64_t firstPath, uint64_t paths) {
  LightTraceOptions o;
  o.paths = paths;
  o.firstPath = firstPath;
  o.run = in.options.run;
  o.nearWindowMm = farFieldWindowMm(in.material);
  o.stopAtFirstExit = true;
  // What crosses unscattered leaves collimated: light no exit model of B describes.
  o.minScatteringOrder = 1;
  o.batches = 16;  // enough for the noise estimate
  o.tallyRadiance = false;
  o.keepBatches = true;
  o.tallyExitCosine = true;
  o.exitCosineOfAllExits = in.options.lobeOfAllExits;
  const TriangleMesh& mesh = in.meshMm;
  const LightTraceResult r = lightTraceSubsurface(mesh.positions, mesh.normals, mesh.triangles,
                                                  DistantLight::environment(in.radiance),
                                                  homogeneousMediumOf(in.material), o);
  const std::size_t n = mesh.positions.size();
  TracedRound round;
  round.paths = paths;
  addLobeMoments(r, lobeAverage, round);
  const std::vector<std::vector<glm::vec3>> far = average(r.batchExitance);
  meanOverBatches(far, round.mean, round.variance);
  if (o.exitCosineOfAllExits) {
    std::vector<std::vector<glm::vec3>> near = r.batchCosineExitance;
    for (std::size_t b = 0; b < near.size(); ++b)
      for (std::size_t i = 0; i < n; ++i) near[b][i] -= r.batchExitance[b][i];
    near = average(near);
    meanOverBatches(near, round.nearMean, round.nearVariance);
    round.nearFarCovariance = covarianceOfMeans(near, far, round.nearMean, round.mean);
  }
  return round;
}

// B ~ P_near E + B_far at vertex i, channel c (the model's two parts, far_field.h): what the far
// field's noise, its averaging's bias and its lobe's noise are relative to. Not P E + B_far, which
// counts the far light twice (P is all that escapes): on a 10 mm skin1 sphere under a sun it makes
// the far field's noise read half the spread of B_far over seeds.
double roughExitance(const FarFieldInput& in, const TracedRound& round, std::size_t i, int c) {
  return double(in.energy.escape.nearProbability[i][c]) * in.irradiance[i][c] + round.mean[i][c];
}

// The relative noise a round leaves in B ~ P_near E + B_far, over vertices and channels,
// area-weighted.
double relativeNoise(const FarFieldInput& in, const TracedRound& round) {
  double noise = 0.0, signal = 0.0;
  for (std::size_t i = 0; i < round.mean.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double b = roughExitance(in, round, i, c);
      noise += in.areasMm2[i] * round.variance[i][c];
      signal += in.areasMm2[i] * b * b;
    }
  return signal > 0.0 ? std::sqrt(noise / signal) : 0.0;
}

// FarFieldReport::averagingBias: S(B_far) - B_far against B ~ P_near E + B_far (relativeNoise's
// normalization); far is round.mean as the far field returns it.
double averagingBias(const FarFieldInput& in, const SurfaceAverage& average,
                     const TracedRound& round, std::span<const glm::vec3> far) {
  const std::vector<glm::vec3> twice = average(far);
  double bias = 0.0, signal = 0.0;
  for (std::size_t i = 0; i < far.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double b = roughExitance(in, round, i, c);
      const double d = double(twice[i][c]) - double(far[i][c]);
      bias += in.areasMm2[i] * d * d;
      signal += in.areasMm2[i] * b * b;
    }
  return signal > 0.0 ? std::sqrt(bias / signal) : 0.0;
}

// Auto's test: the share of B the far field can move (far_field.h), with E averaged over the far
// field's own smoothing first, so that the visibility rays' noise in E does not count as
// variation (under uniform light it would, by its 0.3 % per vertex).
double farFieldSensitivity(const FarFieldInput& in, const SurfaceAverage& average) {
  const std::vector<glm::vec3>& p = in.energy.escape.probability;
  const std::vector<glm::vec3>& near = in.energy.escape.nearProbability;
  const glm::dvec3 tr = in.material.sigmaTr();
  const double length = 1.0 / std::min({tr.x, tr.y, tr.z});
  const std::vector<glm::vec3> local = average(in.irradiance);
  DiffusionOptions o;
  o.run.threads = in.options.run.threads;
  o.run.quiet = true;
  o.tolerance = 0.01;  // a test against the noise budget, not a result
  const std::vector<glm::vec3> wide = gaussianAverageIrradiance(
      {in.meshMm.positions, in.meshMm.normals, in.areasMm2, in.irradiance}, length, o);
  double moved = 0.0, total = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double far = std::max(0.0, double(p[i][c]) - near[i][c]);
      const double d = far * (local[i][c] - wide[i][c]), b = p[i][c] * in.irradiance[i][c];
      moved += in.areasMm2[i] * d * d;
      total += in.areasMm2[i] * b * b;
    }
  return total > 0.0 ? std::sqrt(moved / total) : 0.0;
}

// How many of the smoothing's Gaussians (effective area 4 pi sigma^2) the surface holds: the paths
// grow with it, as each kernel needs its own exits.
double smoothingKernels(const FarFieldInput& in, double sigmaMm) {
  double area = 0.0;
  for (float a : in.areasMm2) area += a;
  return area / (4.0 * M_PI * sigmaMm * sigmaMm);
}

double smoothingSigmaMm(const FarFieldInput& in, const glm::dvec3& window) {
  double area = 0.0;
  for (float a : in.areasMm2) area += a;
  const double edge = std::sqrt(area / double(std::max<std::size_t>(in.areasMm2.size(), 1)));
  return std::max({window.x, window.y, window.z, kSmoothingMinEdges * edge});
}

// Per vertex and channel, the exit lobe's slope (optics/exit_lobe.h) whose mean internal cosine
// is the traced exits' (their cosine-weighted B over their B, both averaged alike), shrunk by
// that mean's noise (ExitLobe::shrunkSlopeFor); 0, the normalized exit model, where nothing left.
std::vector<glm::vec3> exitLobeSlopes(const TracedRound& round, float eta) {
  const ExitLobe lobe(eta);
  std::vector<glm::vec3> slopes(round.mean.size(), glm::vec3(0.0f));
  for (std::size_t i = 0; i < round.mean.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (round.lobeExitance[i][c] > 0.0)
        slopes[i][c] = float(lobe.shrunkSlopeFor(round.cosineMean[i][c] / round.lobeExitance[i][c],
                                                 round.meanCosineVariance[i][c]));
  return slopes;
}

// FarFieldReport::lobeNoise with relativeNoise's normalization (B ~ P_near E + B_far), in units of
// the normalized model's radiance: L / L_0 = (1 + k) A_0 / (A_0 + k A_1) along the normal, whose
// derivative A_0 (A_0 - A_1) / (A_0 + k A_1)^2 takes the slope's noise to the radiance's. The
// shrunk slope k^3 / (k^2 + v) passes (k^4 + 3 k^2 v) / (k^2 + v)^2 of the raw slope's noise.
double lobeNoise(const FarFieldInput& in, const TracedRound& round,
                 std::span<const glm::vec3> slopes) {
  const ExitLobe lobe(float(in.material.eta));
  const double a0 = lobe.moment(0), a1 = lobe.moment(1);
  double noise = 0.0, signal = 0.0;
  for (std::size_t i = 0; i < slopes.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double b = roughExitance(in, round, i, c);
      const double ks = slopes[i][c], d = a0 + ks * a1;
      signal += in.areasMm2[i] * std::pow(b * (1.0 + ks) * a0 / d, 2);
      if (!(round.lobeExitance[i][c] > 0.0)) continue;
      const double m = round.cosineMean[i][c] / round.lobeExitance[i][c];
      const double k = lobe.slopeFor(m), dk = lobe.slopeDerivative(m);
      const double v = dk * dk * std::max(0.0, round.meanCosineVariance[i][c]);
      const double passed = shrunkByNoiseSlope(k, v);
      noise += in.areasMm2[i] * std::pow(b * a0 * (a0 - a1) / (d * d) * passed, 2) * v;
    }
  return signal > 0.0 ? std::sqrt(noise / signal) : 0.0;
}

glm::dvec3 weightedMeanSlope(const FarField& far, std::span<const float> areas) {
  glm::dvec3 sum(0.0), weight(0.0);
  for (std::size_t i = 0; i < far.slope.size(); ++i) {
    const glm::dvec3 w = double(areas[i]) * glm::dvec3(far.exitance[i]);
    sum += w * glm::dvec3(far.slope[i]);
    weight += w;
  }
  return glm::dvec3(weight.x > 0.0 ? sum.x / weight.x : 0.0,
                    weight.y > 0.0 ? sum.y / weight.y : 0.0,
                    weight.z > 0.0 ? sum.z / weight.z : 0.0);
}

FarField skip(FarField out, std::string reason, const Stopwatch& clock) {
  out.exitance.clear();
  out.slope.clear();
  out.nearExitance.clear();
  out.nearVariance.clear();
  out.nearFarCovariance.clear();
  out.report.traced = false;
  out.report.reason = std::move(reason);
  out.report.seconds = clock.seconds();
  return out;
}

// The traced far field from its round: B_far, the exit lobe's slopes, with the near exits'
// tallies for calibrateNearPart where asked, and the report's measures of them.
void keepTracedRound(FarField& out, const FarFieldInput& in, const SurfaceAverage& average,
                     const TracedRound& round, double noise) {
  const FarFieldOptions& o = in.options;
  FarFieldReport& r = out.report;
  out.exitance.assign(round.mean.size(), glm::vec3(0.0f));
  for (std::size_t i = 0; i < round.mean.size(); ++i) out.exitance[i] = glm::vec3(round.mean[i]);
  out.slope = exitLobeSlopes(round, float(in.material.eta));
  r.meanExitSlope = weightedMeanSlope(out, in.areasMm2);
  r.traced = true;
  r.paths = round.paths;
  r.relativeStdError = noise;
  r.averagingBias = averagingBias(in, average, round, out.exitance);
  r.lobeNoise = lobeNoise(in, round, out.slope);
  if (!(o.lobeOfAllExits && o.calibrateNearShare)) return;
  out.nearExitance.resize(round.nearMean.size());
  out.nearVariance.resize(round.nearMean.size());
  out.nearFarCovariance.resize(round.nearMean.size());
  for (std::size_t i = 0; i < round.nearMean.size(); ++i) {
    out.nearExitance[i] = glm::vec3(round.nearMean[i]);
    out.nearVariance[i] = glm::vec3(round.nearVariance[i]);
    out.nearFarCovariance[i] = glm::vec3(round.nearFarCovariance[i]);
  }
}

}  // namespace

FarField traceFarField(const FarFieldInput& in) {
  const Stopwatch clock;
  const FarFieldOptions& o = in.options;
  if (!(o.noiseBudget > 0.0) || o.pilotPaths < 64 || o.maxPaths < o.pilotPaths ||
      !(o.maxWork > 0.0))
    fail("",
         "far field: needs a positive noise budget and work cap, 64 <= pilot paths <= max paths");
  FarField out;
  FarFieldReport& r = out.report;
  r.requested = o.mode;
  if (o.mode == FarFieldMode::Off) return skip(std::move(out), "off", clock);
  if (in.energy.model != EnergyModel::Escape || in.energy.escape.nearProbability.empty())
    return skip(std::move(out), "half-space energy model", clock);
  r.windowMm = farFieldWindowMm(in.material);
  r.smoothingMm = smoothingSigmaMm(in, r.windowMm);
  const bool automatic = o.mode == FarFieldMode::Auto;
  // The paths affordable: the work cap over a path's work (its scattering events, as the escape
  // walks counted them, and the rays at the surface), and the path cap.
  const double pathWork = in.energy.escape.meanScatteringEvents + kRaysPerPath;
  const double pathCap = std::min(double(o.maxPaths), o.maxWork / pathWork);
  if (automatic && in.meshMm.positions.size() > kMaxFarFieldVertices)
    return skip(std::move(out),
                "over " + std::to_string(kMaxFarFieldVertices) +
                    " vertices (the tracer's per-batch tallies would take " +
                    format("%.2g", 600e-9 * double(in.meshMm.positions.size())) + " GB)",
                clock);
  const double kernels = smoothingKernels(in, r.smoothingMm);
  if (automatic && kPathsPerKernel * kernels > pathCap)
    return skip(std::move(out),
                "object large against the far field's smoothing (" + format("%.0f", kernels) +
                    " kernels: more than " + format("%.3g", kPathsPerKernel * kernels) +
                    " light paths, cap " + format("%.3g", pathCap) + ")",
                clock);
  const SurfaceAverage average(in.meshMm, in.areasMm2, r.smoothingMm, o.run.threads);
  r.sensitivity = farFieldSensitivity(in, average);
  if (automatic && r.sensitivity <= o.noiseBudget)
    return skip(std::move(out),
                "irradiance even on the diffusion length's scale (far field moves " +
                    format("%.2g%%", 100.0 * r.sensitivity) + " of B)",
                clock);
  const SurfaceAverage lobeAverage(in.meshMm, in.areasMm2, kLobeSmoothing * r.smoothingMm,
                                   o.run.threads);
  TracedRound round = traceRound(in, average, lobeAverage, 0, o.pilotPaths);
  double noise = relativeNoise(in, round);
  const double ratio = noise / o.noiseBudget;
  const double needed = std::ceil(1.1 * double(o.pilotPaths) * ratio * ratio);
  // Past the cap auto still traces what it affords when the noise left there is below the model
  // error the far field removes (the kernel's, kKernelErrorPerSensitivity times the sensitivity),
  // so that the bake's error falls though its noise stays above the budget: a thin ketchup slab
  // lit from behind, whose cheap paths need more than the cap (docs/accuracy.md, "Under a sun").
  const double noiseAtCap = noise * std::sqrt(double(o.pilotPaths) / pathCap);
  const bool overBudget = needed > pathCap;
  if (automatic && overBudget && noiseAtCap >= kKernelErrorPerSensitivity * r.sensitivity)
    return skip(std::move(out),
                "would need " + format("%.3g", needed) + " light paths (cap " +
                    format("%.3g", pathCap) + ")",
                clock);
  const uint64_t total = static_cast<uint64_t>(std::min(needed, pathCap));
  if (total > round.paths) {
    round = combineRounds(round,
                          traceRound(in, average, lobeAverage, round.paths, total - round.paths));
    noise = relativeNoise(in, round);
  }
  keepTracedRound(out, in, average, round, noise);
  r.reason =
      std::string(automatic ? "irradiance varies on the diffusion length's scale" : "requested") +
      " (far field moves " + format("%.2g%%", 100.0 * r.sensitivity) + " of B" +
      (overBudget ? "; traced to the path cap, noise " + format("%.2g%%", 100.0 * noise) +
                        " over the budget of " + format("%.2g%%", 100.0 * o.noiseBudget)
                  : std::string()) +
      ")";
  r.seconds = clock.seconds();
  return out;
}

double calibrateNearPart(std::span<glm::vec3> exitance, const NearCalibration& near) {
  if (near.traced.empty()) return 0.0;
  const std::size_t n = exitance.size();
  if (near.farExitance.size() != n || near.traced.size() != n || near.variance.size() != n ||
      near.covariance.size() != n)
    fail("", "far field: one far and near exitance per vertex needed");
  std::vector<glm::vec3> model(n);
  for (std::size_t i = 0; i < n; ++i) model[i] = exitance[i] - near.farExitance[i];
  model = SurfaceAverage(near.meshMm, near.areasMm2, near.smoothingMm, near.threads)(
      hatFunctionAverage(near.meshMm, model, kSmoothOneRingCosine));
  double noise = 0.0, signal = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double m = model[i][c], nearPart = exitance[i][c] - near.farExitance[i][c];
      signal += near.areasMm2[i] * double(exitance[i][c]) * exitance[i][c];
      if (!(m > 0.0)) continue;
      const double d = near.traced[i][c] / m - 1.0, var = near.variance[i][c] / (m * m);
      const double scale = 1.0 + shrunkByNoise(d, var);
      exitance[i][c] = near.farExitance[i][c] + float(scale * nearPart);
      // B = B_far + a traced near + ..., a = nearPart / m times the shrinkage's slope: its
      // variance beside B_far's (counted by the far field) is a^2 var_near + 2 a cov_near,far.
      const double a = nearPart / m * shrunkByNoiseSlope(d, var);
      noise += near.areasMm2[i] * (a * a * near.variance[i][c] + 2.0 * a * near.covariance[i][c]);
    }
  return signal > 0.0 ? std::sqrt(std::max(0.0, noise) / signal) : 0.0;
}

}  // namespace sss

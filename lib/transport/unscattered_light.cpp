#include "transport/unscattered_light.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.h"
#include "core/format.h"
#include "core/timer.h"
#include "envmap/cubemap.h"
#include "material/material.h"
#include "mesh/triangle_mesh.h"
#include "pathtrace/light_tracer.h"
#include "transport/traced_round.h"

namespace sss {
namespace {

// Batches per round: enough for the noise estimate; the tracer keeps two tallies per vertex and
// batch (48 bytes), so auto leaves out meshes whose tallies would not fit beside the bake.
constexpr int kBatches = 8;
// Another round only where the noise is this far over its budget: a near miss is not worth one.
constexpr double kRoundAgain = 1.5;
// A round whose noise is this many times what paths^-1/2 predicted marks heavy-tailed tallies.
constexpr double kHeavyTail = 2.0;
constexpr std::size_t kMaxTracedVertices = 500000;
// Its paths apart from the far field's (far_field.h), which trace the same light with the bake's
// seed: the two estimates' noise would otherwise be one draw and not add in quadrature.
constexpr uint64_t kSeedSalt = 0x756e7363617474ULL;

// A round of paths: L_u per vertex and its variance from the batches' standard errors.
TracedRound traceRound(const UnscatteredLightInput& in, uint64_t firstPath, uint64_t paths) {
  LightTraceOptions o;
  o.paths = paths;
  o.firstPath = firstPath;
  o.batches = kBatches;
  o.run = in.options.run;
  o.run.seed ^= kSeedSalt;
  o.coneHalfAngleDeg = in.options.coneHalfAngleDeg;
  o.unscatteredOnly = true;
  const TriangleMesh& mesh = in.meshMm;
  const LightTraceResult r = lightTraceSubsurface(mesh.positions, mesh.normals, mesh.triangles,
                                                  DistantLight::environment(in.radiance),
                                                  homogeneousMediumOf(in.material), o);
  TracedRound round;
  round.paths = paths;
  for (std::size_t i = 0; i < r.radiance.size(); ++i) {
    const glm::dvec3 se(r.radianceStdErr[i]);
    round.mean.push_back(glm::dvec3(r.radiance[i]));
    round.variance.push_back(se * se);
  }
  return round;
}

// Area-weighted sums over vertices and channels: |L_u|^2, var(L_u), |L_s + L_u|^2.
struct Sums {
  double unscattered = 0.0, variance = 0.0, total = 0.0;
  // L_u's share of the radiance along the normal, its own noise removed (unscattered_light.h).
  double share() const {
    return total > 0.0 ? std::sqrt(std::max(0.0, unscattered - variance) / total) : 0.0;
  }
  double relativeNoise() const { return total > 0.0 ? std::sqrt(variance / total) : 0.0; }
};

Sums sumsOf(const UnscatteredLightInput& in, const TracedRound& round) {
  Sums s;
  for (std::size_t i = 0; i < round.mean.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double a = in.areasMm2[i], u = round.mean[i][c];
      const double l = double(in.scatteredRadiance[i][c]) + u;
      s.unscattered += a * u * u;
      s.variance += a * round.variance[i][c];
      s.total += a * l * l;
    }
  return s;
}

// The paths that would bring the noise of `sums` (from `paths` paths) to the budget, 10 % over
// (noise ~ paths^-1/2).
uint64_t pathsForBudget(const Sums& sums, uint64_t paths, double budget) {
  const double ratio = sums.relativeNoise() / budget;
  const double needed = std::ceil(1.1 * double(paths) * ratio * ratio);
  return needed >= 1.8e19 ? UINT64_MAX : uint64_t(needed);
}

// After a round whose noise paths^-1/2 predicted at `predicted`: whether auto should stop tracing,
// the light not worth more paths. Either its noise is not below its share (left out as it is: a
// round sized for the budget that leaves it there found the pilot's noise far too low), or the
// noise fell far more slowly than predicted (heavy-tailed tallies: a sun focused through thin
// parts onto a few small vertices).
bool notWorthMore(const Sums& sums, double predicted) {
  const double noise = sums.relativeNoise();
  return noise >= sums.share() || noise > kHeavyTail * predicted;
}

UnscatteredLight skip(UnscatteredLight out, std::string reason, const Stopwatch& clock) {
  out.radiance.clear();
  out.report.traced = false;
  out.report.reason = std::move(reason);
  out.report.seconds = clock.seconds();
  return out;
}

void validate(const UnscatteredLightInput& in) {
  const UnscatteredLightOptions& o = in.options;
  if (!(o.noiseBudget > 0.0) || o.pilotPaths < uint64_t(2 * kBatches) ||
      o.maxPaths < o.pilotPaths || !(o.coneHalfAngleDeg > 0.0 && o.coneHalfAngleDeg <= 90.0))
    fail("",
         "unscattered light: needs a positive noise budget, 16 <= pilot paths <= max paths and a "
         "cone in (0, 90] degrees");
  if (in.scatteredRadiance.size() != in.meshMm.positions.size() ||
      in.areasMm2.size() != in.meshMm.positions.size())
    fail("", "unscattered light: one area and one radiance per vertex needed");
}

}  // namespace

UnscatteredLight traceUnscatteredLight(const UnscatteredLightInput& in) {
  const Stopwatch clock;
  validate(in);
  const UnscatteredLightOptions& o = in.options;
  UnscatteredLight out;
  UnscatteredLightReport& r = out.report;
  r.requested = o.mode;
  if (o.mode == UnscatteredMode::Off) return skip(std::move(out), "off", clock);
  const bool automatic = o.mode == UnscatteredMode::Auto;
  if (automatic && in.meshMm.positions.size() > kMaxTracedVertices)
    return skip(std::move(out),
                "over " + std::to_string(kMaxTracedVertices) + " vertices (the tracer's tallies)",
                clock);
  TracedRound round = traceRound(in, 0, o.pilotPaths);
  Sums sums = sumsOf(in, round);
  r.share = sums.share();
  if (automatic && r.share <= o.noiseBudget)
    return skip(
        std::move(out),
        "negligible (" + format("%.2g%%", 100.0 * r.share) + " of the radiance along the normal)",
        clock);
  // Paths for the budget (noise ~ paths^-1/2), 10 % over, in rounds: the pilot's estimate of the
  // noise comes from few paths and may be low, so each round's (from all the paths so far) sets
  // the next where the budget was missed by far, up to the cap. Auto stops early where more paths
  // cannot make the light worth keeping (below).
  uint64_t needed = pathsForBudget(sums, round.paths, o.noiseBudget);
  while (needed > round.paths && round.paths < o.maxPaths) {
    const uint64_t before = round.paths, total = std::min(needed, o.maxPaths);
    const double predicted = sums.relativeNoise() * std::sqrt(double(before) / double(total));
    round = combineRounds(round, traceRound(in, before, total - before));
    sums = sumsOf(in, round);
    if (sums.relativeNoise() <= kRoundAgain * o.noiseBudget ||
        (automatic && notWorthMore(sums, predicted)))
      break;
    needed = pathsForBudget(sums, round.paths, o.noiseBudget);
  }
  const bool overBudget = sums.relativeNoise() > o.noiseBudget;
  r.share = sums.share();  // from all the paths
  r.paths = round.paths;
  r.relativeStdError = sums.relativeNoise();
  // Traced, the error it leaves is its noise; left out, its share. Auto keeps the smaller (a light
  // no larger than its own noise only adds fireflies: docs/tools/sss-bake.md, "Unscattered
  // light"); `on` keeps it whatever its noise.
  if (automatic && r.relativeStdError >= r.share)
    return skip(std::move(out),
                "left out: its noise (" + format("%.2g%%", 100.0 * r.relativeStdError) +
                    " of the radiance along the normal after " + std::to_string(round.paths) +
                    " paths) is not below its share (" + format("%.2g%%", 100.0 * r.share) + ")",
                clock);
  out.radiance.reserve(round.mean.size());
  for (const glm::dvec3& l : round.mean) out.radiance.push_back(glm::vec3(l));
  r.traced = true;
  r.reason = std::string(automatic ? "it is " : "requested; ") + format("%.2g%%", 100.0 * r.share) +
             " of the radiance along the normal" +
             (overBudget ? " (noise " + format("%.2g%%", 100.0 * r.relativeStdError) + " after " +
                               std::to_string(round.paths) + " paths, over its budget)"
                         : "");
  r.seconds = clock.seconds();
  return out;
}

}  // namespace sss

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
  // Paths for the budget (noise ~ paths^-1/2), 10 % over; at the cap it is traced all the same:
  // without it the error is the whole share.
  const double ratio = sums.relativeNoise() / o.noiseBudget;
  const double needed = std::ceil(1.1 * double(o.pilotPaths) * ratio * ratio);
  const uint64_t total = uint64_t(std::min(needed, double(o.maxPaths)));
  if (total > round.paths) {
    round = combineRounds(round, traceRound(in, round.paths, total - round.paths));
    sums = sumsOf(in, round);
    r.share = sums.share();  // from all the paths now
  }
  out.radiance.reserve(round.mean.size());
  for (const glm::dvec3& l : round.mean) out.radiance.push_back(glm::vec3(l));
  r.traced = true;
  r.paths = round.paths;
  r.relativeStdError = sums.relativeNoise();
  r.reason = std::string(automatic ? "it is " : "requested; ") + format("%.2g%%", 100.0 * r.share) +
             " of the radiance along the normal" +
             (needed > double(o.maxPaths) ? " (paths capped)" : "");
  r.seconds = clock.seconds();
  return out;
}

}  // namespace sss

#include "pathtrace/light_tracer.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/barycentric.h"
#include "core/bounds.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/random.h"
#include "core/sampling.h"
#include "core/timer.h"
#include "envmap/environment_sampler.h"
#include "mesh/triangle_mesh.h"
#include "optics/exit_lobe.h"
#include "optics/fresnel.h"
#include "pathtrace/medium_walk.h"
#include "raytrace/triangle_scene.h"

namespace sss {

DistantLight::DistantLight(DistantLight&&) noexcept = default;
DistantLight& DistantLight::operator=(DistantLight&&) noexcept = default;
DistantLight::~DistantLight() = default;

DistantLight DistantLight::environment(const Cubemap& radiance) {
  DistantLight light;
  light.environment_ = std::make_unique<EnvironmentSampler>(radiance);
  return light;
}

DistantLight DistantLight::disc(const glm::vec3& towardsLight, double angularRadius,
                                const glm::vec3& irradiance) {
  if (!(glm::length(towardsLight) > 0.0f) || !(angularRadius >= 0.0 && angularRadius < M_PI / 2))
    fail("", "light tracer: a disc light needs a direction and a radius in [0, 90) degrees");
  DistantLight light;
  light.axis_ = glm::normalize(towardsLight);
  light.cosRadius_ = std::cos(angularRadius);
  light.irradiance_ = glm::dvec3(irradiance);
  return light;
}

DistantLight::Sample DistantLight::sample(double u1, double u2) const {
  if (environment_) {
    const EnvironmentSampler::Sample s = environment_->sample(float(u1), float(u2));
    if (!(s.pdf > 0.0f)) return {s.direction, glm::dvec3(0.0)};
    return {s.direction, glm::dvec3(s.radiance) / double(s.pdf)};
  }
  // Uniform in the cone's solid angle: L / pdf = L * Omega = the irradiance, for every sample.
  return {sampleUniformCone(axis_, cosRadius_, u1, u2), irradiance_};
}

namespace {

// One batch's tallies: per vertex sum of Phi l_k (exitance) and of Phi l_k over the cone
// (radiance), and the power bookkeeping.
struct BatchTally {
  std::vector<glm::dvec3> exitance, radiance, exitCosine, cosineExitance;
  glm::dvec3 source{0.0}, hit{0.0}, entered{0.0}, exited{0.0}, escaped{0.0};
  uint64_t reentries = 0, truncatedWalks = 0, lostWalks = 0, truncatedPaths = 0, events = 0;
};

class LightTracer {
 public:
  LightTracer(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
              const std::vector<glm::uvec3>& triangles, const DistantLight& light,
              const HomogeneousMedium& medium, const LightTraceOptions& options)
      : positions_(positions),
        normals_(normals),
        triangles_(triangles),
        light_(light),
        options_(options),
        eta_(float(medium.eta)),
        scene_(positions, triangles),
        walker_(scene_, triangles, medium.sigmaS, medium.sigmaA + medium.sigmaS, eta_, medium.g,
                options.maxScatteringEvents, options.unscatteredOnly),
        cosCone_(std::cos(options.coneHalfAngleDeg * M_PI / 180.0)) {
    const Bounds3 bounds = boundsOf(positions);
    center_ = bounds.center();
    for (const glm::vec3& p : positions)
      radius_ = std::max(radius_, double(glm::length(p - center_)));
    radius_ = radius_ * 1.001 + 4.0 * scene_.epsilon();
  }

  // Paths [begin, end) into tally.
  void trace(uint64_t begin, uint64_t end, BatchTally& tally) const {
    for (uint64_t i = begin; i < end; ++i) tracePath(i, tally);
  }

 private:
  void tracePath(uint64_t index, BatchTally& tally) const;
  void tallyExit(const MediumExit& exit, const glm::vec3& entry, glm::dvec3 power,
                 BatchTally& tally) const;

  const std::vector<glm::vec3>& positions_;
  const std::vector<glm::vec3>& normals_;
  const std::vector<glm::uvec3>& triangles_;
  const DistantLight& light_;
  const LightTraceOptions& options_;
  const float eta_;
  const TriangleScene scene_;
  const MediumWalker walker_;
  const double cosCone_;
  glm::vec3 center_{0.0f};
  double radius_ = 0.0;
};

void LightTracer::tallyExit(const MediumExit& exit, const glm::vec3& entry, glm::dvec3 power,
                            BatchTally& tally) const {
  const glm::vec3 d = exit.point - entry;
  const glm::dvec3 unwindowed = power;
  for (int c = 0; c < 3; ++c) {
    const double w = options_.nearWindowMm[c];
    if (w > 0.0) power[c] *= -std::expm1(-0.5 * double(glm::dot(d, d)) / (w * w));
  }
  const glm::uvec3 tri = triangles_[exit.triangle];
  const glm::dvec3 l =
      barycentricWeights(exit.point, positions_[tri.x], positions_[tri.y], positions_[tri.z]);
  const double muI =
      tally.exitCosine.empty()
          ? 0.0
          : double(ExitLobe::internalCosine(glm::dot(exit.direction, exit.normal), eta_));
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = tri[k];
    tally.exitance[v] += l[k] * power;
    if (!tally.exitCosine.empty()) {
      const glm::dvec3 p = options_.exitCosineOfAllExits ? unwindowed : power;
      tally.exitCosine[v] += (l[k] * muI) * p;
      tally.cosineExitance[v] += l[k] * p;
    }
    if (!tally.radiance.empty() && glm::dot(exit.direction, normals_[v]) >= cosCone_)
      tally.radiance[v] += l[k] * power;
  }
}

void LightTracer::tracePath(uint64_t index, BatchTally& tally) const {
  Pcg32 rng(options_.run.seed, index);
  const DistantLight::Sample s = light_.sample(rng.uniformDouble(), rng.uniformDouble());
  glm::dvec3 power = s.weight * (M_PI * radius_ * radius_);
  tally.source += power;
  // Start on the disc perpendicular to the direction, outside the bounding sphere.
  glm::vec3 b1, b2;
  orthonormalBasis(s.direction, b1, b2);
  const double r = radius_ * std::sqrt(rng.uniformDouble()), phi = 2.0 * M_PI * rng.uniformDouble();
  glm::vec3 p = center_ + float(radius_ * 1.01) * s.direction + float(r * std::cos(phi)) * b1 +
                float(r * std::sin(phi)) * b2;
  glm::vec3 d = -s.direction;
  const float eps = scene_.epsilon();
  uint64_t order = 0;
  bool firstHit = true, exitedBefore = false;
  for (int interaction = 0;; ++interaction) {
    if (interaction >= options_.maxSurfaceInteractions) {
      ++tally.truncatedPaths;
      return;
    }
    const SceneHit hit = scene_.intersect(p, d);
    if (!hit.hit) {
      if (!firstHit) tally.escaped += power;
      return;
    }
    if (firstHit) tally.hit += power;
    firstHit = false;
    // The outward normal is the one facing the ray (a back face of an inconsistent mesh too).
    const glm::vec3 n = glm::dot(d, hit.faceNormal) < 0.0f ? hit.faceNormal : -hit.faceNormal;
    const float cosI = -glm::dot(d, n);
    const glm::vec3 hitPoint = p + hit.t * d;
    if (rng.uniformDouble() < fresnelDielectric(cosI, eta_)) {  // specular reflection
      d = glm::normalize(d + 2.0f * cosI * n);
      p = hitPoint + eps * n;
      continue;
    }
    tally.entered += power;
    if (exitedBefore) ++tally.reentries;
    MediumWalkStats stats;
    const MediumExit exit = walker_.walkToExit(
        hitPoint - eps * n, refractDirection(d, -n, 1.0f / eta_), kNoStartVertex, rng, stats);
    tally.events += stats.events;
    tally.truncatedWalks += stats.truncated;
    tally.lostWalks += stats.escaped;
    if (!exit.exited) return;
    power *= exit.weight;
    order += stats.events;
    tally.exited += power;
    if (order >= uint64_t(options_.minScatteringOrder)) tallyExit(exit, hitPoint, power, tally);
    if (options_.stopAtFirstExit) return;
    exitedBefore = true;
    d = exit.direction;
    p = exit.point + eps * exit.normal;
  }
}

void validateOptions(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
                     const std::vector<glm::uvec3>& triangles, const HomogeneousMedium& medium,
                     const LightTraceOptions& options) {
  if (positions.empty() || triangles.empty()) fail("", "light tracer: empty mesh");
  if (normals.size() != positions.size()) fail("", "light tracer: one normal per vertex needed");
  for (const glm::uvec3& t : triangles)
    if (std::max({t.x, t.y, t.z}) >= positions.size())
      fail("", "light tracer: triangle index out of range");
  validateHomogeneousMedium(medium);
  if (options.paths < 2 || options.batches < 2 || uint64_t(options.batches) > options.paths)
    fail("", "light tracer: at least 2 batches of at least one path each needed");
  const glm::dvec3 w = options.nearWindowMm;
  if (!(w.x >= 0.0 && w.y >= 0.0 && w.z >= 0.0 && std::isfinite(w.x + w.y + w.z)))
    fail("", "light tracer: the near window must be finite and not negative");
  if (options.unscatteredOnly && options.minScatteringOrder > 0)
    fail("", "light tracer: unscattered light has no scattering order above 0");
  if (!(options.coneHalfAngleDeg > 0.0 && options.coneHalfAngleDeg <= 90.0))
    fail("", "light tracer: the radiance cone must be in (0, 90] degrees");
}

// Mean and standard error over the batches of per-vertex batch means.
// B is per vertex area; the radiance per projected area (see the header).
void combineBatches(const std::vector<BatchTally>& batches, const std::vector<uint64_t>& sizes,
                    const std::vector<float>& areas, const std::vector<float>& projectedAreas,
                    double coneProjectedSolidAngle, bool keepBatches, LightTraceResult& result) {
  const std::size_t n = areas.size();
  const double k = double(batches.size());
  result.exitance.assign(n, glm::vec3(0.0f));
  result.exitanceStdErr.assign(n, glm::vec3(0.0f));
  result.radiance.assign(n, glm::vec3(0.0f));
  result.radianceStdErr.assign(n, glm::vec3(0.0f));
  if (keepBatches) result.batchExitance.assign(batches.size(), std::vector<glm::vec3>(n));
  const bool cosine = !batches.empty() && !batches[0].exitCosine.empty();
  if (cosine) {
    result.exitCosine.assign(n, glm::vec3(0.0f));
    result.cosineExitance.assign(n, glm::vec3(0.0f));
  }
  if (cosine && keepBatches) {
    result.batchExitCosine.assign(batches.size(), std::vector<glm::vec3>(n));
    result.batchCosineExitance.assign(batches.size(), std::vector<glm::vec3>(n));
  }
  for (std::size_t v = 0; v < n; ++v) {
    const double perArea = areas[v] > 0.0f ? 1.0 / double(areas[v]) : 0.0;
    const double perProjectedArea =
        projectedAreas[v] > 0.0f ? 1.0 / double(projectedAreas[v]) : 0.0;
    glm::dvec3 sb(0.0), sb2(0.0), sl(0.0), sl2(0.0);
    for (std::size_t b = 0; b < batches.size(); ++b) {
      const double scale = perArea / double(sizes[b]);
      const glm::dvec3 eb = batches[b].exitance[v] * scale;
      if (!result.batchExitance.empty()) result.batchExitance[b][v] = glm::vec3(eb);
      sb += eb;
      sb2 += eb * eb;
      if (cosine) {
        const glm::dvec3 cb = batches[b].exitCosine[v] * scale;
        const glm::dvec3 bb = batches[b].cosineExitance[v] * scale;
        result.exitCosine[v] += glm::vec3(cb / k);
        result.cosineExitance[v] += glm::vec3(bb / k);
        if (!result.batchExitCosine.empty()) {
          result.batchExitCosine[b][v] = glm::vec3(cb);
          result.batchCosineExitance[b][v] = glm::vec3(bb);
        }
      }
      if (batches[b].radiance.empty()) continue;
      const glm::dvec3 el =
          batches[b].radiance[v] * (perProjectedArea / double(sizes[b]) / coneProjectedSolidAngle);
      sl += el;
      sl2 += el * el;
    }
    auto finish = [k](const glm::dvec3& s, const glm::dvec3& s2, glm::vec3& mean, glm::vec3& se) {
      const glm::dvec3 m = s / k;
      mean = glm::vec3(m);
      se = glm::vec3(glm::sqrt(glm::max(glm::dvec3(0.0), s2 / k - m * m) / (k - 1.0)));
    };
    finish(sb, sb2, result.exitance[v], result.exitanceStdErr[v]);
    finish(sl, sl2, result.radiance[v], result.radianceStdErr[v]);
  }
  uint64_t events = 0;
  for (const BatchTally& t : batches) {
    result.sourcePower += t.source;
    result.hitPower += t.hit;
    result.enteredPower += t.entered;
    result.exitedPower += t.exited;
    result.escapedPower += t.escaped;
    result.reentries += t.reentries;
    result.truncatedWalks += t.truncatedWalks;
    result.lostWalks += t.lostWalks;
    result.truncatedPaths += t.truncatedPaths;
    events += t.events;
  }
  const double paths = double(result.paths);
  for (glm::dvec3* p : {&result.sourcePower, &result.hitPower, &result.enteredPower,
                        &result.exitedPower, &result.escapedPower})
    *p /= paths;
  result.meanScatteringEvents = double(events) / paths;
}

}  // namespace

LightTraceResult lightTraceSubsurface(const std::vector<glm::vec3>& positions,
                                      const std::vector<glm::vec3>& normals,
                                      const std::vector<glm::uvec3>& triangles,
                                      const DistantLight& light, const HomogeneousMedium& medium,
                                      const LightTraceOptions& options) {
  const Stopwatch clock;
  validateOptions(positions, normals, triangles, medium, options);
  const LightTracer tracer(positions, normals, triangles, light, medium, options);
  TriangleMesh mesh{positions, normals, triangles};
  const std::vector<float> areas = vertexAreas(mesh);

  const std::size_t batchCount = std::size_t(options.batches);
  std::vector<BatchTally> batches(batchCount);
  std::vector<uint64_t> sizes(batchCount);
  Progress progress("lighttrace", batchCount, options.run.quiet);
  parallelFor(batchCount, options.run.threads, 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b) {
      const uint64_t first = options.paths * b / batchCount;
      const uint64_t last = options.paths * (b + 1) / batchCount;
      BatchTally& tally = batches[b];
      tally.exitance.assign(positions.size(), glm::dvec3(0.0));
      if (options.tallyRadiance) tally.radiance.assign(positions.size(), glm::dvec3(0.0));
      if (options.tallyExitCosine) {
        tally.exitCosine.assign(positions.size(), glm::dvec3(0.0));
        tally.cosineExitance.assign(positions.size(), glm::dvec3(0.0));
      }
      tracer.trace(options.firstPath + first, options.firstPath + last, tally);
      sizes[b] = last - first;
      progress.advance();
    }
  });
  progress.finish();

  LightTraceResult result;
  result.paths = options.paths;
  const double sinCone = std::sin(options.coneHalfAngleDeg * M_PI / 180.0);
  combineBatches(batches, sizes, areas, projectedVertexAreas(mesh), M_PI * sinCone * sinCone,
                 options.keepBatches, result);
  result.seconds = clock.seconds();
  return result;
}

}  // namespace sss

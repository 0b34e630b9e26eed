#include "pathtrace/escape_probability.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/random.h"
#include "core/timer.h"
#include "material/halfspace_albedo.h"
#include "material/material.h"
#include "mesh/triangle_mesh.h"
#include "optics/exit_lobe.h"
#include "optics/fresnel.h"
#include "pathtrace/one_ring_sampler.h"
#include "pathtrace/walk_sampling.h"
#include "raytrace/triangle_scene.h"

namespace sss {
// Named, not anonymous: EscapeWalks::State, declared in the header, holds these (GCC's
// -Wsubobject-linkage, where this file is compiled inside another, as in a unity build).
namespace escape_walks {

// A walk whose absorption weight exp(-sigma_a l) falls below e^-30 scores 0 (bias < 1e-13).
constexpr double kNegligibleOpticalDepth = 30.0;
constexpr int kMaxEvents = 1 << 20;  // safety cap: such walks count as lost
// P's near share is smoothed over this many near windows (smoothing below), not over P's own
// width: it varies on the window's scale. On the 50 mm bunny in skim milk
// (tests/bench/concavity_study.cpp), where P's width is 37 mm, the per-vertex error under
// forest.exr is 4.4 % this way against 5.0 % with P's width.
constexpr double kNearSmoothingWindows = 2.0;

struct WalkOutcome {
  double weight = 0.0;
  uint64_t events = 0;
  bool lost = false;          // left through a hole, or hit the cap
  glm::vec3 exitPoint{0.0f};  // where it left (weight > 0)
  float exitCosine = 0.0f;    // and the cosine of its direction with the face normal, inside
};

class EscapeWalker {
 public:
  EscapeWalker(const TriangleScene& scene, const Material& m)
      : scene_(scene),
        sigmaA_(m.sigmaA),
        sigmaS_(m.sigmaS()),
        g_(m.g),
        eta_(static_cast<float>(m.eta)) {}

  // One walk for channel c entering at point x of triangle `start` (unit face normal n).
  WalkOutcome walk(const glm::vec3& x, const glm::vec3& n, uint32_t start, int c,
                   Pcg32& rng) const {
    glm::vec3 wo = sampleCosineHemispherePolar(n, rng);
    while (rng.uniformDouble() >= fresnelTransmittance(glm::dot(wo, n), eta_))
      wo = sampleCosineHemispherePolar(n, rng);
    const glm::vec3 inward = refractDirection(-wo, -n, 1.0f / eta_);
    return walkInside(x - scene_.epsilon() * n, inward, start, c, rng);
  }

 private:
  WalkOutcome walkInside(glm::vec3 p, glm::vec3 d, uint32_t start, int c, Pcg32& rng) const {
    WalkOutcome out;
    const float eps = scene_.epsilon();
    const double sigmaS = sigmaS_[c], sigmaA = sigmaA_[c];
    double length = 0.0, forced = 1.0;
    uint64_t boundaryHits = 0;
    for (;;) {
      if (out.events >= static_cast<uint64_t>(kMaxEvents)) {
        out.lost = true;
        return out;
      }
      const SceneHit hit = scene_.intersect(p, d);
      if (!hit.hit) {
        out.lost = true;
        return out;
      }
      double t;
      if (out.events == 0) {
        if (boundaryHits == 0 && hit.triangle == start) {  // grazing: out through the entry face
          out.lost = true;
          return out;
        }
        // Forced scattering until the first event: on this segment the walk either scatters
        // (probability p_s = 1 - exp(-sigma_s t_hit)) or reaches the far side and reflects back
        // inside (F_r); it carries their sum q and picks one in proportion. Light that crosses
        // and leaves unscattered is not diffusion's: no zero scores from the first flights.
        const double scatterProbability = -std::expm1(-sigmaS * double(hit.t));
        if (!(scatterProbability > 0.0)) return out;  // no scattering (and no endless bouncing)
        const BoundaryCrossing boundary = boundaryCrossing(d, hit.faceNormal);
        const double q = scatterProbability +
                         (1.0 - scatterProbability) * fresnelDielectric(boundary.cosI, 1.0f / eta_);
        forced *= q;
        if (rng.uniformDouble() * q >= scatterProbability) {
          ++boundaryHits;
          length += hit.t;
          const glm::vec3 hitPoint = p + hit.t * d;
          d = reflectInside(d, boundary);
          p = hitPoint - eps * boundary.normal;
          continue;
        }
        t = -std::log1p(-rng.uniformDouble() * scatterProbability) / sigmaS;
      } else {
        t = sigmaS > 0.0 ? -std::log(1.0 - rng.uniformDouble()) / sigmaS
                         : std::numeric_limits<double>::infinity();
      }
      if (t < hit.t) {
        length += t;
        if (sigmaA * length > kNegligibleOpticalDepth) return out;
        p += static_cast<float>(t) * d;
        d = sampleHenyeyGreenstein(d, g_, rng);
        ++out.events;
        continue;
      }
      ++boundaryHits;
      length += hit.t;
      const glm::vec3 hitPoint = p + hit.t * d;
      const BoundaryCrossing boundary = boundaryCrossing(d, hit.faceNormal);
      if (rng.uniformDouble() < fresnelDielectric(boundary.cosI, 1.0f / eta_)) {
        d = reflectInside(d, boundary);
        p = hitPoint - eps * boundary.normal;
        continue;
      }
      out.weight = forced * std::exp(-sigmaA * length);
      out.exitPoint = hitPoint;
      out.exitCosine = boundary.cosI;
      return out;
    }
  }

  const TriangleScene& scene_;
  glm::dvec3 sigmaA_, sigmaS_;
  double g_;
  float eta_;
};

// Mean and variance of the mean per probe and channel, over the walks that were not lost.
struct ProbeEstimates {
  std::vector<glm::dvec3> mean, variance;
};

// Per probe and channel, over the walks so far that did not get lost: the sums of a score and of
// its square.
struct ProbeSums {
  explicit ProbeSums(std::size_t probes)
      : sum(probes, glm::dvec3(0.0)), sumSq(probes, glm::dvec3(0.0)) {}
  void add(std::size_t k, int c, double score) {
    sum[k][c] += score;
    sumSq[k][c] += score * score;
  }
  std::vector<glm::dvec3> sum, sumSq;
};

// An estimate smoothed per vertex, with its variance.
struct SmoothedEstimate {
  std::vector<glm::vec3> value;
  std::vector<glm::dvec3> variance;
  // RMS over vertices and channels of the standard error, relative to the RMS of the value.
  double relativeStdError() const;
};

// The Gaussians that spread the probes over the surface: a width per estimate (P, its near share)
// and channel, the distinct ones' exponents listed once (the weights' exp is the smoothing's
// cost, and on a large object every width is the probe spacing's floor), and the squared reach of
// the widest.
struct Smoothing {
  Smoothing(const std::array<glm::dvec3, 2>& widths);
  std::array<glm::dvec3, 2> sigma{};
  std::array<double, 6> exponent{};          // -1 / (2 sigma^2), the distinct widths'
  std::array<std::array<int, 3>, 2> slot{};  // per estimate and channel, its exponent
  int distinct = 0;
  double reach2 = 0.0;  // 3 sigma of the widest, squared
};

Smoothing::Smoothing(const std::array<glm::dvec3, 2>& widths) : sigma(widths) {
  double widest = 0.0;
  for (std::size_t e = 0; e < 2; ++e)
    for (int c = 0; c < 3; ++c) {
      const double x = -0.5 / (sigma[e][c] * sigma[e][c]);
      int k = 0;
      while (k < distinct && exponent[k] != x) ++k;
      if (k == distinct) exponent[distinct++] = x;
      slot[e][c] = k;
      widest = std::max(widest, sigma[e][c]);
    }
  reach2 = 9.0 * widest * widest;
}

}  // namespace escape_walks

using escape_walks::EscapeWalker, escape_walks::ProbeEstimates, escape_walks::ProbeSums,
    escape_walks::SmoothedEstimate, escape_walks::Smoothing, escape_walks::WalkOutcome,
    escape_walks::kNearSmoothingWindows;

struct EscapeWalks::State {
  State(const TriangleMesh& m, std::span<const float> a, const Material& material,
        const EscapeOptions& o)
      : mesh(m),
        areas(a),
        options(o),
        sigmaTr(material.sigmaTr()),
        scene(m.positions, m.triangles),
        walker(scene, material),
        entries(m.positions, m.triangles),
        probes(std::min(m.positions.size(), std::max<std::size_t>(o.maxProbes, 1))),
        escaped(probes),
        exitCosine(probes),
        near(probes),
        kept(probes, glm::dvec3(0.0)),
        isotropicCosine(ExitLobe(float(material.eta)).meanCosine(0.0)) {
    const glm::dvec3 albedo = material.reducedAlbedo();
    for (int c = 0; c < 3; ++c) halfSpace[c] = halfSpaceDiffuseAlbedo(albedo[c], material.eta);
  }
  uint32_t probeVertex(std::size_t k) const {
    return static_cast<uint32_t>(k * mesh.positions.size() / probes);
  }
  bool hasNearWindow() const { return options.nearWindowMm.x > 0.0; }
  // W(d) of channel c for a walk that entered at `entry` and left at o.exitPoint.
  double nearWeight(const WalkOutcome& o, const glm::vec3& entry, int c) const {
    const glm::vec3 d = o.exitPoint - entry;
    const double w = options.nearWindowMm[c];
    return std::exp(-0.5 * double(glm::dot(d, d)) / (w * w));
  }
  ProbeEstimates probeEstimates(const ProbeSums& sums) const;
  Smoothing smoothing(double totalArea) const;
  void smoothAt(std::size_t i, std::span<const ProbeEstimates> estimates, const Smoothing& smooth,
                std::span<SmoothedEstimate> out) const;
  void smoothAll(std::span<const ProbeEstimates> estimates, const Smoothing& smooth,
                 std::span<SmoothedEstimate> out) const;

  const TriangleMesh& mesh;
  std::span<const float> areas;
  EscapeOptions options;
  glm::dvec3 sigmaTr;
  TriangleScene scene;
  EscapeWalker walker;
  OneRingSampler entries;
  std::size_t probes;
  // Per probe and channel, over the walks so far that did not get lost: their weights, the same
  // times their exit's internal cosine less isotropicCosine (centred, so that its mean's noise is
  // small against P's), the same times the near window (with one), and their count.
  ProbeSums escaped, exitCosine, near;
  std::vector<glm::dvec3> kept;
  // The mean internal cosine of the light leaving an isotropic interior (ExitLobe::meanCosine(0):
  // the normalized exit model).
  double isotropicCosine;
  glm::dvec3 halfSpace{0.0};  // the albedo where no walk tells anything (halfspace_albedo.h)
  int walks = 0;              // per probe and channel so far
  uint64_t events = 0, lost = 0;
  double seconds = 0.0;
};

EscapeWalks::EscapeWalks(const TriangleMesh& meshMm, std::span<const float> areas,
                         const Material& material, const EscapeOptions& options) {
  const Stopwatch clock;
  const std::size_t n = meshMm.positions.size();
  if (n == 0 || meshMm.triangles.empty()) fail("", "escape probability: empty mesh");
  if (areas.size() != n) fail("", "escape probability: one area per vertex needed");
  validateMaterial(material);
  if (!(std::abs(material.g) < 1.0)) fail("", "escape probability: |g| must be below 1");
  const glm::dvec3 window = options.nearWindowMm;
  if (!(window.x >= 0.0 && window.y >= 0.0 && window.z >= 0.0) ||
      !std::isfinite(window.x + window.y + window.z) ||
      ((window.x > 0.0) != (window.y > 0.0) || (window.x > 0.0) != (window.z > 0.0)))
    fail("",
         "escape probability: the near window must be 0 or finite and positive in every channel");
  state_ = std::make_unique<State>(meshMm, areas, material, options);
  state_->seconds = clock.seconds();
}

EscapeWalks::~EscapeWalks() = default;

int EscapeWalks::walksPerProbe() const {
  return state_->walks;
}

void EscapeWalks::add(int walksPerProbe) {
  if (walksPerProbe < 1) fail("", "escape probability: walks must be at least 1");
  const Stopwatch clock;
  State& st = *state_;
  const int first = st.walks, last = st.walks + walksPerProbe;
  std::atomic<uint64_t> totalEvents{0}, totalLost{0};
  Progress progress("escape walks", st.probes, st.options.run.quiet);
  parallelFor(st.probes, st.options.run.threads, 8, [&](std::size_t begin, std::size_t end) {
    uint64_t events = 0, lost = 0;
    for (std::size_t k = begin; k < end; ++k) {
      const uint32_t v = st.probeVertex(k);
      if (!st.entries.hasSurface(v)) continue;
      for (int c = 0; c < 3; ++c) {
        for (int s = first; s < last; ++s) {
          // Walk s of vertex v in channel c has a stream of its own: rounds add up.
          Pcg32 rng(st.options.run.seed, ((uint64_t(v) * 3u + uint64_t(c)) << 24) | uint64_t(s));
          const SurfacePoint entry = st.entries.sample(v, rng);
          const WalkOutcome o =
              st.walker.walk(entry.position, entry.normal, entry.triangle, c, rng);
          events += o.events;
          if (o.lost) {  // through a hole: the mesh says nothing about the medium there
            ++lost;
            continue;
          }
          st.escaped.add(k, c, o.weight);
          if (o.weight > 0.0)
            st.exitCosine.add(k, c, o.weight * (double(o.exitCosine) - st.isotropicCosine));
          if (st.hasNearWindow() && o.weight > 0.0)
            st.near.add(k, c, o.weight * st.nearWeight(o, entry.position, c));
          st.kept[k][c] += 1.0;
        }
      }
    }
    totalEvents += events;
    totalLost += lost;
    progress.advance(end - begin);
  });
  progress.finish();
  st.walks = last;
  st.events += totalEvents;
  st.lost += totalLost;
  st.seconds += clock.seconds();
}

// A probe without any kept walk carries no weight.
ProbeEstimates EscapeWalks::State::probeEstimates(const ProbeSums& sums) const {
  ProbeEstimates probe{std::vector<glm::dvec3>(probes), std::vector<glm::dvec3>(probes)};
  for (std::size_t k = 0; k < probes; ++k)
    for (int c = 0; c < 3; ++c) {
      const double w = kept[k][c];
      const double mean = w > 0.0 ? sums.sum[k][c] / w : 0.0;
      probe.mean[k][c] = mean;
      probe.variance[k][c] =
          w > 1.0 ? std::max(0.0, sums.sumSq[k][c] / w - mean * mean) / (w - 1.0) : mean * mean;
    }
  return probe;
}

// Widths per channel: a channel's P varies with the object's shape on the scale its own diffusion
// length sees (skim milk's blue light travels 3.5 mm, its red 18 mm: one width for both blurs
// a thin ear's blue P into the body's), and P's near share on the scale of the near window (it
// is the part of P that leaves within the window: on a thin part, through the other face).
// Never below two probe spacings (docs/physics.md, "Finite objects are not half-spaces").
Smoothing EscapeWalks::State::smoothing(double totalArea) const {
  const double spacing = std::sqrt(totalArea / double(probes));
  std::array<glm::dvec3, 2> widths{};
  for (int c = 0; c < 3; ++c) {
    const double length =
        sigmaTr[c] > 0.0 ? options.smoothing / sigmaTr[c] : double(scene.diagonal());
    widths[0][c] = std::max(length, 2.0 * spacing);
    widths[1][c] = std::min(
        widths[0][c], std::max(kNearSmoothingWindows * options.nearWindowMm[c], 2.0 * spacing));
  }
  return Smoothing(widths);
}

// P (and its near share) at vertex i: the area- and Gaussian-weighted mean of the probes within
// reach; else the nearest probe; else (no walk nearby stayed in the mesh) the half-space albedo.
void EscapeWalks::State::smoothAt(std::size_t i, std::span<const ProbeEstimates> estimates,
                                  const Smoothing& smooth, std::span<SmoothedEstimate> out) const {
  const glm::vec3 x = mesh.positions[i];
  std::array<glm::dvec3, 2> num{}, var{}, den{};
  std::size_t nearest = 0;
  float nearestD2 = std::numeric_limits<float>::infinity();
  for (std::size_t k = 0; k < probes; ++k) {
    const uint32_t v = probeVertex(k);
    const glm::vec3 dx = mesh.positions[v] - x;
    const float d2 = glm::dot(dx, dx);
    if (d2 < nearestD2) {
      nearestD2 = d2;
      nearest = k;
    }
    if (d2 > smooth.reach2) continue;
    std::array<double, 6> weights;
    for (int s = 0; s < smooth.distinct; ++s)
      weights[s] = std::exp(smooth.exponent[s] * d2) * areas[v];
    const glm::dvec3 keptMask(glm::greaterThan(kept[k], glm::dvec3(0.0)));
    for (std::size_t e = 0; e < estimates.size(); ++e) {
      const glm::dvec3 w =
          keptMask * glm::dvec3(weights[smooth.slot[e][0]], weights[smooth.slot[e][1]],
                                weights[smooth.slot[e][2]]);
      den[e] += w;
      num[e] += w * estimates[e].mean[k];
      var[e] += w * w * estimates[e].variance[k];
    }
  }
  for (std::size_t e = 0; e < estimates.size(); ++e)
    for (int c = 0; c < 3; ++c) {
      float& value = out[e].value[i][c];
      double& variance = out[e].variance[i][c];
      if (den[e][c] > 0.0) {
        value = static_cast<float>(std::min(1.0, num[e][c] / den[e][c]));
        variance = var[e][c] / (den[e][c] * den[e][c]);
      } else if (kept[nearest][c] > 0.0) {
        value = static_cast<float>(std::min(1.0, estimates[e].mean[nearest][c]));
        variance = estimates[e].variance[nearest][c];
      } else {  // no walk nearby stayed in the mesh: all of it near, as in a half-space
        value = static_cast<float>(halfSpace[c]);
        variance = 0.0;
      }
    }
}

void EscapeWalks::State::smoothAll(std::span<const ProbeEstimates> estimates,
                                   const Smoothing& smooth, std::span<SmoothedEstimate> out) const {
  const std::size_t n = mesh.positions.size();
  for (SmoothedEstimate& o : out) {
    o.value.assign(n, glm::vec3(0.0f));
    o.variance.assign(n, glm::dvec3(0.0));
  }
  parallelFor(n, options.run.threads, 64, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) smoothAt(i, estimates, smooth, out);
  });
}

double SmoothedEstimate::relativeStdError() const {
  double errorSq = 0.0, valueSq = 0.0;
  for (std::size_t i = 0; i < value.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      errorSq += variance[i][c];
      valueSq += double(value[i][c]) * value[i][c];
    }
  return valueSq > 0.0 ? std::sqrt(errorSq / valueSq) : 0.0;
}

EscapeResult EscapeWalks::result() const {
  const Stopwatch clock;
  const State& st = *state_;
  double totalArea = 0.0;
  for (float a : st.areas) totalArea += a;
  const Smoothing smooth = st.smoothing(totalArea);
  // P and (with a window) its near share, in one pass: they share the probes' weights.
  std::vector<ProbeEstimates> estimates{st.probeEstimates(st.escaped)};
  if (st.hasNearWindow()) estimates.push_back(st.probeEstimates(st.near));
  std::vector<SmoothedEstimate> smoothed(estimates.size());
  st.smoothAll(estimates, smooth, smoothed);
  EscapeResult result;
  result.relativeStdError = smoothed[0].relativeStdError();
  result.probability = std::move(smoothed[0].value);
  if (st.hasNearWindow()) {
    result.nearRelativeStdError = smoothed[1].relativeStdError();
    result.nearProbability = std::move(smoothed[1].value);
  }
  glm::dvec3 weighted(0.0);
  double allSq = 0.0, nearSq = 0.0;
  for (std::size_t i = 0; i < result.probability.size(); ++i) {
    const glm::dvec3 p(result.probability[i]);
    weighted += p * double(st.areas[i]);
    allSq += st.areas[i] * glm::dot(p, p);
    if (st.hasNearWindow()) {
      const glm::dvec3 near(result.nearProbability[i]);
      nearSq += st.areas[i] * glm::dot(near, near);
    }
  }
  if (allSq > 0.0) result.nearShare = std::sqrt(nearSq / allSq);
  // The exits' mean internal cosine, isotropicCosine + sum w (cos - isotropicCosine) / sum w, and
  // its variance sum (w (cos - ...))^2 / (sum w)^2 (the centred sum's noise dominates: its mean
  // is small).
  glm::dvec3 weight(0.0), centred(0.0), centredSq(0.0);
  for (std::size_t k = 0; k < st.probes; ++k) {
    weight += st.escaped.sum[k];
    centred += st.exitCosine.sum[k];
    centredSq += st.exitCosine.sumSq[k];
  }
  for (int c = 0; c < 3; ++c) {
    result.exitCosine[c] = st.isotropicCosine + (weight[c] > 0.0 ? centred[c] / weight[c] : 0.0);
    result.exitCosineVariance[c] = weight[c] > 0.0 ? centredSq[c] / (weight[c] * weight[c]) : 0.0;
  }
  result.mean = totalArea > 0.0 ? weighted / totalArea : glm::dvec3(0.0);
  result.probes = st.probes;
  result.walks = uint64_t(st.probes) * 3u * uint64_t(st.walks);
  result.lostWalks = st.lost;
  result.meanScatteringEvents = double(st.events) / double(std::max<uint64_t>(result.walks, 1));
  result.smoothingSigmaMm = smooth.sigma[0];
  result.seconds = st.seconds + clock.seconds();
  return result;
}

EscapeResult estimateEscapeProbability(const TriangleMesh& meshMm, std::span<const float> areas,
                                       const Material& material, const EscapeOptions& options) {
  EscapeWalks walks(meshMm, areas, material, options);
  walks.add(options.walks);
  return walks.result();
}

}  // namespace sss

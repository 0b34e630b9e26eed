// The random walk inside the homogeneous medium shared by the backward path tracer
// (subsurface_path_tracer.h) and the forward light tracer (light_tracer.h): free flights with
// spectral MIS over R, G, B, Henyey-Greenstein scattering, Russian roulette, and at the boundary
// the exact Fresnel choice between internal reflection and refraction out. The walk is the same
// in both directions (the phase function is symmetric and the eta^2 radiance scaling of entry
// and exit cancels along a path), so one implementation serves both.
//
// Spectral MIS: free flights are sampled by one channel ("hero", chosen uniformly per walk) and
// the three channels are combined by the one-sample balance heuristic over the channels' path
// pdfs (Wilkie et al. 2014; Miller, Georgiev & Jarosz 2019): the walk's weight for channel c is
// f_c / ((p_R + p_G + p_B) / 3), unbiased in every channel even when sigma_t differs.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/exponential.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "core/random.h"
#include "optics/fresnel.h"
#include "pathtrace/walk_sampling.h"
#include "raytrace/triangle_scene.h"

namespace sss {

inline constexpr uint32_t kNoStartVertex = std::numeric_limits<uint32_t>::max();

struct MediumWalkStats {
  uint64_t events = 0;        // scattering events
  uint64_t boundaryHits = 0;  // internal reflections + the exit
  bool truncated = false;     // reached the interaction cap
  bool escaped = false;       // no boundary ahead: lost through a hole of an open mesh
  bool blocked = false;       // left through the start vertex's own triangles before scattering
};

// Where and how a walk left the medium.
struct MediumExit {
  bool exited = false;        // false: absorbed (Russian roulette), lost, truncated or blocked
  glm::vec3 point{0.0f};      // on the boundary
  glm::vec3 normal{0.0f};     // unit face normal pointing out of the medium there
  glm::vec3 direction{0.0f};  // refracted direction outside (unit)
  uint32_t triangle = 0;      // the triangle it left through
  glm::dvec3 weight{0.0};     // MIS-weighted throughput per channel, per unit starting weight
};

class MediumWalker {
 public:
  // sigmaS: the real (not reduced) scattering coefficient; eta: medium index relative to outside.
  // unscatteredOnly: the light that crosses without scattering (see above).
  MediumWalker(const TriangleScene& scene, const std::vector<glm::uvec3>& triangles,
               const glm::dvec3& sigmaS, const glm::dvec3& sigmaT, float eta, double g,
               int maxInteractions, bool unscatteredOnly = false)
      : scene_(scene),
        triangles_(triangles),
        sigmaS_(sigmaS),
        sigmaT_(sigmaT),
        eta_(eta),
        g_(g),
        maxInteractions_(maxInteractions),
        unscatteredOnly_(unscatteredOnly) {}

  // One walk from p inside along unit d until it refracts out. start: a vertex whose own
  // triangles, met before any scattering or reflection, mean the entry direction was cut off by
  // the faceted 1-ring (stats.blocked); kNoStartVertex: no such check.
  MediumExit walkToExit(glm::vec3 p, glm::vec3 d, uint32_t start, Pcg32& rng,
                        MediumWalkStats& stats) const {
    MediumExit exit;
    const int hero = std::min(2, static_cast<int>(rng.uniformDouble() * 3.0));
    const double sigmaTh = sigmaT_[hero];
    glm::dvec3 beta(1.0);  // f_c / p_hero over the path so far
    glm::dvec3 ru(1.0);    // p_j / p_hero over the path so far
    const float eps = scene_.epsilon();
    for (int interactions = 0;; ++interactions) {
      if (interactions >= maxInteractions_) {
        stats.truncated = true;
        return exit;
      }
      const SceneHit hit = scene_.intersect(p, d);
      if (!hit.hit) {
        stats.escaped = true;
        return exit;
      }
      const double t = sigmaTh > 0.0 && !unscatteredOnly_
                           ? -std::log(1.0 - rng.uniformDouble()) / sigmaTh
                           : std::numeric_limits<double>::infinity();
      if (t < hit.t) {
        // Scattering event: f_c = sigma_s,c T_c(t), p_j = sigma_t,j T_j(t), relative to hero.
        for (int c = 0; c < 3; ++c) {
          const double ratio = std::exp(-(sigmaT_[c] - sigmaTh) * t);
          beta[c] *= sigmaS_[c] / sigmaTh * ratio;
          ru[c] *= sigmaT_[c] / sigmaTh * ratio;
        }
        ++stats.events;
        p += static_cast<float>(t) * d;
        d = sampleHenyeyGreenstein(d, g_, rng);
        const double m = std::max({beta.x, beta.y, beta.z}) / ((ru.x + ru.y + ru.z) / 3.0);
        if (!(m > 0.0)) return exit;
        if (m < 1.0) {  // Russian roulette on the MIS-weighted throughput
          const double q = std::max(m, 0.05);
          if (rng.uniformDouble() >= q) return exit;
          beta /= q;
        }
        continue;
      }
      if (start != kNoStartVertex && stats.events == 0 && stats.boundaryHits == 0) {
        const glm::uvec3 tri = triangles_[hit.triangle];
        if (tri.x == start || tri.y == start || tri.z == start) {
          stats.blocked = true;
          return exit;
        }
      }
      // Boundary: f_c = p_j = T(t_hit), relative to hero; unscattered only: f_c = T_c(t_hit) and
      // no flight was sampled (p_j = 1).
      if (unscatteredOnly_) {
        beta *= glm::exp(-sigmaT_ * static_cast<double>(hit.t));
        if (!russianRoulette(beta, rng)) return exit;
      } else {
        for (int c = 0; c < 3; ++c) {
          const double ratio = std::exp(-(sigmaT_[c] - sigmaTh) * static_cast<double>(hit.t));
          beta[c] *= ratio;
          ru[c] *= ratio;
        }
      }
      ++stats.boundaryHits;
      const glm::vec3 hitPoint = p + hit.t * d;
      const BoundaryCrossing boundary = boundaryCrossing(d, hit.faceNormal);
      const float fr = fresnelDielectric(boundary.cosI, 1.0f / eta_);
      if (rng.uniformDouble() < fr) {  // reflect back inside (total internal reflection: fr = 1)
        d = reflectInside(d, boundary);
        p = hitPoint - eps * boundary.normal;
        continue;
      }
      exit.exited = true;
      exit.point = hitPoint;
      exit.normal = boundary.normal;
      exit.direction = refractDirection(d, boundary.normal, eta_);
      exit.triangle = hit.triangle;
      exit.weight = beta / ((ru.x + ru.y + ru.z) / 3.0);
      return exit;
    }
  }

 private:
  const TriangleScene& scene_;
  const std::vector<glm::uvec3>& triangles_;
  glm::dvec3 sigmaS_, sigmaT_;
  float eta_;
  double g_;
  int maxInteractions_;
  bool unscatteredOnly_;

  // Unscattered only: roulette once the largest channel's weight falls below 1 % (a flight through
  // many diffusion lengths, or light trapped by internal reflections); false: absorbed.
  static bool russianRoulette(glm::dvec3& beta, Pcg32& rng) {
    const double m = std::max({beta.x, beta.y, beta.z});
    if (m >= 0.01) return true;
    if (!(m > 0.0) || rng.uniformDouble() >= m / 0.01) return false;
    beta *= 0.01 / m;
    return true;
  }
};

}  // namespace sss

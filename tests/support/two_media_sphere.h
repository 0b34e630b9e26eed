// A sphere whose upper half (z > 0) is one material and lower half another, for the bake of
// several materials (bake/material_parts.h): the UV sphere's two halves as a GLB with materials
// "Upper" and "Lower", and a Monte Carlo of the two media that knows nothing of the bake.
//
// The reference: backward random walks in the exact sphere (radius R, the interface the plane
// z = 0, both media of eta 1.3 so the interface does not refract), free flights by delta tracking
// against the larger sigma_t of the two (Woodcock; a tentative collision is real with probability
// sigma_t(x) / sigma_max, so the medium may change anywhere along a flight), isotropic scattering
// with sigma_s = sigma_s' (g = 0), analog absorption, exact Fresnel at the sphere (reflection with
// probability F_r, total internal reflection included). It tallies the radiance leaving along the
// normal directly under uniform light of radiance 1: a walk starts at the surface point along -n
// with weight F_t(1), and each escape adds the environment's radiance. The light is uniform, so the
// sphere is symmetric about z: one point per ring of the UV sphere (polar angle theta).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "core/parallel.h"
#include "core/random.h"
#include "material/material.h"
#include "mesh/baked_ply.h"
#include "optics/fresnel.h"
#include "support/uv_sphere.h"

namespace sss::test {

constexpr int kHalvesSegments = 64, kHalvesRings = 32;  // the equator (z = 0): ring 16
constexpr double kHalvesEta = 1.3;

// One channel of the two media, per mm.
struct TwoMedia {
  double sigmaT[2], albedo[2];  // [0]: z > 0, [1]: z <= 0
  double majorant;
};

inline TwoMedia twoMedia(const Material& upper, const Material& lower, int c) {
  TwoMedia m{};
  const Material* both[2] = {&upper, &lower};
  for (int k = 0; k < 2; ++k) {
    m.sigmaT[k] = both[k]->sigmaA[c] + both[k]->sigmaSPrime[c];
    m.albedo[k] = both[k]->sigmaSPrime[c] / m.sigmaT[k];
  }
  m.majorant = std::max(m.sigmaT[0], m.sigmaT[1]);
  return m;
}

inline glm::dvec3 uniformSphere(Pcg32& rng) {
  const double z = 1.0 - 2.0 * rng.uniformDouble(), phi = 2.0 * M_PI * rng.uniformDouble();
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// 1 when the walk from x (inside the sphere of radius R) along d escapes, else 0.
inline double walk(glm::dvec3 x, glm::dvec3 d, double R, const TwoMedia& m, Pcg32& rng) {
  for (int event = 0; event < 10000000; ++event) {
    const double b = glm::dot(x, d), c = glm::dot(x, x) - R * R;
    const double toBoundary = -b + std::sqrt(std::max(0.0, b * b - c));
    const double flight = -std::log(1.0 - rng.uniformDouble()) / m.majorant;
    if (flight >= toBoundary) {
      x += toBoundary * d;
      const glm::dvec3 n = x / R;
      const double cosOut = glm::dot(d, n);
      if (rng.uniformDouble() >= fresnelDielectric(float(cosOut), float(1.0 / kHalvesEta)))
        return 1.0;
      d -= 2.0 * cosOut * n;
      x = n * (R * (1.0 - 1e-12));
      continue;
    }
    x += flight * d;
    const int k = x.z > 0.0 ? 0 : 1;
    if (rng.uniformDouble() * m.majorant >= m.sigmaT[k]) continue;  // a null collision
    if (rng.uniformDouble() >= m.albedo[k]) return 0.0;
    d = uniformSphere(rng);
  }
  return 0.0;
}

struct RingReference {
  glm::dvec3 radiance{0.0}, stdError{0.0};
};

inline RingReference referenceAt(double theta, double R, const Material& upper,
                                 const Material& lower, int walks, std::uint64_t stream) {
  const glm::dvec3 n(std::sin(theta), 0.0, std::cos(theta));
  const double entry = fresnelTransmittance(1.0f, float(kHalvesEta));
  RingReference out;
  for (int c = 0; c < 3; ++c) {
    const TwoMedia m = twoMedia(upper, lower, c);
    Pcg32 rng(1, stream * 3 + std::uint64_t(c));
    double sum = 0.0;
    for (int w = 0; w < walks; ++w) sum += walk(n * (R * (1.0 - 1e-12)), -n, R, m, rng);
    const double p = sum / walks;
    out.radiance[c] = entry * p;
    out.stdError[c] = entry * std::sqrt(p * (1.0 - p) / walks);
  }
  return out;
}

// Two primitives of one UV sphere: rings above the equator "Upper", below "Lower".
inline void writeHalvesGlb(const std::string& path, double radiusMm) {
  GltfBuilder b;
  const float r = float(radiusMm / 1000.0);
  std::vector<GltfBuilder::Primitive> halves = {
      uvSpherePrimitive(b, kHalvesSegments, kHalvesRings, r, 0, kHalvesRings / 2),
      uvSpherePrimitive(b, kHalvesSegments, kHalvesRings, r, kHalvesRings / 2, kHalvesRings)};
  halves[0].material = b.material("Upper");
  halves[1].material = b.material("Lower");
  b.scene({b.node({{"name", "sphere"}, {"mesh", b.mesh(halves, "sphere")}})});
  std::ofstream(path, std::ios::binary) << b.glb();
}

// Per ring: the mean radiance along the normal of the bake's vertices whose polar angle is the
// ring's (the poles are one vertex each after welding).
inline std::vector<glm::dvec3> ringMeans(const BakedMesh& baked) {
  std::vector<glm::dvec3> sum(kHalvesRings + 1, glm::dvec3(0.0));
  std::vector<int> count(kHalvesRings + 1, 0);
  for (std::size_t i = 0; i < baked.mesh.vertexCount(); ++i) {
    const glm::dvec3 p = glm::normalize(glm::dvec3(baked.mesh.positions[i]));
    const int ring = int(std::lround(std::acos(std::clamp(p.z, -1.0, 1.0)) / M_PI * kHalvesRings));
    sum[ring] += glm::dvec3(baked.radianceNormal[i]);
    ++count[ring];
  }
  for (int r = 0; r <= kHalvesRings; ++r) sum[r] /= std::max(count[r], 1);
  return sum;
}

// The reference at every ring (0: the upper pole) with `walks` walks per channel.
inline std::vector<RingReference> halvesReference(double R, const Material& upper,
                                                  const Material& lower, int walks) {
  std::vector<RingReference> ref(kHalvesRings + 1);
  parallelFor(ref.size(), defaultThreadCount(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end; ++r)
      ref[r] = referenceAt(M_PI * double(r) / kHalvesRings, R, upper, lower, walks, r);
  });
  return ref;
}

// Relative RMS over the sphere's area (each ring weighted by its sin theta), all channels, of
// (a - ref) - (b - refB): with b and refB empty, a's error; else what a's error has beyond b's
// (the mixed bake's beyond the one-material bakes' own model error). The reference's noise
// removed.
inline double ringRms(const std::vector<glm::dvec3>& a, const std::vector<RingReference>& ref,
                      const std::vector<glm::dvec3>& b = {},
                      const std::vector<RingReference>& refB = {}) {
  double err = 0.0, norm = 0.0;
  for (std::size_t r = 0; r < ref.size(); ++r) {
    const double w = std::max(std::sin(M_PI * double(r) / kHalvesRings), 0.5 * M_PI / kHalvesRings);
    for (int c = 0; c < 3; ++c) {
      double d = a[r][c] - ref[r].radiance[c], noise = std::pow(ref[r].stdError[c], 2);
      if (!b.empty()) {
        d -= b[r][c] - refB[r].radiance[c];
        noise += std::pow(refB[r].stdError[c], 2);
      }
      err += w * (d * d - noise);
      norm += w * std::pow(ref[r].radiance[c], 2);
    }
  }
  return std::sqrt(std::max(0.0, err) / norm);
}

}  // namespace sss::test

#include "material/beam_diffusion_profile.h"

#include <algorithm>
#include <cmath>

#include "material/halfspace_albedo.h"
#include "optics/fresnel.h"

namespace sss {

namespace {

constexpr int kRadii = 160;
constexpr int kDepthSamples = 256;

struct Medium {
  double sigmaA, sigmaSPrime, eta;
  double c1, c2;  // Fresnel moments C_1, C_2 for light inside (relative index 1/eta)
};

// Multiple scattering of a unit-power beam refracted normally into the medium (PBD, Habel 2013).
double multipleScattering(const Medium& m, double r) {
  const double st = m.sigmaA + m.sigmaSPrime;
  const double albedo = m.sigmaSPrime / st;
  const double D = (2.0 * m.sigmaA + m.sigmaSPrime) / (3.0 * st * st);
  const double sigmaTr = std::sqrt(m.sigmaA / D);
  const double c1 = m.c1, c2 = m.c2;
  const double ze = 2.0 * D * (1.0 + 3.0 * c2) / (1.0 - 2.0 * c1);  // extrapolation distance
  const double cPhi = 0.25 * (1.0 - 2.0 * c1), cE = 0.5 * (1.0 - 3.0 * c2);
  double sum = 0.0;
  for (int i = 0; i < kDepthSamples; ++i) {
    // Depth of the source, stratified in its density sigma_t' e^{-sigma_t' t}.
    const double zr = -std::log(1.0 - (i + 0.5) / kDepthSamples) / st;
    const double zv = -zr - 2.0 * ze;
    const double dr = std::sqrt(r * r + zr * zr), dv = std::sqrt(r * r + zv * zv);
    const double er = std::exp(-sigmaTr * dr), ev = std::exp(-sigmaTr * dv);
    const double phi = (er / dr - ev / dv) / (4.0 * M_PI * D);
    const double E = (zr * (1.0 + sigmaTr * dr) * er / (dr * dr * dr) -
                      zv * (1.0 + sigmaTr * dv) * ev / (dv * dv * dv)) /
                     (4.0 * M_PI);
    // kappa removes the diffusion term where the source is too close to the exit for diffusion.
    const double kappa = 1.0 - std::exp(-2.0 * st * (dr + zr));
    sum += kappa * albedo * albedo * (cPhi * phi + cE * E);
  }
  return sum / kDepthSamples;
}

// Exact single scattering of the same beam: isotropic phase, exit through the Fresnel boundary
// (below the critical depth r sqrt(eta^2 - 1) the exit direction is totally reflected).
double singleScattering(const Medium& m, double r) {
  const double st = m.sigmaA + m.sigmaSPrime;
  const double albedo = m.sigmaSPrime / st;
  const double tCrit = r * std::sqrt(m.eta * m.eta - 1.0);
  double sum = 0.0;
  for (int i = 0; i < kDepthSamples; ++i) {
    const double t = tCrit - std::log(1.0 - (i + 0.5) / kDepthSamples) / st;
    const double d = std::sqrt(r * r + t * t);
    const double cosO = t / d;
    const double ft =
        fresnelTransmittance(static_cast<float>(cosO), static_cast<float>(1.0 / m.eta));
    sum += albedo * std::exp(-st * (d + tCrit)) / (d * d) / (4.0 * M_PI) * ft * cosO;
  }
  return sum / kDepthSamples;
}

}  // namespace

BeamDiffusionProfile::BeamDiffusionProfile(const Material& material) {
  validateMaterial(material, material.name.empty() ? "material" : material.name);
  const float inside = static_cast<float>(1.0 / material.eta);
  const double c1 = fresnelMoment(inside, 1), c2 = fresnelMoment(inside, 2);
  for (int c = 0; c < 3; ++c) {
    const Medium m{material.sigmaA[c], material.sigmaSPrime[c], material.eta, c1, c2};
    const double st = m.sigmaA + m.sigmaSPrime;
    const double sigmaTr = std::sqrt(3.0 * m.sigmaA * st);
    const double rLo = 1e-4 / st;
    double rHi = sigmaTr > 0.0 ? std::min(64.0 / sigmaTr, 1e4 / st) : 1e4 / st;
    rHi = std::max(rHi, 40.0 / st);
    Channel& ch = channels_[c];
    ch.r.resize(kRadii);
    ch.value.resize(kRadii);
    ch.cumulative.resize(kRadii);
    for (int i = 0; i < kRadii; ++i) {
      const double r = rLo * std::pow(rHi / rLo, i / double(kRadii - 1));
      ch.r[i] = r;
      ch.value[i] = std::max(multipleScattering(m, r) + singleScattering(m, r), 1e-300);
    }
    // Exact integral of the log-log interpolant: R = R_i (r / r_i)^p on each interval; a
    // constant R_0 inside r_0.
    ch.cumulative[0] = M_PI * ch.r[0] * ch.r[0] * ch.value[0];
    for (int i = 1; i < kRadii; ++i) {
      const double p = std::log(ch.value[i] / ch.value[i - 1]) / std::log(ch.r[i] / ch.r[i - 1]);
      const double a = ch.r[i - 1], b = ch.r[i];
      const double q = p + 2.0;
      const double piece =
          std::abs(q) < 1e-9
              ? 2.0 * M_PI * ch.value[i - 1] * a * a * std::log(b / a)
              : 2.0 * M_PI * ch.value[i - 1] * a * a * (std::pow(b / a, q) - 1.0) / q;
      ch.cumulative[i] = ch.cumulative[i - 1] + piece;
    }
    // Energy from transport truth: scale the shape to the half-space diffuse albedo.
    const double raw = ch.cumulative.back();
    const double truth = halfSpaceDiffuseAlbedo(m.sigmaSPrime / st, m.eta);
    const double factor = raw > 0.0 ? truth / raw : 0.0;
    for (int i = 0; i < kRadii; ++i) {
      ch.value[i] = std::max(ch.value[i] * factor, 1e-300);
      ch.cumulative[i] *= factor;
    }
    total_[c] = ch.cumulative.back();
  }
}

glm::dvec3 BeamDiffusionProfile::evaluate(double r) const {
  glm::dvec3 out;
  for (int c = 0; c < 3; ++c) {
    const Channel& ch = channels_[c];
    if (r <= ch.r.front()) {
      out[c] = ch.value.front();
    } else if (r >= ch.r.back()) {
      out[c] = 0.0;
    } else {
      const auto it = std::upper_bound(ch.r.begin(), ch.r.end(), r);
      const std::size_t i = it - ch.r.begin();
      const double p = std::log(ch.value[i] / ch.value[i - 1]) / std::log(ch.r[i] / ch.r[i - 1]);
      out[c] = ch.value[i - 1] * std::pow(r / ch.r[i - 1], p);
    }
  }
  return out;
}

glm::dvec3 BeamDiffusionProfile::integrateDisc(double rho) const {
  glm::dvec3 out;
  for (int c = 0; c < 3; ++c) {
    const Channel& ch = channels_[c];
    if (rho <= ch.r.front()) {
      out[c] = M_PI * rho * rho * ch.value.front();
    } else if (rho >= ch.r.back()) {
      out[c] = ch.cumulative.back();
    } else {
      const std::size_t i = std::upper_bound(ch.r.begin(), ch.r.end(), rho) - ch.r.begin();
      const double p = std::log(ch.value[i] / ch.value[i - 1]) / std::log(ch.r[i] / ch.r[i - 1]);
      const double a = ch.r[i - 1], q = p + 2.0;
      const double piece =
          std::abs(q) < 1e-9
              ? 2.0 * M_PI * ch.value[i - 1] * a * a * std::log(rho / a)
              : 2.0 * M_PI * ch.value[i - 1] * a * a * (std::pow(rho / a, q) - 1.0) / q;
      out[c] = ch.cumulative[i - 1] + piece;
    }
  }
  return out;
}

}  // namespace sss

#include "material/material.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "material/halfspace_albedo.h"

namespace sss {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string channelText(const glm::dvec3& v) {
  std::ostringstream out;
  out << v.x << "," << v.y << "," << v.z;
  return out.str();
}

void checkCoefficient(const std::string& context, const char* what, const glm::dvec3& v) {
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(v[c]))
      fail(context, std::string(what) + " is not a finite number (" + channelText(v) + ")");
    if (v[c] < 0.0) fail(context, std::string(what) + " is negative (" + channelText(v) + ")");
    if (v[c] > kMaxCoefficient)
      fail(context,
           std::string(what) + " is absurdly large (" + channelText(v) + " per mm; at most 1e4)");
  }
}

}  // namespace

glm::dvec3 Material::sigmaTr() const {
  const glm::dvec3 st = sigmaTPrime();
  return glm::dvec3(std::sqrt(3.0 * sigmaA.x * st.x), std::sqrt(3.0 * sigmaA.y * st.y),
                    std::sqrt(3.0 * sigmaA.z * st.z));
}

void checkMaterialEta(double eta, const std::string& context) {
  if (!std::isfinite(eta) || eta < 1.0 || eta > 3.0) {
    std::ostringstream out;
    out << "eta " << eta << " is outside [1, 3]";
    fail(context, out.str());
  }
}

void checkDiffuseAlbedo(const glm::dvec3& albedo, const std::string& context) {
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(albedo[c]) || albedo[c] < 0.0 || albedo[c] > 1.0) {
      fail(context, "albedo " + channelText(albedo) + " must lie in [0, 1]");
    }
  }
}

void validateMaterial(const Material& m, const std::string& context) {
  checkCoefficient(context, "sigma_a", m.sigmaA);
  checkCoefficient(context, "sigma_s'", m.sigmaSPrime);
  const glm::dvec3 st = m.sigmaTPrime();
  for (int c = 0; c < 3; ++c)
    if (st[c] <= 0.0)
      fail(context,
           "zero extinction (sigma_a + sigma_s' = 0) in channel " + std::string(1, "RGB"[c]));
  checkMaterialEta(m.eta, context);
  if (!std::isfinite(m.g) || std::abs(m.g) >= 1.0) {
    std::ostringstream out;
    out << "phase anisotropy g " << m.g << " is outside (-1, 1)";
    fail(context, out.str());
  }
}

const std::vector<Material>& materialPresets() {
  // Jensen et al. 2001, Figure 5: sigma_s' and sigma_a in mm^-1, eta = 1.3.
  static const std::vector<Material> presets = {
      {"apple", {0.0030, 0.0034, 0.046}, {2.29, 2.39, 1.97}, 1.3, 0.0},
      {"chicken1", {0.015, 0.077, 0.19}, {0.15, 0.21, 0.38}, 1.3, 0.0},
      {"chicken2", {0.018, 0.088, 0.20}, {0.19, 0.25, 0.32}, 1.3, 0.0},
      {"cream", {0.0002, 0.0028, 0.0163}, {7.38, 5.47, 3.15}, 1.3, 0.0},
      {"ketchup", {0.061, 0.97, 1.45}, {0.18, 0.07, 0.03}, 1.3, 0.0},
      {"marble", {0.0021, 0.0041, 0.0071}, {2.19, 2.62, 3.00}, 1.3, 0.0},
      {"potato", {0.0024, 0.0090, 0.12}, {0.68, 0.70, 0.55}, 1.3, 0.0},
      {"skimmilk", {0.0014, 0.0025, 0.0142}, {0.70, 1.22, 1.90}, 1.3, 0.0},
      {"skin1", {0.032, 0.17, 0.48}, {0.74, 0.88, 1.01}, 1.3, 0.0},
      {"skin2", {0.013, 0.070, 0.145}, {1.09, 1.59, 1.79}, 1.3, 0.0},
      {"wholemilk", {0.0011, 0.0024, 0.014}, {2.55, 3.21, 3.77}, 1.3, 0.0},
  };
  return presets;
}

std::vector<std::string> materialPresetNames() {
  std::vector<std::string> names;
  for (const Material& m : materialPresets()) names.push_back(m.name);
  return names;
}

Material findMaterialPreset(const std::string& name) {
  const std::string key = lower(name);
  for (const Material& m : materialPresets())
    if (m.name == key) return m;
  std::string known;
  for (const std::string& n : materialPresetNames()) known += (known.empty() ? "" : ", ") + n;
  fail("", "unknown material '" + name + "' (known: " + known + ")");
}

Material materialFromAlbedoMfp(const glm::dvec3& albedo, const glm::dvec3& mfpMm, double eta,
                               const std::string& name) {
  checkMaterialEta(eta, name);
  const double maxAlbedo = halfSpaceDiffuseAlbedo(1.0, eta);
  Material m;
  m.name = name;
  m.eta = eta;
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(albedo[c]) || albedo[c] <= 0.0 || albedo[c] >= maxAlbedo) {
      std::ostringstream out;
      out << "albedo " << channelText(albedo) << " must lie in (0, " << maxAlbedo
          << ") (the half-space albedo's largest value at eta " << eta << ")";
      fail(name, out.str());
    }
    if (!std::isfinite(mfpMm[c]) || mfpMm[c] <= 0.0)
      fail(name, "mean free path " + channelText(mfpMm) + " mm must be positive");
    const double alphaPrime = scatteringAlbedoFromHalfSpaceAlbedo(albedo[c], eta);
    const double sigmaTr = 1.0 / mfpMm[c];
    const double sigmaTPrime = sigmaTr / std::sqrt(3.0 * (1.0 - alphaPrime));
    m.sigmaSPrime[c] = alphaPrime * sigmaTPrime;
    m.sigmaA[c] = sigmaTPrime - m.sigmaSPrime[c];
  }
  validateMaterial(m, name);
  return m;
}

}  // namespace sss

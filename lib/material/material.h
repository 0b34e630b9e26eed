// Homogeneous scattering materials: coefficients, validation, measured presets and the artists'
// (albedo, mean free path) parameterization.
//
// Sources:
// - Presets: Jensen, Marschner, Levoy, Hanrahan, "A Practical Model for Subsurface Light
//   Transport", SIGGRAPH 2001, Figure 5: reduced scattering sigma_s' and absorption sigma_a in
//   mm^-1 for the R, G, B channels, measured with eta = 1.3 (the value the paper renders with).
// - Albedo/mfp inversion: Jensen & Buhler, "A Rapid Hierarchical Rendering Technique for
//   Translucent Materials", SIGGRAPH 2002, Sec. 4: the user gives the total diffuse reflectance
//   R_d and the diffuse mean free path l_d = 1 / sigma_tr; alpha' follows by inverting R_d(alpha')
//   numerically, then sigma_t' = sigma_tr / sqrt(3 (1 - alpha')), sigma_s' = alpha' sigma_t',
//   sigma_a = sigma_t' - sigma_s'. Unlike Jensen & Buhler we invert the Monte Carlo half-space
//   albedo (halfspace_albedo.h), the energy the bake's profiles return on a lit plane, not the
//   dipole's total (off by -5 % to +7 %): the albedo asked for is the albedo the bake gives.
//
// Units: every coefficient is per millimetre; every length is in millimetres.
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sss {

struct Material {
  std::string name;
  glm::dvec3 sigmaA{0.0};       // absorption coefficient, mm^-1
  glm::dvec3 sigmaSPrime{0.0};  // reduced scattering coefficient sigma_s (1 - g), mm^-1
  double eta = 1.3;             // refractive index of the medium relative to outside
  double g = 0.0;               // Henyey-Greenstein mean cosine (Monte Carlo reference only)

  // Reduced extinction sigma_t' = sigma_a + sigma_s'.
  glm::dvec3 sigmaTPrime() const { return sigmaA + sigmaSPrime; }
  // Reduced albedo alpha' = sigma_s' / sigma_t'.
  glm::dvec3 reducedAlbedo() const { return sigmaSPrime / sigmaTPrime(); }
  // Effective transport coefficient sigma_tr = sqrt(3 sigma_a sigma_t') (classic diffusion).
  glm::dvec3 sigmaTr() const;
  // Scattering coefficient sigma_s = sigma_s' / (1 - g) for a walk with phase function g.
  glm::dvec3 sigmaS() const { return sigmaSPrime / (1.0 - g); }
  // Reduced (transport) mean free path 1 / sigma_t', mm: the depth of the dipole's real source.
  glm::dvec3 meanFreePath() const { return 1.0 / sigmaTPrime(); }
  // Diffuse mean free path l_d = 1 / sigma_tr, mm (Jensen & Buhler 2002): how far light
  // diffuses sideways; infinite without absorption.
  glm::dvec3 diffuseMeanFreePath() const { return 1.0 / sigmaTr(); }
};

// Throws sss::Error("<context>: <problem>") for NaN/infinite or negative coefficients, values
// above kMaxCoefficient, zero extinction in a channel, eta outside [1, 3], |g| >= 1.
inline constexpr double kMaxCoefficient = 1e4;  // mm^-1: a 0.1 micrometre mean free path
void validateMaterial(const Material& material, const std::string& context = "material");
// The relative index of refraction a material may have: finite, in [1, 3] (validateMaterial's
// check, for tools that check --eta as it is parsed).
void checkMaterialEta(double eta, const std::string& context = "");

// A diffuse (Lambertian) albedo, as sss-render's BRDF takes it: each channel finite, in [0, 1]
// (energy conservation). Throws Error("<context>: ..."). (materialFromAlbedoMfp needs more: a
// total reflectance in (0, 1) that the half-space albedo can invert.)
void checkDiffuseAlbedo(const glm::dvec3& albedo, const std::string& context = "");

// The measured presets of Jensen et al. 2001 (apple ... wholemilk), eta = 1.3.
const std::vector<Material>& materialPresets();
std::vector<std::string> materialPresetNames();
// Case-insensitive lookup; throws sss::Error listing the known names.
Material findMaterialPreset(const std::string& name);

// Jensen & Buhler 2002 inversion (see header comment). albedo: total diffuse reflectance per
// channel (the half-space albedo) in (0, halfSpaceDiffuseAlbedo(1, eta)); mfp: diffuse mean free
// path l_d = 1 / sigma_tr in mm (> 0). Throws sss::Error on values out of range.
Material materialFromAlbedoMfp(const glm::dvec3& albedo, const glm::dvec3& mfpMm, double eta,
                               const std::string& name = "custom");

}  // namespace sss

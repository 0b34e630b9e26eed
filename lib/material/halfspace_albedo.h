// Total diffuse reflectance of a semi-infinite homogeneous medium: the energy a profile must
// integrate to. Transport truth, not a diffusion approximation.
//
// Setup: isotropic scattering with single-scattering albedo a (reduced coefficients, so
// a = alpha' for the presets), smooth dielectric boundary of relative index eta, uniform
// (diffuse) radiance incident from outside. The value is the flux leaving through the boundary
// per unit flux *transmitted* into the medium (the bake's irradiance E already carries the entry
// Fresnel factor). Computed by an analog 1D Monte Carlo walk (the half-space is translation
// invariant, so only depth and direction cosine matter): entry direction cosine-weighted and
// refracted, exponential free flights, isotropic scattering, absorption with probability 1 - a,
// exact Fresnel reflection at the boundary (total internal reflection included).
// Validated against Chandrasekhar's H-function at eta = 1 (tests/material): the diffuse albedo
// is 1 - 2 sqrt(1 - a) int_0^1 H(mu) mu dmu.
//
// halfSpaceDiffuseAlbedo interpolates a table made once by tests/bench/material_albedo_table
// (2e5 photons per node) over u = sqrt(1 - a) in 33 nodes (Catmull-Rom;
// the albedo is nearly linear in u near a = 1) and eta nodes 1.0, 1.1, ..., 2.0, 2.25, ..., 3.0
// (linear).
#pragma once

#include <cstdint>

namespace sss {

struct HalfSpaceAlbedoEstimate {
  double albedo = 0.0;
  double standardError = 0.0;
};

// Monte Carlo estimate; deterministic for a given seed (photon i uses stream i).
HalfSpaceAlbedoEstimate simulateHalfSpaceAlbedo(double scatteringAlbedo, double eta,
                                                int64_t photons, uint64_t seed = 1);

// The same for collimated light arriving from outside at direction cosine muOutside (0..1),
// refracted in: the directional albedo, per transmitted flux. Light arriving at grazing angles
// enters at the critical angle and scatters shallower, so more of it comes back than at normal
// incidence; by reciprocity the same function of the exit cosine shapes the radiance that leaves
// under uniform light.
HalfSpaceAlbedoEstimate simulateHalfSpaceDirectionalAlbedo(double scatteringAlbedo, double eta,
                                                           double muOutside, int64_t photons,
                                                           uint64_t seed = 1);

// Tabulated value for a in [0, 1], eta in [1, 3] (clamped).
double halfSpaceDiffuseAlbedo(double scatteringAlbedo, double eta);

// Its inverse in the scattering albedo: the a in [0, 1] with halfSpaceDiffuseAlbedo(a, eta) =
// albedo (bisection; the table rises with a). albedo in [0, halfSpaceDiffuseAlbedo(1, eta)].
double scatteringAlbedoFromHalfSpaceAlbedo(double albedo, double eta);

// The directional albedo from a second table (the same generator, 2e5 photons per node) over
// eta nodes as above, u = sqrt(1 - a) = k / 16 and the outside cosine mu = k / 16 (trilinear).
double halfSpaceDirectionalAlbedo(double scatteringAlbedo, double eta, double muOutside);

// The tables' nodes (for the generator).
inline constexpr int kDirectionalAlbedoNodes = 17;  // u = k / 16
inline constexpr int kDirectionalCosineNodes = 17;  // mu = k / 16
inline constexpr int kHalfSpaceAlbedoNodes = 33;
inline constexpr int kHalfSpaceEtaNodes = 15;
inline constexpr double kHalfSpaceEtas[kHalfSpaceEtaNodes] = {
    1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7, 1.8, 1.9, 2.0, 2.25, 2.5, 2.75, 3.0};

}  // namespace sss

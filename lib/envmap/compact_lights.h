// The bright compact sources of an environment (a sun, lamps), split off as directional lights,
// so that the rest is smooth enough for low-order spherical harmonics (a relightable bake,
// bake/relight.h; docs/relighting.md). Real HDR maps put 14-59 % of their flux into 0.1 % of
// their texels; spherical harmonics of order 3-6 ring around such a source and lose the sharp
// shadow it casts, while a directional light keeps both, its visibility traced at relight time.
//
// The split: the texels brighter than minContrast times the map's mean radiance (luminance), the
// brightest first, until they cover maxSolidAngleFraction of the sphere; grouped greedily into
// lights, each the selected texels within clusterDeg of its brightest one (at most maxLights; the
// rest stay in the map). A light's irradiance is its texels' sum of L dw (RGB, at normal
// incidence), its direction their flux-weighted mean. The map that is left has those texels at 0,
// so that the lights and the map add up to the environment's flux exactly.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "envmap/cubemap.h"

namespace sss {

struct CompactLightOptions {
  double maxSolidAngleFraction = 1e-3;  // of 4 pi
  double minContrast = 20.0;            // radiance over the map's mean (luminance)
  double clusterDeg = 4.0;
  int maxLights = 8;
};

struct DirectionalLight {
  glm::vec3 direction{0.0f, 0.0f, 1.0f};  // unit, towards the light
  glm::vec3 irradiance{0.0f};             // sum of L dw over its texels, per channel
  double solidAngle = 0.0;                // sr
};

struct CompactLightSplit {
  std::vector<DirectionalLight> lights;
  Cubemap rest;            // the environment without them
  double fluxShare = 0.0;  // the lights' share of the environment's irradiance (luminance)
};

CompactLightSplit splitCompactLights(const Cubemap& radiance,
                                     const CompactLightOptions& options = {});

}  // namespace sss

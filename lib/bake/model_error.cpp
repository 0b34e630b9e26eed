#include "bake/model_error.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "core/timer.h"
#include "material/directional_albedo_weight.h"
#include "material/material.h"
#include "optics/fresnel.h"

namespace sss {

namespace {

// Per vertex: the facets' mean tilt 1 - n . n_f (area-weighted) and the one-ring's mean E (each
// neighbour once per face it shares with the vertex).
struct OneRing {
  std::vector<double> tilt;
  std::vector<glm::dvec3> meanIrradiance;
};

OneRing oneRing(const TriangleMesh& m, std::span<const glm::vec3> irradiance) {
  const std::size_t n = m.positions.size();
  OneRing ring{std::vector<double>(n, 0.0), std::vector<glm::dvec3>(n, glm::dvec3(0.0))};
  std::vector<double> area(n, 0.0), neighbours(n, 0.0);
  for (const glm::uvec3& t : m.triangles) {
    const glm::vec3 c =
        glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
    const double twiceArea = glm::length(c);
    for (int k = 0; k < 3; ++k) {
      const unsigned v = t[k];
      if (twiceArea > 0.0) {
        ring.tilt[v] += twiceArea * (1.0 - glm::dot(m.normals[v], c / float(twiceArea)));
        area[v] += twiceArea;
      }
      ring.meanIrradiance[v] +=
          glm::dvec3(irradiance[t[(k + 1) % 3]]) + glm::dvec3(irradiance[t[(k + 2) % 3]]);
      neighbours[v] += 2.0;
    }
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (area[v] > 0.0) ring.tilt[v] /= area[v];
    if (neighbours[v] > 0.0) ring.meanIrradiance[v] /= neighbours[v];
  }
  return ring;
}

}  // namespace

ModelErrorReport estimateModelError(const ModelErrorInput& in) {
  const Stopwatch clock;
  const OneRing ring = oneRing(in.mesh, in.irradiance);
  const glm::dvec3 spread2 = glm::dvec3(in.exitModelSpread) * glm::dvec3(in.exitModelSpread);
  double exit2 = 0.0, facets2 = 0.0, light2 = 0.0, weight = 0.0;
  for (std::size_t v = 0; v < in.radianceAlongNormal.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      const double l2 = double(in.radianceAlongNormal[v][c]) * in.radianceAlongNormal[v][c];
      const double e = in.irradiance[v][c], mean = ring.meanIrradiance[v][c];
      const double peak = std::max(e, mean);
      const double contrast = peak > 0.0 ? std::abs(e - mean) / peak : 0.0;
      weight += l2;
      exit2 += l2 * spread2[c];
      facets2 += l2 * ring.tilt[v] * ring.tilt[v];
      light2 += l2 * contrast * contrast;
    }
  ModelErrorReport r;
  if (!(weight > 0.0)) return r;  // a black environment
  r.exitModel = kExitModelWeight * std::sqrt(exit2 / weight);
  r.facets = kFacetWeight * std::sqrt(facets2 / weight);
  r.lightVariation = kLightVariationWeight * std::sqrt(light2 / weight);
  r.total = std::sqrt(r.exitModel * r.exitModel + r.facets * r.facets +
                      r.lightVariation * r.lightVariation);
  r.seconds = clock.seconds();
  return r;
}

glm::vec3 exitModelSpread(const Material& material) {
  const float eta = float(material.eta);
  const glm::vec3 calibrated = calibratedExitRadiance(DirectionalAlbedoWeight(material), 1.0f, eta);
  return glm::abs(calibrated / float(normalExitRadianceScale(eta)) - glm::vec3(1.0f));
}

}  // namespace sss

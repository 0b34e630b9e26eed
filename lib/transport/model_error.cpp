#include "transport/model_error.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "core/timer.h"
#include "irradiance/irradiance.h"
#include "material/directional_albedo_weight.h"
#include "optics/fresnel.h"

namespace sss {

namespace {

// The irradiance sizes an error term, so a few percent will do: it is summed from the radiance at
// 32 texels per face (box-filtered, so a sun keeps its power, spread over a 2.8-degree texel that
// a cosine lobe hardly tells from a point) into 16 texels per face, at a 3 % tolerance (what that
// costs: docs/performance.md, "The bake").
constexpr int kRadianceFaceSize = 32;
constexpr int kIrradianceFaceSize = 16;
constexpr double kIrradianceTolerance = 0.03;

// Per vertex, area-weighted over its faces: the tilt 1 - n . n_f and the facets' light contrast
// |E(n_f) - E(n)| / max(E(n), mean E(n_f)) per channel.
struct Facets {
  std::vector<double> tilt;
  std::vector<glm::dvec3> lightContrast;
};

Facets facetsOf(const TriangleMesh& m, const Cubemap& irradiance) {
  const std::size_t n = m.positions.size();
  Facets f{std::vector<double>(n, 0.0), std::vector<glm::dvec3>(n, glm::dvec3(0.0))};
  std::vector<glm::dvec3> meanE(n, glm::dvec3(0.0));
  std::vector<double> area(n, 0.0);
  std::vector<glm::dvec3> atNormal(n);
  for (std::size_t v = 0; v < n; ++v) atNormal[v] = glm::dvec3(irradiance.sample(m.normals[v]));
  for (const glm::uvec3& t : m.triangles) {
    const glm::vec3 c =
        glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
    const float twiceArea = glm::length(c);
    if (!(twiceArea > 0.0f)) continue;
    const glm::vec3 faceNormal = c / twiceArea;
    const glm::dvec3 e(irradiance.sample(faceNormal));
    for (int k = 0; k < 3; ++k) {
      const unsigned v = t[k];
      f.tilt[v] += twiceArea * (1.0 - glm::dot(m.normals[v], faceNormal));
      f.lightContrast[v] += double(twiceArea) * glm::abs(e - atNormal[v]);
      meanE[v] += double(twiceArea) * e;
      area[v] += twiceArea;
    }
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (!(area[v] > 0.0)) continue;
    f.tilt[v] /= area[v];
    const glm::dvec3 peak = glm::max(atNormal[v], meanE[v] / area[v]);
    for (int c = 0; c < 3; ++c)
      f.lightContrast[v][c] = peak[c] > 0.0 ? f.lightContrast[v][c] / area[v] / peak[c] : 0.0;
  }
  return f;
}

}  // namespace

ModelErrorReport estimateModelError(const ModelErrorInput& in) {
  const Stopwatch clock;
  IrradianceOptions options;
  options.eta = in.eta;
  options.faceSize = kIrradianceFaceSize;
  options.tolerance = kIrradianceTolerance;
  options.threads = in.threads;
  const Cubemap radiance =
      in.radiance.size() > kRadianceFaceSize ? in.radiance.resized(kRadianceFaceSize) : in.radiance;
  const Facets facets = facetsOf(in.mesh, computeIrradiance(radiance, options).irradiance);
  const glm::dvec3 spread2 = glm::dvec3(in.exitModelSpread) * glm::dvec3(in.exitModelSpread);
  double exit2 = 0.0, tilt2 = 0.0, light2 = 0.0, bounce2 = 0.0, weight = 0.0;
  for (std::size_t v = 0; v < in.radianceAlongNormal.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      const double l2 = double(in.radianceAlongNormal[v][c]) * in.radianceAlongNormal[v][c];
      const double modelled = in.vertexModelRadiance.empty() ? in.radianceAlongNormal[v][c]
                                                             : in.vertexModelRadiance[v][c];
      const double m2 = modelled * modelled;
      weight += l2;
      exit2 += m2 * spread2[c];
      tilt2 += l2 * facets.tilt[v] * facets.tilt[v];
      light2 += m2 * facets.lightContrast[v][c] * facets.lightContrast[v][c];
      if (!in.interreflectedRadiance.empty())
        bounce2 += double(in.interreflectedRadiance[v][c]) * in.interreflectedRadiance[v][c];
    }
  ModelErrorReport r;
  if (weight > 0.0) {  // else a black environment
    r.exitModel = kExitModelWeight * std::sqrt(exit2 / weight);
    r.facets = kFacetWeight * std::sqrt(tilt2 / weight);
    r.facetLight = kFacetLightWeight * std::sqrt(light2 / weight);
    r.farField = kFarFieldWeight * in.farFieldError;
    r.interreflection = kInterreflectionWeight * std::sqrt(bounce2 / weight);
    r.total =
        std::sqrt(r.exitModel * r.exitModel + r.facets * r.facets + r.facetLight * r.facetLight +
                  r.farField * r.farField + r.interreflection * r.interreflection);
  }
  r.seconds = clock.seconds();
  return r;
}

glm::vec3 exitModelSpread(const Material& material) {
  const float eta = float(material.eta);
  const glm::vec3 calibrated = calibratedExitRadiance(DirectionalAlbedoWeight(material), 1.0f, eta);
  return glm::abs(calibrated / float(normalExitRadianceScale(eta)) - glm::vec3(1.0f));
}

}  // namespace sss

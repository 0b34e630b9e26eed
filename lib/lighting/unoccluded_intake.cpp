#include "lighting/unoccluded_intake.h"

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "core/luminance.h"
#include "core/parallel.h"
#include "lighting/facet_light.h"
#include "optics/fresnel.h"

namespace sss {

namespace {

// k(mu) = F_t(mu) mu and k(mu) w(mu), tabulated in mu: the exact Fresnel per source texel and
// normal would cost more than the sums themselves.
class IntakeKernel {
 public:
  IntakeKernel(float eta, const DirectionalAlbedoWeight* entry) : hasEntry_(entry != nullptr) {
    for (int i = 0; i < kNodes; ++i) {
      const float mu = static_cast<float>(i) / (kNodes - 1);
      transmitted_[i] = mu > 0.0f ? fresnelTransmittance(mu, eta) * mu : 0.0f;
      entryWeighted_[i] = entry ? transmitted_[i] * entry->at(mu) : glm::vec3(0.0f);
    }
  }

  // t += k(mu) flux and tw += k_w(mu) flux, for 0 < mu <= 1.
  void add(float mu, const glm::vec3& flux, glm::vec3& t, glm::vec3& tw) const {
    const float u = mu * (kNodes - 1);
    const int k = std::min(static_cast<int>(u), kNodes - 2);
    const float a = u - static_cast<float>(k);
    t += ((1.0f - a) * transmitted_[k] + a * transmitted_[k + 1]) * flux;
    if (hasEntry_) tw += ((1.0f - a) * entryWeighted_[k] + a * entryWeighted_[k + 1]) * flux;
  }

 private:
  static constexpr int kNodes = 1025;
  std::array<float, kNodes> transmitted_;
  std::array<glm::vec3, kNodes> entryWeighted_;
  bool hasEntry_;
};

struct SourceTexel {
  glm::vec3 direction, flux;  // flux: L times the texel's solid angle
};

// The radiance's kSharpTexels texels of most flux stay at their own resolution, the rest is
// box-filtered to `size` a face: a sun keeps its place to a texel of the source (the lookup is
// within 0.052 % RMS of the exact sum under a small sun and a sky;
// tests/lighting/visibility_test.cpp, docs/tools/sss-bake.md, "Lighting and visibility"), and a
// smooth sky, which filtering moves only in second order, costs 6 size^2 terms.
constexpr std::size_t kSharpTexels = 512;

std::vector<SourceTexel> sourceTexels(const Cubemap& radiance, int size) {
  std::vector<SourceTexel> texels;
  // Texel (f, x, y) of `map`, unless black (a sky's ground); false if it was.
  const auto addTexel = [&](const Cubemap& map, float solidAngle, int f, int x, int y) {
    const glm::vec3 l = map.at(f, x, y);
    if (l.r <= 0.0f && l.g <= 0.0f && l.b <= 0.0f) return false;
    texels.push_back({map.direction(f, x, y), l * solidAngle});
    return true;
  };
  const auto addAll = [&](const Cubemap& map, const std::vector<float>& solidAngles) {
    forEachTexel(map.size(), [&](int f, int x, int y) {
      addTexel(map, solidAngles[std::size_t(y) * map.size() + x], f, x, y);
    });
  };
  if (radiance.size() < size) {
    // A coarse environment is piecewise constant over texels as wide as 20 degrees (the studies'
    // blurred ones: 4 a face), which the estimator integrates exactly and texel-centre quadrature
    // would not (the cosine bends across a texel, and a horizon cuts it): split each texel into
    // k x k of the same radiance.
    const int k = (size + radiance.size() - 1) / radiance.size();
    Cubemap split(radiance.size() * k);
    forEachTexel(split.size(),
                 [&](int f, int x, int y) { split.at(f, x, y) = radiance.at(f, x / k, y / k); });
    addAll(split, split.faceSolidAngles());
    return texels;
  }
  const std::vector<float>& fineAngles = radiance.faceSolidAngles();
  if (radiance.size() == size) {
    addAll(radiance, fineAngles);
    return texels;
  }
  // The sharp texels: those of most flux (luminance times solid angle).
  std::vector<std::pair<float, std::size_t>> flux;
  const std::size_t perFace = std::size_t(radiance.size()) * radiance.size();
  for (std::size_t i = 0; i < 6 * perFace; ++i)
    flux.push_back({luminance(radiance.data()[i]) * fineAngles[i % perFace], i});
  const std::size_t sharp = std::min(kSharpTexels, flux.size());
  std::nth_element(flux.begin(), flux.begin() + std::ptrdiff_t(sharp) - 1, flux.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  Cubemap rest = radiance;
  for (std::size_t k = 0; k < sharp; ++k) {
    const std::size_t i = flux[k].second;
    const int f = int(i / perFace), y = int(i % perFace) / radiance.size(),
              x = int(i % radiance.size());
    if (addTexel(radiance, fineAngles[i % perFace], f, x, y)) rest.at(f, x, y) = glm::vec3(0.0f);
  }
  const Cubemap coarse = rest.resized(size);
  addAll(coarse, coarse.faceSolidAngles());
  return texels;
}

}  // namespace

UnoccludedIntake::UnoccludedIntake(const Cubemap& radiance, float eta,
                                   const DirectionalAlbedoWeight* entry, int threads, int faceSize,
                                   int sourceFaceSize)
    : transmitted_(faceSize), entryWeighted_(entry ? faceSize : 0), hasEntry_(entry != nullptr) {
  const IntakeKernel kernel(eta, entry);
  const std::vector<SourceTexel> texels = sourceTexels(radiance, sourceFaceSize);
  const std::size_t perFace = std::size_t(faceSize) * faceSize;
  parallelFor(6 * perFace, threads, 64, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const int f = int(i / perFace), y = int(i % perFace) / faceSize, x = int(i % faceSize);
      const glm::vec3 n = transmitted_.direction(f, x, y);
      glm::vec3 t(0.0f), tw(0.0f);
      for (const SourceTexel& s : texels) {
        const float mu = glm::dot(n, s.direction);
        if (mu > 0.0f) kernel.add(mu, s.flux, t, tw);
      }
      transmitted_.at(f, x, y) = t;
      if (hasEntry_) entryWeighted_.at(f, x, y) = tw;
    }
  });
}

UnoccludedIntake::Value UnoccludedIntake::at(const VertexFacets& facets, std::size_t v,
                                             const glm::vec3& normal) const {
  Value value;
  const auto add = [&](const glm::vec3& n, float share) {
    value.transmitted += share * transmitted_.sample(n);
    if (hasEntry_) value.entryWeighted += share * entryWeighted_.sample(n);
  };
  forEachLightFacet(facets, v, normal, add);
  return value;
}

}  // namespace sss

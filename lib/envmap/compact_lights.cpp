#include "envmap/compact_lights.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "core/luminance.h"

namespace sss {

namespace {

struct Texel {
  int face, x, y;
  float luminance;  // of the radiance
};

// The texels above the contrast, brightest first, until they cover the solid angle allowed; and
// the map's irradiance (luminance, sum of L dw).
struct BrightTexels {
  std::vector<Texel> texels;
  double flux = 0.0;
};

// The solid angle of texel (x, y) of any face, from the process's kept table
// (Cubemap::faceSolidAngles: taken once here, not per texel, which would lock it each time).
class TexelSolidAngles {
 public:
  explicit TexelSolidAngles(const Cubemap& radiance)
      : n_(radiance.size()), dw_(radiance.faceSolidAngles()) {}
  float operator()(int x, int y) const { return dw_[std::size_t(y) * n_ + x]; }

 private:
  int n_;
  const std::vector<float>& dw_;
};

BrightTexels brightestTexels(const Cubemap& radiance, const TexelSolidAngles& texelSolidAngle,
                             const CompactLightOptions& o) {
  const int n = radiance.size();
  double flux = 0.0, solidAngle = 0.0;
  forEachTexel(n, [&](int f, int x, int y) {
    const float dw = texelSolidAngle(x, y);
    flux += double(luminance(radiance.at(f, x, y))) * dw;
    solidAngle += dw;
  });
  const double threshold = o.minContrast * flux / std::max(solidAngle, 1e-30);
  std::vector<Texel> all;
  forEachTexel(n, [&](int f, int x, int y) {
    const float l = luminance(radiance.at(f, x, y));
    if (l > threshold) all.push_back({f, x, y, l});
  });
  std::stable_sort(all.begin(), all.end(),
                   [](const Texel& a, const Texel& b) { return a.luminance > b.luminance; });
  const double allowed = o.maxSolidAngleFraction * 4.0 * M_PI;
  double covered = 0.0;
  std::size_t kept = 0;
  for (; kept < all.size(); ++kept) {
    covered += texelSolidAngle(all[kept].x, all[kept].y);
    if (covered > allowed) break;
  }
  all.resize(kept);
  return {std::move(all), flux};
}

}  // namespace

CompactLightSplit splitCompactLights(const Cubemap& radiance, const CompactLightOptions& o) {
  CompactLightSplit out;
  out.rest = radiance;
  const TexelSolidAngles texelSolidAngle(radiance);
  const BrightTexels selected = brightestTexels(radiance, texelSolidAngle, o);
  const std::vector<Texel>& bright = selected.texels;
  const float cosCluster = float(std::cos(o.clusterDeg * M_PI / 180.0));
  std::vector<char> taken(bright.size(), 0);
  for (std::size_t seed = 0; seed < bright.size() && int(out.lights.size()) < o.maxLights; ++seed) {
    if (taken[seed]) continue;
    const glm::vec3 axis = radiance.direction(bright[seed].face, bright[seed].x, bright[seed].y);
    DirectionalLight light;
    glm::dvec3 weighted(0.0);
    for (std::size_t i = seed; i < bright.size(); ++i) {
      const Texel& t = bright[i];
      const glm::vec3 d = radiance.direction(t.face, t.x, t.y);
      if (taken[i] || glm::dot(d, axis) < cosCluster) continue;
      taken[i] = 1;
      const float dw = texelSolidAngle(t.x, t.y);
      const glm::vec3 e = radiance.at(t.face, t.x, t.y) * dw;
      light.irradiance += e;
      light.solidAngle += dw;
      weighted += glm::dvec3(d) * double(luminance(e));
      out.rest.at(t.face, t.x, t.y) = glm::vec3(0.0f);
    }
    light.direction = glm::length(weighted) > 0.0 ? glm::vec3(glm::normalize(weighted)) : axis;
    out.lights.push_back(light);
  }
  double lights = 0.0;
  for (const DirectionalLight& l : out.lights) lights += luminance(l.irradiance);
  out.fluxShare = selected.flux > 0.0 ? lights / selected.flux : 0.0;
  return out;
}

}  // namespace sss

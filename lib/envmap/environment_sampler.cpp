#include "envmap/environment_sampler.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/luminance.h"

namespace sss {

namespace {

// Per texel (storage order): luminance x solid angle; `total` their sum.
std::vector<double> texelWeights(const Cubemap& radiance, double& total) {
  const int n = radiance.size();
  std::vector<double> weight(radiance.texelCount());
  total = 0.0;
  forEachTexel(n, [&](int face, int x, int y) {
    const double w = std::max(0.0f, luminance(radiance.at(face, x, y))) *
                     static_cast<double>(radiance.solidAngle(face, x, y));
    weight[radiance.index(face, x, y)] = w;
    total += w;
  });
  return weight;
}

// The texel indices face by face, each face in Morton (Z-curve) order.
std::vector<uint32_t> mortonTexelOrder(const Cubemap& radiance) {
  const int n = radiance.size();
  std::vector<uint32_t> order;
  order.reserve(radiance.texelCount());
  uint32_t side = 1;  // the Z-curve covers a power-of-two square; codes outside the face skip
  while (side < static_cast<uint32_t>(n)) side *= 2;
  for (int face = 0; face < 6; ++face) {
    for (uint32_t code = 0; code < side * side; ++code) {
      uint32_t x = 0, y = 0;
      for (int b = 0; b < 16; ++b) {
        x |= ((code >> (2 * b)) & 1u) << b;
        y |= ((code >> (2 * b + 1)) & 1u) << b;
      }
      if (x < static_cast<uint32_t>(n) && y < static_cast<uint32_t>(n)) {
        order.push_back(
            static_cast<uint32_t>(radiance.index(face, static_cast<int>(x), static_cast<int>(y))));
      }
    }
  }
  return order;
}

// Guide table (Chen & Asau 1974): entry k is the CDF position of u = k / count, so that sampling
// inverts the CDF by a binary search over the few texels of one bucket instead of all of them.
std::vector<uint32_t> guideTable(const std::vector<double>& cdf) {
  const std::size_t count = cdf.size() - 1;
  std::vector<uint32_t> guide(count + 1);
  std::size_t i = 0;
  for (std::size_t k = 0; k <= count; ++k) {
    const double u = static_cast<double>(k) / static_cast<double>(count);
    while (i + 1 < count && cdf[i + 1] <= u) ++i;
    guide[k] = static_cast<uint32_t>(i);
  }
  return guide;
}

}  // namespace

EnvironmentSampler::EnvironmentSampler(const Cubemap& radiance) : cubemap_(&radiance) {
  const int n = radiance.size();
  if (n <= 0) fail("", "empty environment cubemap");
  const std::size_t count = radiance.texelCount();
  double total = 0.0;
  const std::vector<double> weight = texelWeights(radiance, total);
  if (!(total > 0.0) || !std::isfinite(total)) {
    fail("", "the environment is black (or not finite): nothing to light the mesh with");
  }
  order_ = mortonTexelOrder(radiance);
  cdf_.assign(count + 1, 0.0);
  pdfScale_.resize(count);
  double running = 0.0;
  for (std::size_t j = 0; j < count; ++j) {
    const std::size_t i = order_[j];
    running += weight[i];
    cdf_[j + 1] = running / total;
    // Uniform over the texel's (s, t) square: ds dt = dw |d|^3 / 4 with d = unproject(s, t).
    pdfScale_[i] = static_cast<float>(weight[i] / total * n * n / 4.0);
  }
  cdf_.back() = 1.0;
  guide_ = guideTable(cdf_);
}

EnvironmentSampler::Sample EnvironmentSampler::sample(float u1, float u2) const {
  const double u = u1;
  // cdf_[i] <= u < cdf_[i + 1]: a texel of non-zero probability.
  const std::size_t count = guide_.size() - 1;
  const std::size_t k =
      std::min(static_cast<std::size_t>(u * static_cast<double>(count)), count - 1);
  const auto it =
      std::upper_bound(cdf_.begin() + guide_[k] + 1, cdf_.begin() + guide_[k + 1] + 2, u);
  const std::size_t j = std::min(static_cast<std::size_t>(it - cdf_.begin()) - 1, count - 1);
  const std::size_t i = order_[j];
  const double width = cdf_[j + 1] - cdf_[j];
  const float across =
      width > 0.0 ? static_cast<float>(std::clamp((u - cdf_[j]) / width, 0.0, 1.0)) : 0.5f;
  const int n = cubemap_->size();
  const std::size_t perFace = static_cast<std::size_t>(n) * n;
  const int face = static_cast<int>(i / perFace);
  const int y = static_cast<int>((i % perFace) / n);
  const int x = static_cast<int>(i % n);
  const glm::vec3 d = Cubemap::unproject(face, (static_cast<float>(x) + across) / n,
                                         (static_cast<float>(y) + u2) / n);
  const float length = std::sqrt(glm::dot(d, d));
  return {d / length, pdfScale_[i] * length * length * length, cubemap_->data()[i]};
}

std::size_t EnvironmentSampler::texelIndex(const glm::vec3& direction) const {
  const CubeCoord c = Cubemap::project(direction);
  const int n = cubemap_->size();
  const int x = std::clamp(static_cast<int>(c.s * n), 0, n - 1);
  const int y = std::clamp(static_cast<int>(c.t * n), 0, n - 1);
  return cubemap_->index(c.face, x, y);
}

float EnvironmentSampler::pdf(const glm::vec3& direction) const {
  const float m = std::max({std::abs(direction.x), std::abs(direction.y), std::abs(direction.z)});
  return pdfScale_[texelIndex(direction)] / (m * m * m);
}

glm::vec3 EnvironmentSampler::radiance(const glm::vec3& direction) const {
  return cubemap_->data()[texelIndex(direction)];
}

}  // namespace sss

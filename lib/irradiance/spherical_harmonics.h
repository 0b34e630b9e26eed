// Real spherical harmonics of RGB functions on the sphere, up to a given order (band) L:
// (L + 1)^2 coefficients c_lm, index l (l + 1) + m. Orthonormal real basis as in Sloan 2008
// ("Stupid spherical harmonics tricks"), evaluated by the associated Legendre recurrence.
//
// Irradiance follows Ramamoorthi & Hanrahan 2001: E_lm = kHat_l L_lm (Funk-Hecke), with the
// kernel's zonal coefficients from TransmittedCosineKernel. Truncated at order 2 this is their
// 9-coefficient irradiance environment map. An optional window damps the highest bands against
// ringing near bright sources (Sloan 2008, section 7: Hann or Lanczos sigma factors).
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/enum_names.h"
#include "envmap/cubemap.h"
#include "image/image.h"
#include "irradiance/transmitted_cosine.h"

namespace sss {

enum class ShWindow { None, Hann, Lanczos };
inline constexpr EnumNames<ShWindow, 3> kShWindowNames{
    "SH window",
    {{{ShWindow::None, "none"}, {ShWindow::Hann, "hann"}, {ShWindow::Lanczos, "lanczos"}}}};
// Weight of band l when truncating at `order`: 1 for None.
double shWindowWeight(ShWindow window, int l, int order);

class SphericalHarmonics {
 public:
  static constexpr int kMaxOrder = 16;

  SphericalHarmonics() = default;
  explicit SphericalHarmonics(int order);  // all coefficients zero; 0 <= order <= kMaxOrder

  int order() const { return order_; }
  int coefficientCount() const { return static_cast<int>(coefficients_.size()); }
  static int index(int l, int m) { return l * (l + 1) + m; }
  glm::vec3& operator[](int i) { return coefficients_[i]; }
  const glm::vec3& operator[](int i) const { return coefficients_[i]; }
  const std::vector<glm::vec3>& coefficients() const { return coefficients_; }

  // Y_lm(direction) for every l <= order into out[(order + 1)^2]; direction must be unit length.
  static void evaluateBasis(int order, const glm::vec3& direction, float* out);

  // Projection sum_j L_j Y_lm(w_j) dw_j over every texel with its exact solid angle.
  static SphericalHarmonics project(const Cubemap& radiance, int order, int threads = 0);
  // The same over an equirect image (see envmap/equirect.h), texel solid angles
  // dphi (cos theta0 - cos theta1); no resampling.
  static SphericalHarmonics projectEquirect(const ImageRgb& image, int order, int threads = 0);

  // sum c_lm Y_lm(direction) (direction need not be normalized).
  glm::vec3 evaluate(const glm::vec3& direction) const;

  // Coefficients times kHat_l and the window: radiance SH -> (transmitted) irradiance SH.
  SphericalHarmonics convolved(const TransmittedCosineKernel& kernel,
                               ShWindow window = ShWindow::None) const;
  // Same coefficients cut to a lower order.
  SphericalHarmonics truncated(int order) const;

  // Evaluated at every texel centre of a cubemap.
  Cubemap toCubemap(int faceSize, int threads = 0) const;

 private:
  int order_ = -1;
  std::vector<glm::vec3> coefficients_;
};

}  // namespace sss

#include "irradiance/spherical_harmonics.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/parallel.h"

namespace sss {
namespace {

constexpr int kMax = SphericalHarmonics::kMaxOrder;

// Normalization K_lm = sqrt((2l + 1) / (4 pi) (l - m)! / (l + m)!), times sqrt(2) for m > 0.
struct Normalization {
  std::array<double, (kMax + 1) * (kMax + 1)> k{};
  Normalization() {
    for (int l = 0; l <= kMax; ++l) {
      for (int m = 0; m <= l; ++m) {
        double ratio = 1.0;  // (l - m)! / (l + m)!
        for (int i = l - m + 1; i <= l + m; ++i) ratio /= i;
        k[l * (kMax + 1) + m] =
            std::sqrt((2 * l + 1) / (4.0 * M_PI) * ratio) * (m > 0 ? std::sqrt(2.0) : 1.0);
      }
    }
  }
};
const Normalization kNorm;

void checkOrder(int order) {
  if (order < 0 || order > kMax) {
    throw Error("SH order must be in [0, " + std::to_string(kMax) + "], got " +
                std::to_string(order));
  }
}

// Per-row accumulation in float (vectorized over coefficients); rows add up in double.
struct RowSums {
  explicit RowSums(int order)
      : order(order),
        count((order + 1) * (order + 1)),
        basis(count),
        row(3 * count),
        total(3 * count, 0.0) {}
  void add(const glm::vec3& w, const glm::vec3& lw) {
    SphericalHarmonics::evaluateBasis(order, w, basis.data());
    float* r = row.data();
    float* g = r + count;
    float* b = g + count;
    for (int i = 0; i < count; ++i) {
      r[i] += basis[i] * lw.x;
      g[i] += basis[i] * lw.y;
      b[i] += basis[i] * lw.z;
    }
  }
  void endRow() {
    for (int i = 0; i < 3 * count; ++i) total[i] += row[i];
    std::fill(row.begin(), row.end(), 0.0f);
  }
  int order, count;
  std::vector<float> basis, row;
  std::vector<double> total;  // [channel * count + i]
};

// Deterministic parallel sum over rows: each chunk of rows sums on its own, chunks add up in
// order.
template <class Row>
SphericalHarmonics projectRows(int order, std::size_t rows, int threads, Row&& row) {
  checkOrder(order);
  const std::size_t grain = 8;
  std::vector<std::vector<double>> partial((rows + grain - 1) / grain);
  parallelFor(rows, threads, grain, [&](std::size_t begin, std::size_t end) {
    RowSums sums(order);
    for (std::size_t i = begin; i < end; ++i) {
      row(i, sums);
      sums.endRow();
    }
    partial[begin / grain] = std::move(sums.total);
  });
  SphericalHarmonics sh(order);
  const int count = sh.coefficientCount();
  std::vector<double> total(3 * count, 0.0);
  for (const auto& p : partial) {
    for (int i = 0; i < 3 * count; ++i) total[i] += p[i];
  }
  for (int i = 0; i < count; ++i)
    sh[i] = glm::vec3(total[i], total[count + i], total[2 * count + i]);
  return sh;
}

}  // namespace

double shWindowWeight(ShWindow window, int l, int order) {
  const double x = M_PI * l / (order + 1.0);
  switch (window) {
    case ShWindow::Hann:
      return 0.5 * (1.0 + std::cos(x));
    case ShWindow::Lanczos:
      return l == 0 ? 1.0 : std::sin(x) / x;
    default:
      return 1.0;
  }
}

SphericalHarmonics::SphericalHarmonics(int order) : order_(order) {
  checkOrder(order);
  coefficients_.assign(static_cast<std::size_t>(order + 1) * (order + 1), glm::vec3(0.0f));
}

// Polar axis z. With P~_l^m = P_l^m / sin^m(theta) (a polynomial in z) and
// (x + i y)^m = sin^m(theta) e^{i m phi}, no trigonometric function is needed:
//   Y_l0 = K_l0 P_l(z), Y_lm = K_lm P~_l^m Re (x + iy)^m, Y_l-m = K_lm P~_l^m Im (x + iy)^m.
void SphericalHarmonics::evaluateBasis(int order, const glm::vec3& d, float* out) {
  if (order <= 3) {  // the closed forms (Sloan 2008, appendix), the common case
    const float x = d.x, y = d.y, z = d.z;
    const float z2 = z * z;
    const float all[16] = {0.282094792f,
                           0.488602512f * y,
                           0.488602512f * z,
                           0.488602512f * x,
                           1.092548431f * x * y,
                           1.092548431f * y * z,
                           0.315391565f * (3 * z * z - 1),
                           1.092548431f * x * z,
                           0.546274215f * (x * x - y * y),
                           0.590043589f * y * (3 * x * x - y * y),
                           2.890611442f * x * y * z,
                           0.457045799f * y * (5 * z2 - 1),
                           0.373176332f * z * (5 * z2 - 3),
                           0.457045799f * x * (5 * z2 - 1),
                           1.445305721f * z * (x * x - y * y),
                           0.590043589f * x * (x * x - 3 * y * y)};
    std::copy(all, all + (order + 1) * (order + 1), out);
    return;
  }
  double c = 1.0, s = 0.0;  // Re, Im of (x + iy)^m
  double pmm = 1.0;         // P~_m^m = (2m - 1)!!
  const double z = d.z;
  for (int m = 0; m <= order; ++m) {
    if (m > 0) {
      const double cNext = d.x * c - d.y * s;
      s = d.x * s + d.y * c;
      c = cNext;
      pmm *= 2 * m - 1;
    }
    double prev2 = 0.0, prev1 = 0.0;  // P~_{l-2}^m, P~_{l-1}^m
    for (int l = m; l <= order; ++l) {
      double p;
      if (l == m) {
        p = pmm;
      } else if (l == m + 1) {
        p = z * (2 * m + 1) * pmm;
      } else {
        p = ((2 * l - 1) * z * prev1 - (l + m - 1) * prev2) / (l - m);
      }
      prev2 = prev1;
      prev1 = p;
      const double k = kNorm.k[l * (kMax + 1) + m] * p;
      if (m == 0) {
        out[index(l, 0)] = static_cast<float>(k);
      } else {
        out[index(l, m)] = static_cast<float>(k * c);
        out[index(l, -m)] = static_cast<float>(k * s);
      }
    }
  }
}

SphericalHarmonics SphericalHarmonics::project(const Cubemap& radiance, int order, int threads) {
  const int n = radiance.size();
  if (n == 0) throw Error("cannot project an empty cubemap");
  const std::vector<float>& omega = radiance.faceSolidAngles();
  return projectRows(
      order, 6 * static_cast<std::size_t>(n), threads, [&](std::size_t row, RowSums& sums) {
        const int f = static_cast<int>(row / n), y = static_cast<int>(row % n);
        for (int x = 0; x < n; ++x) {
          sums.add(radiance.direction(f, x, y), radiance.at(f, x, y) * omega[y * n + x]);
        }
      });
}

SphericalHarmonics SphericalHarmonics::projectEquirect(const ImageRgb& image, int order,
                                                       int threads) {
  const int w = image.width, h = image.height;
  if (w == 0 || h == 0) throw Error("cannot project an empty image");
  std::vector<float> sinPhi(w), cosPhi(w);
  for (int x = 0; x < w; ++x) {
    const double phi = 2.0 * M_PI * ((x + 0.5) / w - 0.5);
    sinPhi[x] = static_cast<float>(std::sin(phi));
    cosPhi[x] = static_cast<float>(std::cos(phi));
  }
  return projectRows(
      order, static_cast<std::size_t>(h), threads, [&](std::size_t y, RowSums& sums) {
        const double t0 = M_PI * y / h, t1 = M_PI * (y + 1) / h;
        const double tc = 0.5 * (t0 + t1);
        const float omega = static_cast<float>(2.0 * M_PI / w * (std::cos(t0) - std::cos(t1)));
        const float st = static_cast<float>(std::sin(tc));
        const float ct = static_cast<float>(std::cos(tc));
        for (int x = 0; x < w; ++x) {
          const glm::vec3 d(st * sinPhi[x], ct, -st * cosPhi[x]);
          sums.add(d, image.at(x, static_cast<int>(y)) * omega);
        }
      });
}

glm::vec3 SphericalHarmonics::evaluate(const glm::vec3& direction) const {
  if (order_ < 0) return glm::vec3(0.0f);
  std::array<float, (kMax + 1) * (kMax + 1)> basis;
  evaluateBasis(order_, glm::normalize(direction), basis.data());
  glm::vec3 sum(0.0f);
  for (int i = 0; i < coefficientCount(); ++i) sum += basis[i] * coefficients_[i];
  return sum;
}

SphericalHarmonics SphericalHarmonics::convolved(const TransmittedCosineKernel& kernel,
                                                 ShWindow window) const {
  SphericalHarmonics out = *this;
  for (int l = 0; l <= order_; ++l) {
    const float f =
        static_cast<float>(kernel.zonalCoefficient(l) * shWindowWeight(window, l, order_));
    for (int m = -l; m <= l; ++m) out[index(l, m)] *= f;
  }
  return out;
}

SphericalHarmonics SphericalHarmonics::truncated(int order) const {
  if (order > order_) throw Error("cannot truncate SH to a higher order");
  SphericalHarmonics out(order);
  for (int i = 0; i < out.coefficientCount(); ++i) out[i] = coefficients_[i];
  return out;
}

Cubemap SphericalHarmonics::toCubemap(int faceSize, int threads) const {
  Cubemap cube(faceSize);
  parallelFor(6 * static_cast<std::size_t>(faceSize), threads, 4,
              [&](std::size_t begin, std::size_t end) {
                for (std::size_t row = begin; row < end; ++row) {
                  const int f = static_cast<int>(row / faceSize);
                  const int y = static_cast<int>(row % faceSize);
                  for (int x = 0; x < faceSize; ++x)
                    cube.at(f, x, y) = evaluate(cube.direction(f, x, y));
                }
              });
  return cube;
}

}  // namespace sss

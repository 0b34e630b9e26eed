#include "irradiance/radiance_grid.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/luminance.h"
#include "core/parallel.h"
#include "envmap/equirect.h"

namespace sss {
namespace {

// Adds a texel of radiance l, solid angle omega and first moment m (integral of w dw over it)
// to the kValues values v.
void addMoment(const glm::vec3& m, const glm::vec3& l, float omega, float* v) {
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < 3; ++k) v[3 * c + k] += l[c] * m[k];
  }
  v[9] += luminance(l) * omega;
}

}  // namespace

RadianceGrid RadianceGrid::fromCubemap(const Cubemap& radiance) {
  if (radiance.empty()) throw Error("cannot integrate an empty cubemap");
  RadianceGrid grid;
  const int n = radiance.size();
  grid.faces_ = 6;
  grid.width_ = grid.height_ = grid.rootSize_ = n;
  grid.sourceTexels_ = radiance.texelCount();
  grid.cells_.assign(grid.cellCount() * kValues, 0.0f);
  const std::vector<float>& omega = radiance.faceSolidAngles();
  forEachTexel(n, [&](int f, int x, int y) {
    // Centre direction times solid angle, as the exact sum over texels has it.
    addMoment(radiance.direction(f, x, y) * omega[y * n + x], radiance.at(f, x, y),
              omega[y * n + x], &grid.cells_[radiance.index(f, x, y) * kValues]);
  });
  grid.buildTables();
  return grid;
}

int RadianceGrid::equirectBlockSize(const ImageRgb& image, int wanted) {
  int b = 1;
  while (2 * b <= wanted && image.width % (2 * b) == 0 && image.height % (2 * b) == 0) b *= 2;
  return b;
}

RadianceGrid RadianceGrid::fromEquirect(const ImageRgb& image, int blockSize, int threads) {
  const int w = image.width, h = image.height, b = blockSize;
  if (w <= 0 || h <= 0) throw Error("cannot integrate an empty image");
  if (b < 1 || w % b != 0 || h % b != 0) {
    throw Error("equirect block size " + std::to_string(b) + " does not divide " +
                std::to_string(w) + "x" + std::to_string(h));
  }
  RadianceGrid grid;
  grid.equirect_ = true;
  grid.faces_ = 1;
  grid.width_ = w / b;
  grid.height_ = h / b;
  grid.rootSize_ = std::max(1, grid.height_ / 4);
  grid.sourceTexels_ = static_cast<std::size_t>(w) * h;
  grid.cells_.assign(grid.cellCount() * kValues, 0.0f);
  // Each texel's first moment m = integral of w dw over it, exactly (equirect.h: w = (sin theta
  // sin phi, cos theta, -sin theta cos phi), dw = sin theta dtheta dphi), so that max(0, n . L m)
  // is the texel's exact cosine sum for every normal that sees all of it; per column the phi
  // integrals, per row the theta integrals of sin^2 and cos sin.
  std::vector<float> sinMoment(w), cosMoment(w);
  for (int x = 0; x < w; ++x) {
    const double phi0 = 2.0 * M_PI * (static_cast<double>(x) / w - 0.5);
    const double phi1 = 2.0 * M_PI * (static_cast<double>(x + 1) / w - 0.5);
    sinMoment[x] = static_cast<float>(std::cos(phi0) - std::cos(phi1));
    cosMoment[x] = static_cast<float>(std::sin(phi1) - std::sin(phi0));
  }
  const double dphi = 2.0 * M_PI / w;
  parallelFor(grid.height_, threads, 4, [&](std::size_t begin, std::size_t end) {
    for (std::size_t by = begin; by < end; ++by) {
      float* cells = &grid.cells_[by * grid.width_ * kValues];
      for (int y = static_cast<int>(by) * b; y < static_cast<int>(by + 1) * b; ++y) {
        const double t0 = M_PI * y / h, t1 = M_PI * (y + 1) / h;
        const float omega = static_cast<float>(dphi * (std::cos(t0) - std::cos(t1)));
        const float sin2 =
            static_cast<float>(0.5 * (t1 - t0) - 0.25 * (std::sin(2 * t1) - std::sin(2 * t0)));
        const float cosSin = static_cast<float>(
            0.5 * dphi * (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0)));
        const glm::vec3* texel = &image.at(0, y);
        for (int bx = 0; bx < grid.width_; ++bx) {
          // This row's b texels of the cell: sums of L sin(phi) dphi, L cos(phi) dphi, L.
          glm::vec3 sinSum(0.0f), cosSum(0.0f), sum(0.0f);
          for (int x = bx * b; x < (bx + 1) * b; ++x) {
            sinSum += texel[x] * sinMoment[x];
            cosSum += texel[x] * cosMoment[x];
            sum += texel[x];
          }
          float* v = cells + bx * kValues;
          for (int c = 0; c < 3; ++c) {
            v[3 * c] += sin2 * sinSum[c];
            v[3 * c + 1] += cosSin * sum[c];
            v[3 * c + 2] -= sin2 * cosSum[c];
          }
          v[9] += luminance(sum) * omega;
        }
      }
    }
  });
  grid.buildTables();
  return grid;
}

// Summed-area tables in double, one per face.
void RadianceGrid::buildTables() {
  table_.assign(static_cast<std::size_t>(faces_) * (width_ + 1) * (height_ + 1) * kValues, 0.0);
  for (int f = 0; f < faces_; ++f) {
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        const float* v = cell(f, x, y);
        double* out = &table_[tableAt(f, x + 1, y + 1)];
        const double* left = &table_[tableAt(f, x, y + 1)];
        const double* up = &table_[tableAt(f, x + 1, y)];
        const double* diagonal = &table_[tableAt(f, x, y)];
        for (int k = 0; k < kValues; ++k) out[k] = v[k] + left[k] + up[k] - diagonal[k];
      }
    }
  }
}

void RadianceGrid::sum(int face, int x0, int y0, int x1, int y1, double* out) const {
  const double* a = &table_[tableAt(face, x1, y1)];
  const double* b = &table_[tableAt(face, x0, y1)];
  const double* c = &table_[tableAt(face, x1, y0)];
  const double* d = &table_[tableAt(face, x0, y0)];
  for (int k = 0; k < kValues; ++k) out[k] = a[k] - b[k] - c[k] + d[k];
}

double RadianceGrid::totalLuminousFlux() const {
  double flux = 0.0;
  for (int f = 0; f < faces_; ++f) {
    double total[kValues];
    sum(f, 0, 0, width_, height_, total);
    flux += total[9];
  }
  return flux;
}

glm::vec3 RadianceGrid::direction(int face, float x, float y) const {
  if (equirect_) return equirectDirection(x / width_, y / height_);
  return glm::normalize(Cubemap::unproject(face, x / width_, y / height_));
}

}  // namespace sss

#include "envmap/cubemap.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>

#include <glm/geometric.hpp>

#include "core/error.h"

namespace sss {
namespace {

// Signed solid angle of the face-plane rectangle [0, x] x [0, y] at distance 1 (the standard
// four-corner formula's building block).
double cornerArea(double x, double y) {
  return std::atan2(x * y, std::sqrt(x * x + y * y + 1.0));
}

}  // namespace

Cubemap::Cubemap(int size, glm::vec3 fill) : size_(size) {
  if (size < 0) throw Error("cubemap face size must not be negative");
  texels_.assign(static_cast<std::size_t>(6) * size * size, fill);
}

// OpenGL 4.5, table 8.19: the major axis picks the face, (sc, tc) / |ma| give s and t.
CubeCoord Cubemap::project(const glm::vec3& d) {
  const float ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
  int face;
  float sc, tc, ma;
  if (ax >= ay && ax >= az) {
    face = d.x >= 0 ? 0 : 1;
    ma = ax;
    sc = d.x >= 0 ? -d.z : d.z;
    tc = -d.y;
  } else if (ay >= az) {
    face = d.y >= 0 ? 2 : 3;
    ma = ay;
    sc = d.x;
    tc = d.y >= 0 ? d.z : -d.z;
  } else {
    face = d.z >= 0 ? 4 : 5;
    ma = az;
    sc = d.z >= 0 ? d.x : -d.x;
    tc = -d.y;
  }
  if (ma == 0.0f) return {4, 0.5f, 0.5f};
  return {face, 0.5f * (sc / ma + 1.0f), 0.5f * (tc / ma + 1.0f)};
}

glm::vec3 Cubemap::unproject(int face, float s, float t) {
  const float a = 2.0f * s - 1.0f, b = 2.0f * t - 1.0f;
  switch (face) {
    case 0:
      return {1.0f, -b, -a};
    case 1:
      return {-1.0f, -b, a};
    case 2:
      return {a, 1.0f, b};
    case 3:
      return {a, -1.0f, -b};
    case 4:
      return {a, -b, 1.0f};
    default:
      return {-a, -b, -1.0f};
  }
}

glm::vec3 Cubemap::direction(int face, int x, int y) const {
  const float inv = 1.0f / static_cast<float>(size_);
  return glm::normalize(unproject(face, (x + 0.5f) * inv, (y + 0.5f) * inv));
}

float Cubemap::solidAngle(int /*face*/, int x, int y) const {
  const double inv = 2.0 / size_;
  const double x0 = x * inv - 1.0, x1 = (x + 1) * inv - 1.0;
  const double y0 = y * inv - 1.0, y1 = (y + 1) * inv - 1.0;
  return static_cast<float>(cornerArea(x1, y1) - cornerArea(x0, y1) - cornerArea(x1, y0) +
                            cornerArea(x0, y0));
}

namespace {

std::vector<float> computeFaceSolidAngles(int n) {
  std::vector<double> corner(static_cast<std::size_t>(n + 1) * (n + 1));
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      corner[j * (n + 1) + i] = cornerArea(2.0 * i / n - 1.0, 2.0 * j / n - 1.0);
    }
  }
  std::vector<float> omega(static_cast<std::size_t>(n) * n);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const std::size_t c = static_cast<std::size_t>(y) * (n + 1) + x;
      omega[y * n + x] =
          static_cast<float>(corner[c + n + 2] - corner[c + n + 1] - corner[c + 1] + corner[c]);
    }
  }
  return omega;
}

}  // namespace

const std::vector<float>& Cubemap::faceSolidAngles() const {
  // Face sizes are few (kMaxFaceSize bounds them); the tables live as long as the process.
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<const std::vector<float>>> tables;
  const std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<const std::vector<float>>& table = tables[size_];
  if (!table) table = std::make_unique<const std::vector<float>>(computeFaceSolidAngles(size_));
  return *table;
}

glm::vec3 Cubemap::sample(const glm::vec3& dir) const {
  if (size_ == 0) return glm::vec3(0.0f);
  const CubeCoord c = project(dir);
  const float fx = c.s * size_ - 0.5f, fy = c.t * size_ - 0.5f;
  const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
  const float wx = fx - x0, wy = fy - y0;
  // A tap outside the face is looked up where its texel centre lands on the neighbouring face.
  auto tap = [&](int x, int y) -> const glm::vec3& {
    if (x >= 0 && y >= 0 && x < size_ && y < size_) return at(c.face, x, y);
    const CubeCoord n = project(unproject(c.face, (x + 0.5f) / size_, (y + 0.5f) / size_));
    const int nx = std::clamp(static_cast<int>(n.s * size_), 0, size_ - 1);
    const int ny = std::clamp(static_cast<int>(n.t * size_), 0, size_ - 1);
    return at(n.face, nx, ny);
  };
  return (1 - wy) * ((1 - wx) * tap(x0, y0) + wx * tap(x0 + 1, y0)) +
         wy * ((1 - wx) * tap(x0, y0 + 1) + wx * tap(x0 + 1, y0 + 1));
}

Cubemap Cubemap::resized(int faceSize) const {
  if (faceSize <= 0) throw Error("cubemap face size must be positive");
  if (faceSize == size_) return *this;
  Cubemap out(faceSize);
  if (size_ % faceSize == 0) {
    // Box filter weighted by texel solid angle, so the flux of each output texel is kept. The
    // solid angles are the same on every face: taken once.
    const int k = size_ / faceSize;
    const std::vector<float>& texelSolidAngle = faceSolidAngles();
    forEachTexel(faceSize, [&](int f, int x, int y) {
      glm::dvec3 flux(0.0);
      double omega = 0.0;
      for (int j = 0; j < k; ++j) {
        for (int i = 0; i < k; ++i) {
          const double w =
              texelSolidAngle[std::size_t(y * k + j) * std::size_t(size_) + std::size_t(x * k + i)];
          flux += w * glm::dvec3(at(f, x * k + i, y * k + j));
          omega += w;
        }
      }
      out.at(f, x, y) = glm::vec3(flux / omega);
    });
    return out;
  }
  const int k = std::max(2, (2 * size_ + faceSize - 1) / faceSize);
  forEachTexel(faceSize, [&](int f, int x, int y) {
    out.at(f, x, y) = averageOverTexel<glm::vec3>(f, x, y, faceSize, k,
                                                  [this](const glm::vec3& d) { return sample(d); });
  });
  return out;
}

}  // namespace sss

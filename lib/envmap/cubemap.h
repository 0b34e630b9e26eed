// A float RGB cubemap in the project's one layout, shared by every tool:
// six square faces in the order +X, -X, +Y, -Y, +Z, -Z, each in OpenGL cubemap orientation
// (the OpenGL 4.5 spec, table 8.19), world Y up. Row 0 of a face is its t = 0 row, i.e. the first
// row glTexImage uploads, so faces go to the GPU as they are. On disk (see cubemap_io.h) the
// faces are stacked vertically in the same order: an N x 6N RGB float EXR.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace sss {

enum class CubeFace : int { PosX = 0, NegX, PosY, NegY, PosZ, NegZ };

// Calls f(face, x, y) for every texel of a cubemap of face size `size`, in storage order: face by
// face, row y by row, column x by column. Sums over texels taken in it keep their rounding.
template <typename F>
void forEachTexel(int size, F&& f) {
  for (int face = 0; face < 6; ++face)
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) f(face, x, y);
}

// Where a direction hits the cube: face and (s, t) in [0, 1]^2 on it.
struct CubeCoord {
  int face;
  float s, t;
};

class Cubemap {
 public:
  Cubemap() = default;
  explicit Cubemap(int size, glm::vec3 fill = glm::vec3(0.0f));

  int size() const { return size_; }
  bool empty() const { return size_ == 0; }
  std::size_t texelCount() const { return texels_.size(); }

  glm::vec3& at(int face, int x, int y) { return texels_[index(face, x, y)]; }
  const glm::vec3& at(int face, int x, int y) const { return texels_[index(face, x, y)]; }
  // Face f starts at data() + f * size * size; rows top (t = 0) to bottom.
  glm::vec3* data() { return texels_.data(); }
  const glm::vec3* data() const { return texels_.data(); }
  std::size_t index(int face, int x, int y) const {
    return (static_cast<std::size_t>(face) * size_ + y) * size_ + x;
  }

  // Unit direction through the centre of texel (x, y) of a face.
  glm::vec3 direction(int face, int x, int y) const;
  // Solid angle of that texel (exact: the four-corner formula). Sums to 4 pi over the cube.
  float solidAngle(int face, int x, int y) const;
  // All texel solid angles of one face, [y * size + x] (the same on every face): computed once per
  // face size in the process and kept (a relight's every environment, a bake's every sky).
  const std::vector<float>& faceSolidAngles() const;
  // Bilinear lookup along a (not necessarily normalized) direction, seamless across edges.
  glm::vec3 sample(const glm::vec3& direction) const;

  // The same environment at another face size: box-filtered when the size divides this one
  // (flux-preserving), else supersampled bilinear lookups.
  Cubemap resized(int faceSize) const;

  // The GL mapping, independent of resolution.
  static CubeCoord project(const glm::vec3& direction);
  static glm::vec3 unproject(int face, float s, float t);  // not normalized

  // The mean of sample(d) over k x k directions d (unproject's, not normalized) at the centres of
  // a regular grid over texel (x, y) of a face of faceSize texels: the supersampling every
  // resampler shares. Sum (glm::vec3 or glm::dvec3) sets the precision of the accumulation.
  template <typename Sum, typename Sample>
  static Sum averageOverTexel(int face, int x, int y, int faceSize, int k, Sample&& sample) {
    Sum sum(0);
    for (int j = 0; j < k; ++j) {
      for (int i = 0; i < k; ++i) {
        sum += sample(
            unproject(face, (x + (i + 0.5f) / k) / faceSize, (y + (j + 0.5f) / k) / faceSize));
      }
    }
    return sum / static_cast<typename Sum::value_type>(k * k);
  }

 private:
  int size_ = 0;
  std::vector<glm::vec3> texels_;
};

}  // namespace sss

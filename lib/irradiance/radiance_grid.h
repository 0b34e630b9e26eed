// Radiance gathered into the cells of a grid for clustered irradiance sums (brute_force.h): per
// cell the vectors V_c = sum_j L_c,j dw_j w_j (channel c; w_j a texel's direction, dw_j its exact
// solid angle) and the luminous flux sum_j Y(L_j) dw_j, with summed-area tables for the sums over
// any rectangle of cells.
//
// Two sources: a cubemap (one cell a texel, six faces), or an equirect image straight from its
// rows (one face; one cell a block of b x b texels, each texel with its exact solid angle
// dphi (cos theta0 - cos theta1)). A block keeps its texels' first moment, so the cosine sum
// max(0, n . V_c) over a block is exact for every normal n that sees the whole block (the cosine
// is linear there); only normals whose horizon cuts the block see a difference, of at most the
// block's flux times the sine of twice its angular radius. No radiance cubemap is resampled.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "envmap/cubemap.h"
#include "image/image.h"

namespace sss {

class RadianceGrid {
 public:
  static constexpr int kValues = 10;  // V_R, V_G, V_B (x, y, z each), luminous flux

  static RadianceGrid fromCubemap(const Cubemap& radiance);
  // blockSize must divide the image's width and height (see equirectBlockSize).
  static RadianceGrid fromEquirect(const ImageRgb& image, int blockSize, int threads = 0);
  // The largest power of two up to `wanted` (at least 1) that divides both sides of the image.
  static int equirectBlockSize(const ImageRgb& image, int wanted);

  int faces() const { return faces_; }
  int width() const { return width_; }  // cells per face row
  int height() const { return height_; }
  int rootSize() const { return rootSize_; }  // side of the square root nodes of a quadtree
  std::size_t cellCount() const { return static_cast<std::size_t>(faces_) * width_ * height_; }
  std::size_t sourceTexels() const { return sourceTexels_; }

  // Unit direction of grid point (x, y) of a face, x in [0, width], y in [0, height] (cell
  // (i, j) spans [i, i + 1] x [j, j + 1]).
  glm::vec3 direction(int face, float x, float y) const;
  // The kValues values of one cell.
  const float* cell(int face, int x, int y) const {
    return &cells_[((static_cast<std::size_t>(face) * height_ + y) * width_ + x) * kValues];
  }
  // Sums over cells [x0, x1) x [y0, y1) of a face into out[kValues].
  void sum(int face, int x0, int y0, int x1, int y1, double* out) const;
  double totalLuminousFlux() const;

 private:
  void buildTables();
  std::size_t tableAt(int face, int x, int y) const {
    return ((static_cast<std::size_t>(face) * (height_ + 1) + y) * (width_ + 1) + x) * kValues;
  }
  bool equirect_ = false;
  int faces_ = 0, width_ = 0, height_ = 0, rootSize_ = 0;
  std::size_t sourceTexels_ = 0;
  std::vector<float> cells_;
  std::vector<double> table_;
};

}  // namespace sss

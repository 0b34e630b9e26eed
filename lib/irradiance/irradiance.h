// Diffuse (optionally Fresnel-transmitted) irradiance cubemaps from a radiance cubemap, choosing
// between direct summation (brute_force.h, the reference) and spherical harmonics
// (spherical_harmonics.h) to meet an error tolerance estimated for this very environment:
// the relative RMS difference from the exact sum over every texel at probe normals spread evenly
// over the sphere.
#pragma once

#include <string>

#include "core/enum_names.h"
#include "envmap/cubemap.h"
#include "image/image.h"
#include "irradiance/spherical_harmonics.h"

namespace sss {

enum class IrradianceMethod { Auto, Brute, Sh };
inline constexpr EnumNames<IrradianceMethod, 3> kIrradianceMethodNames{
    "irradiance method",
    {{{IrradianceMethod::Auto, "auto"},
      {IrradianceMethod::Brute, "brute"},
      {IrradianceMethod::Sh, "sh"}}}};

struct IrradianceOptions {
  IrradianceMethod method = IrradianceMethod::Auto;
  int faceSize = 0;  // 0: from the content: the smallest of 16, 32, 64 whose bilinear lookups
                     // meet the tolerance
  int shOrder = 2;   // for Sh; Auto tries order 2, then Brute
  ShWindow window = ShWindow::None;
  double tolerance = 0.01;  // relative RMS on the sphere
  float eta = 1.0f;         // relative index of the surface; 1: plain irradiance
  int threads = 0;          // <= 0: all cores
  bool quiet = true;        // no progress bar on stderr for long direct sums
  int probes = 256;         // probe normals for the error estimates
  // computeIrradianceFromEquirect: cells across the width of the image (radiance_grid.h): a
  // cell is width / equirectCells texels on a side (a power of two dividing both sides, at
  // least 1), 2.8 degrees for 128.
  int equirectCells = 128;
};

struct IrradianceTimings {
  double gridMs = 0;        // equirect rows -> cells (computeIrradianceFromEquirect)
  double projectionMs = 0;  // radiance -> SH
  double referenceMs = 0;   // exact sums at the probe normals
  double evaluationMs = 0;  // the output cubemap (SH evaluation or brute force)
  double totalMs = 0;
};

struct IrradianceResult {
  Cubemap irradiance;
  IrradianceMethod method = IrradianceMethod::Brute;  // Brute or Sh: what made `irradiance`
  int shOrder = -1;                                   // the SH order used (Sh), else -1
  double estimatedError = 0.0;      // relative RMS against the exact sum at the probes
  std::string reason;               // one line: what was chosen and why
  SphericalHarmonics radianceSh;    // the radiance projection when SH was computed
  SphericalHarmonics irradianceSh;  // its convolution (windowed), idem
  std::size_t bruteClusters = 0;    // Brute: terms summed per output texel
  std::size_t sourceTexels = 0;
  IrradianceTimings timings;
};

IrradianceResult computeIrradiance(const Cubemap& radiance, const IrradianceOptions& options);

// The same straight from an equirect image (envmap/equirect.h), without a radiance cubemap: the
// direct sum clusters blocks of texels (radiance_grid.h), the reference at the probes sums every
// block, and SH order 2 for auto is projected from the blocks (--method sh: from every texel).
IrradianceResult computeIrradianceFromEquirect(const ImageRgb& image,
                                               const IrradianceOptions& options);

}  // namespace sss

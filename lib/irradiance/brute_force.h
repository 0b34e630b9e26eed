// Diffuse irradiance by direct summation, Li & Guo Eq. 12 with real solid angles and the
// Fresnel-transmitting kernel k of TransmittedCosineKernel:
//   E(n) = sum_j k(n . w_j) L_j dw_j   over every texel j of the radiance cubemap.
//
// Speed without losing the reference: texels are grouped into directional clusters (quadtree
// nodes of each face) only where that stays inside the tolerance. A cluster carries per channel
// the vector sum V = sum_j L_j dw_j w_j, so for normals that see the whole cluster (all
// n . w_j > 0) max(0, n . V) is exactly the sum of its texels (the cosine is linear); only clusters
// cut by the horizon of n (and the Fresnel factor, smooth in mu) make an error, bounded by the
// cluster's flux times its angular radius. A node is refined while that bound exceeds a
// threshold; the threshold is tightened until the relative RMS error measured against the full
// sum at probe normals is below the tolerance. tolerance 0 sums every texel.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "envmap/cubemap.h"
#include "irradiance/radiance_grid.h"
#include "irradiance/transmitted_cosine.h"

namespace sss {

struct BruteForceOptions {
  int faceSize = 32;        // output face size
  float eta = 1.0f;         // 1: plain irradiance
  double tolerance = 0.01;  // relative RMS on the sphere; 0: every texel
  int threads = 0;          // <= 0: all cores
  bool quiet = true;        // no progress bar on stderr for long sums
  // Probe normals and the exact sums there, when the caller has them already (else 256
  // Fibonacci normals, summed here).
  const std::vector<glm::vec3>* probeNormals = nullptr;
  const std::vector<glm::vec3>* probeReference = nullptr;
};

struct BruteForceStats {
  std::size_t sourceTexels = 0;  // texels of the radiance cubemap
  std::size_t clusters = 0;      // terms summed per output texel
  double estimatedError = 0.0;   // measured relative RMS at probe normals (0 when exact)
  int refinements = 0;           // threshold tightenings needed
};

// Terms of the sum in structure-of-arrays form, zero-padded to a multiple of 8 (brute_force.cpp).
struct SummationTerms {
  std::size_t count = 0;
  std::vector<float> a[12];
};

// The cut is built (and checked at the probes) once; evaluate it at any normals.
class BruteForceIrradiance {
 public:
  BruteForceIrradiance(const Cubemap& radiance, const BruteForceOptions& options);
  // From cells (radiance_grid.h: cubemap texels or equirect blocks): the reference is the sum
  // over every cell, and tolerance 0 sums every cell.
  BruteForceIrradiance(const RadianceGrid& grid, const BruteForceOptions& options);
  std::vector<glm::vec3> at(const std::vector<glm::vec3>& normals) const;  // unit normals
  Cubemap cubemap(int faceSize) const;
  const BruteForceStats& stats() const { return stats_; }

 private:
  void buildToTolerance(const RadianceGrid& grid);
  BruteForceOptions options_;
  TransmittedCosineKernel kernel_;
  bool exact_ = false;
  SummationTerms terms_;
  BruteForceStats stats_;
};

// BruteForceIrradiance(radiance, options).cubemap(options.faceSize).
Cubemap bruteForceIrradiance(const Cubemap& radiance, const BruteForceOptions& options,
                             BruteForceStats* stats = nullptr);

// The exact sum over every texel at the given normals (unit length): the reference the error
// estimates use. Threaded over normals, vectorized over texels.
std::vector<glm::vec3> irradianceAtNormals(const Cubemap& radiance,
                                           const std::vector<glm::vec3>& normals, float eta,
                                           int threads = 0);

// The sum over every cell of a grid, sum_c F_t(n . d_c) max(0, n . V_c) (d_c the cell's
// luminance-weighted direction): exact for cubemap texels when eta = 1.
std::vector<glm::vec3> irradianceAtNormals(const RadianceGrid& grid,
                                           const std::vector<glm::vec3>& normals, float eta,
                                           int threads = 0);

// Evenly spread unit vectors (spherical Fibonacci lattice), for error estimates on the sphere.
std::vector<glm::vec3> fibonacciSphere(int count);

}  // namespace sss

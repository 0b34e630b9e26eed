#include "irradiance/brute_force.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/luminance.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/relative_rms.h"
#include "irradiance/radiance_grid.h"

namespace sss {
namespace {

// GCC vector extensions: 8 floats, unaligned loads allowed. The hot loops are compiled for AVX2
// and for the baseline (target_clones); the CPU picks at load time.
typedef float v8 __attribute__((vector_size(32)));
typedef float v8u __attribute__((vector_size(32), aligned(4)));
// clang 14 (the first clang with target_clones) crashes in the avx2 clone of sumClusters under
// AddressSanitizer (a wild read at the first load): clang builds (the checked build) compile the
// baseline only.
#if defined(__clang__)
#define SSS_AVX2_CLONES
#else
#define SSS_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#endif
constexpr std::size_t kLanes = 8;
constexpr std::size_t kChunk = 2048;  // terms per cache block (each array 8 KiB)
constexpr std::size_t kNormalGrain = 32;

// Vectors cross these helpers by reference: a vector passed by value to or from a function
// compiled without AVX changes the ABI (clang refuses it in the avx2 clones).
inline const v8u& load(const float* p) {
  return *reinterpret_cast<const v8u*>(p);
}
inline float horizontalSum(const v8& v) {
  return ((v[0] + v[4]) + (v[1] + v[5])) + ((v[2] + v[6]) + (v[3] + v[7]));
}

// Texel terms: a[0..2] the direction w, a[3..5] L_c dw. Cluster terms: a[3c..3c+2] the vector
// V_c of channel c, a[9..11] the direction d of the Fresnel factor.
using Terms = SummationTerms;
void resizeTerms(Terms& t, std::size_t n, int arrays) {
  t.count = (n + kLanes - 1) / kLanes * kLanes;
  for (int i = 0; i < arrays; ++i) t.a[i].assign(t.count, 0.0f);
}
// Initial cut threshold, relative to tolerance x total luminous flux.
constexpr double kInitialThreshold = 0.05;

inline void fresnelFactor(const TransmittedCosineKernel& kernel, const v8& mu, v8& t) {
  for (std::size_t k = 0; k < kLanes; ++k) t[k] = kernel.transmittance(mu[k]);
}

// sum_j k(n . w_j) (L dw)_j over terms [begin, end) for one normal.
SSS_AVX2_CLONES glm::vec3 sumTexels(const Terms& t, std::size_t begin, std::size_t end,
                                    const glm::vec3& n, const TransmittedCosineKernel* fresnel) {
  const v8 zero = {};
  v8 sr = zero, sg = zero, sb = zero;
  for (std::size_t j = begin; j < end; j += kLanes) {
    v8 mu = n.x * load(&t.a[0][j]) + n.y * load(&t.a[1][j]) + n.z * load(&t.a[2][j]);
    mu = mu > zero ? mu : zero;
    if (fresnel) {
      v8 transmitted;
      fresnelFactor(*fresnel, mu, transmitted);
      mu *= transmitted;
    }
    sr += mu * load(&t.a[3][j]);
    sg += mu * load(&t.a[4][j]);
    sb += mu * load(&t.a[5][j]);
  }
  return {horizontalSum(sr), horizontalSum(sg), horizontalSum(sb)};
}

// sum_c max(0, n . V_c) F_t(n . d) over clusters [begin, end) for one normal.
SSS_AVX2_CLONES glm::vec3 sumClusters(const Terms& t, std::size_t begin, std::size_t end,
                                      const glm::vec3& n, const TransmittedCosineKernel* fresnel) {
  const v8 zero = {};
  v8 s[3] = {zero, zero, zero};
  for (std::size_t j = begin; j < end; j += kLanes) {
    v8 f = {1, 1, 1, 1, 1, 1, 1, 1};
    if (fresnel) {
      v8 mu = n.x * load(&t.a[9][j]) + n.y * load(&t.a[10][j]) + n.z * load(&t.a[11][j]);
      fresnelFactor(*fresnel, mu > zero ? mu : zero, f);
    }
    for (int c = 0; c < 3; ++c) {
      const v8 e = n.x * load(&t.a[3 * c][j]) + n.y * load(&t.a[3 * c + 1][j]) +
                   n.z * load(&t.a[3 * c + 2][j]);
      s[c] += (e > zero ? e : zero) * f;
    }
  }
  return {horizontalSum(s[0]), horizontalSum(s[1]), horizontalSum(s[2])};
}

// Evaluates the sum at every normal: threads over normals, cache blocks over terms. Each
// normal's sum runs over the blocks in one fixed order: the same result for any thread count.
template <class Sum>
std::vector<glm::vec3> sumAtNormals(const Terms& terms, const std::vector<glm::vec3>& normals,
                                    const TransmittedCosineKernel& kernel, int threads, Sum sum,
                                    Progress* progress = nullptr) {
  std::vector<glm::vec3> out(normals.size());
  const TransmittedCosineKernel* fresnel = kernel.isPlainCosine() ? nullptr : &kernel;
  parallelFor(normals.size(), threads, kNormalGrain, [&](std::size_t begin, std::size_t end) {
    std::vector<glm::dvec3> acc(end - begin, glm::dvec3(0.0));
    for (std::size_t j = 0; j < terms.count; j += kChunk) {
      const std::size_t jEnd = std::min(terms.count, j + kChunk);
      for (std::size_t i = begin; i < end; ++i) {
        acc[i - begin] += glm::dvec3(sum(terms, j, jEnd, normals[i], fresnel));
      }
    }
    for (std::size_t i = begin; i < end; ++i) out[i] = glm::vec3(acc[i - begin]);
    if (progress) progress->advance(end - begin);
  });
  return out;
}

Terms texelTerms(const Cubemap& radiance) {
  const int n = radiance.size();
  const std::vector<float>& omega = radiance.faceSolidAngles();
  Terms t;
  resizeTerms(t, radiance.texelCount(), 6);
  forEachTexel(n, [&](int f, int x, int y) {
    const std::size_t i = radiance.index(f, x, y);
    const glm::vec3 w = radiance.direction(f, x, y);
    const glm::vec3 l = radiance.at(f, x, y) * omega[y * n + x];
    for (int k = 0; k < 3; ++k) {
      t.a[k][i] = w[k];
      t.a[3 + k][i] = l[k];
    }
  });
  return t;
}

struct Cluster {
  float v[9];
  glm::vec3 d;
};

// The cluster of grid cells [x0, x1) x [y0, y1) of a face, from their sums v.
Cluster makeCluster(const double* v, const glm::vec3& centre) {
  Cluster c;
  for (int k = 0; k < 9; ++k) c.v[k] = static_cast<float>(v[k]);
  // The luminance-weighted sum of the channels' vectors V_c, component by component.
  const glm::dvec3 lum(luminance(glm::dvec3(v[0], v[3], v[6])),
                       luminance(glm::dvec3(v[1], v[4], v[7])),
                       luminance(glm::dvec3(v[2], v[5], v[8])));
  const double len = glm::length(lum);
  c.d = len > 0.0 ? glm::vec3(lum / len) : centre;
  return c;
}

struct Node {
  int f, x0, y0, x1, y1;
};

// Angular radius of a node about its centre: the largest angle to its corners and edge
// midpoints (on an equirect grid the edges of constant latitude are not great circles).
double nodeRadius(const RadianceGrid& grid, const Node& node, const glm::vec3& centre) {
  const float xs[3] = {float(node.x0), 0.5f * (node.x0 + node.x1), float(node.x1)};
  const float ys[3] = {float(node.y0), 0.5f * (node.y0 + node.y1), float(node.y1)};
  float minCos = 1.0f;
  for (float x : xs) {
    for (float y : ys) minCos = std::min(minCos, glm::dot(centre, grid.direction(node.f, x, y)));
  }
  return std::acos(std::clamp(minCos, -1.0f, 1.0f));
}

// The cut: quadtree nodes of each face (from square roots of rootSize cells), refined while
// flux x angular radius > threshold.
std::vector<Cluster> buildCut(const RadianceGrid& grid, double threshold) {
  std::vector<Cluster> cut;
  const int root = grid.rootSize();
  for (int f = 0; f < grid.faces(); ++f) {
    std::vector<Node> roots;
    for (int y = 0; y < grid.height(); y += root) {
      for (int x = 0; x < grid.width(); x += root) {
        roots.push_back(
            {f, x, y, std::min(x + root, grid.width()), std::min(y + root, grid.height())});
      }
    }
    std::vector<Node> stack(roots.rbegin(), roots.rend());  // popped in row order
    while (!stack.empty()) {
      const Node node = stack.back();
      stack.pop_back();
      double v[RadianceGrid::kValues];
      grid.sum(node.f, node.x0, node.y0, node.x1, node.y1, v);
      bool black = true;
      for (int k = 0; k < 9; ++k) black = black && v[k] == 0.0;
      if (black) continue;  // contributes nothing
      const bool single = node.x1 - node.x0 == 1 && node.y1 - node.y0 == 1;
      const glm::vec3 centre =
          grid.direction(node.f, 0.5f * (node.x0 + node.x1), 0.5f * (node.y0 + node.y1));
      if (!single && v[9] * nodeRadius(grid, node, centre) > threshold) {
        const int xm = (node.x0 + node.x1 + 1) / 2, ym = (node.y0 + node.y1 + 1) / 2;
        // Children pushed in reverse so that they are emitted in row order.
        const Node kids[4] = {{node.f, node.x0, node.y0, xm, ym},
                              {node.f, xm, node.y0, node.x1, ym},
                              {node.f, node.x0, ym, xm, node.y1},
                              {node.f, xm, ym, node.x1, node.y1}};
        for (int k = 3; k >= 0; --k) {
          if (kids[k].x1 > kids[k].x0 && kids[k].y1 > kids[k].y0) stack.push_back(kids[k]);
        }
        continue;
      }
      cut.push_back(makeCluster(v, centre));
    }
  }
  return cut;
}

// Every cell of the grid as a cluster: the finest cut.
std::vector<Cluster> allCells(const RadianceGrid& grid) {
  std::vector<Cluster> cells;
  cells.reserve(grid.cellCount());
  for (int f = 0; f < grid.faces(); ++f) {
    for (int y = 0; y < grid.height(); ++y) {
      for (int x = 0; x < grid.width(); ++x) {
        const float* c = grid.cell(f, x, y);
        double v[RadianceGrid::kValues];
        std::copy(c, c + RadianceGrid::kValues, v);
        cells.push_back(makeCluster(v, grid.direction(f, x + 0.5f, y + 0.5f)));
      }
    }
  }
  return cells;
}

Terms clusterTerms(const std::vector<Cluster>& cut) {
  Terms t;
  resizeTerms(t, cut.size(), 12);
  for (std::size_t i = 0; i < cut.size(); ++i) {
    for (int k = 0; k < 9; ++k) t.a[k][i] = cut[i].v[k];
    for (int k = 0; k < 3; ++k) t.a[9 + k][i] = cut[i].d[k];
  }
  return t;
}

}  // namespace

std::vector<glm::vec3> fibonacciSphere(int count) {
  std::vector<glm::vec3> dirs(std::max(count, 0));
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    dirs[i] = glm::vec3(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  return dirs;
}

std::vector<glm::vec3> irradianceAtNormals(const Cubemap& radiance,
                                           const std::vector<glm::vec3>& normals, float eta,
                                           int threads) {
  if (radiance.empty()) throw Error("cannot integrate an empty cubemap");
  const TransmittedCosineKernel kernel(eta);
  return sumAtNormals(texelTerms(radiance), normals, kernel, threads, sumTexels);
}

std::vector<glm::vec3> irradianceAtNormals(const RadianceGrid& grid,
                                           const std::vector<glm::vec3>& normals, float eta,
                                           int threads) {
  const TransmittedCosineKernel kernel(eta);
  return sumAtNormals(clusterTerms(allCells(grid)), normals, kernel, threads, sumClusters);
}

BruteForceIrradiance::BruteForceIrradiance(const Cubemap& radiance,
                                           const BruteForceOptions& options)
    : options_(options), kernel_(options.eta) {
  if (radiance.empty()) throw Error("cannot integrate an empty cubemap");
  if (options.tolerance <= 0.0) {
    exact_ = true;
    terms_ = texelTerms(radiance);
    stats_.sourceTexels = stats_.clusters = radiance.texelCount();
    return;
  }
  std::vector<glm::vec3> ownReference;
  if (options.probeNormals && !options.probeReference) {
    ownReference =
        irradianceAtNormals(radiance, *options.probeNormals, options.eta, options.threads);
    options_.probeReference = &ownReference;
  }
  buildToTolerance(RadianceGrid::fromCubemap(radiance));
}

BruteForceIrradiance::BruteForceIrradiance(const RadianceGrid& grid,
                                           const BruteForceOptions& options)
    : options_(options), kernel_(options.eta) {
  if (options.tolerance <= 0.0) {
    terms_ = clusterTerms(allCells(grid));
    stats_.sourceTexels = grid.sourceTexels();
    stats_.clusters = grid.cellCount();
    return;
  }
  buildToTolerance(grid);
}

// Start from a threshold that usually meets the tolerance at once (calibrated on the sample
// environments); tighten it by 4 until the probes agree with the sum over every cell.
void BruteForceIrradiance::buildToTolerance(const RadianceGrid& grid) {
  stats_.sourceTexels = grid.sourceTexels();
  std::vector<glm::vec3> ownProbes, ownReference;
  const std::vector<glm::vec3>* probes = options_.probeNormals;
  const std::vector<glm::vec3>* reference = options_.probeReference;
  if (!probes) {
    ownProbes = fibonacciSphere(256);
    probes = &ownProbes;
    reference = nullptr;
  }
  if (!reference) {
    ownReference = irradianceAtNormals(grid, *probes, options_.eta, options_.threads);
    reference = &ownReference;
  }
  options_.probeNormals = options_.probeReference = nullptr;  // not kept past construction
  double threshold = kInitialThreshold * options_.tolerance * grid.totalLuminousFlux();
  for (int round = 0;; ++round) {
    const std::vector<Cluster> cut = buildCut(grid, threshold);
    terms_ = clusterTerms(cut);
    stats_.clusters = cut.size();
    stats_.refinements = round;
    stats_.estimatedError = relativeRms(at(*probes), *reference);
    if (stats_.estimatedError <= options_.tolerance || cut.size() >= grid.cellCount() ||
        round == 12) {
      break;
    }
    threshold *= 0.25;
  }
}

std::vector<glm::vec3> BruteForceIrradiance::at(const std::vector<glm::vec3>& normals) const {
  // A bar only for long sums (more than 1e9 terms).
  std::optional<Progress> progress;
  if (!options_.quiet && normals.size() * terms_.count > 1'000'000'000) {
    progress.emplace("irradiance (brute)", normals.size(), false);
  }
  Progress* bar = progress ? &*progress : nullptr;
  return exact_ ? sumAtNormals(terms_, normals, kernel_, options_.threads, sumTexels, bar)
                : sumAtNormals(terms_, normals, kernel_, options_.threads, sumClusters, bar);
}

Cubemap BruteForceIrradiance::cubemap(int faceSize) const {
  if (faceSize <= 0) throw Error("irradiance face size must be positive");
  Cubemap cube(faceSize);
  std::vector<glm::vec3> normals(cube.texelCount());
  forEachTexel(faceSize, [&](int f, int x, int y) {
    normals[cube.index(f, x, y)] = cube.direction(f, x, y);
  });
  const std::vector<glm::vec3> values = at(normals);
  std::copy(values.begin(), values.end(), cube.data());
  return cube;
}

Cubemap bruteForceIrradiance(const Cubemap& radiance, const BruteForceOptions& options,
                             BruteForceStats* stats) {
  const BruteForceIrradiance brute(radiance, options);
  if (stats) *stats = brute.stats();
  return brute.cubemap(options.faceSize);
}

}  // namespace sss

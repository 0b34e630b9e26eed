#include "irradiance/irradiance.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <optional>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/format.h"
#include "core/relative_rms.h"
#include "core/timer.h"
#include "irradiance/brute_force.h"

namespace sss {
namespace {

// Share of the tolerance the method may use; the rest is left to the cubemap's bilinear lookups.
constexpr double kMethodShare = 0.7;
constexpr int kAutoFaceSizes[] = {16, 32, 64};

// Probe normals spread over the sphere and the exact sums there: what every estimate compares
// against.
struct Probes {
  std::vector<glm::vec3> normals, reference;
};

std::vector<glm::vec3> evaluateSh(const SphericalHarmonics& sh,
                                  const std::vector<glm::vec3>& normals) {
  std::vector<glm::vec3> out(normals.size());
  for (std::size_t i = 0; i < normals.size(); ++i) out[i] = sh.evaluate(normals[i]);
  return out;
}

std::vector<glm::vec3> sampleCubemap(const Cubemap& cube, const std::vector<glm::vec3>& normals) {
  std::vector<glm::vec3> out(normals.size());
  for (std::size_t i = 0; i < normals.size(); ++i) out[i] = cube.sample(normals[i]);
  return out;
}

void checkOptions(bool emptySource, const IrradianceOptions& o) {
  if (emptySource) throw Error("the radiance source is empty");
  if (!(o.tolerance >= 0.0) || !std::isfinite(o.tolerance)) {
    throw Error("tolerance must be a non-negative number");
  }
  if (o.faceSize < 0) throw Error("irradiance face size must not be negative");
  if (o.shOrder < 0 || o.shOrder > SphericalHarmonics::kMaxOrder) {
    throw Error("SH order must be in [0, " + std::to_string(SphericalHarmonics::kMaxOrder) + "]");
  }
  if (o.probes < 16) throw Error("at least 16 probe normals are needed");
}

// Takes SH of `order` (cut from `radianceSh`) for the result; returns the irradiance SH and sets
// `error` to its relative RMS error at the probes.
SphericalHarmonics useSh(IrradianceResult& result, const SphericalHarmonics& radianceSh, int order,
                         const TransmittedCosineKernel& kernel, ShWindow window,
                         const Probes& probes, double& error) {
  result.radianceSh = radianceSh.truncated(order);
  result.irradianceSh = result.radianceSh.convolved(kernel, window);
  result.method = IrradianceMethod::Sh;
  result.shOrder = order;
  error = relativeRms(evaluateSh(result.irradianceSh, probes.normals), probes.reference);
  return result.irradianceSh;
}

// Radiance SH of an order: `exact` from every source texel (for --method sh), `quick` for auto's
// order-2 trial (checked at the probes either way).
struct ShProjector {
  std::function<SphericalHarmonics(int)> exact, quick;
};

// The SH side of the choice (methods Sh and Auto): the irradiance SH when SH is taken, nothing
// when the direct sum must be (Auto missing the budget, or method Brute). Sets the result's
// method, order, reason and projection time.
std::optional<SphericalHarmonics> chooseSh(const ShProjector& projector, const IrradianceOptions& o,
                                           const TransmittedCosineKernel& kernel,
                                           const Probes& probes, IrradianceResult& result) {
  double methodError = 0.0;
  Stopwatch watch;
  if (o.method == IrradianceMethod::Sh) {
    const SphericalHarmonics sh = projector.exact(o.shOrder);
    result.timings.projectionMs = watch.milliseconds();
    SphericalHarmonics irradianceSh =
        useSh(result, sh, o.shOrder, kernel, o.window, probes, methodError);
    result.reason = "sh order " + std::to_string(o.shOrder) + " as asked (estimated error " +
                    percent(methodError) + ")";
    return irradianceSh;
  }
  if (o.method != IrradianceMethod::Auto) return std::nullopt;
  // Cheapest first: SH of order 2 (nine coefficients), else the direct sum over the cut, which
  // costs less than higher SH orders projected from every texel.
  SphericalHarmonics irradianceSh =
      useSh(result, projector.quick(2), 2, kernel, o.window, probes, methodError);
  result.timings.projectionMs = watch.milliseconds();
  if (methodError <= kMethodShare * o.tolerance) {
    result.reason =
        "sh order 2: estimated error " + percent(methodError) + " within " + percent(o.tolerance);
    return irradianceSh;
  }
  result.method = IrradianceMethod::Brute;
  result.shOrder = -1;
  result.reason = o.tolerance > 0.0 ? "brute: sh order 2 misses " + percent(o.tolerance) +
                                          " (estimated " + percent(methodError) + ")"
                                    : "brute: tolerance 0 asks for the exact sum";
  return std::nullopt;
}

// The direct sum's cut over `source` (a Cubemap or a RadianceGrid), built to the method's share
// of the tolerance.
template <class Source>
BruteForceIrradiance buildBrute(const Source& source, const IrradianceOptions& o,
                                const Probes& probes, IrradianceResult& result) {
  const Stopwatch watch;
  BruteForceOptions bo;
  bo.eta = o.eta;
  bo.tolerance = kMethodShare * o.tolerance;
  bo.threads = o.threads;
  bo.quiet = o.quiet;
  bo.probeNormals = &probes.normals;
  bo.probeReference = &probes.reference;
  BruteForceIrradiance brute(source, bo);
  result.bruteClusters = brute.stats().clusters;
  const std::string terms = std::to_string(result.bruteClusters) + " terms for " +
                            std::to_string(result.sourceTexels) + " texels";
  result.reason = o.method == IrradianceMethod::Brute ? "brute as asked: " + terms
                                                      : result.reason + "; " + terms;
  result.timings.evaluationMs += watch.milliseconds();
  return brute;
}

// The output cubemap at the asked face size, or at the smallest automatic size whose bilinear
// lookups meet the tolerance at the probes.
template <class Build>
void buildCubemap(const IrradianceOptions& o, const Probes& probes, Build build,
                  IrradianceResult& result) {
  const Stopwatch watch;
  if (o.faceSize > 0) {
    result.irradiance = build(o.faceSize);
    result.estimatedError =
        relativeRms(sampleCubemap(result.irradiance, probes.normals), probes.reference);
  } else {
    for (int size : kAutoFaceSizes) {
      // Tolerance 0 cannot be met by interpolation: go straight to the largest size.
      if (o.tolerance <= 0.0 && size != kAutoFaceSizes[std::size(kAutoFaceSizes) - 1]) continue;
      result.irradiance = build(size);
      result.estimatedError =
          relativeRms(sampleCubemap(result.irradiance, probes.normals), probes.reference);
      if (result.estimatedError <= o.tolerance) break;
    }
    result.reason += "; face size " + std::to_string(result.irradiance.size());
  }
  result.timings.evaluationMs += watch.milliseconds();
}

// The choice and the output cubemap, given the probes' reference sums: shared by every source.
template <class Source>
IrradianceResult computeFromSource(const Source& source, const ShProjector& projector,
                                   Probes probes, const IrradianceOptions& o,
                                   IrradianceResult result) {
  const Stopwatch total;
  const TransmittedCosineKernel kernel(o.eta);
  const std::optional<SphericalHarmonics> irradianceSh =
      chooseSh(projector, o, kernel, probes, result);
  std::optional<BruteForceIrradiance> brute;
  if (result.method == IrradianceMethod::Brute)
    brute.emplace(buildBrute(source, o, probes, result));
  buildCubemap(
      o, probes,
      [&](int size) {
        return irradianceSh ? irradianceSh->toCubemap(size, o.threads) : brute->cubemap(size);
      },
      result);
  result.timings.totalMs += total.milliseconds();
  return result;
}

// Radiance SH with every cell of a grid taken as a point source per channel: |V_c| along V_c.
SphericalHarmonics projectCells(const RadianceGrid& grid, int order) {
  SphericalHarmonics sh(order);
  std::vector<float> basis(sh.coefficientCount());
  std::vector<glm::dvec3> sum(sh.coefficientCount(), glm::dvec3(0.0));
  for (int f = 0; f < grid.faces(); ++f) {
    for (int y = 0; y < grid.height(); ++y) {
      glm::dvec3 row[(SphericalHarmonics::kMaxOrder + 1) * (SphericalHarmonics::kMaxOrder + 1)]{};
      for (int x = 0; x < grid.width(); ++x) {
        const float* v = grid.cell(f, x, y);
        for (int c = 0; c < 3; ++c) {
          const glm::vec3 vc(v[3 * c], v[3 * c + 1], v[3 * c + 2]);
          const float flux = glm::length(vc);
          if (flux <= 0.0f) continue;
          SphericalHarmonics::evaluateBasis(order, vc / flux, basis.data());
          for (int i = 0; i < sh.coefficientCount(); ++i) row[i][c] += basis[i] * flux;
        }
      }
      for (int i = 0; i < sh.coefficientCount(); ++i) sum[i] += row[i];
    }
  }
  for (int i = 0; i < sh.coefficientCount(); ++i) sh[i] = glm::vec3(sum[i]);
  return sh;
}

// Texels per cell side: width / equirectCells, but cells no wider than sqrt(1.4 tolerance)
// radians, so that what a cell loses where a horizon cuts it (its texels below the horizon
// cancel some above: at most 0.07 theta^2 of E for cells theta wide, measured on a uniform map)
// stays under a tenth of the tolerance.
int equirectBlock(const ImageRgb& image, const IrradianceOptions& o) {
  const double texelAngle = 2.0 * M_PI / image.width;
  const double widest = std::sqrt(1.4 * o.tolerance) / texelAngle;
  const int wanted = std::min<double>(image.width / std::max(o.equirectCells, 1), widest);
  return RadianceGrid::equirectBlockSize(image, wanted);
}

// At tolerance 0 a map narrower than this is summed as this wide, each texel split into s x s
// sub-texels of its radiance, each with its exact first moment. A texel the horizon of n cuts
// loses the part of it below the horizon that its moment cancels, O(texel angle^2) of E in all
// (on a uniform map 2.5e-4 of the closed form at 128 x 64, 6e-5 at 256 x 128, 1e-5 at 512 x 256;
// the SH projection's texel-centre rule errs alike): 512 keeps the exact sum within 1e-5 of
// pi L.
constexpr int kExactSumWidth = 512;

// The image with each texel repeated s x s times.
ImageRgb splitTexels(const ImageRgb& image, int s) {
  ImageRgb fine;
  fine.width = image.width * s;
  fine.height = image.height * s;
  fine.pixels.resize(static_cast<std::size_t>(fine.width) * fine.height);
  for (int y = 0; y < fine.height; ++y) {
    for (int x = 0; x < fine.width; ++x) fine.at(x, y) = image.at(x / s, y / s);
  }
  return fine;
}

}  // namespace

IrradianceResult computeIrradiance(const Cubemap& radiance, const IrradianceOptions& o) {
  checkOptions(radiance.empty(), o);
  IrradianceResult result;
  result.sourceTexels = radiance.texelCount();
  const Stopwatch watch;
  Probes probes;
  probes.normals = fibonacciSphere(o.probes);
  probes.reference = irradianceAtNormals(radiance, probes.normals, o.eta, o.threads);
  result.timings.referenceMs = watch.milliseconds();
  result.timings.totalMs = result.timings.referenceMs;
  auto project = [&](int order) { return SphericalHarmonics::project(radiance, order, o.threads); };
  return computeFromSource(radiance, {project, project}, std::move(probes), o, std::move(result));
}

IrradianceResult computeIrradianceFromEquirect(const ImageRgb& original,
                                               const IrradianceOptions& o) {
  checkOptions(original.width <= 0 || original.height <= 0, o);
  IrradianceResult result;
  Stopwatch watch;
  std::optional<ImageRgb> split;
  if (o.tolerance <= 0.0 && original.width < kExactSumWidth) {
    split = splitTexels(original, (kExactSumWidth + original.width - 1) / original.width);
  }
  const ImageRgb& image = split ? *split : original;
  const RadianceGrid grid = RadianceGrid::fromEquirect(image, equirectBlock(image, o), o.threads);
  result.sourceTexels = static_cast<std::size_t>(original.width) * original.height;
  result.timings.gridMs = watch.milliseconds();
  watch.restart();
  Probes probes;
  probes.normals = fibonacciSphere(o.probes);
  probes.reference = irradianceAtNormals(grid, probes.normals, o.eta, o.threads);
  result.timings.referenceMs = watch.milliseconds();
  result.timings.totalMs = result.timings.gridMs + result.timings.referenceMs;
  const ShProjector projector{
      [&](int order) { return SphericalHarmonics::projectEquirect(image, order, o.threads); },
      [&](int order) { return projectCells(grid, order); }};
  return computeFromSource(grid, projector, std::move(probes), o, std::move(result));
}

}  // namespace sss

#include "irradiance/irradiance.h"

#include <cmath>
#include <iterator>
#include <optional>

#include "core/error.h"
#include "core/format.h"
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

void checkOptions(const Cubemap& radiance, const IrradianceOptions& o) {
  if (radiance.empty()) throw Error("the radiance cubemap is empty");
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
  error = relativeRmsError(evaluateSh(result.irradianceSh, probes.normals), probes.reference);
  return result.irradianceSh;
}

// The SH side of the choice (methods Sh and Auto): the irradiance SH when SH is taken, nothing
// when the direct sum must be (Auto missing the budget, or method Brute). Sets the result's
// method, order, reason and projection time.
std::optional<SphericalHarmonics> chooseSh(const Cubemap& radiance, const IrradianceOptions& o,
                                           const TransmittedCosineKernel& kernel,
                                           const Probes& probes, IrradianceResult& result) {
  double methodError = 0.0;
  Stopwatch watch;
  if (o.method == IrradianceMethod::Sh) {
    const SphericalHarmonics sh = SphericalHarmonics::project(radiance, o.shOrder, o.threads);
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
      useSh(result, SphericalHarmonics::project(radiance, 2, o.threads), 2, kernel, o.window,
            probes, methodError);
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

// The direct sum's cut, built to the method's share of the tolerance.
BruteForceIrradiance buildBrute(const Cubemap& radiance, const IrradianceOptions& o,
                                const Probes& probes, IrradianceResult& result) {
  const Stopwatch watch;
  BruteForceOptions bo;
  bo.eta = o.eta;
  bo.tolerance = kMethodShare * o.tolerance;
  bo.threads = o.threads;
  bo.quiet = o.quiet;
  bo.probeNormals = &probes.normals;
  bo.probeReference = &probes.reference;
  BruteForceIrradiance brute(radiance, bo);
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
        relativeRmsError(sampleCubemap(result.irradiance, probes.normals), probes.reference);
  } else {
    for (int size : kAutoFaceSizes) {
      // Tolerance 0 cannot be met by interpolation: go straight to the largest size.
      if (o.tolerance <= 0.0 && size != kAutoFaceSizes[std::size(kAutoFaceSizes) - 1]) continue;
      result.irradiance = build(size);
      result.estimatedError =
          relativeRmsError(sampleCubemap(result.irradiance, probes.normals), probes.reference);
      if (result.estimatedError <= o.tolerance) break;
    }
    result.reason += "; face size " + std::to_string(result.irradiance.size());
  }
  result.timings.evaluationMs += watch.milliseconds();
}

}  // namespace

IrradianceResult computeIrradiance(const Cubemap& radiance, const IrradianceOptions& o) {
  checkOptions(radiance, o);
  const Stopwatch total;
  const TransmittedCosineKernel kernel(o.eta);
  IrradianceResult result;
  result.sourceTexels = radiance.texelCount();

  const Stopwatch watch;
  Probes probes;
  probes.normals = fibonacciSphere(o.probes);
  probes.reference = irradianceAtNormals(radiance, probes.normals, o.eta, o.threads);
  result.timings.referenceMs = watch.milliseconds();

  const std::optional<SphericalHarmonics> irradianceSh =
      chooseSh(radiance, o, kernel, probes, result);
  std::optional<BruteForceIrradiance> brute;
  if (result.method == IrradianceMethod::Brute)
    brute.emplace(buildBrute(radiance, o, probes, result));
  buildCubemap(
      o, probes,
      [&](int size) {
        return irradianceSh ? irradianceSh->toCubemap(size, o.threads) : brute->cubemap(size);
      },
      result);
  result.timings.totalMs = total.milliseconds();
  return result;
}

}  // namespace sss

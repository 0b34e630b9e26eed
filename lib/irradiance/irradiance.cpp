#include "irradiance/irradiance.h"

#include <cmath>
#include <cstdio>
#include <iterator>
#include <optional>

#include "core/error.h"
#include "core/timer.h"
#include "irradiance/brute_force.h"

namespace sss {
namespace {

// Share of the tolerance the method may use; the rest is left to the cubemap's bilinear lookups.
constexpr double kMethodShare = 0.7;
constexpr int kAutoFaceSizes[] = {16, 32, 64};

std::string percent(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g%%", 100.0 * x);
  return buf;
}

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

}  // namespace

IrradianceMethod parseIrradianceMethod(const std::string& name) {
  if (name == "auto") return IrradianceMethod::Auto;
  if (name == "brute") return IrradianceMethod::Brute;
  if (name == "sh") return IrradianceMethod::Sh;
  throw Error("unknown irradiance method '" + name + "' (auto, brute, sh)");
}

const char* irradianceMethodName(IrradianceMethod method) {
  switch (method) {
    case IrradianceMethod::Brute:
      return "brute";
    case IrradianceMethod::Sh:
      return "sh";
    default:
      return "auto";
  }
}

IrradianceResult computeIrradiance(const Cubemap& radiance, const IrradianceOptions& o) {
  if (radiance.empty()) throw Error("the radiance cubemap is empty");
  if (!(o.tolerance >= 0.0) || !std::isfinite(o.tolerance)) {
    throw Error("tolerance must be a non-negative number");
  }
  if (o.faceSize < 0) throw Error("irradiance face size must not be negative");
  if (o.shOrder < 0 || o.shOrder > SphericalHarmonics::kMaxOrder) {
    throw Error("SH order must be in [0, " + std::to_string(SphericalHarmonics::kMaxOrder) + "]");
  }
  if (o.probes < 16) throw Error("at least 16 probe normals are needed");
  const Stopwatch total;
  const TransmittedCosineKernel kernel(o.eta);
  IrradianceResult result;
  result.sourceTexels = radiance.texelCount();

  Stopwatch watch;
  const std::vector<glm::vec3> probes = fibonacciSphere(o.probes);
  const std::vector<glm::vec3> reference = irradianceAtNormals(radiance, probes, o.eta, o.threads);
  result.timings.referenceMs = watch.milliseconds();

  const double methodBudget = kMethodShare * o.tolerance;
  std::optional<SphericalHarmonics> irradianceSh;
  double methodError = 0.0;
  auto useSh = [&](const SphericalHarmonics& radianceSh, int order) {
    result.radianceSh = radianceSh.truncated(order);
    result.irradianceSh = result.radianceSh.convolved(kernel, o.window);
    irradianceSh = result.irradianceSh;
    result.method = IrradianceMethod::Sh;
    result.shOrder = order;
    methodError = relativeRmsError(evaluateSh(*irradianceSh, probes), reference);
  };

  if (o.method == IrradianceMethod::Sh) {
    watch.restart();
    const SphericalHarmonics sh = SphericalHarmonics::project(radiance, o.shOrder, o.threads);
    result.timings.projectionMs = watch.milliseconds();
    useSh(sh, o.shOrder);
    result.reason = "sh order " + std::to_string(o.shOrder) + " as asked (estimated error " +
                    percent(methodError) + ")";
  } else if (o.method == IrradianceMethod::Auto) {
    // Cheapest first: SH of order 2 (nine coefficients), else the direct sum over the cut, which
    // costs less than higher SH orders projected from every texel.
    watch.restart();
    useSh(SphericalHarmonics::project(radiance, 2, o.threads), 2);
    result.timings.projectionMs = watch.milliseconds();
    if (methodError <= methodBudget) {
      result.reason =
          "sh order 2: estimated error " + percent(methodError) + " within " + percent(o.tolerance);
    } else {
      irradianceSh.reset();
      result.method = IrradianceMethod::Brute;
      result.shOrder = -1;
      result.reason = o.tolerance > 0.0 ? "brute: sh order 2 misses " + percent(o.tolerance) +
                                              " (estimated " + percent(methodError) + ")"
                                        : "brute: tolerance 0 asks for the exact sum";
    }
  }

  std::optional<BruteForceIrradiance> brute;
  if (result.method == IrradianceMethod::Brute) {
    watch.restart();
    BruteForceOptions bo;
    bo.eta = o.eta;
    bo.tolerance = methodBudget;
    bo.threads = o.threads;
    bo.quiet = o.quiet;
    bo.probeNormals = &probes;
    bo.probeReference = &reference;
    brute.emplace(radiance, bo);
    result.bruteClusters = brute->stats().clusters;
    if (o.method == IrradianceMethod::Brute) {
      result.reason = "brute as asked: " + std::to_string(result.bruteClusters) + " terms for " +
                      std::to_string(result.sourceTexels) + " texels";
    } else {
      result.reason += "; " + std::to_string(result.bruteClusters) + " terms for " +
                       std::to_string(result.sourceTexels) + " texels";
    }
    result.timings.evaluationMs += watch.milliseconds();
  }

  watch.restart();
  auto build = [&](int size) {
    return irradianceSh ? irradianceSh->toCubemap(size, o.threads) : brute->cubemap(size);
  };
  if (o.faceSize > 0) {
    result.irradiance = build(o.faceSize);
    result.estimatedError = relativeRmsError(sampleCubemap(result.irradiance, probes), reference);
  } else {
    for (int size : kAutoFaceSizes) {
      // Tolerance 0 cannot be met by interpolation: go straight to the largest size.
      if (o.tolerance <= 0.0 && size != kAutoFaceSizes[std::size(kAutoFaceSizes) - 1]) continue;
      result.irradiance = build(size);
      result.estimatedError = relativeRmsError(sampleCubemap(result.irradiance, probes), reference);
      if (result.estimatedError <= o.tolerance) break;
    }
    result.reason += "; face size " + std::to_string(result.irradiance.size());
  }
  result.timings.evaluationMs += watch.milliseconds();
  result.timings.totalMs = total.milliseconds();
  return result;
}

}  // namespace sss

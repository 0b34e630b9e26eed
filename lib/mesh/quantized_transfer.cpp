#include "mesh/quantized_transfer.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace sss {

namespace {

// The smallest power of two s with largest <= limit s (0 where s would be below 2^-126, so that
// the GLB's exponents hold every step: scaleExponent): every coefficient then rounds
// to at most `limit` steps, within half a step, and the stored values give the same s again (their
// largest is above limit s / 2 steps, so s / 2 does not hold them).
float stepFor(float largest, int limit) {
  if (!(largest > float(limit) * std::ldexp(1.0f, kMinStepExponent - 1))) return 0.0f;
  int e = 0;
  std::frexp(largest / float(limit), &e);  // largest / limit < 2^e, to float's rounding
  float step = std::ldexp(1.0f, e - 2);
  while (largest > float(limit) * step) step *= 2.0f;  // exact: limit * 2^k
  return step;
}

// Coefficients [first, last) of one vertex's channel c in steps of stepFor (at most `limit`
// steps); returns the step.
float quantizeRange(std::span<const glm::vec3> t, std::size_t first, std::size_t last, int c,
                    int limit, std::span<std::array<int16_t, 3>> out) {
  float largest = 0.0f;
  for (std::size_t k = first; k < last; ++k) largest = std::max(largest, std::abs(t[k][c]));
  const float step = stepFor(largest, limit);
  for (std::size_t k = first; k < last; ++k) {
    const float steps = step > 0.0f ? std::nearbyint(t[k][c] / step) : 0.0f;
    out[k][c] = int16_t(std::clamp(steps, -float(limit), float(limit)));
  }
  return step;
}

}  // namespace

QuantizedTransfer quantizeTransfer(const std::string& path, std::span<const glm::vec3> transfer,
                                   std::size_t count) {
  QuantizedTransfer q;
  const std::size_t n = count == 0 ? 0 : transfer.size() / count;
  const std::size_t low = std::min(count, kShortTransferCoefficients);
  q.scale.resize(n);
  if (hasHighBands(count)) q.scaleHigh.resize(n);
  q.values.resize(n * count);
  for (std::size_t v = 0; v < n; ++v) {
    const std::span<const glm::vec3> t = transfer.subspan(v * count, count);
    const std::span<std::array<int16_t, 3>> out(q.values.data() + v * count, count);
    for (int c = 0; c < 3; ++c) {
      for (const glm::vec3& x : t)
        if (!(std::abs(x[c]) <= 1e30f)) fail(path, "relight transfer value out of range");
      q.scale[v][c] = quantizeRange(t, 0, low, c, kTransferSteps, out) * kTransferNormalizer;
      if (hasHighBands(count)) {
        q.scaleHigh[v][c] =
            quantizeRange(t, low, count, c, kHighTransferSteps, out) * kHighTransferNormalizer;
      }
    }
  }
  return q;
}

std::vector<glm::vec3> dequantizeTransfer(const QuantizedTransfer& quantized, std::size_t count) {
  std::vector<glm::vec3> out(quantized.values.size());
  const bool high = !quantized.scaleHigh.empty();
  for (std::size_t v = 0; v < quantized.scale.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      // scale / 32767 (and scaleHigh / 127) is the power-of-two step exactly for the files this
      // library writes.
      const float step = quantized.scale[v][c] / kTransferNormalizer;
      const float highStep = high ? quantized.scaleHigh[v][c] / kHighTransferNormalizer : step;
      for (std::size_t k = 0; k < count; ++k) {
        const float s = k < kShortTransferCoefficients ? step : highStep;
        out[v * count + k][c] = float(quantized.values[v * count + k][c]) * s;
      }
    }
  return out;
}

int scaleExponent(float scale, float normalizer) {
  if (scale == 0.0f) return kZeroScaleExponent;
  int e = 0;
  std::frexp(scale / normalizer, &e);  // step = 2^(e - 1) exactly
  return e - 1;
}

float scaleOfExponent(const std::string& path, int exponent, float normalizer) {
  if (exponent == kZeroScaleExponent) return 0.0f;
  if (exponent < kMinStepExponent || exponent > kMaxStepExponent)
    fail(path, "transfer scale exponent " + std::to_string(exponent) + " is outside [" +
                   std::to_string(kMinStepExponent) + ", " + std::to_string(kMaxStepExponent) +
                   "]");
  return std::ldexp(1.0f, exponent) * normalizer;
}

void checkTransferScales(const std::string& path, std::span<const glm::vec3> scales) {
  for (const glm::vec3& s : scales)
    for (int c = 0; c < 3; ++c)
      if (!(s[c] >= 0.0f && std::isfinite(s[c])))
        fail(path, "transfer scale is negative or not finite");
}

std::vector<glm::vec3> storedTransfer(const std::string& path, std::span<const glm::vec3> transfer,
                                      std::size_t count) {
  return dequantizeTransfer(quantizeTransfer(path, transfer, count), count);
}

}  // namespace sss

#include "mesh/quantized_transfer.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace sss {

namespace {

// The step 2^(e - 14) for a largest magnitude m: 2^e the smallest power of two >= m (0 for 0).
float stepFor(float largest) {
  if (!(largest > 0.0f)) return 0.0f;
  int e = 0;
  const float mantissa = std::frexp(largest, &e);  // largest = mantissa 2^e, mantissa in [0.5, 1)
  if (mantissa == 0.5f) --e;                       // a power of two itself
  return std::ldexp(1.0f, e - 14);
}

}  // namespace

QuantizedTransfer quantizeTransfer(const std::string& path, std::span<const glm::vec3> transfer,
                                   std::size_t count) {
  QuantizedTransfer q;
  const std::size_t n = count == 0 ? 0 : transfer.size() / count;
  q.scale.resize(n);
  q.values.resize(n * count);
  for (std::size_t v = 0; v < n; ++v) {
    const std::span<const glm::vec3> t = transfer.subspan(v * count, count);
    for (int c = 0; c < 3; ++c) {
      float largest = 0.0f;
      for (const glm::vec3& x : t) largest = std::max(largest, std::abs(x[c]));
      if (!(largest <= 1e30f)) fail(path, "relight transfer value out of range");
      const float step = stepFor(largest);
      q.scale[v][c] = step * kTransferNormalizer;
      for (std::size_t k = 0; k < count; ++k) {
        const float steps = step > 0.0f ? std::nearbyint(t[k][c] / step) : 0.0f;
        q.values[v * count + k][c] =
            int16_t(std::clamp(steps, -float(kTransferSteps), float(kTransferSteps)));
      }
    }
  }
  return q;
}

std::vector<glm::vec3> dequantizeTransfer(const QuantizedTransfer& quantized, std::size_t count) {
  std::vector<glm::vec3> out(quantized.values.size());
  for (std::size_t v = 0; v < quantized.scale.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      // scale / 32767 is the power-of-two step exactly for the files this library writes.
      const float step = quantized.scale[v][c] / kTransferNormalizer;
      for (std::size_t k = v * count; k < (v + 1) * count; ++k)
        out[k][c] = float(quantized.values[k][c]) * step;
    }
  return out;
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

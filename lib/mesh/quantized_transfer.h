// A relightable bake's transfer as the files store it: per vertex and channel one scale and, per
// coefficient, a 16-bit integer (baked PLY `short transfer<k>_r/g/b` beside `float
// transfer_scale_r/g/b`; baked GLB normalized SHORT `_TRANSFER_<k>` beside `_TRANSFER_SCALE`),
//
//   T_k,c = q_k,c / 32767 * scale_c,   scale_c = 32767 * 2^(e_c - 14),   |q| <= 2^14,
//
// 2^e_c the smallest power of two at or above the vertex's largest |T_k,c|. Each coefficient is
// kept within 2^-14 of its vertex's largest (half a step; 6e-5), half the bytes of floats, and
// the stored values are exact in float: quantizing them again gives them back bit for bit, so
// that a file read and written again holds the same transfer (the step is a power of two and
// q has at most 15 bits). An engine decodes a normalized SHORT as q / 32767 and multiplies by the
// scale.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sss {

// The normalized SHORT's divisor, and the largest |q| the format writes.
inline constexpr float kTransferNormalizer = 32767.0f;
inline constexpr int kTransferSteps = 1 << 14;

struct QuantizedTransfer {
  std::vector<glm::vec3> scale;                // per vertex, per channel (>= 0)
  std::vector<std::array<int16_t, 3>> values;  // at [vertex * count + k]
};

// `transfer` at [vertex * count + k] (finite), quantized. Throws Error naming `path` on a
// coefficient above 1e30 in magnitude (its scale would not be a float).
QuantizedTransfer quantizeTransfer(const std::string& path, std::span<const glm::vec3> transfer,
                                   std::size_t count);

// Throws Error naming `path` unless every scale is finite and >= 0 (what the readers check).
void checkTransferScales(const std::string& path, std::span<const glm::vec3> scales);

// q / 32767 * scale per coefficient, at [vertex * count + k].
std::vector<glm::vec3> dequantizeTransfer(const QuantizedTransfer& quantized, std::size_t count);

// What a file stores of `transfer`: quantizeTransfer then dequantizeTransfer.
std::vector<glm::vec3> storedTransfer(const std::string& path, std::span<const glm::vec3> transfer,
                                      std::size_t count);

}  // namespace sss

// A relightable bake's transfer as the files store it: per vertex and channel one scale and, per
// coefficient of bands 0-3 (k < 16), a 16-bit integer (baked PLY `short transfer<k>_r/g/b` beside
// `float transfer_scale_r/g/b`; baked GLB normalized SHORT VEC4s `_TRANSFER_LOW_<j>`, the steps
// packed four to an element, beside `_TRANSFER_SCALE`),
//
//   T_k,c = q_k,c / 32767 * scale_c,   scale_c = 32767 s_c,   |q| <= 2^14,
//
// s_c the smallest power of two with the vertex's largest |T_k,c| over those bands at most 2^14
// steps. The bands from 4 (orders 4-8) have a scale of their own and 8 bits (PLY
// `char transfer<k>_*` beside `float transfer_scale_high_*`; GLB normalized BYTE VEC4s
// `_TRANSFER_HIGH_<j>` beside `_TRANSFER_SCALE_HIGH`):
//
//   T_k,c = q_k,c / 127 * high_c,   high_c = 127 h_c,   |q| <= 127,
//
// h_c the smallest power of two with the largest of those bands at most 127 steps. Bands 0-3 are
// kept within 2^-14 of their vertex's largest (half a step; 6e-5), the higher bands within 1/127
// of theirs (half a step), which are small against band 0 (their share of the relit radiance is
// the SH detail above order 3): at order 6 the transfer takes 195 bytes per vertex where 16 bits
// throughout took 294 and floats 588. The stored values are exact in float: quantizing them again
// gives them back bit for bit, so that a file read and written again holds the same transfer (the
// steps are powers of two, q has at most 15 bits, and the stored largest needs the same step). An
// engine decodes a normalized SHORT as q / 32767, a BYTE as q / 127, and multiplies by the scale.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sss {

// The normalized SHORT's divisor, and the largest |q| the format writes; the same for the high
// bands' normalized BYTE, which start at coefficient kShortTransferCoefficients.
inline constexpr float kTransferNormalizer = 32767.0f;
inline constexpr int kTransferSteps = 1 << 14;
inline constexpr float kHighTransferNormalizer = 127.0f;
inline constexpr int kHighTransferSteps = 127;
inline constexpr std::size_t kShortTransferCoefficients = 16;  // bands 0-3

struct QuantizedTransfer {
  std::vector<glm::vec3> scale;  // per vertex, per channel (>= 0)
  // Per vertex, per channel, the bands from 4 (>= 0). Empty: every band has `scale` (a file of
  // format 2 at orders above 3, read as written).
  std::vector<glm::vec3> scaleHigh;
  std::vector<std::array<int16_t, 3>> values;  // at [vertex * count + k]
};

// A scale as the GLB stores it: the exponent e of its step, scale = normalizer 2^e, in
// [kMinStepExponent, kMaxStepExponent], or kZeroScaleExponent for a scale of 0 (its steps are all
// 0). quantizeTransfer's steps are such powers of two: it rounds a channel whose largest is below
// limit 2^-127 (1e-34 for bands 0-3) to zero, and refuses coefficients above 1e30.
inline constexpr int kMinStepExponent = -126;
inline constexpr int kMaxStepExponent = 100;
inline constexpr int kZeroScaleExponent = -128;
int scaleExponent(float scale, float normalizer);
// Throws Error naming `path` unless `exponent` is one scaleExponent gives.
float scaleOfExponent(const std::string& path, int exponent, float normalizer);

// Whether a transfer of `count` coefficients per channel has bands from 4 (orders 4-8), which
// take 8 bits with a scale of their own.
inline bool hasHighBands(std::size_t count) {
  return count > kShortTransferCoefficients;
}

// The largest |q| coefficient k may have (k >= 16: with a high scale).
inline int transferStepLimit(std::size_t k, bool highScale) {
  return highScale && k >= kShortTransferCoefficients ? kHighTransferSteps : kTransferSteps;
}

// `transfer` at [vertex * count + k] (finite), quantized. Throws Error naming `path` on a
// coefficient above 1e30 in magnitude (its scale would not be a float).
QuantizedTransfer quantizeTransfer(const std::string& path, std::span<const glm::vec3> transfer,
                                   std::size_t count);

// Throws Error naming `path` unless every scale is finite and >= 0 (what the readers check).
void checkTransferScales(const std::string& path, std::span<const glm::vec3> scales);

// q / 32767 * scale per coefficient (q / 127 * scaleHigh from k = 16), at [vertex * count + k].
std::vector<glm::vec3> dequantizeTransfer(const QuantizedTransfer& quantized, std::size_t count);

// What a file stores of `transfer`: quantizeTransfer then dequantizeTransfer.
std::vector<glm::vec3> storedTransfer(const std::string& path, std::span<const glm::vec3> transfer,
                                      std::size_t count);

}  // namespace sss

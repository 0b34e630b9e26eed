// PCG32 (O'Neill 2014): small, fast, and seeded per item (vertex, texel) so that Monte Carlo
// results do not depend on the thread count or the order of work.
#pragma once

#include <cstdint>

namespace sss {

class Pcg32 {
 public:
  // stream selects an independent sequence: use the item index. The start state is a hash of
  // both: PCG's streams are one LCG under affine maps of its state, so with the seed merely added
  // (O'Neill's pcg32_srandom) the draws of consecutive streams are affine in the stream index, a
  // lattice rather than independent sequences, and batches of consecutive paths look less noisy
  // than they are (docs/conventions.md, "Determinism and random numbers";
  // tests/core/random_test.cpp).
  Pcg32(uint64_t seed, uint64_t stream) : inc_((stream << 1u) | 1u) {
    next();
    state_ += splitMix64(seed ^ splitMix64(stream));
    next();
  }
  uint32_t next() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
  }
  // Uniform in [0, 1).
  float uniform() { return static_cast<float>(next() >> 8) * 0x1p-24f; }
  double uniformDouble() {
    const uint64_t hi = next() >> 5, lo = next() >> 6;
    return static_cast<double>(hi * 67108864ULL + lo) * 0x1p-53;
  }

 private:
  // Steele, Lea & Flood 2014 (SplitMix64's finalizer): a bijective 64-bit mix.
  static uint64_t splitMix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
  }

  uint64_t state_ = 0;
  uint64_t inc_;
};

}  // namespace sss

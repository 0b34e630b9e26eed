// An estimate shrunk towards 0 by its own noise, x x^2 / (x^2 + v) for an estimate x of noise
// variance v: a Wiener-like weight, so that an estimate well above its noise stays and one within
// it fades. Where a noisy correction would add more error than it removes (the far field's exit
// lobe slope, optics/exit_lobe.h; its near part's scale, transport/far_field.h).
#pragma once

namespace sss {

// x x^2 / (x^2 + v); 0 where both are 0.
inline double shrunkByNoise(double x, double variance) {
  const double x2 = x * x;
  return x2 + variance > 0.0 ? x * x2 / (x2 + variance) : 0.0;
}

// d shrunkByNoise / dx = (x^4 + 3 x^2 v) / (x^2 + v)^2: how much of x's noise the shrunk value
// keeps (1 far above the noise, 9/8 at x^2 = 3 v, 3 x^2 / v within it); 0 where both are 0.
inline double shrunkByNoiseSlope(double x, double variance) {
  const double x2 = x * x;
  return x2 + variance > 0.0 ? (x2 * x2 + 3.0 * x2 * variance) / ((x2 + variance) * (x2 + variance))
                             : 0.0;
}

}  // namespace sss

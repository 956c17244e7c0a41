// Integer square roots, exact: floor(sqrt(v)) for 64- and 128-bit inputs, and ceil(sqrt(v)) derived from the
// floor. The device's square-root unit takes its closed form from isqrt (device/sqrt_unit.h), the fast model
// sizes its balls with ceil_isqrt, and the tests compare the unit against isqrt.
#pragma once

#include <cmath>
#include <cstdint>

#include <tripsitter/core/fixed.h>

namespace tripsitter::core {

// floor(sqrt(v)), for every 64-bit v. The double estimate is off by at most one (v rounds to 53 bits and the
// square root is correctly rounded), and the loops make it exact. The result is below 2^32, and the estimate
// is at most 2^32 (for v near 2^64), taken down to 2^32 - 1; so s^2 never overflows, and neither does the
// second loop's test, (s + 1)^2 <= v written as v - s^2 > 2s once s^2 <= v.
inline std::uint64_t isqrt(std::uint64_t v) {
  std::uint64_t s = static_cast<std::uint64_t>(std::sqrt(static_cast<double>(v)));
  s -= s >> 32;
  while (s * s > v) --s;
  while (v - s * s > 2 * s) ++s;
  return s;
}

// floor(sqrt(v)), for every 128-bit v (the result fits 64 bits). Above 2^64, Newton's method from the double
// estimate: its first step lands at or above floor(sqrt(v)) (the mean of x and v/x is at least sqrt(v)), and
// from there the steps decrease strictly until they reach it.
inline std::uint64_t isqrt(UInt128 v) {
  if ((v >> 64) == 0) return isqrt(static_cast<std::uint64_t>(v));
  // v >= 2^64, so the estimate is near sqrt(v) >= 2^32 (at most 2^64, for v near 2^128), and x + v / x < 2^66.
  UInt128 x = static_cast<UInt128>(std::sqrt(static_cast<double>(v)));
  x = (x + v / x) / 2;
  while (true) {
    const UInt128 y = (x + v / x) / 2;
    if (y >= x) return static_cast<std::uint64_t>(x);
    x = y;
  }
}

// ceil(sqrt(v)), for every 64-bit v.
inline std::uint64_t ceil_isqrt(std::uint64_t v) {
  const std::uint64_t s = isqrt(v);
  return s * s == v ? s : s + 1;
}

}  // namespace tripsitter::core

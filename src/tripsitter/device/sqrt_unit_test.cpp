#include <tripsitter/device/sqrt_unit.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>

#include <gtest/gtest.h>

#include <tripsitter/core/isqrt.h>

namespace tripsitter::device {
namespace {

using core::Int128;
using core::UInt128;

// |unit(v) - sqrt(v)| measured against the exact integer square root (core/isqrt.h, tested in core), in
// units of the result.
double error_of(const SqrtUnit& unit, UInt128 v) {
  const std::uint64_t f = core::isqrt(v);
  // sqrt(v) lies in [f, f + 1); compare with its double estimate refined by the exact floor.
  const double frac = std::sqrt(static_cast<double>(v)) - static_cast<double>(f);
  const double exact = static_cast<double>(f) + std::clamp(frac, 0.0, 1.0);
  return std::abs(static_cast<double>(unit(v)) - exact);
}

TEST(SqrtUnit, EdgeCases) {
  const SqrtUnit unit(16);
  EXPECT_EQ(unit(0), 0);
  EXPECT_EQ(unit(1), 1);
  EXPECT_EQ(unit(4), 2);
  EXPECT_EQ(unit(2), 1);        // 1.414 rounds to 1
  EXPECT_EQ(unit(3), 2);        // 1.732 rounds to 2
  EXPECT_EQ(unit(65536), 256);
  // The non-restoring recurrence ends on an odd multiple of 2^-N, so even exact squares come out
  // 2^(e-N) off: sqrt(2^64) = 2^32 with e = 33 is 2^32 - 2^17.
  EXPECT_EQ(unit(UInt128{1} << 64), (Int128{1} << 32) - (Int128{1} << 17));
  // The board's unit returned 0 for small inputs and sqrt(v)/sqrt(2) for half of them; this one does not.
  for (std::uint64_t v = 1; v < 64; ++v) EXPECT_GE(unit(v), 1) << v;
}

// Inputs below 4^N need no more than N result bits: the unit is then within one unit of sqrt(v).
TEST(SqrtUnit, WithinOneUnitBelowFourToTheN) {
  const SqrtUnit unit(16);
  for (std::uint64_t v = 0; v < 200000; ++v) ASSERT_LE(error_of(unit, v), 1.0) << v;
  std::mt19937_64 rng(7);
  for (int i = 0; i < 200000; ++i) {
    const std::uint64_t v = rng() >> 32;  // below 2^32 = 4^16
    ASSERT_LE(error_of(unit, v), 1.0) << v;
  }
}

// Above that, the error is relative: at most 2^-N of the normalised root, plus rounding.
TEST(SqrtUnit, RelativeErrorBoundForLargeInputs) {
  std::mt19937_64 rng(11);
  for (int n : {8, 12, 16, 20, 24}) {
    const SqrtUnit unit(n);
    for (int i = 0; i < 50000; ++i) {
      const int bits = 1 + static_cast<int>(rng() % 100);
      UInt128 v = (UInt128{rng()} << 64 | rng()) >> (128 - bits);
      const double s = std::sqrt(static_cast<double>(v));
      const double e = (bits + 1) / 2;  // normalising exponent
      // 2^-N from the recurrence, 2^(1-2N) from truncating m to 2N bits, 1/2 from the final rounding.
      const double bound = std::ldexp(1.0, static_cast<int>(e) - n) + std::ldexp(1.0, static_cast<int>(e) + 1 - 2 * n) +
                           0.5 + s * 1e-15;
      ASSERT_LE(std::abs(static_cast<double>(unit(v)) - s), bound) << "n=" << n << " bits=" << bits;
    }
  }
}

// The figure docs/measured.md quotes: the worst error of the 16-iteration unit, absolute below 2^32 (exhaustive
// over the first 2^22 inputs and every power-of-two neighbourhood, random elsewhere) and relative above.
TEST(SqrtUnit, WorstCaseForSixteenIterations) {
  const SqrtUnit unit(16);
  double worst_abs = 0;
  for (std::uint64_t v = 0; v < (1u << 22); ++v) worst_abs = std::max(worst_abs, error_of(unit, v));
  std::mt19937_64 rng(5);
  for (int i = 0; i < 1000000; ++i) worst_abs = std::max(worst_abs, error_of(unit, rng() >> 32));
  for (int b = 22; b < 32; ++b)
    for (std::uint64_t d = 0; d <= 6; ++d) worst_abs = std::max(worst_abs, error_of(unit, (std::uint64_t{1} << b) + d - 3));
  double worst_rel = 0;
  for (int i = 0; i < 1000000; ++i) {
    const int bits = 33 + static_cast<int>(rng() % 64);
    const UInt128 v = ((UInt128{rng()} << 64 | rng()) >> (128 - bits)) | (UInt128{1} << (bits - 1));
    const double s = std::sqrt(static_cast<double>(v));
    worst_rel = std::max(worst_rel, std::abs(static_cast<double>(unit(v)) - s) / s);
  }
  std::cout << "sqrt unit, 16 iterations: worst absolute error below 2^32 = " << worst_abs
            << " units; worst relative error from 2^32 to 2^96 = 2^" << std::log2(worst_rel) << "\n";
  EXPECT_LE(worst_abs, 1.0);
  EXPECT_LE(worst_rel, std::ldexp(1.0, -15));
}

TEST(SqrtUnit, MoreIterationsNeverHurtOnAverage) {
  std::mt19937_64 rng(3);
  double err8 = 0, err16 = 0;
  const SqrtUnit u8(8), u16(16);
  for (int i = 0; i < 10000; ++i) {
    const UInt128 v = rng() >> 4;
    err8 += error_of(u8, v);
    err16 += error_of(u16, v);
  }
  EXPECT_LT(err16, err8 / 100);
}

// The closed form (sqrt_unit.h) is the recurrence: for every register value m in [4^(N-1), 4^N) with
// N <= 12 (inputs of 2N - 1 or 2N bits are their own register, unshifted), ...
TEST(SqrtUnit, ClosedFormIsTheRecurrenceForEveryRegisterValueUpToTwelveIterations) {
  for (int n = 1; n <= 12; ++n) {
    const SqrtUnit unit(n);
    for (std::uint64_t v = std::uint64_t{1} << (2 * n - 2); v < (std::uint64_t{1} << (2 * n)); ++v)
      ASSERT_EQ(unit.closed_form(v), unit(v)) << "n=" << n << " v=" << v;
  }
}

// ... for 16 iterations on both sides of every leaf boundary (2j)^2, where the binary search turns ...
TEST(SqrtUnit, ClosedFormIsTheRecurrenceAtEveryLeafBoundaryForSixteenIterations) {
  const SqrtUnit unit(16);
  for (std::uint64_t j = std::uint64_t{1} << 14; j < (std::uint64_t{1} << 15); ++j) {
    const std::uint64_t square = 4 * j * j;
    for (std::uint64_t v : {square - 1, square, square + 1}) {
      if (v < (std::uint64_t{1} << 30) || v >= (std::uint64_t{1} << 32)) continue;
      ASSERT_EQ(unit.closed_form(v), unit(v)) << v;
    }
  }
}

// ... and on random inputs of every width for every iteration count (normalising shifts and truncation).
TEST(SqrtUnit, ClosedFormIsTheRecurrenceOnRandomInputs) {
  std::mt19937_64 rng(17);
  for (int n = 1; n <= kMaxSqrtIterations; ++n) {
    const SqrtUnit unit(n);
    for (int i = 0; i < 20000; ++i) {
      const int bits = 1 + static_cast<int>(rng() % 126);
      const UInt128 v = (UInt128{rng()} << 64 | rng()) >> (128 - bits);
      ASSERT_EQ(unit.closed_form(v), unit(v)) << "n=" << n << " bits=" << bits;
    }
    EXPECT_EQ(unit.closed_form(0), 0);
    EXPECT_EQ(unit.closed_form((UInt128{1} << 126) - 1), unit((UInt128{1} << 126) - 1));
  }
}

TEST(SqrtUnit, RejectsImpossibleIterationCounts) {
  EXPECT_THROW(SqrtUnit(0), std::invalid_argument);
  EXPECT_THROW(SqrtUnit(kMaxSqrtIterations + 1), std::invalid_argument);
}

}  // namespace
}  // namespace tripsitter::device

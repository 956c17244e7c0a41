#include <tripsitter/core/isqrt.h>

#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace tripsitter::core {
namespace {

// r is floor(sqrt(v)): r^2 <= v < (r + 1)^2, computed in 128 bits so that nothing wraps.
::testing::AssertionResult is_floor_sqrt(UInt128 v, std::uint64_t r) {
  const UInt128 r2 = UInt128{r} * r;
  const UInt128 next = (UInt128{r} + 1) * (UInt128{r} + 1);  // at most 2^128 - 2^65 + 1: no wrap
  if (r2 <= v && v < next) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "isqrt(" << static_cast<std::uint64_t>(v >> 64) << " * 2^64 + "
                                       << static_cast<std::uint64_t>(v) << ") gave " << r;
}

TEST(IntegerSqrt, IsTheFloorOfTheSquareRoot) {
  for (std::uint64_t v = 0; v < 100000; ++v) {
    const std::uint64_t r = isqrt(v);
    ASSERT_LE(r * r, v);
    ASSERT_GT((r + 1) * (r + 1), v);
  }
  const UInt128 big = (UInt128{1} << 100) - 1;
  const UInt128 r = isqrt(big);
  EXPECT_LE(r * r, big);
  EXPECT_GT((r + 1) * (r + 1), big);
}

TEST(IntegerSqrt, EveryInputBelowTwoToTheTwentyFour) {
  std::uint64_t r = 0;  // floor(sqrt(v)), stepped along
  for (std::uint64_t v = 0; v < (std::uint64_t{1} << 24); ++v) {
    if ((r + 1) * (r + 1) == v) ++r;
    ASSERT_EQ(isqrt(v), r) << v;
    ASSERT_EQ(isqrt(UInt128{v}), r) << v;
    ASSERT_EQ(ceil_isqrt(v), r * r == v ? r : r + 1) << v;
  }
}

TEST(IntegerSqrt, PerfectSquaresAndTheirNeighbours) {
  std::mt19937_64 rng(11);
  std::vector<std::uint64_t> roots{1, 2, 3, 0xFFFF, 0x10000, 0xFFFF'FFFF, 0x1'0000'0000, 0xFFFF'FFFF'FFFF'FFFF};
  for (int i = 0; i < 20000; ++i) roots.push_back(rng() >> (rng() % 64));
  for (const std::uint64_t s : roots) {
    if (s == 0) continue;
    const UInt128 sq = UInt128{s} * s;
    EXPECT_EQ(isqrt(sq), s);
    EXPECT_EQ(isqrt(sq - 1), s - 1);
    EXPECT_EQ(isqrt(sq + 1), s);
    if (s <= 0xFFFF'FFFF) {
      const std::uint64_t sq64 = s * s;
      EXPECT_EQ(isqrt(sq64), s);
      EXPECT_EQ(isqrt(sq64 - 1), s - 1);
      EXPECT_EQ(ceil_isqrt(sq64), s);
      EXPECT_EQ(ceil_isqrt(sq64 - 1), s == 1 ? 0 : s);  // ceil(sqrt(0)) = 0
      if (s != 0xFFFF'FFFF) {
        EXPECT_EQ(isqrt(sq64 + 1), s);
        EXPECT_EQ(ceil_isqrt(sq64 + 1), s + 1);
      }
    }
  }
  // The ends of both ranges.
  EXPECT_EQ(isqrt(~std::uint64_t{0}), 0xFFFF'FFFFu);
  EXPECT_EQ(ceil_isqrt(~std::uint64_t{0}), std::uint64_t{1} << 32);
  EXPECT_EQ(isqrt(~UInt128{0}), ~std::uint64_t{0});
  EXPECT_EQ(isqrt(UInt128{1} << 64), std::uint64_t{1} << 32);
}

TEST(IntegerSqrt, RandomInputsOfEveryLength) {
  std::mt19937_64 rng(5);
  for (int bits = 1; bits <= 128; ++bits) {
    for (int i = 0; i < 2000; ++i) {
      UInt128 v = (UInt128{rng()} << 64) | rng();
      if (bits < 128) v &= (UInt128{1} << bits) - 1;
      ASSERT_TRUE(is_floor_sqrt(v, isqrt(v)));
      if (bits <= 64) {
        const auto v64 = static_cast<std::uint64_t>(v);
        const std::uint64_t r = isqrt(v64);
        ASSERT_TRUE(is_floor_sqrt(v64, r));
        const std::uint64_t c = ceil_isqrt(v64);
        ASSERT_EQ(c, UInt128{r} * r == v64 ? r : r + 1) << v64;
      }
    }
  }
}

}  // namespace
}  // namespace tripsitter::core

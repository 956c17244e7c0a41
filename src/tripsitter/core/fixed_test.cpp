#include <tripsitter/core/fixed.h>

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace tripsitter::core {
namespace {

TEST(FixedFormat, RangeAndStepOfTheBoardFormats) {
  const FixedFormat x{16, 3, true};
  EXPECT_EQ(x.max_raw(), 32767);
  EXPECT_EQ(x.min_raw(), -32768);
  EXPECT_DOUBLE_EQ(x.step(), 0.125);
  EXPECT_DOUBLE_EQ(x.max_value(), 4095.875);
  EXPECT_DOUBLE_EQ(x.min_value(), -4096.0);
  const FixedFormat r{12, 3, false};
  EXPECT_EQ(r.min_raw(), 0);
  EXPECT_EQ(r.max_raw(), 4095);
  EXPECT_EQ(x.name(), "s16.3");
  EXPECT_EQ(r.name(), "u12.3");
}

TEST(FixedFormat, RoundsToNearestWithTiesAwayFromZero) {
  const FixedFormat f{16, 3, true};
  EXPECT_EQ(f.quantize(0.0625).raw, 1);    // exactly half a step
  EXPECT_EQ(f.quantize(-0.0625).raw, -1);
  EXPECT_EQ(f.quantize(0.0624).raw, 0);
  EXPECT_EQ(f.quantize(100.0).raw, 800);
  EXPECT_FALSE(f.quantize(100.0).saturated);
}

TEST(FixedFormat, SaturatesAndSaysSo) {
  const FixedFormat f{15, 3, true};
  EXPECT_EQ(f.quantize(1e9).raw, f.max_raw());
  EXPECT_TRUE(f.quantize(1e9).saturated);
  EXPECT_EQ(f.quantize(-1e9).raw, f.min_raw());
  EXPECT_TRUE(f.quantize(-1e9).saturated);
  EXPECT_TRUE(f.quantize(std::nan("")).saturated);
  EXPECT_EQ(f.quantize(std::nan("")).raw, 0);
  EXPECT_TRUE(f.quantize(INFINITY).saturated);
  // The largest representable value itself does not saturate.
  EXPECT_FALSE(f.quantize(f.max_value()).saturated);
  EXPECT_EQ(FixedFormat(12, 3, false).quantize(-1.0).raw, 0);
}

// Seeded property test against double: inside the range the error is at most half a step.
TEST(FixedFormat, QuantizeIsWithinHalfAStepOfDouble) {
  std::mt19937_64 rng(42);
  for (const FixedFormat f : {FixedFormat{16, 3, true}, FixedFormat{24, 4, true}, FixedFormat{32, 16, true},
                              FixedFormat{12, 3, false}}) {
    std::uniform_real_distribution<double> dist(f.min_value(), f.max_value());
    for (int i = 0; i < 100000; ++i) {
      const double v = dist(rng);
      const Quantized q = f.quantize(v);
      ASSERT_FALSE(q.saturated) << f.name() << " " << v;
      ASSERT_TRUE(f.contains(q.raw));
      ASSERT_LE(std::abs(f.to_double(q.raw) - v), f.step() / 2) << f.name() << " " << v;
    }
  }
}

TEST(RescaleRaw, WidensExactlyAndNarrowsWithRounding) {
  EXPECT_EQ(rescale_raw(800, 3, 4), 1600);
  EXPECT_EQ(rescale_raw(-800, 3, 8), -25600);
  EXPECT_EQ(rescale_raw(3, 2, 1), 2);    // 0.75 -> 1.0 (1.5 rounds away from zero)
  EXPECT_EQ(rescale_raw(-3, 2, 1), -2);
  EXPECT_EQ(rescale_raw(5, 2, 0), 1);    // 1.25 -> 1
  EXPECT_EQ(rescale_raw(7, 3, 3), 7);
}

}  // namespace
}  // namespace tripsitter::core

// simd::F8's lane-wise operations that are not arithmetic (|a|, the float with given bits) and its data movement
// (3-vectors to planes and back, the tails of rows), each against the lane-by-lane meaning. Built twice
// (render/CMakeLists.txt): for baseline x86-64, where F8 is two SSE registers, and, where the render library is
// built for x86-64-v3, for that too, where F8 is one AVX register.
#include <tripsitter/render/simd8.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

namespace tripsitter::render {
namespace {

using simd::F8;
constexpr int kN = F8::kLanes;

std::vector<float> lanes(F8 a) {
  std::vector<float> out(kN);
  a.storeu(out.data());
  return out;
}

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

TEST(Simd8, AbsClearsOnlyTheSignBit) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const float in[kN] = {-0.0f, 0.0f, -3.5f, 2.25f, -inf, inf, -nan, -1e-40f};
  const std::vector<float> out = lanes(abs(F8::loadu(in)));
  for (int i = 0; i < kN; ++i) EXPECT_EQ(bits(out[i]), bits(std::fabs(in[i]))) << "lane " << i;
}

TEST(Simd8, FloatWithBitsIsTheTruncatedWholePart) {
  const float in[kN] = {0.0f, 0.99f, 1.0f, 1.5f, 8388608.5f, 503316480.0f, 1065353216.0f, 2147483520.0f};
  const std::vector<float> out = lanes(float_with_bits(F8::loadu(in)));
  for (int i = 0; i < kN; ++i)
    EXPECT_EQ(bits(out[i]), static_cast<std::uint32_t>(std::trunc(in[i]))) << "lane " << i;
  EXPECT_EQ(out[6], 1.0f);  // 0x3f800000
}

TEST(Simd8, Load3SplitsTriplesIntoPlanesAndStore3JoinsThem) {
  float xyz[3 * kN];
  for (int i = 0; i < 3 * kN; ++i) xyz[i] = static_cast<float>(100 + i);
  F8 x, y, z;
  F8::load3(xyz, x, y, z);
  const std::vector<float> xs = lanes(x), ys = lanes(y), zs = lanes(z);
  for (int i = 0; i < kN; ++i) {
    EXPECT_EQ(xs[i], xyz[3 * i]) << "lane " << i;
    EXPECT_EQ(ys[i], xyz[3 * i + 1]) << "lane " << i;
    EXPECT_EQ(zs[i], xyz[3 * i + 2]) << "lane " << i;
  }
  float back[3 * kN + 1];
  back[3 * kN] = -1.0f;
  F8::store3(back, x, y, z);
  for (int i = 0; i < 3 * kN; ++i) EXPECT_EQ(back[i], xyz[i]) << "float " << i;
  EXPECT_EQ(back[3 * kN], -1.0f);
}

// A row of `count` floats followed by sentinels, so that a write past it shows.
constexpr float kSentinel = -7.0f;

TEST(Simd8, TailsReadAndWriteOnlyTheirCount) {
  for (int count = 1; count <= kN + 1; ++count) {
    const int used = std::min(count, kN);
    std::vector<float> row(static_cast<std::size_t>(used) + kN, kSentinel);
    for (int i = 0; i < used; ++i) row[static_cast<std::size_t>(i)] = static_cast<float>(i + 1);
    const std::vector<float> loaded = lanes(F8::load_first(row.data(), count));
    for (int i = 0; i < kN; ++i) EXPECT_EQ(loaded[i], i < used ? static_cast<float>(i + 1) : 0.0f) << count;

    std::vector<float> out(row.size(), kSentinel);
    F8::set1(5.0f).store_first(out.data(), count);
    for (std::size_t i = 0; i < out.size(); ++i)
      EXPECT_EQ(out[i], i < static_cast<std::size_t>(used) ? 5.0f : kSentinel) << count;
  }
}

TEST(Simd8, TripleTailsReadAndWriteOnlyTheirCount) {
  for (int count = 1; count <= kN + 1; ++count) {
    const std::size_t used = static_cast<std::size_t>(std::min(count, kN));
    std::vector<float> row(3 * used + 3 * kN, kSentinel);
    for (std::size_t i = 0; i < 3 * used; ++i) row[i] = static_cast<float>(i + 1);
    F8 x, y, z;
    F8::load3_first(row.data(), count, x, y, z);
    const std::vector<float> xs = lanes(x), ys = lanes(y), zs = lanes(z);
    for (std::size_t i = 0; i < kN; ++i) {
      const bool in = i < used;
      EXPECT_EQ(xs[i], in ? row[3 * i] : 0.0f) << count;
      EXPECT_EQ(ys[i], in ? row[3 * i + 1] : 0.0f) << count;
      EXPECT_EQ(zs[i], in ? row[3 * i + 2] : 0.0f) << count;
    }

    std::vector<float> out(row.size(), kSentinel);
    F8::store3_first(out.data(), count, x, y, z);
    for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i], i < 3 * used ? row[i] : kSentinel) << count;
  }
}

}  // namespace
}  // namespace tripsitter::render

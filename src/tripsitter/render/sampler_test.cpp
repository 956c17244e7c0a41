// The low-discrepancy sampler: Sobol's points, the scrambles' properties, stratification of every pair's points,
// independence between pairs and pixels, and the maps from the square to sphere, disk and cosine-weighted bounces.
#include <tripsitter/render/sampler.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/render/material.h>
#include <tripsitter/render/test_util.h>

namespace tripsitter::render {
namespace {

using sobol::reverse_bits;

// Sobol's dimension 1 the textbook way: direction numbers v_k = m_k / 2^k with m_k = (2 m_{k-1}) xor m_{k-1} (the
// recurrence of the polynomial x + 1), m_1 = 1, xored for the set bits of the index. As 32-bit fractions
// v_1 = 2^31, and each next one is v xor (v >> 1).
std::uint32_t sobol1_by_direction_numbers(std::uint32_t index) {
  std::uint32_t result = 0;
  for (std::uint32_t v = 1u << 31; index != 0; index >>= 1, v ^= v >> 1)
    if (index & 1) result ^= v;
  return result;
}

TEST(Sobol, ReverseBits) {
  EXPECT_EQ(reverse_bits(1), 1u << 31);
  EXPECT_EQ(reverse_bits(0x80000000u), 1u);
  EXPECT_EQ(reverse_bits(0x12345678u), 0x1E6A2C48u);
  for (std::uint32_t i = 0, x = 1; i < 1000; ++i, x = x * 2654435769u + 1) ASSERT_EQ(reverse_bits(reverse_bits(x)), x);
}

TEST(Sobol, DimensionOneMatchesItsDirectionNumbers) {
  for (std::uint32_t i = 0; i < 70000; ++i)
    ASSERT_EQ(reverse_bits(sobol::sobol1_reversed(i)), sobol1_by_direction_numbers(i)) << i;
  for (std::uint32_t k = 0, i = 1; k < 10000; ++k, i = i * 2654435769u + 12345)
    ASSERT_EQ(reverse_bits(sobol::sobol1_reversed(i)), sobol1_by_direction_numbers(i)) << i;
}

// Owen's scramble on reversed digits: the low k bits of the output depend only on the low k bits of the input, and
// for each k the map of the low k bits is a permutation (a bit flips or not as a function of the bits below it).
TEST(Sobol, NestedScrambleIsNestedAndBijective) {
  for (const std::uint32_t seed : {0u, 1u, 0xdeadbeefu, 0x12345678u, 0xffffffffu}) {
    for (const int k : {1, 5, 12, 16}) {
      const std::uint32_t mask = (1u << k) - 1;
      std::vector<bool> seen(std::size_t{1} << k);
      for (std::uint32_t x = 0; x <= mask; ++x) {
        const std::uint32_t y = sobol::nested_scramble_reversed(x, seed) & mask;
        ASSERT_FALSE(seen[y]) << seed << " " << k;
        seen[y] = true;
        // Changing bits at k and above leaves the low k bits of the output alone.
        ASSERT_EQ(sobol::nested_scramble_reversed(x | 0xabcd1234u << k, seed) & mask, y);
      }
    }
  }
}

// Every pair's first 2^m points (and any aligned block of 2^m) have one point in each elementary box
// [i 2^-a, (i + 1) 2^-a) x [j 2^-b, (j + 1) 2^-b) with a + b = m: a (0, m, 2)-net, as Sobol's dimensions 0 and 1
// are unscrambled, so the index shuffle and the scrambles keep it.
TEST(SobolSampler, EveryPairsPointsAreStratified) {
  const SobolSampler sampler(7);
  for (const std::uint64_t pixel : {0ull, 1ull, 12345ull}) {
    const std::uint32_t key = sampler.pixel_key(pixel);
    for (int pair = 0; pair < 2 + kSobolBounces; ++pair) {
      for (const int m : {0, 1, 2, 4, 7, 10}) {
        for (const std::uint32_t start : {0u, 1u << m, 5u << m}) {
          const std::uint32_t n = 1u << m;
          for (int a = 0; a <= m; ++a) {
            const int b = m - a;
            std::vector<int> count(n, 0);
            for (std::uint32_t i = start; i < start + n; ++i) {
              const SquareSample p = SobolSampler::sample(key, i, pair);
              const auto col = static_cast<std::uint32_t>(std::ldexp(p.u, a));
              const auto row = static_cast<std::uint32_t>(std::ldexp(p.v, b));
              ++count[(row << a) | col];
            }
            ASSERT_TRUE(std::all_of(count.begin(), count.end(), [](int c) { return c == 1; }))
                << "pixel " << pixel << " pair " << pair << " points " << start << "+" << n << " box 2^-" << a
                << " x 2^-" << b;
          }
        }
      }
    }
  }
}

TEST(SobolSampler, ValuesAreInTheUnitSquareOnTheGrid) {
  const SobolSampler sampler(1);
  for (std::uint64_t pixel = 0; pixel < 64; ++pixel) {
    for (std::uint32_t i = 0; i < 256; ++i) {
      const SquareSample p = SobolSampler::sample(sampler.pixel_key(pixel), i, static_cast<int>(i % 4));
      for (const float x : {p.u, p.v}) {
        ASSERT_GE(x, 0.0f);
        ASSERT_LT(x, 1.0f);
        ASSERT_EQ(x, std::ldexp(std::floor(std::ldexp(x, 24)), -24));
      }
      ASSERT_EQ(p.turn.cos, cos_sin_turns(p.v).cos);
      ASSERT_EQ(p.turn.sin, cos_sin_turns(p.v).sin);
    }
  }
}

TEST(SobolSampler, IsDeterministicAndEightAtATimeGivesTheSameValues) {
  const SobolSampler a(99), b(99), c(100);
  EXPECT_EQ(a.pixel_key(5), b.pixel_key(5));
  EXPECT_NE(a.pixel_key(5), c.pixel_key(5));
  EXPECT_NE(a.pixel_key(5), a.pixel_key(6));
  EXPECT_EQ(a.stream(5, 3).next_u64(), b.stream(5, 3).next_u64());
  EXPECT_NE(a.stream(5, 3).next_u64(), a.stream(5, 4).next_u64());
  EXPECT_NE(a.stream(5, 3).next_u64(), a.stream(6, 3).next_u64());
  std::uint32_t keys[8];
  for (int i = 0; i < 8; ++i) keys[i] = a.pixel_key(static_cast<std::uint64_t>(100 + i));
  for (const std::uint32_t index : {0u, 1u, 17u, 0xffffffffu}) {
    for (int pair = 0; pair < 4; ++pair) {
      sobol::Samples8 eight;
      sobol::samples8(keys, index, pair, eight);
      for (int i = 0; i < 8; ++i) {
        const SquareSample one = SobolSampler::sample(keys[i], index, pair);
        EXPECT_EQ(eight[i].u, one.u);
        EXPECT_EQ(eight[i].v, one.v);
        EXPECT_EQ(eight[i].turn.cos, one.turn.cos);
        EXPECT_EQ(eight[i].turn.sin, one.turn.sin);
      }
    }
  }
}

// Pearson's correlation of paired values.
double correlation(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    syy += y[i] * y[i];
    sxy += x[i] * y[i];
  }
  return (sxy / n - sx / n * sy / n) / std::sqrt((sxx / n - sx / n * sx / n) * (syy / n - sy / n * sy / n));
}

// Chi-square of points in [0, 1)^2 against the uniform distribution on bins x bins cells, and its mean plus six
// standard deviations: independent uniform points stay below with probability above 1 - 1e-6.
struct Chi2 {
  double statistic, bound;
};
Chi2 joint_chi_square(const std::vector<double>& x, const std::vector<double>& y, int bins) {
  std::vector<double> count(static_cast<std::size_t>(bins * bins), 0);
  for (std::size_t i = 0; i < x.size(); ++i)
    ++count[static_cast<std::size_t>(static_cast<int>(y[i] * bins) * bins + static_cast<int>(x[i] * bins))];
  const double expected = static_cast<double>(x.size()) / (bins * bins);
  double chi2 = 0;
  for (const double c : count) chi2 += (c - expected) * (c - expected) / expected;
  const double dof = bins * bins - 1;
  return {chi2, dof + 6 * std::sqrt(2 * dof)};
}

// Different pairs of one sample, and one pair of neighbouring pixels, are independent: over 4096 pixels of 16
// samples each their values are uncorrelated and jointly uniform, and within a pixel the first digits of one pair's
// points are no guide to the other's. That last statistic: s = the sum over a pixel's 16 samples of (+-1 for the
// first binary digit of a coordinate of a) (+-1 for that of b). Samples 2j and 2j + 1 differ in that digit in
// every coordinate (the index shuffle, a nested scramble, keeps them neighbours, and the digit is their last bit
// scrambled by a constant), so s is twice a sum of eight signs, one per j, and E s^2 = 32 where those are
// independent, as they are between pixels. Without the index shuffle, the first coordinates of two pairs are Owen
// scrambles of one van der Corput point: the sign is the same for all samples, s^2 = 256.
TEST(SobolSampler, PairsAndPixelsAreIndependent) {
  const SobolSampler sampler(3);
  struct Case {
    int pair_a, pair_b;
    std::uint64_t pixel_offset;
  };
  constexpr int kPixels = 4096, kPerPixel = 16;
  for (const Case c : {Case{0, 1, 0}, Case{1, 2, 0}, Case{2, 3, 0}, Case{0, 3, 0}, Case{0, 0, 1}, Case{2, 2, 1},
                       Case{2, 2, 640}}) {
    std::vector<double> au, av, bu, bv;
    double s2[3] = {};  // coordinates u-u, u-v, v-v
    for (std::uint64_t pixel = 0; pixel < kPixels; ++pixel) {
      const std::uint32_t key_a = sampler.pixel_key(pixel), key_b = sampler.pixel_key(pixel + c.pixel_offset);
      double s[3] = {};
      for (std::uint32_t i = 0; i < kPerPixel; ++i) {
        const SquareSample a = SobolSampler::sample(key_a, i, c.pair_a), b = SobolSampler::sample(key_b, i, c.pair_b);
        au.push_back(a.u);
        av.push_back(a.v);
        bu.push_back(b.u);
        bv.push_back(b.v);
        const auto sign = [](float x) { return x < 0.5f ? -1.0 : 1.0; };
        s[0] += sign(a.u) * sign(b.u);
        s[1] += sign(a.u) * sign(b.v);
        s[2] += sign(a.v) * sign(b.v);
      }
      for (int k = 0; k < 3; ++k) s2[k] += s[k] * s[k] / kPixels;
    }
    const std::string what = std::to_string(c.pair_a).append(" ").append(std::to_string(c.pair_b)).append(" ").append(
        std::to_string(c.pixel_offset));
    // Standard deviation of a correlation of 65,536 independent pairs: 0.0039.
    EXPECT_NEAR(correlation(au, bu), 0.0, 0.025) << what;
    EXPECT_NEAR(correlation(au, bv), 0.0, 0.025) << what;
    EXPECT_NEAR(correlation(av, bv), 0.0, 0.025) << what;
    for (const auto& [x, y] : {std::pair{&au, &bu}, std::pair{&au, &bv}, std::pair{&av, &bv}}) {
      const Chi2 chi2 = joint_chi_square(*x, *y, 16);
      EXPECT_LT(chi2.statistic, chi2.bound) << what;
    }
    // The mean of 4096 values of s^2, each of standard deviation about 45: 32 within 0.7 (measured: 31.4 to 33.5).
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(s2[k], 32.0, 5.0) << what << " coordinates " << k;
  }
}

TEST(CosSinTurns, MatchesTheLibraryWithinTwoTenMillionths) {
  double worst = 0;
  for (std::uint32_t i = 0; i < (1u << 24); i += 7) {
    const float t = static_cast<float>(i) * 0x1.0p-24f;
    const CosSin cs = cos_sin_turns(t);
    const double angle = 2 * std::numbers::pi * t;
    worst = std::max({worst, std::fabs(cs.cos - std::cos(angle)), std::fabs(cs.sin - std::sin(angle))});
  }
  EXPECT_LT(worst, 2e-7);
  for (const float t : {0.0f, 0.25f, 0.5f, 0.75f}) {
    const CosSin cs = cos_sin_turns(t);
    EXPECT_EQ(std::fabs(cs.cos) + std::fabs(cs.sin), 1.0f) << t;  // exact at the quarter turns
  }
}

using testing::below_one;
using testing::Histogram;
using testing::kSamples;
using testing::turn;

// The maps of the square, fed independent uniform points: unit_vector uniform on the sphere (z and the angle
// uniform, moments of the uniform measure), in_unit_disk uniform in the disk (r^2 and the angle uniform).
TEST(SquareSample, MapsTheSquareUniformlyOntoSphereAndDisk) {
  Rng rng(21);
  Histogram z(20), angle(20), x_axis(20), r2(20), disk_angle(20);
  double m2[3] = {0, 0, 0}, xy = 0;
  for (int i = 0; i < kSamples; ++i) {
    const SquareSample p = SquareSample::at(rng.uniform(), rng.uniform());
    const Vec3f v = p.unit_vector();
    ASSERT_NEAR(core::dot(v, v), 1.0f, 1e-6f);
    z.add(below_one(0.5 * (v.z + 1.0)));
    angle.add(turn(v.x, v.y));
    x_axis.add(below_one(0.5 * (v.x + 1.0)));
    for (int a = 0; a < 3; ++a) m2[a] += v[a] * v[a];
    xy += v.x * v.y;
    const Vec3f d = p.in_unit_disk();
    const double d2 = static_cast<double>(d.x) * d.x + static_cast<double>(d.y) * d.y;
    ASSERT_LT(d2, 1.0 + 1e-6);
    ASSERT_EQ(d.z, 0.0f);
    r2.add(below_one(d2));
    disk_angle.add(turn(d.x, d.y));
  }
  EXPECT_LT(z.chi_square(), z.bound());
  EXPECT_LT(angle.chi_square(), angle.bound());
  EXPECT_LT(x_axis.chi_square(), x_axis.bound());
  EXPECT_LT(r2.chi_square(), r2.bound());
  EXPECT_LT(disk_angle.chi_square(), disk_angle.bound());
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(m2[a] / kSamples, 1.0 / 3.0, 0.004) << a;
  EXPECT_NEAR(xy / kSamples, 0.0, 0.004);
}

// A lambertian bounce from Sobol points (the bounce pair of one pixel's samples) is cosine-weighted: cos^2(theta)
// and the angle around the normal uniform. So is a fuzzed metal's perturbation uniform on the sphere, and a
// dielectric reflects with Schlick's probability.
TEST(SquareSample, ScatterFromSobolPointsHasTheRightDistributions) {
  const SobolSampler sampler(5);
  const std::uint32_t key = sampler.pixel_key(77);
  const PathMaterial lambertian{scene::MaterialType::kLambertian, {0.5f, 0.5f, 0.5f}, 0, 1.5f};
  const PathMaterial glass{scene::MaterialType::kDielectric, {1, 1, 1}, 0, 1.5f};
  const Vec3f n = Vec3f{1, 2, -2} / 3.0f;
  const Vec3f e1 = core::normalize(core::cross(n, Vec3f{0, 0, 1}));
  const Vec3f e2 = core::cross(n, e1);
  const SurfacePoint s{{0, 0, 0}, n, true};
  Histogram cos2(20), angle(20);
  int reflected = 0;
  const Vec3f in = core::normalize(Vec3f{0.3f, -0.2f, 1.0f} - n * 2.0f);
  for (std::uint32_t i = 0; i < kSamples; ++i) {
    const SquareSample p = SobolSampler::sample(key, i, bounce_pair(1));
    const Scatter sc = scatter(lambertian, {0, 0, 1}, s, p);
    ASSERT_TRUE(sc.scattered);
    const Vec3f d = core::normalize(sc.dir);
    const double c = core::dot(d, n);
    ASSERT_GE(c, -1e-6);
    cos2.add(std::min(c * c, 0.999999));
    angle.add(turn(core::dot(d, e1), core::dot(d, e2)));
    const Vec3f g = scatter(glass, in, s, p).dir;
    reflected += core::dot(g, n) > 0;
  }
  EXPECT_LT(cos2.chi_square(), cos2.bound());
  EXPECT_LT(angle.chi_square(), angle.bound());
  const float cos_theta = -core::dot(in, n);
  const double p_reflect = schlick(cos_theta, 1 / 1.5f);
  // Stratified points: far closer than the binomial standard deviation, sqrt(p (1 - p) / n) = 0.0005.
  EXPECT_NEAR(reflected / static_cast<double>(kSamples), p_reflect, 0.002);
}

}  // namespace
}  // namespace tripsitter::render

// Where the path tracer's random numbers come from (PathSettings::sampler): the independent streams of rng.h, or
// low-discrepancy points, padded 2D Sobol points with hash-based Owen scrambling in the manner of Burley,
// "Practical Hash-based Owen Scrambling" (JCGT 9(4), 2020). docs/path_tracer.md, "Sampler", has the design.
//
// A sample of a pixel takes one point of the unit square per "pair": pair 0 jitters the camera ray within the
// pixel, pair 1 picks its point on the lens, and bounce d (1, 2, ...) takes pair 1 + d while d <= kSobolBounces;
// later bounces draw from an Rng of the sample's own. Each pair is the pixel's own Sobol sequence in dimensions 0
// and 1: its sample index shuffled by a nested-uniform scramble seeded per (pixel, pair), each coordinate
// Owen-scrambled with its own seed. So the first 2^k samples of a pixel put one point of every pair in each
// elementary box of area 2^-k of the square (the (0, 2)-sequence property, which both scrambles keep), while
// different pairs and pixels are independent of each other.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>

#include <tripsitter/core/vec.h>
#include <tripsitter/render/isa.h>
#include <tripsitter/render/rng.h>

namespace tripsitter::render {

enum class SamplerKind {
  kSobol,        // Owen-scrambled Sobol points for the camera ray and the first kSobolBounces bounces
  kIndependent,  // every pixel's own xorshift stream (rng.h) for everything
};

// Bounces that take a Sobol pair; later ones draw from an Rng. On `field`, on `field` made all lambertian and on
// `cluster` made all lambertian, a third or fourth such bounce (or an eighth) lowered the error no more than the
// noise of the measurement, and each costs about one per cent more instructions (docs/path_tracer.md, "Sampler").
inline constexpr int kSobolBounces = 2;
inline constexpr int kPixelPair = 0;  // the jitter of the camera ray within its pixel
inline constexpr int kLensPair = 1;   // the camera ray's start on the lens
inline constexpr int bounce_pair(int depth) { return 1 + depth; }  // REQUIRES 1 <= depth <= kSobolBounces

// cos(2 pi t) and sin(2 pi t) for t in [0, 1) within 2e-7, branch-free (so that eight at a time vectorise):
// t = k / 4 + x with |x| <= 1/8, the Taylor polynomials of cos and sin of 2 pi x (terms to x^8 and x^9: their
// remainders are below 3e-8 there), turned by k quarter turns. x is exact: t is a multiple of 2^-24.
struct CosSin {
  float cos, sin;
};
namespace detail {
// (2 pi)^n / n!, the magnitude of the Taylor coefficient of x^n in cos or sin of 2 pi x.
constexpr float turn_term(int n) {
  double r = 1;
  for (int i = 1; i <= n; ++i) r *= 2 * std::numbers::pi / i;
  return static_cast<float>(r);
}
}  // namespace detail

inline CosSin cos_sin_turns(float t) {
  constexpr float c2 = detail::turn_term(2), c4 = detail::turn_term(4), c6 = detail::turn_term(6),
                  c8 = detail::turn_term(8);
  constexpr float s1 = detail::turn_term(1), s3 = detail::turn_term(3), s5 = detail::turn_term(5),
                  s7 = detail::turn_term(7), s9 = detail::turn_term(9);
  const int k = static_cast<int>(4 * t + 0.5f);
  const float x = t - 0.25f * static_cast<float>(k);
  const float x2 = x * x;
  const float c = 1 - x2 * (c2 - x2 * (c4 - x2 * (c6 - x2 * c8)));
  const float s = x * (s1 - x2 * (s3 - x2 * (s5 - x2 * (s7 - x2 * s9))));
  // A quarter turn takes (c, s) to (-s, c).
  const float a = k & 1 ? s : c;
  const float b = k & 1 ? c : s;
  return {(k + 1) & 2 ? -a : a, k & 2 ? -b : b};
}

// One point (u, v) of the unit square, both in [0, 1) on the grid 2^-24: the random numbers of one camera jitter,
// one lens point or one bounce under kSobol. It offers what the camera and scatter() draw from an Rng, each a
// function of the one point: a caller takes one of them, once.
struct SquareSample {
  float u = 0;
  float v = 0;
  CosSin turn{1, 0};  // cos_sin_turns(v), computed with the point (SquareSample::at)

  static SquareSample at(float u, float v) { return {u, v, cos_sin_turns(v)}; }

  float uniform() const { return u; }
  // (u, v) mapped to [-h, h)^2, as Rng::symmetric_pair (h a power of two: exact).
  Rng::Pair symmetric_pair(float h) const { return {(2 * u - 1) * h, (2 * v - 1) * h}; }
  // Uniform on the unit sphere: z = 1 - 2u uniform in (-1, 1] (Archimedes), the angle around z 2 pi v. Continuous
  // in (u, v), and area-preserving, so well-spread points of the square give well-spread directions.
  core::Vec3f unit_vector() const {
    const float r = 2 * std::sqrt(u * (1 - u));  // sqrt(1 - z^2), without its cancellation near the poles
    return {r * turn.cos, r * turn.sin, 1 - 2 * u};
  }
  // Uniform in the unit disk (z = 0): radius sqrt(u), angle 2 pi v.
  core::Vec3f in_unit_disk() const {
    const float r = std::sqrt(u);
    return {r * turn.cos, r * turn.sin, 0};
  }
};

namespace sobol {

// The bits of x in reverse order: bit i goes to bit 31 - i.
constexpr std::uint32_t reverse_bits(std::uint32_t x) {
  x = __builtin_bswap32(x);  // the bytes (one shuffle when vectorised), then the bits within each
  x = ((x & 0x0F0F0F0Fu) << 4) | ((x >> 4) & 0x0F0F0F0Fu);
  x = ((x & 0x33333333u) << 2) | ((x >> 2) & 0x33333333u);
  return ((x & 0x55555555u) << 1) | ((x >> 1) & 0x55555555u);
}

// Values in [0, 1) are 32-bit fractions, digit k (weight 2^-(k + 1)) in bit 31 - k; "reversed", digit k in bit k.
//
// Sobol's dimension 0 of sample index i is the van der Corput sequence, digit k = bit k of i: reversed, that is i
// itself. Dimension 1 (primitive polynomial x + 1) has the generator matrix of Pascal's triangle mod 2: digit k is
// the parity of the bits j of i with binom(j, k) odd, which by Lucas's theorem are the j whose binary digits
// include k's (k & j == k). The sum over those supersets takes five shift-and-xor steps, one per bit of k.
constexpr std::uint32_t sobol1_reversed(std::uint32_t index) {
  std::uint32_t w = index;
  w ^= (w >> 1) & 0x55555555u;
  w ^= (w >> 2) & 0x33333333u;
  w ^= (w >> 4) & 0x0F0F0F0Fu;
  w ^= (w >> 8) & 0x00FF00FFu;
  w ^= (w >> 16) & 0x0000FFFFu;
  return w;
}

// A random nested-uniform (Owen) scramble of reversed digits, chosen by `seed`: every step changes bit k only as a
// function of bits 0 to k - 1 (and the seed) — adding, multiplying by an odd number, and xoring with a multiple by
// an even number carry information only upward — so digit k flips or not according to the digits before it, which
// is Owen's scramble. Its randomness is a hash's: scrambled nets integrated with it gave the errors of a scramble
// drawn bit by bit (a 64-bit hash per tree node) within a few per cent, from 16 to 1024 points, on a smooth and on
// a discontinuous integrand. Constants drawn at random (even ones for the xor steps).
constexpr std::uint32_t nested_scramble_reversed(std::uint32_t x, std::uint32_t seed) {
  x += seed;
  x ^= x * 0x9b9b1324u;
  x *= (seed >> 16) | 1u;
  x ^= x * 0xc55a45f8u;
  x ^= x * 0x4243ed52u;
  return x;
}

// A 32-bit hash with full avalanche (xorshift-multiply rounds), for seeds.
constexpr std::uint32_t hash32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0xd1a6e55fu;
  x ^= x >> 15;
  x *= 0x566bf9d7u;
  x ^= x >> 16;
  return x;
}

// Pair `pair` of sample `index` of the pixel with key `pixel_key`, as two 32-bit fractions.
struct Bits {
  std::uint32_t x, y;
};
constexpr Bits pair_bits(std::uint32_t pixel_key, std::uint32_t index, int pair) {
  // Three seeds per (pixel, pair), each a hash of the one before. (Hashes of the key with three constants, which run
  // side by side, took 2% more instructions and were no faster.)
  const std::uint32_t shuffle_seed = hash32(pixel_key ^ (static_cast<std::uint32_t>(pair) * 0xcf0c26efu));
  const std::uint32_t x_seed = hash32(shuffle_seed ^ 0x5d96cf7fu);
  const std::uint32_t y_seed = hash32(x_seed ^ 0xc1d77cffu);
  // The index shuffled by a nested scramble with the most significant bit as the root: the first 2^k indices go to
  // an aligned block of 2^k, whose Sobol points are a (0, k, 2)-net like the first 2^k.
  const std::uint32_t shuffled = reverse_bits(nested_scramble_reversed(reverse_bits(index), shuffle_seed));
  return {reverse_bits(nested_scramble_reversed(shuffled, x_seed)),
          reverse_bits(nested_scramble_reversed(sobol1_reversed(shuffled), y_seed))};
}

constexpr float to_unit(std::uint32_t bits) { return static_cast<float>(bits >> 8) * 0x1.0p-24f; }

}  // namespace sobol

// The Sobol samples of one job (PathSettings::seed): each pixel has a key, hashed from the seed and the pixel's
// index, that chooses its scrambles, and each sample of a pixel an Rng stream for the bounces past kSobolBounces.
class SobolSampler {
 public:
  explicit SobolSampler(std::uint64_t seed)
      : key_hash_(mix64(seed ^ 0x6a09e667f3bcc908ull)), stream_hash_(mix64(seed ^ 0xbb67ae8584caa73bull)) {}

  std::uint32_t pixel_key(std::uint64_t pixel) const {
    return static_cast<std::uint32_t>(mix64(key_hash_ ^ pixel) >> 32);
  }
  // The stream of the bounces past kSobolBounces of sample `index` of the pixel: one per sample, so that a sample
  // is the same whether it is taken in a render of many or in a pass of one (PathSettings::first_sample).
  Rng stream(std::uint64_t pixel, std::uint32_t index) const { return RngStreams(stream_hash_ ^ index).stream(pixel); }

  // Pair `pair` of sample `index` of the pixel with key `pixel_key`.
  static SquareSample sample(std::uint32_t pixel_key, std::uint32_t index, int pair) {
    const sobol::Bits b = sobol::pair_bits(pixel_key, index, pair);
    return SquareSample::at(sobol::to_unit(b.x), sobol::to_unit(b.y));
  }

 private:
  std::uint64_t key_hash_;
  std::uint64_t stream_hash_;
};

// SobolSampler::sample for a group of eight pixels, with one sample index and pair: one loop of integer arithmetic
// that the compiler turns into SIMD code (hence the instruction-set namespace, isa.h). The same values as sample().
namespace sobol {
inline namespace TRIPSITTER_RENDER_ISA {

struct Samples8 {
  float u[8], v[8], cos[8], sin[8];
  SquareSample operator[](int lane) const { return {u[lane], v[lane], {cos[lane], sin[lane]}}; }
};

inline void samples8(const std::uint32_t (&pixel_keys)[8], std::uint32_t index, int pair, Samples8& out) {
  for (int i = 0; i < 8; ++i) {
    const Bits b = pair_bits(pixel_keys[i], index, pair);
    out.u[i] = to_unit(b.x);
    out.v[i] = to_unit(b.y);
    const CosSin t = cos_sin_turns(out.v[i]);
    out.cos[i] = t.cos;
    out.sin[i] = t.sin;
  }
}

}  // namespace TRIPSITTER_RENDER_ISA
}  // namespace sobol

}  // namespace tripsitter::render

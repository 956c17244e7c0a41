// Random numbers of the path tracer: xorshift, as the report's section 7 suggests, seeded per pixel by a
// hash of (seed, pixel), so an image does not depend on how pixels are shared among threads.
#pragma once

#include <cmath>
#include <cstdint>

#include <tripsitter/core/vec.h>

namespace tripsitter::render {

// SplitMix64 finaliser: a bijective mix of 64 bits, used to derive independent seeds.
constexpr std::uint64_t mix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Marsaglia's xorshift64* (a 64-bit xorshift with a multiplied output); period 2^64 - 1.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(mix64(seed) | 1u) {}
  // An independent stream for one item (pixel) of a job with this seed (RngStreams hashes the seed once for many).
  static Rng for_item(std::uint64_t seed, std::uint64_t item);

  std::uint64_t next_u64() {
    state_ ^= state_ >> 12;
    state_ ^= state_ << 25;
    state_ ^= state_ >> 27;
    return state_ * 0x2545F4914F6CDD1Dull;
  }
  // Uniform in [0, 1).
  float uniform() { return static_cast<float>(next_u64() >> 40) * 0x1.0p-24f; }

  // Two independent values uniform in [-h, h) from one draw, h a power of two (the default 1 gives the values of
  // 2 uniform() - 1, multiples of 2^-23). Half the draws of two uniform() calls.
  struct Pair {
    float a, b;
  };
  Pair symmetric_pair(float h = 1.0f) {
    const GridPoint p = grid_point();
    const float step = h * 0x1.0p-23f;
    return {static_cast<float>(p.a) * step, static_cast<float>(p.b) * step};
  }

  // Uniform on the unit sphere, by Marsaglia's method (1972): (a, b) uniform in the unit disk, s = a^2 + b^2, gives
  // (2a sqrt(1 - s), 2b sqrt(1 - s), 1 - 2s). s is uniform in [0, 1) (the disk's area), so z = 1 - 2s is uniform in
  // (-1, 1], which is Archimedes' theorem for the sphere's uniform measure; the angle of (a, b) is uniform and
  // independent of s. One square root and on average 4 / pi draws, where rejection in the cube took 3 uniform()
  // draws per try, 18 / pi on average, and a square root and a division.
  core::Vec3f unit_vector() {
    const GridPoint p = grid_point_in_disk();
    const float s = static_cast<float>(p.norm2) * 0x1.0p-46f;
    const float scale = std::sqrt(1 - s) * 0x1.0p-22f;  // 2 sqrt(1 - s) times the grid step 2^-23
    return {static_cast<float>(p.a) * scale, static_cast<float>(p.b) * scale, 1 - 2 * s};
  }
  // Uniform in the unit disk (z = 0).
  core::Vec3f in_unit_disk() {
    const GridPoint p = grid_point_in_disk();
    return {static_cast<float>(p.a) * 0x1.0p-23f, static_cast<float>(p.b) * 0x1.0p-23f, 0};
  }

 private:
  // A point uniform on the grid [-2^23, 2^23)^2 of integers, from one draw: its top 24 bits and the 24 below them.
  // xorshift64*'s weak bits are its lowest (its multiplication mixes each bit only into the ones above), and bits
  // 16 to 39 are well above them. norm2 = a^2 + b^2, exact.
  struct GridPoint {
    std::int64_t a, b, norm2;
  };
  GridPoint grid_point() {
    const std::uint64_t bits = next_u64();
    // Arithmetic shifts of the signed bits give the integers in [-2^23, 2^23) directly.
    const auto a = static_cast<std::int64_t>(bits) >> 40;
    const auto b = static_cast<std::int64_t>(bits << 24) >> 40;
    return {a, b, a * a + b * b};
  }
  // Scaled by 2^-23, uniform in the open unit disk: rejection in the square, on average 4 / pi draws. The test is
  // exact in integers, and a rejected try costs no conversion to float.
  GridPoint grid_point_in_disk() {
    while (true) {
      const GridPoint p = grid_point();
      if (p.norm2 < (std::int64_t{1} << 46)) return p;
    }
  }

  std::uint64_t state_;
};

// The streams of one job: stream(item) is Rng::for_item(seed, item), the seed's hash computed once. Rng's
// constructor mixes (seed hash ^ item) again, and mix64 is a bijection, so the items of a job get distinct states.
class RngStreams {
 public:
  explicit RngStreams(std::uint64_t seed) : seed_hash_(mix64(seed)) {}
  Rng stream(std::uint64_t item) const { return Rng(seed_hash_ ^ item); }

 private:
  std::uint64_t seed_hash_;
};

inline Rng Rng::for_item(std::uint64_t seed, std::uint64_t item) { return RngStreams(seed).stream(item); }

}  // namespace tripsitter::render

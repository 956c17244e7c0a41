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

  // Uniform on the unit sphere.
  core::Vec3f unit_vector() {
    while (true) {
      const core::Vec3f p{2 * uniform() - 1, 2 * uniform() - 1, 2 * uniform() - 1};
      const float len2 = core::dot(p, p);
      if (len2 > 1e-12f && len2 <= 1.0f) return p / std::sqrt(len2);
    }
  }
  // Uniform in the unit disk (z = 0).
  core::Vec3f in_unit_disk() {
    while (true) {
      const core::Vec3f p{2 * uniform() - 1, 2 * uniform() - 1, 0};
      if (core::dot(p, p) < 1.0f) return p;
    }
  }

 private:
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

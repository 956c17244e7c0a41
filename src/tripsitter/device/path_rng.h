// The path preset's random numbers: Marsaglia's xorshift32 (J. Stat. Softw. 8(14), 2003; the generator family
// Numerical Recipes' third edition builds its fast generators from), with the shift triple (13, 17, 5): three
// shifts and three XORs per draw, no multiplier, period 2^32 - 1 over the non-zero states.
//
// A pixel's colour must not depend on which worker traced it or when, so no generator carries state from one
// sample to the next: each sample seeds its own from (pixel, sample index), sample index = frame * spp + s
// counted from the frame its world was swapped in, through a 32-bit integer hash (two multiplies by constants,
// five shifts and XORs; an avalanche mix, so neighbouring pixels' streams are unrelated). The key
// pixel + 307200 * sample index wraps after 13,981 samples of one world, far beyond what a pixel accumulates
// (docs/device.md, "The path preset").
#pragma once

#include <cstdint>

namespace tripsitter::device {

class PathRng {
 public:
  explicit PathRng(std::uint32_t state) : state_(state != 0 ? state : kZeroStandIn) {}

  // The stream of one sample of one pixel (row * 640 + col).
  static PathRng for_sample(std::uint32_t pixel, std::uint32_t sample_index) {
    return PathRng(hash(pixel + 307200u * sample_index));
  }

  std::uint32_t next() {
    state_ ^= state_ << 13;
    state_ ^= state_ >> 17;
    state_ ^= state_ << 5;
    return state_;
  }

  // The seed hash: xor-shift-multiply rounds with odd constants.
  static std::uint32_t hash(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
  }

 private:
  static constexpr std::uint32_t kZeroStandIn = 0x9e3779b9u;  // xorshift never leaves 0: one hash value maps here
  std::uint32_t state_;
};

}  // namespace tripsitter::device

// The path preset's frame memory: per pixel, the sums of the samples accumulated since its world was swapped in
// and their count, and what the workers show from them (docs/device.md, "Frame memory").
//
// An entry is 64 bits: three 17-bit sums of 9-bit samples, an 8-bit count (at most 255 samples, then the pixel
// stops tracing: it has converged as far as its sums go) and a 5-bit epoch, the world it belongs to. A new world
// moves the device to the next epoch, so stale entries read as empty without clearing 307,200 entries in
// vertical blanking. (A pixel late through exactly 32 world changes would read its old entry; docs/device.md.)
//
// The colour shown: the mean, sum * (2^18 / count) from a 256-entry reciprocal table, as 9 bits; a 512-entry
// table of 240 * sRGB(mean / 512) (the float path tracer's encoding, 16 steps per output level); then the 4-bit
// channel (G + t) >> 4 with t the pixel's 4x4 Bayer threshold (ordered dithering), or t = 8 (rounding) without.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/core/screen.h>

namespace tripsitter::device {

inline constexpr int kSampleBits = 9;     // a sample's channel: light times 2^9, at most 511
inline constexpr int kMaxSamples = 255;   // per pixel, per world
inline constexpr int kEpochs = 32;
inline constexpr int kAccumEntryBits = 64;  // an entry in frame memory: 3 x 17 + 8 + 5

struct AccumEntry {
  std::array<std::uint32_t, 3> sum{};  // 17 bits each: 255 * 511 < 2^17
  std::uint8_t count = 0;
  std::uint8_t epoch = 0;               // 5 bits
  bool operator==(const AccumEntry&) const = default;
};

// A sample's light (times 2^16, 1.0 = 65536) as a 9-bit channel, rounded, at most 511.
constexpr std::uint32_t sample_channel(std::int64_t light) {
  const std::int64_t v = (light + 64) >> 7;
  return static_cast<std::uint32_t>(v < 511 ? v : 511);
}

// A channel's mean as the display computes it, sum * round(2^18 / count) rounded, in the sample's 9 bits.
// 1 <= count <= kMaxSamples, sum <= count * 511.
std::uint32_t display_mean(std::uint32_t sum, int count);

// The 4-bit colour of an entry with count >= 1 at pixel (col, row).
core::Rgb444 display_colour(const AccumEntry& entry, int col, int row, bool dither);

// The entry's mean light per channel in [0, 1) (its sums over its count, times 2^-9): what --compare reads.
std::array<double, 3> entry_mean(const AccumEntry& entry);

class FrameMemory {
 public:
  FrameMemory() : entries_(static_cast<std::size_t>(core::kScreenWidth) * core::kScreenHeight) {}
  std::span<AccumEntry> row(int r) {
    return std::span(entries_).subspan(static_cast<std::size_t>(r) * core::kScreenWidth, core::kScreenWidth);
  }
  std::span<const AccumEntry> entries() const { return entries_; }

 private:
  std::vector<AccumEntry> entries_;
};

}  // namespace tripsitter::device

#include <tripsitter/device/frame_memory.h>

#include <cmath>

namespace tripsitter::device {
namespace {

// 2^18 / count, rounded: the reciprocal table (count 1..255; entry 0 unused).
struct Tables {
  std::array<std::uint32_t, kMaxSamples + 1> reciprocal{};
  std::array<std::uint8_t, 512> gamma{};  // 240 * sRGB(v / 512), rounded
  Tables() {
    for (int c = 1; c <= kMaxSamples; ++c)
      reciprocal[static_cast<std::size_t>(c)] = static_cast<std::uint32_t>(((1u << 18) + c / 2) / static_cast<unsigned>(c));
    for (int v = 0; v < 512; ++v) {
      const double x = v / 512.0;
      const double srgb = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055;
      gamma[static_cast<std::size_t>(v)] = static_cast<std::uint8_t>(std::lround(240 * srgb));
    }
  }
};

const Tables& tables() {
  static const Tables t;
  return t;
}

constexpr std::array<std::array<int, 4>, 4> kBayer{{{0, 8, 2, 10}, {12, 4, 14, 6}, {3, 11, 1, 9}, {15, 7, 13, 5}}};

}  // namespace

std::uint32_t display_mean(std::uint32_t sum, int count) {
  const std::uint64_t r = tables().reciprocal[static_cast<std::size_t>(count)];
  return static_cast<std::uint32_t>((sum * r + (1u << 17)) >> 18);
}

core::Rgb444 display_colour(const AccumEntry& entry, int col, int row, bool dither) {
  const Tables& t = tables();
  const int threshold = dither ? kBayer[static_cast<std::size_t>(row & 3)][static_cast<std::size_t>(col & 3)] : 8;
  int ch[3];
  for (std::size_t k = 0; k < 3; ++k) {
    const std::uint32_t mean = display_mean(entry.sum[k], entry.count);  // <= 511 + 1 rounding: sum <= count * 511
    ch[k] = (t.gamma[mean < 511 ? mean : 511] + threshold) >> 4;
  }
  return core::Rgb444::from_channels(ch[0], ch[1], ch[2]);
}

std::array<double, 3> entry_mean(const AccumEntry& entry) {
  if (entry.count == 0) return {0, 0, 0};
  const double scale = 1.0 / (512.0 * entry.count);
  return {entry.sum[0] * scale, entry.sum[1] * scale, entry.sum[2] * scale};
}

}  // namespace tripsitter::device

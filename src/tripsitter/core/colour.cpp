#include <tripsitter/core/colour.h>

#include <algorithm>
#include <bit>
#include <cmath>

namespace tripsitter::core {

std::uint8_t srgb_encode(float linear) {
  const float v = std::fmin(std::fmax(linear, 0.0f), 1.0f);
  const float e = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return static_cast<std::uint8_t>(std::lround(e * 255.0f));
}

namespace {

// srgb_encode without pow: it is monotonic, so level k covers [start[k], start[k + 1]); a 4096-bin table gives
// the level at each bin's start, and one bin never spans more than one level boundary (the curve's steepest
// slope, 12.92 * 255 levels per unit, is under 4096 bins per unit), so one comparison finishes the job.
class SrgbTable {
 public:
  SrgbTable() {
    start_[0] = -INFINITY;
    for (int k = 1; k < 256; ++k) {
      // The smallest float in [0, 1] that encodes to k or more, by bisection on the bit patterns (ordered like
      // the values for non-negative floats).
      std::uint32_t lo = 0, hi = std::bit_cast<std::uint32_t>(1.0f);
      while (lo < hi) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        if (srgb_encode(std::bit_cast<float>(mid)) >= k) hi = mid;
        else lo = mid + 1;
      }
      start_[k] = std::bit_cast<float>(lo);
    }
    start_[256] = INFINITY;
    int level = 0;
    for (int bin = 0; bin < kBins; ++bin) {
      const float x = static_cast<float>(bin) / kBins;
      while (start_[level + 1] <= x) ++level;
      bin_level_[bin] = static_cast<std::uint8_t>(level);
    }
  }
  std::uint8_t encode(float linear) const {
    // Clamped to [0, 1], NaN to 0, as in srgb_encode (comparisons: std::fmin and std::fmax are library calls).
    const float v = linear > 0.0f ? (linear < 1.0f ? linear : 1.0f) : 0.0f;
    const int bin = std::min(static_cast<int>(v * kBins), kBins - 1);
    const int level = bin_level_[bin];
    return static_cast<std::uint8_t>(v >= start_[level + 1] ? level + 1 : level);
  }

 private:
  static constexpr int kBins = 4096;
  float start_[257];
  std::uint8_t bin_level_[kBins];
};

}  // namespace

ImageRgb8 to_srgb8(const ImageRgbF& image) { return to_srgb8(image, 1.0f); }

ImageRgb8 to_srgb8(const ImageRgbF& image, float scale) {
  ImageRgb8 out(image.width, image.height);
  encode_srgb8(image.pixels.data(), image.pixels.size(), scale, out.pixels.data());
  return out;
}

void encode_srgb8(const Vec3f* linear, std::size_t count, float scale, std::uint8_t* out) {
  static const SrgbTable table;
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3f p = linear[i] * scale;
    out[3 * i + 0] = table.encode(p.x);
    out[3 * i + 1] = table.encode(p.y);
    out[3 * i + 2] = table.encode(p.z);
  }
}

}  // namespace tripsitter::core

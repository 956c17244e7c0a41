// Colour of linear RGB with Rec. 709 (sRGB) primaries: its luminance, and its encoding to 8-bit sRGB.
#pragma once

#include <cstddef>
#include <cstdint>

#include <tripsitter/core/image.h>
#include <tripsitter/core/vec.h>

namespace tripsitter::core {

// The weights of red, green and blue in the luminance of linear RGB (ITU-R BT.709).
inline constexpr Vec3f kRec709Luminance{0.2126f, 0.7152f, 0.0722f};

// Linear luminance: 0.2126 r + 0.7152 g + 0.0722 b, summed in that order. The denoiser's eight-lane form
// (render/denoise.cpp) takes the same products in the same order and gives the same bits.
inline float luminance(const Vec3f& c) {
  return kRec709Luminance.x * c.x + kRec709Luminance.y * c.y + kRec709Luminance.z * c.z;
}

// The IEC 61966-2-1 sRGB transfer function of a linear value clamped to [0, 1], to 8 bits.
std::uint8_t srgb_encode(float linear);
// Every channel through srgb_encode (by table: the same bytes, without pow), after multiplying by `scale`.
ImageRgb8 to_srgb8(const ImageRgbF& image);
ImageRgb8 to_srgb8(const ImageRgbF& image, float scale);
// The same for `count` pixels from `linear` into 3 * count bytes at `out`: a part of an image, for callers that
// share an image's rows among threads.
void encode_srgb8(const Vec3f* linear, std::size_t count, float scale, std::uint8_t* out);

}  // namespace tripsitter::core

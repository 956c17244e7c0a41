// The colour helpers: Rec. 709 luminance, and sRGB encoding by the curve and by its table.
#include <tripsitter/core/colour.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

namespace tripsitter::core {
namespace {

TEST(Luminance, WeighsTheRec709Primaries) {
  EXPECT_EQ(luminance({1, 0, 0}), 0.2126f);
  EXPECT_EQ(luminance({0, 1, 0}), 0.7152f);
  EXPECT_EQ(luminance({0, 0, 1}), 0.0722f);
  EXPECT_NEAR(luminance({1, 1, 1}), 1.0f, 1e-6f);
  // Summed in the order r, g, b: the bits a caller (the denoiser's lanes) reproduces.
  const Vec3f c{0.3f, 1.7f, 0.01f};
  EXPECT_EQ(std::bit_cast<std::uint32_t>(luminance(c)),
            std::bit_cast<std::uint32_t>((0.2126f * c.x + 0.7152f * c.y) + 0.0722f * c.z));
}

TEST(Srgb, EncodesTheStandardCurve) {
  EXPECT_EQ(srgb_encode(0.0f), 0);
  EXPECT_EQ(srgb_encode(1.0f), 255);
  EXPECT_EQ(srgb_encode(2.0f), 255);
  EXPECT_EQ(srgb_encode(-1.0f), 0);
  EXPECT_EQ(srgb_encode(0.5f), 188);        // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354
  EXPECT_EQ(srgb_encode(0.002f), 7);        // linear segment: 12.92 * 0.002 * 255 = 6.6
  EXPECT_EQ(srgb_encode(0.2159f), 128);     // 128 / 255 decodes to 0.21586
}

TEST(Srgb, TheTableEncodesEveryValueAsTheCurveDoes) {
  // Every 97th float in [0, 1] (11 million values, so every level boundary is approached within 97 floats),
  // values outside [0, 1] and NaN.
  ImageRgbF img{1, 0, {}};
  std::vector<float> values;
  for (std::uint32_t bits = 0; bits <= std::bit_cast<std::uint32_t>(1.0f); bits += 97) values.push_back(std::bit_cast<float>(bits));
  for (float v : {-1.0f, 1.5f, INFINITY, -INFINITY, NAN, 1.0f}) values.push_back(v);
  for (std::size_t i = 0; i < values.size(); i += 3)
    img.pixels.push_back({values[i], values[std::min(i + 1, values.size() - 1)], values[std::min(i + 2, values.size() - 1)]});
  img.height = static_cast<int>(img.pixels.size());
  const ImageRgb8 out = to_srgb8(img);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) {
    const Vec3f& p = img.pixels[i];
    ASSERT_EQ(out.pixels[3 * i + 0], srgb_encode(p.x)) << p.x;
    ASSERT_EQ(out.pixels[3 * i + 1], srgb_encode(p.y)) << p.y;
    ASSERT_EQ(out.pixels[3 * i + 2], srgb_encode(p.z)) << p.z;
  }
}

}  // namespace
}  // namespace tripsitter::core

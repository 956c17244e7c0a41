#include <tripsitter/render/image_error.h>

#include <cmath>

#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/core/colour.h>
#include <tripsitter/render/aov.h>

namespace tripsitter::render {
namespace {

using core::Vec3f;

TEST(ImageError, ZeroForTheReferenceItself) {
  const std::vector<Vec3f> ref(12 * 9, Vec3f{0.3f, 0.5f, 0.7f});
  const ImageError e = image_error(ref, ref, 12, 9);
  EXPECT_EQ(e.relmse, 0.0);
  EXPECT_EQ(e.bias, 0.0);
  EXPECT_EQ(e.block_relmse, 0.0);
}

TEST(ImageError, FollowsTheDefinitions) {
  // Reference 1 everywhere; the picture 1.1 in every channel: relMSE 0.01 / 1.01, bias 0.1 / 1.01.
  const std::vector<Vec3f> ref(16 * 16, Vec3f{1, 1, 1}), image(16 * 16, Vec3f{1.1f, 1.1f, 1.1f});
  const ImageError e = image_error(image, ref, 16, 16);
  EXPECT_NEAR(e.relmse, 0.01 / 1.01, 1e-6);
  EXPECT_NEAR(e.bias, 0.1 / 1.01, 1e-6);
  EXPECT_NEAR(e.block_relmse, 0.01 / 1.01, 1e-6);
}

TEST(ImageError, NoiseThatAveragesOutLeavesNoBiasAndLittleBlockError) {
  // A checkerboard of 0.5 and 1.5 around a reference of 1: large relMSE, zero bias, zero block error.
  std::vector<Vec3f> ref(16 * 8, Vec3f{1, 1, 1}), image(ref.size());
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) image[static_cast<std::size_t>(y * 16 + x)] = Vec3f{1, 1, 1} * ((x + y) % 2 ? 1.5f : 0.5f);
  const ImageError e = image_error(image, ref, 16, 8);
  EXPECT_NEAR(e.relmse, 0.25 / 1.01, 1e-6);
  EXPECT_NEAR(e.bias, 0.0, 1e-9);
  EXPECT_NEAR(e.block_relmse, 0.0, 1e-9);
}

TEST(ImageError, PartialBlocksCount) {
  // 10 x 3: blocks 8x3 and 2x3; only the last column is off, by 1, so only the second block's mean moves (by 0.5).
  std::vector<Vec3f> ref(30, Vec3f{1, 1, 1}), image = ref;
  for (int y = 0; y < 3; ++y) image[static_cast<std::size_t>(y * 10 + 9)] = {2, 2, 2};
  const ImageError e = image_error(image, ref, 10, 3);
  EXPECT_NEAR(e.block_relmse, (0.25 / 1.01) / 2, 1e-6);
}

}  // namespace
}  // namespace tripsitter::render

namespace tripsitter::render {

TEST(AovImages, DepthRunsByInverseDepthFromWhiteAtTheNearestToBlackAtTheFarthest) {
  Aovs a(4, 1);
  a.depth = {2.0f, 4.0f, 6.0f, INFINITY};
  a.normal = {{0, 0, -1}, {1, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  a.albedo = {{1, 1, 1}, {0, 0, 0}, {0.5f, 0.5f, 0.5f}, {1, 1, 1}};
  const core::ImageRgb8 depth = depth_image(a), normal = normal_image(a), albedo = albedo_image(a);
  EXPECT_EQ(depth.pixels[0], 255);
  EXPECT_EQ(depth.pixels[3], 64);  // 1/4 is a quarter of the way from 1/6 to 1/2
  EXPECT_EQ(depth.pixels[6], 0);
  EXPECT_EQ(depth.pixels[9], 0);
  EXPECT_EQ(normal.pixels[2], 0);     // z = -1
  EXPECT_EQ(normal.pixels[3], 255);   // x = 1
  EXPECT_EQ(normal.pixels[6], 127);   // 0: grey
  EXPECT_EQ(albedo.pixels[0], 255);
  EXPECT_EQ(albedo.pixels[3], 0);
  EXPECT_EQ(albedo.pixels[6], core::srgb_encode(0.5f));
}

}  // namespace tripsitter::render

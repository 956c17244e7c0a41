#include <tripsitter/core/albedo.h>

#include <gtest/gtest.h>

namespace tripsitter::core {
namespace {

TEST(AlbedoByte, RoundsTheClampedAlbedo) {
  EXPECT_EQ(albedo_byte(0.0), 0);
  EXPECT_EQ(albedo_byte(0.5), 128);  // 127.5 rounds away from zero
  EXPECT_EQ(albedo_byte(2.0 / 3.0), 170);
  EXPECT_EQ(albedo_byte(1.0), 255);
  EXPECT_EQ(albedo_byte(1.5), 255);
  EXPECT_EQ(albedo_byte(-0.2), 0);
  for (int k = 0; k <= 255; ++k) EXPECT_EQ(albedo_byte(k / 255.0), k) << k;
}

}  // namespace
}  // namespace tripsitter::core

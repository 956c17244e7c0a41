#include <tripsitter/core/screen.h>

#include <cstdint>
#include <random>

#include <gtest/gtest.h>

namespace tripsitter::core {
namespace {

TEST(Screen, TheDevicesRaysAreTheBoards) {
  // SPEC.md section B: (col - 320, row - 240, 320).
  EXPECT_EQ(kScreenWidth, 640);
  EXPECT_EQ(kScreenHeight, 480);
  EXPECT_EQ(kImagePlaneZ, 320);
  EXPECT_EQ(device_ray(0, 0), (Vec3<Int128>{-320, -240, 320}));
  EXPECT_EQ(device_ray(639, 479), (Vec3<Int128>{319, 239, 320}));
  EXPECT_EQ(device_ray<std::int64_t>(320, 240), (Vec3<std::int64_t>{0, 0, 320}));
  for (int row = 0; row < kScreenHeight; row += 7)
    for (int col = 0; col < kScreenWidth; col += 5)
      ASSERT_EQ(pixel_ray<double>(col, row, kScreenWidth, kScreenHeight),
                (Vec3d{double(col - 320), double(row - 240), 320.0}));
}

TEST(Screen, OtherSizesUseIntegerHalves) {
  EXPECT_EQ(image_plane_z(161), 80);
  EXPECT_EQ(pixel_ray<double>(0, 0, 161, 91), (Vec3d{-80.0, -45.0, 80.0}));
  EXPECT_EQ(pixel_ray<double>(160, 90, 161, 91), (Vec3d{80.0, 45.0, 80.0}));
}

// Whether the device ray of (col, row) meets the sphere (centre c, radius r): its discriminant, exactly.
bool ray_meets(int col, int row, const Vec3<std::int64_t>& c, std::int64_t r) {
  const Vec3<Int128> d = device_ray(col, row);
  const Vec3<Int128> oc{c.x, c.y, c.z};
  const Int128 b = 2 * dot(d, oc);
  return b * b - 4 * dot(d, d) * (dot(oc, oc) - Int128{r} * r) >= 0;
}

// Every pixel whose ray meets a sphere lies within its bounds (the rows' only where some column's plane meets it).
TEST(ScreenBounds, HoldEveryRayThatMeetsTheSphere) {
  std::mt19937_64 rng(4);
  std::uniform_int_distribution<std::int64_t> coord(-3000, 3000), radius(1, 600);
  int hits = 0;
  for (int world = 0; world < 60; ++world) {
    const Vec3<std::int64_t> c{coord(rng), coord(rng), coord(rng) / 3 + 900};
    const std::int64_t r = radius(rng);
    const ScreenBounds b = screen_bounds<Int128>(c, r * r, kScreenWidth, kScreenHeight, kScreenWidth);
    for (int row = 0; row < kScreenHeight; row += 3) {
      for (int col = 0; col < kScreenWidth; col += 3) {
        if (!ray_meets(col, row, c, r)) continue;
        ++hits;
        ASSERT_TRUE(b.col_lo <= col && col <= b.col_hi && b.row_lo <= row && row <= b.row_hi)
            << "world " << world << " pixel " << col << "," << row;
      }
    }
  }
  EXPECT_GT(hits, 10000);  // the worlds are seen
}

// One definition for every number type: on inputs small enough for double to be exact, the integer and
// double instantiations agree plane by plane and bound by bound.
TEST(ScreenBounds, IntegersAndDoublesAgreeWhereDoublesAreExact) {
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<std::int64_t> coord(-5000, 5000), radius(0, 2000);
  for (int i = 0; i < 400; ++i) {
    const Vec3<std::int64_t> c{coord(rng), coord(rng), coord(rng)};
    const std::int64_t r2 = radius(rng) * radius(rng);
    const Vec3d cd{double(c.x), double(c.y), double(c.z)};
    for (const int columns : {kScreenWidth, 333}) {
      const ScreenBounds bi = screen_bounds<Int128>(c, r2, kScreenWidth, kScreenHeight, columns);
      const ScreenBounds bd = screen_bounds<double>(cd, double(r2), kScreenWidth, kScreenHeight, columns);
      ASSERT_EQ(bi.col_lo, bd.col_lo) << i;
      ASSERT_EQ(bi.col_hi, bd.col_hi) << i;
      ASSERT_EQ(bi.row_lo, bd.row_lo) << i;
      ASSERT_EQ(bi.row_hi, bd.row_hi) << i;
      ASSERT_LE(bi.col_hi, columns - 1);
    }
  }
}

TEST(ScreenBounds, ASphereNoPlaneMeetsHasNoColumnsAndNoRows) {
  // Far to the right of the screen, beyond the 90 degree field of view.
  const ScreenBounds b = screen_bounds<Int128>(Vec3<std::int64_t>{5000, 0, 1000}, std::int64_t{100}, kScreenWidth,
                                               kScreenHeight, kScreenWidth);
  EXPECT_GT(b.col_lo, b.col_hi);
  EXPECT_GT(b.row_lo, b.row_hi);
  // On the axis: every column's and row's plane near the middle meets it, the middle ones included.
  const ScreenBounds m = screen_bounds<Int128>(Vec3<std::int64_t>{0, 0, 1000}, std::int64_t{100 * 100}, kScreenWidth,
                                               kScreenHeight, kScreenWidth);
  EXPECT_LE(m.col_lo, 320);
  EXPECT_GE(m.col_hi, 320);
  EXPECT_LE(m.row_lo, 240);
  EXPECT_GE(m.row_hi, 240);
}

}  // namespace
}  // namespace tripsitter::core

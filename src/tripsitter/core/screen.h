// The screen and the camera's rays (SPEC.md section B), and the screen-space bounds of a sphere.
//
// The camera sits at the origin of view space, x to the right, y down (screen rows), z into the screen. On a
// screen `width` x `height` pixels, the pixel in column col and row row shoots (col - width/2, row - height/2,
// width/2) (integer halves): the image plane is at z = width/2, a 90 degree horizontal field of view. The
// device's screen is 640 x 480, so its rays are (col - 320, row - 240, 320); the float renderers use the same
// rule at any size. Host, device and renderers take these from here.
//
// Screen-space bounds: the rays of one column all lie in the column's plane through the camera, with normal
// (f, 0, -x) for f = width/2 and x = col - width/2; those of a row in the row's plane, normal (0, f, -y). A ray
// meets a sphere only if it passes within r of the centre, and then so does every plane holding it. So each
// sphere has a range of columns and a range of rows whose planes meet it, and camera rays outside them miss it.
// The test is written once for every number type (exact integers on the device's fast model, double with a
// margin in the float renderer); each caller supplies its r^2 and states why its test is sound.
#pragma once

#include <algorithm>
#include <array>

#include <tripsitter/core/fixed.h>
#include <tripsitter/core/vec.h>

namespace tripsitter::core {

// The device's screen, in pixels (the visible part of the VGA mode).
inline constexpr int kScreenWidth = 640;
inline constexpr int kScreenHeight = 480;

// The image plane's z (the rays' z) on a screen `width` pixels wide.
constexpr int image_plane_z(int width) { return width / 2; }
// The device's image plane, z = 320 in pixel units.
inline constexpr int kImagePlaneZ = image_plane_z(kScreenWidth);

// The camera ray of pixel (col, row) on a width x height screen: (col - width/2, row - height/2, width/2).
template <class T>
constexpr Vec3<T> pixel_ray(int col, int row, int width, int height) {
  return {T(col - width / 2), T(row - height / 2), T(image_plane_z(width))};
}

// The device's ray of the pixel in column col (0..639) and row (0..479): (col - 320, row - 240, 320).
template <class T = Int128>
constexpr Vec3<T> device_ray(int col, int row) {
  return pixel_ray<T>(col, row, kScreenWidth, kScreenHeight);
}

// Whether the plane through the camera with normal (f, -offset) in the (across, depth) coordinates meets the
// sphere whose centre lies at (across, depth) in them: (f across - offset depth)^2 <= r2 (f^2 + offset^2).
// For a column's plane across is the centre's x and offset = col - width/2; for a row's, y and row - height/2;
// depth is the centre's z and f the image plane's z. T holds the coordinates, f, offset and r2 and the sums
// of their products; Square the squares.
template <class Square, class T>
constexpr bool plane_meets(T across, T depth, T r2, T f, T offset) {
  const T side = f * across - offset * depth;  // the normal (f, -offset) . centre
  return Square(side) * Square(side) <= Square(r2) * Square(f * f + offset * offset);
}

// The hull [lo, hi] of the indices in [0, count) whose plane (offset = index - centre) meets the sphere; lo > hi
// when none does. The meeting planes of a pencil are an interval of angles, which may wrap through the plane
// z = 0: the hull then holds planes between that do not meet the sphere, which only costs tests.
template <class Square, class T>
constexpr std::array<int, 2> meeting_range(T across, T depth, T r2, T f, int count, int centre) {
  int lo = count, hi = -1;
  for (int i = 0; i < count; ++i) {
    if (!plane_meets<Square>(across, depth, r2, f, T(i - centre))) continue;
    lo = std::min(lo, i);
    hi = i;
  }
  return {lo, hi};
}

// The columns and rows whose planes meet a sphere (inclusive; empty when lo > hi).
struct ScreenBounds {
  int col_lo = 0, col_hi = -1, row_lo = 0, row_hi = -1;
};

// The screen bounds of the sphere with centre c and r2 (the radius squared, plus the caller's margin) on a
// width x height screen, over the columns [0, columns) only (columns <= width). The rows are left empty when
// no column's plane meets the sphere.
template <class Square, class T>
constexpr ScreenBounds screen_bounds(const Vec3<T>& c, T r2, int width, int height, int columns) {
  const T f = T(image_plane_z(width));
  const auto cols = meeting_range<Square>(c.x, c.z, r2, f, columns, width / 2);
  if (cols[0] > cols[1]) return {};
  const auto rows = meeting_range<Square>(c.y, c.z, r2, f, height, height / 2);
  return {cols[0], cols[1], rows[0], rows[1]};
}

}  // namespace tripsitter::core

// The float reference: the device's rays and shading model (SPEC.md section B, and the mirror model of
// docs/device.md) in double precision, with the same kernel the device runs in fixed point
// (core/sphere_kernel.h).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

#include <tripsitter/core/albedo.h>
#include <tripsitter/core/image.h>
#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::render {

struct DoubleArith {
  using Coord = double;
  using Wide = double;
  double sqrt(double d) const { return std::sqrt(d); }
  static int floor_div(double n, double d) {
    const double q = std::floor(n / d);
    return q > 1e9 ? 1'000'000'000 : (q < -1e9 ? -1'000'000'000 : static_cast<int>(q));
  }
  // The hit point is not rounded in double.
  static double round_div(double n, double d) { return n / d; }
  // The device's power-of-two scaling of a reflected direction; exact in double (only the exponent changes).
  static core::Vec3d scale_direction(const core::Vec3d& r) {
    const double largest = std::max({std::abs(r.x), std::abs(r.y), std::abs(r.z)});
    int exponent = 0;  // largest < 2^exponent, as the bit length of an integer
    std::frexp(largest, &exponent);
    const int shift = exponent - core::kDirectionBits;
    if (shift <= 0) return r;
    return {std::ldexp(r.x, -shift), std::ldexp(r.y, -shift), std::ldexp(r.z, -shift)};
  }
};

// The albedo bytes both sides mix with: round(a * 255) of a clamped to [0, 1], as the host sends them
// (core/albedo.h).
using core::albedo_byte;

// Renders view-space spheres (pixel units, as the host computes them). The pixel in column col and row
// row shoots core::pixel_ray (col - width/2, row - height/2, width/2) (integer halves, core/screen.h): for
// 640x480 exactly the device's rays, and a 90 degree horizontal field of view at every size. Metals reflect up to max_bounces times
// (0: every sphere is normal-map shaded, the board's image); other materials are normal-map shaded.
// REQUIRES 0 <= max_bounces <= core::kMaxBounces.
core::Image444 render_normal(std::span<const scene::Sphere> view_spheres, int width, int height, int max_bounces = 0);

// The same image as render_normal, bit for bit, made faster: each 8x8 tile of camera rays tests only the spheres
// that can meet it (screen-space bounds, see normal.cpp), and rows of tiles are shared among `threads` threads
// (0: all). Reflected rays test every sphere, as in render_normal. The window's and `render`'s normal mode.
// REQUIRES 0 <= max_bounces <= core::kMaxBounces.
core::Image444 render_normal_fast(std::span<const scene::Sphere> view_spheres, int width, int height,
                                  int max_bounces = 0, int threads = 0);

}  // namespace tripsitter::render

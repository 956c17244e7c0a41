// A ray-tracing worker: the pure per-pixel function of the device, in the device's fixed point.
#pragma once

#include <cstdint>
#include <limits>

#include <tripsitter/core/fixed.h>
#include <tripsitter/core/rgb444.h>
#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/device/sqrt_unit.h>

namespace tripsitter::device {

// The kernel's arithmetic on the device: raw fixed point in 64 bits, products in 128, the square-root unit.
struct FixedArith {
  using Coord = std::int64_t;
  using Wide = core::Int128;

  SqrtUnit sqrt_unit;

  Wide sqrt(Wide d) const { return sqrt_unit(static_cast<core::UInt128>(d)); }
  static int floor_div(Wide n, Wide d) {
    Wide q = n / d;
    if (n % d != 0 && n < 0) --q;
    if (q > std::numeric_limits<int>::max()) return std::numeric_limits<int>::max();
    if (q < std::numeric_limits<int>::min()) return std::numeric_limits<int>::min();
    return static_cast<int>(q);
  }
};

// The ray of the pixel in column col (0..639) and row (0..479): (col - 320, row - 240, 320).
inline core::Vec3<core::Int128> device_ray(int col, int row) { return {col - 320, row - 240, 320}; }

class Worker {
 public:
  explicit Worker(int sqrt_iterations) : arith_{SqrtUnit(sqrt_iterations)} {}

  // The colour of one pixel: closest hit over all spheres, normal-map shaded, background 0x036.
  core::Rgb444 shade(int col, int row, const SceneMemory& scene) const {
    return core::normal_shade_pixel(arith_, device_ray(col, row),
                                    std::span<const core::KernelSphere<std::int64_t>>(scene.geometry),
                                    core::kBackground);
  }

 private:
  FixedArith arith_;
};

}  // namespace tripsitter::device

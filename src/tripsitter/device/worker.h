// A ray-tracing worker: the pure per-pixel function of the device, in the device's fixed point.
#pragma once

#include <algorithm>
#include <bit>
#include <cassert>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <utility>

#include <tripsitter/core/fixed.h>
#include <tripsitter/core/rgb444.h>
#include <tripsitter/core/screen.h>
#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/device/sqrt_unit.h>
#include <tripsitter/link/frame.h>

// Checks of the device's fixed-point invariants (docs/device.md, "Widths"): 1 compiles them in. Unless the
// build defines it (CMake's TRIPSITTER_CHECK_FIXED, for every target using the device library; on in the
// sanitizer presets), it follows NDEBUG: on in Debug builds, off in Release.
#ifndef TRIPSITTER_CHECK_FIXED
#ifdef NDEBUG
#define TRIPSITTER_CHECK_FIXED 0
#else
#define TRIPSITTER_CHECK_FIXED 1
#endif
#endif

namespace tripsitter::device {

inline constexpr bool kCheckFixed = TRIPSITTER_CHECK_FIXED != 0;

// The kernel's arithmetic on the device: raw fixed point in 64 bits, products in 128, the square-root unit.
// docs/device.md bounds every intermediate; the widest (b^2 and 4ac' of a reflected ray) stays below 2^95.
struct FixedArith {
  using Coord = std::int64_t;
  using Wide = core::Int128;

  SqrtUnit sqrt_unit;
  // Bits the preset's formats add to each length beyond the wide preset's 24 (0 for narrower formats).
  int extra_bits = 0;

  // The extra bits of a preset's formats (the widest of x, y, z and the radius).
  static int extra_bits_of(const DevicePreset& preset) {
    return std::max({0, preset.x.total_bits - 24, preset.y.total_bits - 24, preset.z.total_bits - 24,
                     preset.radius.total_bits - 24});
  }

  // |v| < 2^bits for the bound docs/device.md ("Widths") gives `which` in the wide preset, plus
  // extra_bits for each length it is the product of (the bounds grow with the formats); den and the
  // radius at least 1 (the shading divides by den = 2ar). Throws core::FixedPointOverflow otherwise.
  // Compiled in with TRIPSITTER_CHECK_FIXED (above).
  void check(Wide v, core::Width which) const {
    if constexpr (kCheckFixed) {
      const auto [bits, lengths] = width_of(which);
      const int allowed = bits + lengths * extra_bits;
      const bool positive = which != core::Width::kShadeDen && which != core::Width::kRadius;
      if ((magnitude(v) >> allowed) != 0 || (!positive && v < 1)) overflow(v, which, allowed);
    }
  }

  Wide sqrt(Wide d) const {
    assert(d >= 0 && d < (Wide{1} << 126));
    return sqrt_unit(static_cast<core::UInt128>(d));
  }
  // Divisions take 64 bits when both operands fit (the same quotient, faster than a 128-bit division).
  static int floor_div(Wide n, Wide d) {
    Wide q = fits_64(n) && fits_64(d) ? Wide{static_cast<std::int64_t>(n) / static_cast<std::int64_t>(d)} : n / d;
    if (n < 0 && q * d != n) --q;
    if (q > std::numeric_limits<int>::max()) return std::numeric_limits<int>::max();
    if (q < std::numeric_limits<int>::min()) return std::numeric_limits<int>::min();
    return static_cast<int>(q);
  }
  // n / d rounded to the nearest integer, ties away from zero. d > 0.
  static Wide round_div(Wide n, Wide d) {
    const Wide q = fits_64(n) && fits_64(d) ? Wide{static_cast<std::int64_t>(n) / static_cast<std::int64_t>(d)} : n / d;
    const Wide r = n - q * d;
    if (2 * (r < 0 ? -r : r) >= d) return n < 0 ? q - 1 : q + 1;
    return q;
  }
  // r shifted right by the least s >= 0 that brings every |r_k| to at most 2^kDirectionBits, rounding to
  // nearest (ties away from zero, symmetric in sign): a leading-zero count and a barrel shifter.
  static core::Vec3<Wide> scale_direction(const core::Vec3<Wide>& r) {
    core::UInt128 largest = 0;
    for (int k = 0; k < 3; ++k) largest = std::max(largest, magnitude(r[k]));
    assert(largest < (core::UInt128{1} << 100));
    const int shift = bit_length(largest) - core::kDirectionBits;
    if (shift <= 0) return r;
    core::Vec3<Wide> out;
    const core::UInt128 half = core::UInt128{1} << (shift - 1);
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<Wide>((magnitude(r[k]) + half) >> shift);
      out[k] = r[k] < 0 ? -v : v;
    }
    return out;
  }

 private:
  // Each intermediate's width in the wide preset (bits of its magnitude) and how many lengths it is the
  // product of: the table of docs/device.md, "Widths".
  static std::pair<int, int> width_of(core::Width which) {
    switch (which) {
      case core::Width::kCentre: return {24, 1};
      case core::Width::kRadius: return {24, 1};
      case core::Width::kOrigin: return {25, 1};
      case core::Width::kDirection: return {21, 0};
      case core::Width::kToCentre: return {26, 1};
      case core::Width::kA: return {42, 0};
      case core::Width::kB: return {48, 1};
      case core::Width::kCPrime: return {51, 2};
      case core::Width::kSquare: return {95, 2};
      case core::Width::kDisc: return {95, 2};
      case core::Width::kNum: return {49, 1};
      case core::Width::kNumTimesD: return {70, 1};
      case core::Width::kShadeDen: return {68, 1};
      case core::Width::kShadeSum: return {73, 1};
      case core::Width::kHitNormal: return {25, 1};
      case core::Width::kNormalSquare: return {50, 2};
      case core::Width::kDirNormal: return {46, 1};
      case core::Width::kReflected: return {72, 2};
      case core::Width::kTint: return {52, 0};
      case core::Width::kUnitVector: return {15, 0};
      case core::Width::kScattered: return {19, 0};
      case core::Width::kRefractPerp: return {19, 0};
      case core::Width::kRadicand: return {38, 0};
      case core::Width::kReflectance: return {15, 0};
      case core::Width::kThroughput: return {17, 0};
      case core::Width::kLight: return {33, 0};
      case core::Width::kAccumSum: return {17, 0};
    }
    return {0, 0};
  }
  [[noreturn]] static void overflow(Wide v, core::Width which, int allowed) {
    const auto m = magnitude(v);
    throw core::FixedPointOverflow("fixed-point invariant broken: intermediate #" +
                                   std::to_string(static_cast<int>(which)) + " needs " +
                                   std::to_string(bit_length(m)) + " bits, at most " + std::to_string(allowed) +
                                   " allowed (docs/device.md, Widths)" + (v < 1 ? " or it must be at least 1" : ""));
  }
  static bool fits_64(Wide v) {
    return v >= std::numeric_limits<std::int64_t>::min() && v <= std::numeric_limits<std::int64_t>::max();
  }
  static core::UInt128 magnitude(Wide v) { return static_cast<core::UInt128>(v < 0 ? -v : v); }
  static int bit_length(core::UInt128 v) {
    const auto hi = static_cast<std::uint64_t>(v >> 64);
    if (hi != 0) return 128 - std::countl_zero(hi);
    return 64 - std::countl_zero(static_cast<std::uint64_t>(v));
  }
};

// The ray of the pixel in column col (0..639) and row (0..479): (col - 320, row - 240, 320) (core/screen.h).
using core::device_ray;

// Sphere i's surface as the kernel sees it: lambertian when scene memory holds no surface for it.
inline core::KernelSurface kernel_surface(const SceneMemory& scene, int i) {
  const auto index = static_cast<std::size_t>(i);
  if (index >= scene.surfaces.size()) return core::KernelSurface{};
  const SurfaceWord& s = scene.surfaces[index];
  return core::KernelSurface{s.material == link::kMaterialMetal, s.albedo};
}

class Worker {
 public:
  // REQUIRES 0 <= max_bounces <= core::kMaxBounces.
  // Formats up to 24 bits (the widths checked are the wide preset's).
  explicit Worker(int sqrt_iterations, int max_bounces = 0)
      : arith_{SqrtUnit(sqrt_iterations)}, max_bounces_(max_bounces) {}
  explicit Worker(const DevicePreset& preset)
      : arith_{SqrtUnit(preset.sqrt_iterations), FixedArith::extra_bits_of(preset)}, max_bounces_(preset.max_bounces) {}

  // One pixel in the mirror model: closest hit over all spheres; a metal reflects (up to max_bounces
  // times) and tints what its reflected ray sees; anything else is normal-map shaded; a miss is 0x036.
  // Sphere i is lambertian when scene memory holds no surface for it.
  core::PixelTrace trace(int col, int row, const SceneMemory& scene) const {
    const auto surface_of = [&scene](int i) { return kernel_surface(scene, i); };
    return core::trace_pixel(arith_, device_ray(col, row),
                             std::span<const core::KernelSphere<std::int64_t>>(scene.geometry), surface_of,
                             core::kBackground, max_bounces_);
  }
  // The colour of one pixel (trace without the bounce count).
  core::Rgb444 shade(int col, int row, const SceneMemory& scene) const { return trace(col, row, scene).colour; }
  int max_bounces() const { return max_bounces_; }
  // The worker's arithmetic (its square-root unit and checks), which the path preset's kernel runs on too.
  const FixedArith& arith() const { return arith_; }

 private:
  FixedArith arith_;
  int max_bounces_;
};

}  // namespace tripsitter::device

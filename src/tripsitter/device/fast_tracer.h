// The fast model of the workers (Device's DeviceModel::kFast): for every line, exactly the colours, late
// pixels, reflections and demand of Controller::render_line (the plain model, a Worker::trace per pixel), from exact integer
// shortcuts (docs/device.md, "The fast model"):
//  - screen-space bounds. The rays of column x all lie in one plane through the camera, those of a row in
//    another; a ray can only hit a sphere that both its planes meet, and no ray hits a sphere wholly behind
//    the camera. So each sphere gets a range of columns and of rows, tested exactly in integers once per
//    frame, and a line tests only the spheres whose rows hold it, each over its columns;
//  - reflected rays search a hierarchy of balls around groups of spheres: a ray whose line misses a ball,
//    or that finds the ball wholly behind its origin, hits none of the spheres inside;
//  - 64-bit sums and products where the bounds below keep them under 2^63; 128 bits for b^2 and 4ac'
//    (NarrowArith). The quadratic of each ray and sphere is the kernel's own (core::hit_num), fed with
//    coefficients shared among many rays, so the kernel's width checks cover the fast model too;
//  - the square-root unit's closed form (SqrtUnit::closed_form) instead of its step-by-step recurrence.
// The schedule is the controller's own (schedule_line). Worlds beyond the 64-bit bounds (a coordinate or
// radius of kNarrowLimit raw units or more, possible only with formats wider than 29 bits) are traced by
// the plain worker. The artix preset's units have shortcuts of their own (artix_units.h).
#pragma once

#include <algorithm>
#include <array>
#include <cassert>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/device/artix_units.h>
#include <tripsitter/device/ball_tree.h>
#include <tripsitter/device/controller.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/device/worker.h>

namespace tripsitter::device {

// The kernel's arithmetic on the fast model's narrow paths (core/sphere_kernel.h): the same integers as
// FixedArith's, with coordinates, sums and products of two lengths in 64 bits and only b^2, 4ac' and D in 128
// (the bounds are in FastTracer::closest_hit and docs/device.md, "The fast model"). Enough for
// core::hit_num and, for a camera ray, core::normal_colour (n_num < 2^48.2, 7 n_num + 7 den < 2^52); not for
// reflecting. The square root is the unit's closed form; the checks are FixedArith's.
struct NarrowArith {
  using Coord = std::int64_t;
  using Wide = std::int64_t;
  using Square = core::Int128;

  FixedArith fixed;  // the square-root unit, and the width checks with the preset's extra bits

  void check(core::Int128 v, core::Width which) const { fixed.check(v, which); }
  std::int64_t sqrt(Square d) const {
    assert(d >= 0 && d < (Square{1} << 126));
    return static_cast<std::int64_t>(fixed.sqrt_unit.closed_form(static_cast<core::UInt128>(d)));
  }
  static int floor_div(Wide n, Wide d) {
    Wide q = n / d;
    if (n < 0 && q * d != n) --q;
    return static_cast<int>(std::clamp<Wide>(q, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
  }
};

// FixedArith with the square-root unit's closed form (the same values, SqrtUnit::closed_form): the path kernel's
// arithmetic in the fast model.
struct ClosedFormArith : FixedArith {
  core::Int128 sqrt(core::Int128 d) const {
    assert(d >= 0 && d < (core::Int128{1} << 126));
    return sqrt_unit.closed_form(static_cast<core::UInt128>(d));
  }
};

class FastTracer {
 public:
  // |centre_k| and radius below this (raw) keep every sum and product of the fast paths within 64 bits.
  static constexpr std::int64_t kNarrowLimit = std::int64_t{1} << 28;

  // REQUIRES preset.validate() is empty.
  explicit FastTracer(const DevicePreset& preset);

  // Takes the world of a frame. REQUIRES `scene` to outlive the render_line calls and stay unchanged.
  void load(const SceneMemory& scene);

  // Row `row` (0..479) of the loaded world's frame: what Controller::render_line(row, scene, line) gives.
  // Calls may run on several threads at once.
  LineResult render_line(int row, std::span<core::Rgb444> line) const;

  // The path preset's row `row` of `frame`: what Controller::render_path_line(row, scene, frame, memory, line,
  // counters) gives, and the same counters. Calls may run on several threads at once for different rows.
  LineResult render_path_line(int row, const PathFrame& frame, std::span<AccumEntry> memory,
                              std::span<core::Rgb444> line, PathCounters& counters) const;

  // Whether the loaded world takes the fast paths (false: the plain worker traces it). Always on the artix preset.
  bool narrow() const { return narrow_; }

 private:
  // The closest hit of every camera ray of row `row`: best[col] the sphere (-1: none), best_num[col] its num.
  void primary_hits(int row, std::array<int, kLineWidth>& best, std::array<std::int64_t, kLineWidth>& best_num) const;
  // The closest hit of a reflected ray (or any ray whose origin and direction fit the 64-bit bounds).
  core::KernelHit<core::Int128> closest_hit(const core::KernelRay<core::Int128>& ray, int excluded) const;

  DevicePreset preset_;
  Controller controller_;
  FixedArith arith_;
  NarrowArith narrow_arith_;  // arith_'s unit and checks, in 64 bits
  ClosedFormArith path_arith_;  // arith_ with the closed-form square root, for the path kernel
  const SceneMemory* scene_ = nullptr;
  bool narrow_ = false;
  // Columns that can be on time: workers * pixels_in_time (later ones are late for sure); every column on the path
  // preset and with trace_late_pixels.
  int columns_ = 0;
  // The spheres, structure of arrays: centre, radius squared, c' = centre.centre - r^2 (a camera ray's).
  std::vector<std::int64_t> cx_, cy_, cz_, r2_, c_prime_;
  // Columns [col_lo_, col_hi_] whose planes meet sphere i (empty when col_lo_ > col_hi_).
  std::vector<int> col_lo_, col_hi_;
  // Spheres whose rows hold row y, in the order sent: row_spheres_[row_start_[y] .. row_start_[y + 1]).
  std::vector<int> row_start_;
  std::vector<int> row_spheres_;
  // The hierarchy of balls around the spheres, for reflected rays (ball_tree.h).
  BallTree balls_;
  // The artix preset's world (its units' own search and cull, artix_units.h): none of the above is used.
  artix::UnitWorld units_;
};

}  // namespace tripsitter::device

// The artix path preset's per-sample function (docs/device.md, "Path tracing on the artix datapath"): the path
// preset's materials, rules and random streams (path_kernel.h: scatter, sky_light, PathRng) on the artix preset's
// geometry (artix_kernel.h), so that its rays go through the sphere units sized to the DSP48E1.
//
// A path ray is a UnitRay (a raw origin, a unit direction times 2^17), the sphere it leaves and whether it went
// into it. Its closest hit is the sphere units' over every sphere but the one it leaves, and when it is inside that
// one, the far root t = b + s 2^e of it competes (ties to the lower index, as the path preset's). At a hit the
// bounce takes the hit point o + round(t) d (the reflection's, to the position grid) and the outward unit normal
// (the reflection's n, with the far root's sign for a far-side hit), both as the units compute them; scatter()
// then works in the path preset's 2^14 unit vectors (the normal and the incoming direction rounded to them), and
// its new direction is normalised back to 2^17 (approx::unit at 17 bits: the same reciprocal square-root table,
// one more multiply's worth of precision kept). A dielectric of index 1 passes the ray on unchanged.
//
// The square roots the bounce takes (the random unit vector's rho, the refraction's; inputs up to 2^28) are the
// exact digit recurrence with a rounding bit, round(sqrt(q)) (docs/device.md, "Approximations": the candidate as
// close as the path preset's square-root unit, which gives the same on these inputs, with the artix datapath's
// kind of unit, ts_artix_isqrt). Every value the path preset checks is checked against the same widths
// (TRIPSITTER_CHECK_FIXED).
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include <tripsitter/core/isqrt.h>
#include <tripsitter/device/artix_kernel.h>
#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/worker.h>

namespace tripsitter::device::artix {

// The bounce's arithmetic: the path preset's width checks, and square roots rounded to nearest.
struct PathArith {
  FixedArith bounds{SqrtUnit(1), 0};
  void check(core::Int128 v, core::Width which) const { bounds.check(v, which); }
  // round(sqrt(x)) = (floor(sqrt(4x)) + 1) / 2, as sqrt(x) is never k + 1/2 for an integer x.
  core::Int128 sqrt(core::Int128 x) const { return (core::isqrt(static_cast<core::UInt128>(4 * x)) + 1) / 2; }
};
inline const PathArith& path_arith() {
  static const PathArith arith;
  return arith;
}

struct PathUnitRay {
  UnitRay ray;
  int from = -1;      // the sphere the ray leaves, -1 for the camera's
  bool into = false;  // the ray went into `from`
};

struct PathUnitHit {
  int index = -1;
  std::int64_t td = 0;  // t times 2^17
  bool inside = false;  // the far side of the sphere the ray is in
};

// The closest hit of `path` given the closest near hit over every sphere but path.from (closest_hit's, or a
// narrower search's with the same result).
PathUnitHit with_far_side(const PathUnitRay& path, const Hit& near, std::span<const UnitSphere> spheres);

// A direction v (components times 2^14 of a vector of length about 1, v.v >= 64) as a unit vector times 2^17,
// saturated to 18 bits.
Vec3i unit_direction(const approx::Unit3& v);

// What the bounce stage makes of a path's ray at its closest hit, or of its escape (a miss): the sky's light (the
// path's end), the path's end without light (absorbed, or a scattered direction too short to normalise), or the
// path's next ray, written over `path`. The cut at the path's last ray is the unit's, before the stage.
// `throughput` (times 2^16 per channel) takes the surface's albedo at a bounce; the sky's light (times 2^16) goes to
// `light`; draw() is the sample's next random number, asked at most once.
enum class PathStep { kRay, kLight, kAbsorbed };

// A 2^17 unit direction as the path preset's 2^14 unit vector.
inline approx::Unit3 to_unit14(const Vec3i& v) {
  constexpr int kShift = kDirectionFrac - approx::kUnitBits;
  return {approx::round_shift(v[0], kShift), approx::round_shift(v[1], kShift), approx::round_shift(v[2], kShift)};
}

template <class Draw>
PathStep bounce_stage(PathUnitRay& path, const PathUnitHit& hit, std::span<const UnitSphere> spheres,
                      std::span<const PathSurface> surfaces, std::array<std::int64_t, 3>& throughput,
                      std::array<std::int64_t, 3>& light, const Draw& draw, PathCounters& counters,
                      PathBounces& bounces) {
  const PathArith& arith = path_arith();
  if (hit.index < 0) {
    ++counters.sky;
    light = sky_light(arith, throughput, -to_unit14(path.ray.d).y);
    return PathStep::kLight;
  }
  const auto i = static_cast<std::size_t>(hit.index);
  const PathSurface& surface = surfaces[i];
  const approx::Unit3 n = checked(arith, to_unit14(normal(path.ray, spheres[i], hit.inside)), core::Width::kUnitVector);
  const Scattered bounce = scatter(
      arith, surface, n, hit.inside,
      [&] { return checked(arith, to_unit14(path.ray.d), core::Width::kUnitVector); }, draw, counters);
  if (bounce.bounce == Bounce::kAbsorbed) return PathStep::kAbsorbed;
  Vec3i next = path.ray.d;
  if (bounce.bounce == Bounce::kScattered) {
    const approx::Unit3& v = bounce.next;
    if (core::dot(v, v) < 64) {  // shorter than 2^-11, nothing to normalise (a refraction at grazing incidence)
      ++counters.absorbed;
      return PathStep::kAbsorbed;
    }
    checked(arith, v, core::Width::kScattered);
    next = unit_direction(v);
  }
  take_albedo(arith, surface, throughput);
  // In place, field by field: a whole new ray built beside it and copied in would be loaded while its stores are in
  // flight (the fast model's store-forwarding stalls).
  path.ray.o = hit_point(path.ray, hit.td);
  path.ray.d = next;
  path.from = hit.index;
  path.into = bounce.into;
  count_bounce(surface, bounces);
  return PathStep::kRay;
}

// One sample of the pixel (col, row), with the closest-hit search supplied: closest(path) must return
// with_far_side(path, closest_hit(path.ray, spheres, path.from), spheres), or the same from a narrower search
// (the camera's ray: its tile's spheres).
template <class Closest>
PathSample trace_path_sample(int col, int row, std::span<const UnitSphere> spheres,
                             std::span<const PathSurface> surfaces, int depth, PathRng& rng, PathCounters& counters,
                             const Closest& closest) {
  PathSample out;
  PathUnitRay path{{{}, camera_direction(col, row)}, -1, false};
  std::array<std::int64_t, 3> throughput{65536, 65536, 65536};
  ++counters.samples;
  const auto draw = [&] {
    ++counters.draws;
    return rng.next();
  };
  for (int rays = 1;; ++rays) {
    ++counters.rays;
    out.rays = rays;
    const PathUnitHit hit = closest(path);
    if (hit.index >= 0 && rays == depth) {
      ++counters.cut;
      return out;
    }
    if (bounce_stage(path, hit, spheres, surfaces, throughput, out.light, draw, counters, out.bounces) !=
        PathStep::kRay)
      return out;
  }
}

// The plain reference: every pass tests every sphere.
PathSample trace_path_sample(int col, int row, std::span<const UnitSphere> spheres,
                             std::span<const PathSurface> surfaces, int depth, PathRng& rng, PathCounters& counters);

}  // namespace tripsitter::device::artix

// The artix preset's per-pixel function (docs/device.md, "The artix preset"): the mirror model (normal-map
// shading, metals reflect up to max_bounces times) in arithmetic sized to the XC7A100T's DSP48E1 (a 25 x 18
// signed multiplier with a pre-adder and a 48-bit post-adder), so that one (ray, sphere) pair enters a sphere
// unit every cycle and every product of the unit fits one slice.
//
// A ray is a raw origin o and a unit direction d (components times 2^17, 18 bits signed, saturated). The camera's
// rays are the board's (col - 320, row - 240, 320) normalised by a reciprocal square root (a 313-entry seed table
// and one Newton step). Against a sphere (centre c, radius r, raw) the unit uses the geometric form:
//   oc = c - o,  b = d.oc (the distance along the ray to the point nearest the centre),
//   f = oc - b d (the centre's offset from the ray),  D = r^2 - f.f,  t = b - sqrt(D),
// a hit when D >= 0 and t > 0; the closest t wins, ties to the sphere sent first. f.f is taken in each sphere's
// own scale: f / 2^(17 + e) with e = bitlen(r) - 17, so that r scales into [2^16, 2^17) and f into 18 bits (a
// component beyond them is beyond r: a miss), and r^2 / 4^e is prepared once per world. The normal at the hit is
// n = -(f + sqrt(D) d) / r (f corrected for b's rounding); a channel is floor(7 n + 7) clamped to 0..14, an exact
// four-bit quotient. A metal reflects d into d - 2 (d.n) n, n times 2^17 through the reciprocal 1 / r (prepared per
// world), from the hit point o + t d rounded to the position grid, and the reflected ray excludes the sphere it
// leaves; the colour is tinted as the mirror model's (core::tint_colour). Every operation is an integer one here,
// exactly as the hardware does it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/device/worker.h>

namespace tripsitter::device::artix {

inline constexpr int kDirectionFrac = 17;                              // unit vectors: times 2^17
inline constexpr std::int64_t kDirectionMax = (std::int64_t{1} << 17) - 1;  // 18 bits signed
inline constexpr int kScaledRadiusBits = 17;                           // r / 2^e in [2^16, 2^17)
inline constexpr std::int64_t kScaledMax = (std::int64_t{1} << 17) - 1;  // f / 2^(16 + e), saturated to 18 bits
// The formats the datapath is sized for: coordinates of at most 22 bits and radii of at most 21, so that
// oc = c - o (o on a sphere: |o_k| < 2^21 + 2^21) takes at most 24 bits signed, the pre-adder's 25 with room.
inline constexpr int kMaxCoordinateBits = 22;
inline constexpr int kMaxRadiusBits = 21;
// The registers of the sphere unit and the reflection, in bits signed (the RTL's ts_artix_pkg states the same): a
// ray's origin (a hit point: |c| + r + 2 < 2^22 + 2), oc = c - o, b = d.oc rounded, and f = (oc << 17) - b d. The
// kernel checks its values against them (TRIPSITTER_CHECK_FIXED).
inline constexpr int kOriginBits = 24;
inline constexpr int kOcBits = 25;
inline constexpr int kBBits = 25;
inline constexpr int kFBits = 48;
// The reciprocal square root's seed table: entry i - kSeedFirst for n >> 9 = i, n = x^2 + y^2 + 320^2.
inline constexpr int kSeedFirst = 200;  // 102400 >> 9
inline constexpr int kSeedLast = 512;   // 262400 >> 9
inline constexpr int kSeedEntries = kSeedLast - kSeedFirst + 1;

using Vec3i = std::array<std::int64_t, 3>;

// One sphere as a sphere unit reads it: the wire's centre and radius, and the constants prepared once per world
// as the world is written to scene memory.
struct UnitSphere {
  Vec3i c{};              // centre, raw
  std::int64_t r = 1;     // radius, raw, >= 1
  int e = 0;              // bitlen(r) - 17, in -16..4: the sphere's scale
  std::int64_t r2s = 0;   // round(r^2 / 4^e), below 2^34
  std::int64_t rinv = 0;  // round(2^(34 + e) / r), in (2^17, 2^18]: the reflection's 1 / r
  bool metal = false;
  std::array<std::uint8_t, 3> albedo{};
};

// REQUIRES |c_k| < 2^21 and 1 <= r < 2^21.
UnitSphere prepare_sphere(const core::KernelSphere<std::int64_t>& s, const core::KernelSurface& surface);

struct UnitRay {
  Vec3i o{};  // origin, raw (0 for the camera's rays)
  Vec3i d{};  // unit direction, times 2^17
};

// The seed table of the camera rays' reciprocal square root: round-down of 2^25 / sqrt(512 i + 256).
const std::array<std::int64_t, kSeedEntries>& rsqrt_seeds();
// g ~ 2^28 / sqrt(n) for 102400 <= n <= 262400, to about 2^-18.
std::int64_t camera_rsqrt(std::int64_t n);
// The unit direction of the pixel in column col (0..639) and row (0..479), times 2^17.
Vec3i camera_direction(int col, int row);

// What the sphere unit computes of one pair.
struct Quadratic {
  std::int64_t bd = 0;    // d.oc, times 2^17
  Vec3i f{};              // oc - b d, times 2^17 (b rounded to the position grid)
  std::int64_t disc = 0;  // r^2 / 4^e - F.F, F = f / 2^(17 + e) floored (-1 when a component is beyond 18 bits)
  std::int64_t s = 0;     // floor(sqrt(disc)) when disc >= 0
  std::int64_t td = 0;    // b - s 2^e, times 2^17: a hit in front of the origin when disc >= 0 and td > 0
  bool hit() const { return disc >= 0 && td > 0; }
};
inline Quadratic quadratic(const UnitRay& ray, const UnitSphere& s);

struct Hit {
  int index = -1;         // -1: nothing hit in front of the origin
  std::int64_t td = 0;    // t times 2^17
};
// The closest hit over `candidates` (sphere indices, ascending) but `excluded`.
Hit closest_hit(const UnitRay& ray, std::span<const UnitSphere> spheres, std::span<const int> candidates,
                int excluded);
// The closest hit over every sphere but `excluded`: the sphere units' plain search.
Hit closest_hit(const UnitRay& ray, std::span<const UnitSphere> spheres, int excluded);

// The unit normal at the hit of `ray` on `s`, times 2^17 (saturated to 18 bits): at the near root, or with `far`
// at the far root b + s 2^e (a ray inside the sphere; the artix path preset's dielectrics).
Vec3i normal(const UnitRay& ray, const UnitSphere& s, bool far = false);
// The far root's t d of `ray` on `s`, b + s 2^e times 2^17, when the ray meets the sphere; else -1.
std::int64_t far_td(const UnitRay& ray, const UnitSphere& s);
// Whether `ray` meets `bound` ahead of its origin: far_td(ray, bound) > 0 (a hierarchy's bound entered).
inline bool enters(const UnitRay& ray, const UnitSphere& bound);
// The hit point o + round(t) d of `ray` at td > 0, on the position grid: where a reflected ray starts.
Vec3i hit_point(const UnitRay& ray, std::int64_t td);
// The normal-map colour of the hit of `ray` on `s`: floor(7 n_k + 7) clamped to 0..14, exact (a four-bit quotient).
core::Rgb444 normal_colour(const UnitRay& ray, const UnitSphere& s);
// The ray reflected off `s`, which `ray` hits at td (> 0).
UnitRay reflect(const UnitRay& ray, const UnitSphere& s, std::int64_t td);

// The tint's arithmetic (core::tint_colour): products of albedos below 255^6 < 2^48, all non-negative.
struct TintArith {
  using Wide = std::int64_t;
  static int floor_div(Wide n, Wide d) { return static_cast<int>(n / d); }
};

// The colour of pixel (col, row) and its reflections, with the closest-hit search supplied: closest(ray,
// excluded, pass) must return closest_hit(ray, spheres, excluded) (pass 0 is the camera's ray, k after k
// reflections; the fast model narrows the camera's search to its tile's spheres).
template <class ClosestHit>
core::PixelTrace trace_pixel_with(int col, int row, std::span<const UnitSphere> spheres, int max_bounces,
                                  const ClosestHit& closest) {
  UnitRay ray{{}, camera_direction(col, row)};
  int excluded = -1;
  int bounces = 0;
  std::array<std::int64_t, 3> tint{1, 1, 1};  // product of the albedos reflected off
  std::int64_t tint_scale = 1;                // 255^bounces
  core::Rgb444 base = core::kBackground;
  while (true) {
    const Hit hit = closest(ray, excluded, bounces);
    if (hit.index < 0) break;
    const UnitSphere& s = spheres[static_cast<std::size_t>(hit.index)];
    if (!s.metal || bounces >= max_bounces) {
      base = normal_colour(ray, s);
      break;
    }
    ray = reflect(ray, s, hit.td);
    excluded = hit.index;
    ++bounces;
    for (std::size_t k = 0; k < 3; ++k) tint[k] *= s.albedo[k];
    tint_scale *= 255;
  }
  return {core::tint_colour(TintArith{}, base, tint, tint_scale), bounces};
}

// The plain reference: every pass tests every sphere.
core::PixelTrace trace_pixel(int col, int row, std::span<const UnitSphere> spheres, int max_bounces);

// The sphere unit's pair, inline: the fast model calls it for every pair its filter keeps.
namespace kernel_detail {

// Throws core::FixedPointOverflow: `what` needs more than bits + 1 bits signed (artix_kernel.cpp).
[[noreturn]] void width_overflow(int bits, const char* what);

// -2^bits <= v < 2^bits, the range of the (bits + 1)-bit signed operand or register the hardware gives `what`
// (docs/device.md, "The artix preset"). Compiled in with TRIPSITTER_CHECK_FIXED (worker.h).
inline void check(std::int64_t v, int bits, const char* what) {
  if constexpr (kCheckFixed) {
    const std::int64_t limit = std::int64_t{1} << bits;
    if (v < -limit || v >= limit) width_overflow(bits, what);
  }
}

// The unit's pair up to its square root: bd, f and disc.
inline Quadratic discriminant(const UnitRay& ray, const UnitSphere& s) {
  constexpr int D = kDirectionFrac;
  Quadratic q;
  Vec3i oc{};
  for (std::size_t k = 0; k < 3; ++k) {
    oc[k] = s.c[k] - ray.o[k];  // the pre-adder
    check(oc[k], kOcBits - 1, "oc = c - o");
    check(ray.d[k], kDirectionFrac, "a direction");
  }
  q.bd = oc[0] * ray.d[0] + oc[1] * ray.d[1] + oc[2] * ray.d[2];
  const std::int64_t b = (q.bd + (std::int64_t{1} << (D - 1))) >> D;  // to the position grid
  check(b, kBBits - 1, "b");
  const int shift = D + s.e;  // 1..21
  std::int64_t ff = 0;
  bool saturated = false;  // f beyond 2^17 - 1 > r in the sphere's scale: a miss
  for (std::size_t k = 0; k < 3; ++k) {
    q.f[k] = (oc[k] << D) - b * ray.d[k];  // the post-adder: C - A x B
    check(q.f[k], kFBits - 1, "f");
    const std::int64_t scaled = q.f[k] >> shift;
    saturated = saturated || scaled > kScaledMax || scaled < -kScaledMax;
    const std::int64_t operand = std::clamp(scaled, -kScaledMax, kScaledMax);
    ff += operand * operand;
  }
  q.disc = saturated ? -1 : s.r2s - ff;
  return q;
}

// floor(sqrt(disc)), < 2^17: a correctly rounded square root of an integer below 2^52 never reaches the next
// integer, so its floor is exact (core::isqrt's estimate, without the corrections it needs above 2^52).
inline std::int64_t root_of(const Quadratic& q) {
  return static_cast<std::int64_t>(std::sqrt(static_cast<double>(q.disc)));
}

}  // namespace kernel_detail

inline Quadratic quadratic(const UnitRay& ray, const UnitSphere& s) {
  Quadratic q = kernel_detail::discriminant(ray, s);
  if (q.disc < 0) return q;
  q.s = kernel_detail::root_of(q);
  q.td = q.bd - (q.s << (kDirectionFrac + s.e));
  return q;
}

inline bool enters(const UnitRay& ray, const UnitSphere& bound) {
  const Quadratic q = kernel_detail::discriminant(ray, bound);
  // The far root b + s 2^e is above 0 when b is, whatever s: the square root only for a ray pointing away.
  return q.disc >= 0 && (q.bd > 0 || q.bd + (kernel_detail::root_of(q) << (kDirectionFrac + bound.e)) > 0);
}

}  // namespace tripsitter::device::artix

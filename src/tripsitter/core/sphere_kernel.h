// The per-pixel function of the board, written once for every arithmetic (SPEC.md section B, report
// table 1 and section 7.1.3): rays against spheres, normal-map shading, and mirror reflection off metals.
//
// A ray leaves o along d; for each sphere (centre c, radius r), with oc = c - o:
//   a = d.d,  b = 2 d.oc,  c' = oc.oc - r^2,  D = b^2 - 4 a c'
// no hit when D < 0, else the near distance is t = (b - sqrt(D)) / (2a). The closest t > 0 wins.
// The unit normal at the hit, n = (t d - oc) / r, is the colour: channel_k = floor(7 n_k + 7), clamped to 0..14.
// A primary ray has o = 0, and then these are exactly the board's formulas.
//
// Everything is kept as ratios so that no division happens before the colour: with num = b - sqrt(D),
// t = num / (2a) and n_k = (num d_k - 2a oc_k) / (2a r). Because a is the same for every sphere of a
// ray, comparing num compares t. In fixed point, positions carry 2^-F and the formulas are homogeneous in
// that scale, so the kernel never needs to know F: only the host's rounding does.
//
// The quadratic is written once, in discriminant and hit_num (from a, b and c' to num; far_hit_num takes the
// other root for the device's path preset). closest_hit runs sphere_num for each sphere, which computes b and c'
// (sphere_coefficients) and calls hit_num; the device's fast model calls hit_num itself with
// coefficients it shares among many rays (device/fast_tracer.h), so both run the same steps and checks.
//
// The mirror model (docs/device.md): a ray that hits a metal, while fewer than max_bounces reflections
// have been traced, reflects and the pixel takes the colour of the reflected ray times the metal's albedo;
// a metal hit at the cut-off is shaded with its normal-map colour. Channel = floor(base * prod(albedo_i) /
// 255^k) over the k metals reflected off, exact in integers. The reflection, at the hit point
// p = o + num d / (2a) (rounded to the position grid in fixed point) with m = p - c:
//   r = d (m.m) - 2 (d.m) m           (the mirror image of d, scaled by m.m: no square root, no division)
// then scaled by a power of two so that its largest component is at most 2^kDirectionBits. The reflected
// ray excludes the sphere it leaves: a ray reflected off the outside of a convex sphere never meets it
// again, so no epsilon is needed against self-intersection.
//
// The Arith policy supplies the number types and the non-ring operations:
//   typename Arith::Coord        sphere coordinates and radius (raw fixed point, or double)
//   typename Arith::Wide         products and sums of products (128-bit integer, or double)
//   arith.sqrt(Square D)         D >= 0; sqrt(D) as anything Wide is made from
//   int  Arith::floor_div(Wide n, Wide d)      d > 0; floor(n / d), saturated to the int range
//   Wide Arith::round_div(Wide n, Wide d)      d > 0; n / d on the position grid: to nearest, or exact
//   Vec3<Wide> Arith::scale_direction(Vec3<Wide> r)   r times 2^-s, s >= 0 the least making max |r_k| <= 2^20
// (a policy used only for closest hits and shading needs neither round_div nor scale_direction, which only
// reflect calls)
// and optionally
//   typename Arith::Square       b^2, 4ac' and D, when they need more than Wide (default: Wide). The device's
//                                fast model sums in 64 bits and squares in 128 (device/fast_tracer.h).
//   void arith.check(v, Width which)           checks v (a Wide or a Square) against the bound of `which`
// (the device's fixed point checks the widths docs/device.md gives, in builds with TRIPSITTER_CHECK_FIXED).
// Every intermediate is checked before it enters a product, so a check sees the true value, never a
// wrapped one.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/core/vec.h>

namespace tripsitter::core {

// Reflected directions are scaled down to at most this many bits per component (only the direction matters).
inline constexpr int kDirectionBits = 20;
// The bounce cut-off's upper limit: the colour mix base * prod(albedo) stays below 14 * 255^6 < 2^53, so the
// double instantiation computes it as exactly as the integer one.
inline constexpr int kMaxBounces = 6;

// The intermediates with a documented bound (docs/device.md, "Widths").
enum class Width {
  kCentre,        // c_k of scene memory
  kRadius,        // r of scene memory (and r >= 1)
  kOrigin,        // o_k, a ray's origin: 0 or a hit point
  kDirection,     // d_k
  kToCentre,      // oc_k = c_k - o_k
  kA,             // a = d.d
  kB,             // b = 2 d.oc
  kCPrime,        // c' = oc.oc - r^2
  kSquare,        // b^2, 4ac'
  kDisc,          // D = b^2 - 4ac'
  kNum,           // num = b - sqrt(D)
  kNumTimesD,     // num d_k, and n_num = num d_k - 2a oc_k
  kShadeDen,      // den = 2a r (and den >= 1)
  kShadeSum,      // 7 n_num + 7 den
  kHitNormal,     // m_k = p_k - c_k
  kNormalSquare,  // m.m
  kDirNormal,     // d.m
  kReflected,     // r_k = d_k (m.m) - 2 (d.m) m_k
  kTint,          // base channel * prod(albedo), and 255^bounces
  // The device's path preset (device/path_kernel.h), whose formats are at most 24 bits wide:
  kUnitVector,    // a unit vector's component, times 2^14
  kScattered,     // a scattered direction's component
  kRefractPerp,   // eta (d^ + cos n_f), the refracted direction's part across the normal
  kRadicand,      // 2^28 - |perp|^2, under the refraction's square root
  kReflectance,   // Schlick's reflectance and r0, times 2^14
  kThroughput,    // the path's throughput per channel, times 2^16
  kLight,         // throughput times sky per channel, times 2^32 before rounding
  kAccumSum,      // a frame-memory sum of 9-bit samples
};

// Lets arith check v when it has a check member (the device's fixed point); nothing otherwise.
template <class Arith, class V>
void check_width(const Arith& arith, const V& v, Width which) {
  if constexpr (requires { arith.check(v, which); }) arith.check(v, which);
}

// The type of b^2, 4ac' and D: Arith::Square where the policy has one, else Arith::Wide.
template <class Arith>
struct SquareOf {
  using type = typename Arith::Wide;
};
template <class Arith>
  requires requires { typename Arith::Square; }
struct SquareOf<Arith> {
  using type = typename Arith::Square;
};
template <class Arith>
using SquareT = typename SquareOf<Arith>::type;

template <class Coord>
struct KernelSphere {
  Vec3<Coord> center;
  Coord radius{};
};

// What the kernel needs of a sphere's surface.
struct KernelSurface {
  bool metal = false;                      // a mirror; every other material is normal-map shaded
  std::array<std::uint8_t, 3> albedo{};    // 0..255 stands for 0..1 (the v2 wire's bytes)
};

template <class Wide>
struct KernelRay {
  Vec3<Wide> origin;     // raw position (0 for the camera's rays)
  Vec3<Wide> direction;  // any length; integer pixel coordinates for the camera's rays
};

template <class Wide>
struct KernelHit {
  int index = -1;  // closest sphere, -1 when nothing is hit in front of the ray's origin
  Wide num{};      // b - sqrt(D) of that sphere: t * 2a
};

// What a pixel came to: its colour and how many reflections were traced for it (the passes over the
// spheres are bounces + 1; the device's schedule depends on it).
struct PixelTrace {
  Rgb444 colour;
  int bounces = 0;
};

// The discriminant D = b^2 - 4ac' of one ray and one sphere, from its coefficients a = d.d, b = 2 d.oc and
// c' = oc.oc - r^2, every step checked: negative when the ray's line misses the sphere. REQUIRES a checked (kA).
template <class Arith>
inline SquareT<Arith> discriminant(const Arith& arith, typename Arith::Wide a, typename Arith::Wide b,
                                   typename Arith::Wide c_prime) {
  using Wide = typename Arith::Wide;
  using Square = SquareT<Arith>;
  check_width(arith, b, Width::kB);
  check_width(arith, c_prime, Width::kCPrime);
  const Square b2 = Square(b) * Square(b);
  const Square ac4 = Square(Wide(4) * a) * Square(c_prime);
  check_width(arith, b2, Width::kSquare);
  check_width(arith, ac4, Width::kSquare);
  const Square disc = b2 - ac4;
  check_width(arith, disc, Width::kDisc);
  return disc;
}

// The quadratic of one ray and one sphere, from its coefficients (each caller computes them its own way:
// sphere_num below, or the device's fast model from terms it shares among many rays). The result is > 0 exactly
// when the ray hits the sphere in front of its origin, and then it is num = b - sqrt(D). Otherwise it is <= 0: 0
// when the ray misses (D < 0), b - sqrt(D) when it meets the sphere only behind its origin or starts inside it.
// REQUIRES a checked (kA).
template <class Arith>
inline typename Arith::Wide hit_num(const Arith& arith, typename Arith::Wide a, typename Arith::Wide b,
                                    typename Arith::Wide c_prime) {
  using Wide = typename Arith::Wide;
  const SquareT<Arith> disc = discriminant(arith, a, b, c_prime);
  if (disc < SquareT<Arith>(0)) return Wide(0);
  const Wide num = b - Wide(arith.sqrt(disc));
  check_width(arith, num, Width::kNum);
  return num;  // <= 0: the near intersection is behind the origin (or the origin is inside)
}

// The far intersection's num = b + sqrt(D), for a ray inside the sphere (the device's path preset, whose
// refracted rays travel inside dielectrics): > 0 exactly when the line meets the sphere ahead of the origin's
// far side; 0 when it misses (D < 0). REQUIRES a checked (kA).
template <class Arith>
inline typename Arith::Wide far_hit_num(const Arith& arith, typename Arith::Wide a, typename Arith::Wide b,
                                        typename Arith::Wide c_prime) {
  using Wide = typename Arith::Wide;
  const SquareT<Arith> disc = discriminant(arith, a, b, c_prime);
  if (disc < SquareT<Arith>(0)) return Wide(0);
  const Wide num = b + Wide(arith.sqrt(disc));
  check_width(arith, num, Width::kNum);
  return num;
}

// b = 2 d.oc and c' = oc.oc - r^2 of the ray against sphere s, its centre, radius and oc = c - o checked.
template <class Arith>
inline std::array<typename Arith::Wide, 2> sphere_coefficients(const Arith& arith,
                                                              const KernelRay<typename Arith::Wide>& ray,
                                                              const KernelSphere<typename Arith::Coord>& s) {
  using Wide = typename Arith::Wide;
  const Vec3<Wide>& d = ray.direction;
  const Vec3<Wide>& o = ray.origin;
  for (int k = 0; k < 3; ++k) check_width(arith, Wide(s.center[k]), Width::kCentre);
  check_width(arith, Wide(s.radius), Width::kRadius);
  const Vec3<Wide> oc{Wide(s.center.x) - o.x, Wide(s.center.y) - o.y, Wide(s.center.z) - o.z};
  for (int k = 0; k < 3; ++k) check_width(arith, oc[k], Width::kToCentre);
  const Wide r = Wide(s.radius);
  return {Wide(2) * dot(d, oc), dot(oc, oc) - r * r};
}

// The ray against sphere s: hit_num of its coefficients, > 0 exactly when the ray hits s in front of its
// origin, and then num = b - sqrt(D) (t = num / 2a). a = d.d of the ray, checked (kA).
template <class Arith>
inline typename Arith::Wide sphere_num(const Arith& arith, const KernelRay<typename Arith::Wide>& ray,
                                       typename Arith::Wide a, const KernelSphere<typename Arith::Coord>& s) {
  const auto [b, c_prime] = sphere_coefficients(arith, ray, s);
  return hit_num(arith, a, b, c_prime);
}

// Closest hit along the ray over all spheres but `excluded` (-1: none). Ties go to the lower index.
// Flattened (sphere_num and hit_num inlined into the loop): without it GCC compiles the plain worker's search
// to about 5% more instructions than the same steps written out in the loop. (Forcing hit_num inline
// everywhere instead slows the fast model's loops, which GCC inlines well by itself.)
template <class Arith>
[[gnu::flatten]] KernelHit<typename Arith::Wide> closest_hit(
    const Arith& arith, const KernelRay<typename Arith::Wide>& ray,
    std::span<const KernelSphere<typename Arith::Coord>> spheres, int excluded = -1) {
  using Wide = typename Arith::Wide;
  const Vec3<Wide>& d = ray.direction;
  const Vec3<Wide>& o = ray.origin;
  for (int k = 0; k < 3; ++k) {
    check_width(arith, o[k], Width::kOrigin);
    check_width(arith, d[k], Width::kDirection);
  }
  const Wide a = dot(d, d);
  check_width(arith, a, Width::kA);
  KernelHit<Wide> best;
  for (int i = 0; i < static_cast<int>(spheres.size()); ++i) {
    if (i == excluded) continue;
    const Wide num = sphere_num(arith, ray, a, spheres[static_cast<std::size_t>(i)]);
    if (!(num > Wide(0))) continue;  // a miss, or a hit behind the ray's origin
    if (best.index < 0 || num < best.num) best = {i, num};
  }
  return best;
}

// Normal-map colour of a hit (SPEC.md section B).
template <class Arith>
Rgb444 normal_colour(const Arith& arith, const KernelRay<typename Arith::Wide>& ray,
                     const KernelSphere<typename Arith::Coord>& s, typename Arith::Wide num) {
  using Wide = typename Arith::Wide;
  const Vec3<Wide>& d = ray.direction;
  const Wide two_a = Wide(2) * dot(d, d);
  const Wide den = two_a * Wide(s.radius);
  check_width(arith, den, Width::kShadeDen);
  int ch[3];
  for (int k = 0; k < 3; ++k) {
    const Wide num_d = num * d[k];
    check_width(arith, num_d, Width::kNumTimesD);
    const Wide n_num = num_d - two_a * (Wide(s.center[k]) - ray.origin[k]);  // n_k = n_num / den
    check_width(arith, n_num, Width::kNumTimesD);
    const Wide sum = Wide(7) * n_num + Wide(7) * den;
    check_width(arith, sum, Width::kShadeSum);
    ch[k] = std::clamp(Arith::floor_div(sum, den), 0, 14);
  }
  return Rgb444::from_channels(ch[0], ch[1], ch[2]);
}

// The ray reflected off sphere s, which `ray` hits with `num` (from closest_hit).
template <class Arith>
KernelRay<typename Arith::Wide> reflect(const Arith& arith, const KernelRay<typename Arith::Wide>& ray,
                                        const KernelSphere<typename Arith::Coord>& s, typename Arith::Wide num) {
  using Wide = typename Arith::Wide;
  const Vec3<Wide>& d = ray.direction;
  const Wide two_a = Wide(2) * dot(d, d);
  Vec3<Wide> p, m;
  for (int k = 0; k < 3; ++k) {
    const Wide num_d = num * d[k];
    check_width(arith, num_d, Width::kNumTimesD);
    p[k] = ray.origin[k] + Arith::round_div(num_d, two_a);  // the hit point o + t d
    check_width(arith, p[k], Width::kOrigin);
    m[k] = p[k] - Wide(s.center[k]);  // the outward normal, length about r
    check_width(arith, m[k], Width::kHitNormal);
  }
  const Wide mm = dot(m, m);
  const Wide dm = dot(d, m);
  check_width(arith, mm, Width::kNormalSquare);
  check_width(arith, dm, Width::kDirNormal);
  Vec3<Wide> r;
  for (int k = 0; k < 3; ++k) {
    r[k] = d[k] * mm - Wide(2) * dm * m[k];
    check_width(arith, r[k], Width::kReflected);
  }
  return {p, Arith::scale_direction(r)};
}

// The mirror model's colour after k reflections: channel = floor(base * prod(albedo) / 255^k) over the metals
// reflected off (tint = prod(albedo) per channel, tint_scale = 255^k), exact in integers; base itself when
// nothing was reflected (tint_scale 1).
template <class Arith>
Rgb444 tint_colour(const Arith& arith, Rgb444 base, const std::array<typename Arith::Wide, 3>& tint,
                   typename Arith::Wide tint_scale) {
  using Wide = typename Arith::Wide;
  if (tint_scale == Wide(1)) return base;
  const std::array<int, 3> channels{base.r(), base.g(), base.b()};
  std::array<int, 3> mixed{};
  for (std::size_t k = 0; k < 3; ++k) {
    const Wide tinted = Wide(channels[k]) * tint[k];
    check_width(arith, tinted, Width::kTint);
    check_width(arith, tint_scale, Width::kTint);
    mixed[k] = std::clamp(Arith::floor_div(tinted, tint_scale), 0, 15);
  }
  return Rgb444::from_channels(mixed[0], mixed[1], mixed[2]);
}

// The colour of the camera's ray along d in the mirror model, with the closest-hit search supplied:
// closest(ray, excluded, pass) must return closest_hit(arith, ray, spheres, excluded) for an Arith of this
// Wide, where pass is 0 for the camera's ray and k after k reflections. surface_of(i) gives sphere i's
// KernelSurface. (The device's fast model supplies exact shortcuts; trace_pixel below the plain search.)
// REQUIRES 0 <= max_bounces <= kMaxBounces.
template <class Arith, class SurfaceOf, class ClosestHit>
PixelTrace trace_pixel_with(const Arith& arith, const Vec3<typename Arith::Wide>& d,
                            std::span<const KernelSphere<typename Arith::Coord>> spheres, const SurfaceOf& surface_of,
                            Rgb444 background, int max_bounces, const ClosestHit& closest) {
  using Wide = typename Arith::Wide;
  KernelRay<Wide> ray{{}, d};
  int excluded = -1;
  int bounces = 0;
  std::array<Wide, 3> tint{Wide(1), Wide(1), Wide(1)};  // product of the albedos reflected off
  Wide tint_scale(1);                                  // 255^bounces
  Rgb444 base = background;
  while (true) {
    const KernelHit<Wide> hit = closest(ray, excluded, bounces);
    if (hit.index < 0) break;
    const auto& s = spheres[static_cast<std::size_t>(hit.index)];
    const KernelSurface surface = surface_of(hit.index);
    if (!surface.metal || bounces >= max_bounces) {
      base = normal_colour(arith, ray, s, hit.num);
      break;
    }
    ray = reflect(arith, ray, s, hit.num);
    excluded = hit.index;
    ++bounces;
    for (std::size_t k = 0; k < 3; ++k) tint[k] = tint[k] * Wide(surface.albedo[k]);
    tint_scale = tint_scale * Wide(255);
  }
  return {tint_colour(arith, base, tint, tint_scale), bounces};
}

// The colour of the camera's ray along d in the mirror model. surface_of(i) gives sphere i's KernelSurface.
// REQUIRES 0 <= max_bounces <= kMaxBounces.
template <class Arith, class SurfaceOf>
PixelTrace trace_pixel(const Arith& arith, const Vec3<typename Arith::Wide>& d,
                       std::span<const KernelSphere<typename Arith::Coord>> spheres, const SurfaceOf& surface_of,
                       Rgb444 background, int max_bounces) {
  return trace_pixel_with(arith, d, spheres, surface_of, background, max_bounces,
                                 [&](const KernelRay<typename Arith::Wide>& ray, int excluded, int) {
                                   return closest_hit(arith, ray, spheres, excluded);
                                 });
}

}  // namespace tripsitter::core

#include <tripsitter/device/artix_kernel.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <string>

#include <tripsitter/core/isqrt.h>
#include <tripsitter/device/worker.h>

namespace tripsitter::device::artix {
namespace {

using kernel_detail::check;

int bit_length(std::uint64_t v) { return 64 - std::countl_zero(v); }

std::int64_t dot(const Vec3i& a, const Vec3i& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

}  // namespace

void kernel_detail::width_overflow(int bits, const char* what) {
  throw core::FixedPointOverflow(std::string("artix datapath: ") + what + " needs more than " +
                                 std::to_string(bits + 1) + " bits signed (docs/device.md, The artix preset)");
}

UnitSphere prepare_sphere(const core::KernelSphere<std::int64_t>& s, const core::KernelSurface& surface) {
  UnitSphere u;
  u.c = {s.center.x, s.center.y, s.center.z};
  for (const std::int64_t c : u.c) check(c, kMaxCoordinateBits - 1, "a centre");
  u.r = s.radius;
  check(u.r, kMaxRadiusBits, "a radius");
  assert(u.r >= 1);
  u.e = bit_length(static_cast<std::uint64_t>(u.r)) - kScaledRadiusBits;  // -16..4
  const auto r2 = static_cast<std::uint64_t>(u.r) * static_cast<std::uint64_t>(u.r);
  u.r2s = u.e <= 0 ? static_cast<std::int64_t>(r2 << (-2 * u.e))
                   : static_cast<std::int64_t>((r2 + (std::uint64_t{1} << (2 * u.e - 1))) >> (2 * u.e));
  const int shift = 34 + u.e;  // 18..38
  u.rinv = static_cast<std::int64_t>(((std::uint64_t{1} << shift) + static_cast<std::uint64_t>(u.r) / 2) /
                                     static_cast<std::uint64_t>(u.r));
  u.metal = surface.metal;
  u.albedo = surface.albedo;
  return u;
}

const std::array<std::int64_t, kSeedEntries>& rsqrt_seeds() {
  static const std::array<std::int64_t, kSeedEntries> seeds = [] {
    std::array<std::int64_t, kSeedEntries> t{};
    for (int i = kSeedFirst; i <= kSeedLast; ++i) {
      const std::uint64_t middle = std::uint64_t{512} * static_cast<std::uint64_t>(i) + 256;
      t[static_cast<std::size_t>(i - kSeedFirst)] =
          static_cast<std::int64_t>(core::isqrt((std::uint64_t{1} << 50) / middle));
    }
    return t;
  }();
  return seeds;
}

std::int64_t camera_rsqrt(std::int64_t n) {
  assert(n >= std::int64_t{kSeedFirst} << 9 && n < std::int64_t{kSeedLast + 1} << 9);
  const std::int64_t y0 = rsqrt_seeds()[static_cast<std::size_t>((n >> 9) - kSeedFirst)];  // 17 bits, ~2^25 / sqrt(n)
  const std::int64_t sq = y0 * y0;                                                         // 34 bits, ~2^50 / n
  const std::int64_t e = static_cast<std::int64_t>((static_cast<core::Int128>(n) * sq) >> 30);  // ~2^20
  // y0 (3 - n y0^2) / 2, times 2^3. The step never overshoots and both shifts floor, so g is low: the 1 added
  // to 3 2^20 centres it (the directions' mean length over the screen 1 - 7.7e-7 without it, 1 - 2.9e-7 with
  // it; docs/device.md).
  return (y0 * ((std::int64_t{3} << 20) + 1 - e)) >> 18;
}

Vec3i camera_direction(int col, int row) {
  const auto v = core::device_ray<std::int64_t>(col, row);
  const std::int64_t g = camera_rsqrt(v.x * v.x + v.y * v.y + v.z * v.z);  // 2^28 / |v|
  constexpr int shift = 28 - kDirectionFrac;
  constexpr std::int64_t half = std::int64_t{1} << (shift - 1);
  Vec3i d{};
  const std::int64_t v3[3] = {v.x, v.y, v.z};
  for (std::size_t k = 0; k < 3; ++k) d[k] = std::clamp((v3[k] * g + half) >> shift, -kDirectionMax, kDirectionMax);
  return d;
}

namespace {

// The closest hit over the spheres index(0), ..., index(count - 1) (ascending) but `excluded`: the least t, ties to
// the lower index.
template <class Index>
Hit closest_over(const UnitRay& ray, std::span<const UnitSphere> spheres, std::size_t count, const Index& index,
                 int excluded) {
  Hit best;
  for (std::size_t j = 0; j < count; ++j) {
    const int i = index(j);
    if (i == excluded) continue;
    const Quadratic q = quadratic(ray, spheres[static_cast<std::size_t>(i)]);
    if (!q.hit()) continue;
    if (best.index < 0 || q.td < best.td) best = {i, q.td};
  }
  return best;
}

}  // namespace

Hit closest_hit(const UnitRay& ray, std::span<const UnitSphere> spheres, std::span<const int> candidates,
                int excluded) {
  return closest_over(ray, spheres, candidates.size(), [&](std::size_t j) { return candidates[j]; }, excluded);
}

Hit closest_hit(const UnitRay& ray, std::span<const UnitSphere> spheres, int excluded) {
  return closest_over(ray, spheres, spheres.size(), [](std::size_t j) { return static_cast<int>(j); }, excluded);
}

namespace {

// The normal at the hit of `ray` on `s` as exact integers: n_k = Q_k / R, with Q_k = -(f_k 2^z + s d_k 2^(e + z))
// and R = r 2^(D + z), z = max(0, -e) (so R = r_s 2^(D + max(e, 0))); at the far root p - c = -(f - s d), so the
// second term's sign turns.
Vec3i scaled_normal(const UnitRay& ray, const UnitSphere& s, std::int64_t& scale, bool far = false) {
  constexpr int D = kDirectionFrac;
  const Quadratic q = quadratic(ray, s);
  assert(q.disc >= 0);
  const int z = std::max(0, -s.e);
  scale = s.r << (D + z);
  // f took b rounded to the position grid; b's fraction beta puts back what that moved f along d.
  const std::int64_t beta = q.bd - (((q.bd + (std::int64_t{1} << (D - 1))) >> D) << D);  // in [-2^(D-1), 2^(D-1))
  Vec3i n{};
  for (std::size_t k = 0; k < 3; ++k) {
    const std::int64_t f = q.f[k] - ((beta * ray.d[k]) >> D);
    const std::int64_t along = (q.s * ray.d[k]) << (s.e + z);
    n[k] = -((f << z) + (far ? -along : along));
    check(n[k], 40, "a normal's numerator");
  }
  return n;
}

}  // namespace

Vec3i normal(const UnitRay& ray, const UnitSphere& s, bool far) {
  constexpr int D = kDirectionFrac;
  std::int64_t scale = 0;
  const Vec3i q = scaled_normal(ray, s, scale, far);
  Vec3i n{};
  for (std::size_t k = 0; k < 3; ++k) {
    const std::int64_t top = q[k] >> (D + std::max(s.e, 0) + 1);  // n_k r_s / 2: 18 bits signed
    check(top, 17, "the normal's operand");
    n[k] = std::clamp((top * s.rinv) >> (33 - D), -kDirectionMax, kDirectionMax);  // rinv = 2^34 / r_s
  }
  return n;
}

core::Rgb444 normal_colour(const UnitRay& ray, const UnitSphere& s) {
  // floor(7 n + 7) = floor(7 (Q + R) / R): a four-bit quotient, four compare-and-subtract steps.
  std::int64_t scale = 0;
  const Vec3i q = scaled_normal(ray, s, scale);
  int ch[3];
  for (std::size_t k = 0; k < 3; ++k) {
    const std::int64_t num = 7 * (q[k] + scale);
    ch[k] = num < 0 ? 0 : static_cast<int>(std::min<std::int64_t>(num / scale, 14));
  }
  return core::Rgb444::from_channels(ch[0], ch[1], ch[2]);
}

std::int64_t far_td(const UnitRay& ray, const UnitSphere& s) {
  const Quadratic q = quadratic(ray, s);
  return q.disc < 0 ? -1 : q.bd + (q.s << (kDirectionFrac + s.e));
}

Vec3i hit_point(const UnitRay& ray, std::int64_t td) {
  constexpr int D = kDirectionFrac;
  assert(td > 0);
  const std::int64_t t = (td + (std::int64_t{1} << (D - 1))) >> D;
  check(t, 24, "t");
  Vec3i p{};
  for (std::size_t k = 0; k < 3; ++k) {
    p[k] = ray.o[k] + ((t * ray.d[k] + (std::int64_t{1} << (D - 1))) >> D);
    check(p[k], kOriginBits - 1, "a hit point");
  }
  return p;
}

UnitRay reflect(const UnitRay& ray, const UnitSphere& s, std::int64_t td) {
  constexpr int D = kDirectionFrac;
  const Vec3i n = normal(ray, s);
  UnitRay out;
  out.o = hit_point(ray, td);
  // |d|, |n| <= 1 + 2^-16 or so: d.n may pass 1 by a few units, and the product's 18-bit operand saturates.
  const std::int64_t dn = std::clamp(dot(ray.d, n) >> D, -kDirectionMax, kDirectionMax);
  for (std::size_t k = 0; k < 3; ++k) {
    const std::int64_t twice = (dn * n[k] + (std::int64_t{1} << (D - 2))) >> (D - 1);  // 2 (d.n) n_k
    out.d[k] = std::clamp(ray.d[k] - twice, -kDirectionMax, kDirectionMax);
  }
  return out;
}

core::PixelTrace trace_pixel(int col, int row, std::span<const UnitSphere> spheres, int max_bounces) {
  return trace_pixel_with(col, row, spheres, max_bounces,
                          [&](const UnitRay& ray, int excluded, int) { return closest_hit(ray, spheres, excluded); });
}

}  // namespace tripsitter::device::artix

// The path preset's worker: one sample of a pixel as a path through the world, in the device's fixed point
// (docs/device.md, "The path preset"). The report's section 7 done on the device: lambertian surfaces drawn
// from an xorshift generator, fuzzed metal, dielectrics (Snell, total internal reflection, Schlick), several
// bounces with a cut-off, the colour carried as an integer throughput, the sky as light.
//
// Geometry is the mirror model's (core/sphere_kernel.h): a ray is a raw origin and an integer direction of any
// length; the closest hit compares num = t * 2a. A path ray also knows the sphere it leaves (`from`) and
// whether it went into it (`into`, a refracted ray or one reflected inside a dielectric). The closest-hit
// search skips `from` (a ray leaving a convex sphere outwards never meets it again, so no epsilon is needed
// against self-intersection) and, for a ray inside `from`, adds `from`'s far intersection, num = b + sqrt(D)
// (far_hit below). A sphere that holds a ray's origin without the ray having entered it is not seen, as on the
// board (num = b - sqrt(D) <= 0): nested dielectrics are approximated (the float path tracer sees them).
//
// One bounce, at the hit point p = o + num d / 2a (rounded to the position grid, as the mirror model does):
// n = unit(p - c), the outward normal; then by material
//   lambertian  d' = n + u, u uniform on the unit sphere (n itself when the sum is shorter than 2^-6)
//   metal       d' = r + fuzz u, r = d^ - 2 (d^.n) n; absorbed (the path ends black) when d'.n <= 0
//   dielectric  eta = 1/ior entering, ior leaving; cos = -d^.n_f with n_f the normal facing the ray;
//               total internal reflection when eta^2 (1 - cos^2) > 1; otherwise reflect when a 14-bit draw
//               is below Schlick's r0 + (1 - r0)(1 - cos)^5, else refract: d' = eta (d^ + cos n_f)
//               - sqrt(|1 - |eta (d^ + cos n_f)|^2|) n_f. ior exactly 1 goes straight on.
// and the throughput takes the albedo. A path that leaves the world takes the sky's colour of its direction;
// one still bouncing after `depth` rays is black (the float path tracer's max_depth).
//
// Formats: unit vectors, cosines and reflectances times 2^14 (approx.h); the throughput and light per channel
// times 2^16 (1.0 = 65536); an albedo byte a as (257 a + a/128) / 2^16, so 255 is exactly 1 and every byte is
// within 2^-16 of a / 255.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>

#include <tripsitter/core/fixed.h>
#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/device/approx.h>
#include <tripsitter/device/frame_memory.h>
#include <tripsitter/device/path_rng.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/device/worker.h>
#include <tripsitter/link/frame.h>

namespace tripsitter::device {

// A hit of a path ray: the sphere, num = t * 2a, and whether it is the far side of the sphere the ray is in.
struct PathHit {
  int index = -1;
  core::Int128 num = 0;
  bool inside = false;
};

// The ray of a path: where it starts, where it goes, and the sphere it leaves.
struct PathRay {
  core::KernelRay<core::Int128> ray;
  int from = -1;      // the sphere the ray leaves, -1 for the camera's
  bool into = false;  // the ray went into `from` (it meets `from` again only from inside)
};

// Per sphere, what the dielectric needs, computed as the world enters scene memory (one division each):
// eta entering and leaving (times 2^14) and Schlick's r0 = ((ior - 1)/(ior + 1))^2 (times 2^14).
struct PathSurface {
  std::uint8_t material = link::kMaterialLambertian;
  std::array<std::uint32_t, 3> albedo{};  // a * 257 + a/128: 0..65536, times 2^-16
  std::uint16_t fuzz = 0;                 // times 2^-16
  bool passes_straight = false;           // ior exactly 1
  std::int64_t eta_enter = 0, eta_leave = 0, r0 = 0;
};

// The supported indices of refraction, in the wire's u4.12: 0.25 to 8. The receiver refuses others and the
// host saturates to them (docs/device.md, "The path preset").
inline constexpr std::uint16_t kPathIorMin = 1024;
inline constexpr std::uint16_t kPathIorMax = 32768;

PathSurface path_surface(const SurfaceWord& word);

// Bounces that led to another ray, by the material that scattered them (their cycle costs differ).
struct PathBounces {
  int lambertian = 0, metal = 0, dielectric = 0;
  int total() const { return lambertian + metal + dielectric; }
  PathBounces& operator+=(const PathBounces& o) {
    lambertian += o.lambertian;
    metal += o.metal;
    dielectric += o.dielectric;
    return *this;
  }
};

// What one sample came to.
struct PathSample {
  std::array<std::int64_t, 3> light{};  // times 2^16
  int rays = 0;                         // closest-hit passes over the spheres: bounces.total() + 1
  PathBounces bounces;
};

// Counts of what the worker did, for the operation ledger (docs/device.md, "Operations").
struct PathCounters {
  std::uint64_t samples = 0, rays = 0, lambertian = 0, metal = 0, dielectric = 0, refracted = 0, absorbed = 0,
                sky = 0, cut = 0, draws = 0;
  PathCounters& operator+=(const PathCounters& o);
};

// The far intersection of `ray` with sphere s, num = b + sqrt(D), when the ray is inside it (core::far_hit_num).
template <class Arith>
core::Int128 far_num(const Arith& arith, const core::KernelRay<core::Int128>& ray,
                     const core::KernelSphere<std::int64_t>& s) {
  const auto [b, c_prime] = core::sphere_coefficients(arith, ray, s);
  return core::far_hit_num(arith, core::dot(ray.direction, ray.direction), b, c_prime);
}

// The closest hit of a path ray given the closest near hit over every sphere but `from` (core::closest_hit's
// result, or the fast model's): `from`'s far side competes when the ray is inside it; ties go to the lower index.
template <class Arith>
PathHit with_far_side(const Arith& arith, const PathRay& path, core::KernelHit<core::Int128> near,
                             std::span<const core::KernelSphere<std::int64_t>> spheres) {
  PathHit hit{near.index, near.num, false};
  if (!path.into) return hit;
  const core::Int128 far = far_num(arith, path.ray, spheres[static_cast<std::size_t>(path.from)]);
  if (far > 0 && (hit.index < 0 || far < hit.num || (far == hit.num && path.from < hit.index)))
    hit = {path.from, far, true};
  return hit;
}

// The components of v checked against the bound of `which`; v itself.
template <class Arith>
const approx::Unit3& checked(const Arith& arith, const approx::Unit3& v, core::Width which) {
  for (int k = 0; k < 3; ++k) arith.check(v[k], which);
  return v;
}

// approx::unit(v), its components checked (kUnitVector).
template <class Arith>
approx::Unit3 checked_unit(const Arith& arith, const core::Vec3<core::Int128>& v) {
  return checked(arith, approx::unit(v), core::Width::kUnitVector);
}

// The sky's light along a direction whose unit vector's up component (-y, times 2^14) is `up`, times `throughput`
// (times 2^16 each): the float path tracer's blend of white and blue by a = (1 + up)/2.
template <class Arith>
std::array<std::int64_t, 3> sky_light(const Arith& arith, const std::array<std::int64_t, 3>& throughput,
                                      std::int64_t up) {
  using approx::kUnit;
  const std::int64_t a = (kUnit + up + 1) >> 1;  // 0..2^14
  constexpr std::array<std::int64_t, 3> kBottom{65536, 65536, 65536};
  constexpr std::array<std::int64_t, 3> kTop{32768, 45875, 65536};
  std::array<std::int64_t, 3> light{};
  for (std::size_t k = 0; k < 3; ++k) {
    const std::int64_t sky = kBottom[k] + approx::round_shift((kTop[k] - kBottom[k]) * a, approx::kUnitBits);
    arith.check(throughput[k] * sky, core::Width::kLight);
    light[k] = approx::round_shift(throughput[k] * sky, 16);
  }
  return light;
}

// What one bounce does (the header's rules by material): the next ray's direction, not normalised (times 2^14
// for a unit vector), and whether it goes into the sphere; or the ray goes straight on (a dielectric of index 1:
// the caller keeps its direction), or the path is absorbed (fuzz below the surface). `n` is the outward unit
// normal at the hit, `inside` whether the hit is the far side of the sphere the ray is in, incoming() the ray's
// unit direction (asked only by the materials that use it), draw() the sample's next random number. Both path
// tracers of the device take it: the path preset's (below) and the artix path preset's (artix_path.h).
enum class Bounce { kScattered, kStraight, kAbsorbed };
struct Scattered {
  Bounce bounce = Bounce::kScattered;
  approx::Unit3 next;
  bool into = false;
};

template <class Arith, class Incoming, class Draw>
Scattered scatter(const Arith& arith, const PathSurface& surface, const approx::Unit3& n, bool inside,
                  const Incoming& incoming, const Draw& draw, PathCounters& counters) {
  using approx::kUnit;
  using approx::kUnitBits;
  using approx::round_shift;
  using approx::Unit3;
  using core::Int128;
  const auto sqrt = [&arith](Int128 x) { return arith.sqrt(x); };
  Scattered out;
  switch (surface.material) {
    case link::kMaterialMetal: {
      ++counters.metal;
      out.next = approx::reflect(incoming(), n);
      if (surface.fuzz != 0) {
        const Unit3 u = checked(arith, approx::random_unit(draw(), sqrt), core::Width::kUnitVector);
        for (int k = 0; k < 3; ++k) out.next[k] += round_shift(u[k] * surface.fuzz, 16);
      }
      if (core::dot(out.next, n) <= 0) {  // fuzz pushed it below the surface
        ++counters.absorbed;
        out.bounce = Bounce::kAbsorbed;
      }
      return out;
    }
    case link::kMaterialDielectric: {
      ++counters.dielectric;
      const bool front = !inside;
      if (surface.passes_straight) {
        out.bounce = Bounce::kStraight;
        out.into = front;
        return out;
      }
      const Unit3 nf = front ? n : -n;
      const Unit3 in = incoming();
      const std::int64_t cos = std::min(-approx::dot_unit(in, nf), kUnit);
      const std::int64_t eta = front ? surface.eta_enter : surface.eta_leave;
      const std::int64_t sin2 = kUnit * kUnit - cos * cos;  // times 2^28
      const bool total_internal = static_cast<Int128>(eta * eta) * sin2 > (Int128{1} << 56);
      const std::int64_t reflectance =
          surface.r0 + round_shift((kUnit - surface.r0) * approx::pow5(kUnit - std::max<std::int64_t>(cos, 0)), kUnitBits);
      arith.check(reflectance, core::Width::kReflectance);
      const bool reflects = total_internal || static_cast<std::int64_t>(draw() >> 18) < reflectance;
      if (reflects) {
        out.next = approx::reflect(in, nf);
        out.into = !front;  // reflected inside, the ray stays in
      } else {
        ++counters.refracted;
        Unit3 perp;
        for (int k = 0; k < 3; ++k) perp[k] = round_shift(eta * (in[k] + round_shift(cos * nf[k], kUnitBits)), kUnitBits);
        checked(arith, perp, core::Width::kRefractPerp);
        const std::int64_t q = kUnit * kUnit - core::dot(perp, perp);
        arith.check(q, core::Width::kRadicand);
        const auto along = static_cast<std::int64_t>(arith.sqrt(q < 0 ? -q : q));
        for (int k = 0; k < 3; ++k) out.next[k] = perp[k] - round_shift(along * nf[k], kUnitBits);
        out.into = front;  // refracted in, or out
      }
      return out;
    }
    default: {
      ++counters.lambertian;
      const Unit3 u = checked(arith, approx::random_unit(draw(), sqrt), core::Width::kUnitVector);
      out.next = n + u;
      if (core::dot(out.next, out.next) < (std::int64_t{1} << 16)) out.next = n;  // |n + u| < 2^-6: the normal
      return out;
    }
  }
}

// A bounce that led to another ray, counted by the material that scattered it.
inline void count_bounce(const PathSurface& surface, PathBounces& bounces) {
  switch (surface.material) {
    case link::kMaterialMetal: ++bounces.metal; break;
    case link::kMaterialDielectric: ++bounces.dielectric; break;
    default: ++bounces.lambertian; break;
  }
}
// The path's throughput (times 2^16 per channel) times the albedo of the surface it bounced off.
template <class Arith>
void take_albedo(const Arith& arith, const PathSurface& surface, std::array<std::int64_t, 3>& throughput) {
  for (std::size_t k = 0; k < 3; ++k) {
    throughput[k] = (throughput[k] * surface.albedo[k] + (1 << 15)) >> 16;
    arith.check(throughput[k], core::Width::kThroughput);
  }
}

// One sample of the pixel whose camera ray is d0. closest(path) returns the path ray's PathHit (the plain
// search, or the fast model's). `depth` rays at most (1..). Arith is FixedArith, or the fast model's with the same
// square root in closed form (FastTracer).
template <class Arith, class Closest>
PathSample trace_path_sample(const Arith& arith, const core::Vec3<core::Int128>& d0,
                             std::span<const core::KernelSphere<std::int64_t>> spheres,
                             std::span<const PathSurface> surfaces, int depth, PathRng& rng, PathCounters& counters,
                             const Closest& closest) {
  using core::Int128;
  using approx::Unit3;
  PathSample out;
  PathRay path{{{}, d0}, -1, false};
  std::array<std::int64_t, 3> throughput{65536, 65536, 65536};
  ++counters.samples;
  const auto draw = [&] {
    ++counters.draws;
    return rng.next();
  };
  for (int rays = 1;; ++rays) {
    ++counters.rays;
    out.rays = rays;
    const PathHit hit = closest(path);
    const core::Vec3<Int128>& d = path.ray.direction;
    if (hit.index < 0) {
      ++counters.sky;
      out.light = sky_light(arith, throughput, -checked_unit(arith, d).y);
      return out;
    }
    if (rays == depth) {
      ++counters.cut;
      return out;
    }
    const auto i = static_cast<std::size_t>(hit.index);
    const auto& s = spheres[i];
    const PathSurface& surface = surfaces[i];
    // The hit point and the outward normal, as the mirror model's reflect computes them.
    const Int128 two_a = 2 * core::dot(d, d);
    core::Vec3<Int128> p, m;
    for (int k = 0; k < 3; ++k) {
      const Int128 num_d = hit.num * d[k];
      arith.check(num_d, core::Width::kNumTimesD);
      p[k] = path.ray.origin[k] + FixedArith::round_div(num_d, two_a);
      arith.check(p[k], core::Width::kOrigin);
      m[k] = p[k] - s.center[k];
      arith.check(m[k], core::Width::kHitNormal);
    }
    if (m.x == 0 && m.y == 0 && m.z == 0) m = {0, 0, -1};  // a radius-1 sphere seen head-on: the grid's centre
    const Unit3 n = checked_unit(arith, m);
    Scattered bounce =
        scatter(arith, surface, n, hit.inside, [&] { return checked_unit(arith, d); }, draw, counters);
    if (bounce.bounce == Bounce::kAbsorbed) return out;
    if (bounce.bounce == Bounce::kStraight)
      bounce.next = {static_cast<std::int64_t>(d.x), static_cast<std::int64_t>(d.y), static_cast<std::int64_t>(d.z)};
    const Unit3& next = bounce.next;
    if (next.x == 0 && next.y == 0 && next.z == 0) {  // no direction left (a refraction at a grazing 0)
      ++counters.absorbed;
      return out;
    }
    checked(arith, next, core::Width::kScattered);
    take_albedo(arith, surface, throughput);
    path = PathRay{{p, {next.x, next.y, next.z}}, hit.index, bounce.into};
    count_bounce(surface, out.bounces);
  }
}

// What the path workers need of a frame besides scene memory.
struct PathFrame {
  std::span<const PathSurface> surfaces;  // path_surface of each sphere
  std::uint32_t frame = 0;                // frames drawn of this world before this one
  std::uint8_t epoch = 0;                 // the world's epoch in frame memory
  int spp = 1;
  int depth = 4;
  bool dither = true;
};

// One pixel of a frame: its colour, its new frame-memory entry, and what its samples cost.
struct PathPixel {
  core::Rgb444 colour;
  AccumEntry entry;
  int rays = 0;          // passes over the spheres, every sample's
  PathBounces bounces;   // scatters followed by another pass
};

// Pixel (col, row) of a frame: its entry from frame memory (empty if of another epoch), spp more samples
// unless that would pass kMaxSamples (a converged pixel traces nothing), and the colour shown. sample(rng) traces
// one sample on its stream (PathRng::for_sample(pixel, frame * spp + s)): the path preset's kernel (below) or the
// artix path preset's (artix_path.h).
template <class Arith, class Sample>
PathPixel path_pixel(const Arith& arith, int col, int row, const AccumEntry& stored, const PathFrame& frame,
                     const Sample& sample) {
  PathPixel out;
  // The entry is updated where it is returned: a copy of one just written field by field would make the loads that
  // read it wait for those stores (the artix path preset's fast model spent 10% of its time there).
  AccumEntry& e = out.entry;
  if (stored.epoch == frame.epoch) {
    e = stored;
  } else {
    e.epoch = frame.epoch;  // (out.entry starts empty)
  }
  if (e.count + frame.spp <= kMaxSamples) {
    const auto pixel = static_cast<std::uint32_t>(row * core::kScreenWidth + col);
    for (int s = 0; s < frame.spp; ++s) {
      PathRng rng = PathRng::for_sample(pixel, frame.frame * static_cast<std::uint32_t>(frame.spp) + static_cast<std::uint32_t>(s));
      const PathSample one = sample(rng);
      out.rays += one.rays;
      out.bounces += one.bounces;
      for (std::size_t k = 0; k < 3; ++k) {
        e.sum[k] += sample_channel(one.light[k]);
        arith.check(e.sum[k], core::Width::kAccumSum);
      }
    }
    e.count = static_cast<std::uint8_t>(e.count + frame.spp);
  }
  out.colour = e.count > 0 ? display_colour(e, col, row, frame.dither) : core::kBlack;
  return out;
}

template <class Arith, class Closest>
PathPixel trace_path_pixel(const Arith& arith, int col, int row, const AccumEntry& stored,
                           std::span<const core::KernelSphere<std::int64_t>> spheres, const PathFrame& frame,
                           PathCounters& counters, const Closest& closest) {
  const core::Vec3<core::Int128> d0 = device_ray(col, row);
  return path_pixel(arith, col, row, stored, frame, [&](PathRng& rng) {
    return trace_path_sample(arith, d0, spheres, frame.surfaces, frame.depth, rng, counters, closest);
  });
}

}  // namespace tripsitter::device

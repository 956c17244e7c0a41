// What the sphere unit's tests share (ts_artix_sphere_unit.sv, as the artix preset's unit and as the path preset's):
// a ray or a sphere packed into a port, and the random rays and spheres they draw.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include <tripsitter/device/artix_kernel.h>

namespace tripsitter::rtl::sphere_unit {

namespace artix = device::artix;

constexpr int kOriginW = 24, kDirW = 18, kCoordW = 22, kTdW = 45, kBdW = 44, kFW = 48, kExpW = 6;

// Component k of v in bits k * bits .. (k + 1) * bits - 1.
inline UInt128 pack3(const artix::Vec3i& v, int bits) {
  UInt128 out = 0;
  for (int k = 0; k < 3; ++k)
    out |= (static_cast<UInt128>(v[static_cast<std::size_t>(k)]) & ((UInt128{1} << bits) - 1)) << (k * bits);
  return out;
}

class Draw {
 public:
  explicit Draw(std::uint64_t seed) : rng_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  int below(int n) { return static_cast<int>(rng_() % static_cast<std::uint64_t>(n)); }
  std::int64_t clamp_coord(double v) {
    const double limit = std::ldexp(1.0, kCoordW - 1) - 1;
    return static_cast<std::int64_t>(std::llround(std::clamp(v, -limit, limit)));
  }
  // A ray: the camera's for a random pixel, or from a random point (a hit point's range) along a unit direction.
  artix::UnitRay ray() {
    if (below(2) == 0) return {{}, artix::camera_direction(below(640), below(480))};
    artix::UnitRay r;
    const double reach = std::ldexp(1.0, 4 + below(18));
    for (auto& o : r.o) o = clamp_coord(uniform(-reach, reach));
    double v[3], len = 0;
    for (double& x : v) {
      x = uniform(-1, 1);
      len += x * x;
    }
    len = std::sqrt(len);
    for (std::size_t k = 0; k < 3; ++k)
      r.d[k] = std::clamp<std::int64_t>(std::llround(v[k] / len * 131072.0), -artix::kDirectionMax, artix::kDirectionMax);
    return r;
  }
  // A sphere near the ray (most hit or graze it, some behind, some around the origin), or anywhere.
  artix::UnitSphere sphere(const artix::UnitRay& ray) {
    const double r = std::max(1.0, std::ldexp(uniform(1, 2), below(21)) - 1);
    std::array<std::int64_t, 3> c{};
    if (below(6) == 0) {
      for (auto& x : c) x = clamp_coord(uniform(-2097151, 2097151));
    } else {
      const double t = below(8) == 0 ? uniform(-r, r) : std::ldexp(uniform(0.5, 1), below(22)) * (below(6) == 0 ? -1 : 1);
      const double off = r * uniform(0, 1.3);
      for (std::size_t k = 0; k < 3; ++k)
        c[k] = clamp_coord(static_cast<double>(ray.o[k]) + t * static_cast<double>(ray.d[k]) / 131072.0 +
                           off * uniform(-0.6, 0.6));
    }
    return ball(c, r);
  }
  // A sphere around the ray's origin (the ray inside it), its centre up to 0.9 r away.
  artix::UnitSphere around_origin(const artix::UnitRay& ray) {
    const double r = std::max(4.0, std::ldexp(uniform(1, 2), 2 + below(19)) - 1);
    std::array<std::int64_t, 3> c{};
    for (std::size_t k = 0; k < 3; ++k) c[k] = clamp_coord(static_cast<double>(ray.o[k]) + 0.52 * r * uniform(-1, 1));
    return ball(c, r);
  }

 private:
  static artix::UnitSphere ball(const std::array<std::int64_t, 3>& c, double r) {
    core::KernelSphere<std::int64_t> k;
    k.center = {c[0], c[1], c[2]};
    k.radius = std::min<std::int64_t>(static_cast<std::int64_t>(r), (std::int64_t{1} << 21) - 1);
    return artix::prepare_sphere(k, core::KernelSurface{});
  }
  std::mt19937_64 rng_;
};

}  // namespace tripsitter::rtl::sphere_unit

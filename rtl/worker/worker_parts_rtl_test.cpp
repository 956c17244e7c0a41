// Two parts of the worker's RTL held to the kernel's functions directly, on values a pixel's colour can hide:
// the sphere test (ts_sphere_test.sv) against core::sphere_num, and the reflection (ts_reflect.sv) against
// core::reflect, both with device::FixedArith (the device's arithmetic), in the `wide` preset's widths, on
// random rays from anywhere (origins up to the hit points' bound, directions up to 2^20 per component) and
// spheres at the formats' limits.
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_reflect_wide.h>
#include <Vts_sphere_test_wide.h>

#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/worker.h>

namespace tripsitter::rtl {
namespace {

using Ray = core::KernelRay<Int128>;
using Sphere = core::KernelSphere<std::int64_t>;

constexpr int kCentreBits = 24, kRadiusBits = 24, kOriginBits = 26, kDirBits = 22, kOcBits = 27, kNumBits = 51;

UInt128 raw(Int128 v, int bits) { return static_cast<UInt128>(v) & ((UInt128{1} << bits) - 1); }

// The device's arithmetic as the wide preset's worker has it.
device::FixedArith wide_arith() {
  const device::DevicePreset p = device::wide_preset();
  return device::FixedArith{device::SqrtUnit(p.sqrt_iterations), device::FixedArith::extra_bits_of(p)};
}

// Random values within the Widths table's premises: centres of 24 bits, radii 1 .. 2^24 - 1, origins below 2^25
// (hit points), directions up to 2^20 per component. Lengths log-uniform, so that small and large both occur.
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : rng_(seed) {}
  std::int64_t signed_below(int bits) {  // |v| < 2^bits, log-uniform length
    const int b = static_cast<int>(rng_() % static_cast<std::uint64_t>(bits + 1));
    const std::int64_t v = b == 0 ? 0 : static_cast<std::int64_t>(rng_() & static_cast<std::uint64_t>(mask(b)));
    return rng_() % 2 ? -v : v;
  }
  std::int64_t centre() { return rng_() % 8 == 0 ? edge(kCentreBits) : signed_below(kCentreBits - 1); }
  std::int64_t radius() {
    if (rng_() % 8 == 0) return rng_() % 2 ? mask(kRadiusBits) : 1 + static_cast<std::int64_t>(rng_() % 4);
    return std::max<std::int64_t>(1, signed_below(kRadiusBits) & mask(kRadiusBits));
  }
  Int128 direction() { return rng_() % 8 == 0 ? (rng_() % 2 ? 1 : -1) * (Int128{1} << 20) : signed_below(20); }
  Int128 origin() { return signed_below(25); }
  core::Vec3<Int128> unit_direction_to(const core::Vec3<Int128>& v) {  // v scaled to at most 2^20 per component
    Int128 largest = 1;
    for (int k = 0; k < 3; ++k) largest = std::max(largest, v[k] < 0 ? -v[k] : v[k]);
    const Int128 limit = Int128{1} << (1 + static_cast<int>(rng_() % 20));
    core::Vec3<Int128> d;
    for (int k = 0; k < 3; ++k) d[k] = largest <= limit ? v[k] : v[k] * limit / largest;
    return d;
  }
  std::uint64_t operator()() { return rng_(); }

 private:
  std::int64_t edge(int bits) {
    const std::int64_t e = rng_() % 2 ? mask(bits - 1) : -mask(bits - 1) - 1;
    return e > 0 ? e - static_cast<std::int64_t>(rng_() % 3) : e + static_cast<std::int64_t>(rng_() % 3);
  }
  std::mt19937_64 rng_;
};

// A ray and a sphere: anything, or a ray aimed at a point near the sphere's surface (so that half of them hit,
// some graze it, some start inside it).
struct Case {
  Ray ray;
  Sphere sphere;
};
Case random_case(Draw& draw) {
  Case c;
  c.sphere = {{draw.centre(), draw.centre(), draw.centre()}, draw.radius()};
  c.ray.origin = draw() % 4 == 0 ? core::Vec3<Int128>{0, 0, 0}
                                 : core::Vec3<Int128>{draw.origin(), draw.origin(), draw.origin()};
  if (draw() % 3 == 0) {
    c.ray.direction = {draw.direction(), draw.direction(), draw.direction()};
  } else {
    core::Vec3<Int128> target;
    for (int k = 0; k < 3; ++k) {
      const Int128 spread = c.sphere.radius + 2;
      target[k] = c.sphere.center[k] + static_cast<Int128>(draw() % static_cast<std::uint64_t>(2 * spread)) - spread;
    }
    c.ray.direction = draw.unit_direction_to(
        {target.x - c.ray.origin.x, target.y - c.ray.origin.y, target.z - c.ray.origin.z});
  }
  return c;
}

// ---- the sphere test ------------------------------------------------------------------------------------

TEST(WorkerPartsRtl, SphereTestMatchesTheKernel) {
  const device::FixedArith arith = wide_arith();
  Draw draw(21);
  VerilatedContext context;
  context.randReset(2);
  auto top = std::make_unique<Vts_sphere_test_wide>(&context);
  const auto settle = [&] {
    top->clk = 0;
    top->eval();
  };
  const auto tick = [&] {
    settle();
    top->clk = 1;
    top->eval();
  };
  top->rst = 1;
  top->flush = 0;
  top->in_valid = 0;
  for (int i = 0; i < 3; ++i) tick();
  top->rst = 0;

  // Rays of 1..6 pairs each, issued back to back; the reflected-ray inputs held until the last pair has read
  // a at S4. Camera rays (in_refl = 0) for a quarter of them.
  struct Expected {
    Int128 num;
    bool hit;
    std::string what;
  };
  std::vector<Expected> expected;
  std::size_t received = 0;
  int hits = 0, misses = 0, behind = 0, bad = 0;
  const auto collect = [&] {
    if (!top->out_valid) return;
    ASSERT_LT(received, expected.size());
    const Expected& e = expected[received++];
    const Int128 num = sign_extend(get(top->out_num), kNumBits);
    const bool hit = top->out_hit != 0;
    const bool same = hit == e.hit && (e.num == 0 || num == e.num);
    if (!same && bad++ == 0) {
      ADD_FAILURE() << e.what << ": the RTL gives num " << to_string(num) << " (hit " << hit << "), the kernel "
                    << to_string(e.num) << " (hit " << e.hit << ")";
    }
  };
  for (int ray_index = 0; ray_index < 10000; ++ray_index) {
    const bool camera = draw() % 4 == 0;
    const int col = static_cast<int>(draw() % 640), row = static_cast<int>(draw() % 480);
    Case first = random_case(draw);
    Ray ray = camera ? Ray{{0, 0, 0}, core::device_ray(col, row)} : first.ray;
    const Int128 a = core::dot(ray.direction, ray.direction);
    put(top->refl_ox, raw(ray.origin.x, kOriginBits));
    put(top->refl_oy, raw(ray.origin.y, kOriginBits));
    put(top->refl_oz, raw(ray.origin.z, kOriginBits));
    put(top->refl_dx, raw(ray.direction.x, kDirBits));
    put(top->refl_dy, raw(ray.direction.y, kDirBits));
    put(top->refl_dz, raw(ray.direction.z, kDirBits));
    put(top->refl_a, static_cast<UInt128>(a));
    const int pairs = 1 + static_cast<int>(draw() % 6);
    for (int i = 0; i < pairs + 4; ++i) {
      top->in_valid = i < pairs;
      if (i < pairs) {
        // The first sphere is the one the ray was aimed at; the others anywhere, or around a point of the ray.
        Sphere s = i == 0 ? first.sphere : random_case(draw).sphere;
        if (i > 0 && draw() % 2 == 0) {
          const Int128 t = 1 + static_cast<Int128>(draw() % 64);
          for (int k = 0; k < 3; ++k) {
            const Int128 p = ray.origin[k] + ray.direction[k] * t / 4 + static_cast<Int128>(draw() % 64) - 32;
            s.center[k] = static_cast<std::int64_t>(std::clamp<Int128>(p, -(Int128{1} << 23), (Int128{1} << 23) - 1));
          }
        }
        top->in_refl = !camera;
        top->in_kill = 0;
        top->in_col = static_cast<SData>(col);
        top->in_row = static_cast<SData>(row);
        put(top->in_cx, raw(s.center.x, kCentreBits));
        put(top->in_cy, raw(s.center.y, kCentreBits));
        put(top->in_cz, raw(s.center.z, kCentreBits));
        put(top->in_r, static_cast<UInt128>(s.radius));
        top->in_tag = static_cast<CData>(expected.size());
        const auto [b, c_prime] = core::sphere_coefficients(arith, ray, s);
        const Int128 num = core::hit_num(arith, a, b, c_prime);
        std::ostringstream what;
        what << "ray " << ray_index << " pair " << i << " (o " << to_string(ray.origin.x) << " "
             << to_string(ray.origin.y) << " " << to_string(ray.origin.z) << ", d " << to_string(ray.direction.x)
             << " " << to_string(ray.direction.y) << " " << to_string(ray.direction.z) << ", c " << s.center.x << " "
             << s.center.y << " " << s.center.z << ", r " << s.radius << ")";
        expected.push_back({num, num > 0, what.str()});
        if (num > 0) {
          ++hits;
        } else if (num == 0) {
          ++misses;
        } else {
          ++behind;
        }
      }
      tick();
      collect();
    }
  }
  for (int i = 0; i < 40; ++i) {
    top->in_valid = 0;
    tick();
    collect();
  }
  EXPECT_EQ(received, expected.size());
  EXPECT_EQ(bad, 0);
  EXPECT_GT(hits, 3000);
  EXPECT_GT(misses, 3000);
  EXPECT_GT(behind, 300);
}

// ---- the reflection -----------------------------------------------------------------------------------------

TEST(WorkerPartsRtl, ReflectionMatchesTheKernel) {
  const device::FixedArith arith = wide_arith();
  Draw draw(22);
  VerilatedContext context;
  context.randReset(2);
  auto top = std::make_unique<Vts_reflect_wide>(&context);
  std::int64_t cycle = 0;
  const auto tick = [&] {
    top->clk = 0;
    top->eval();
    top->clk = 1;
    top->eval();
    ++cycle;
  };
  top->rst = 1;
  top->flush = 0;
  top->in_valid = 0;
  for (int i = 0; i < 3; ++i) tick();
  top->rst = 0;

  int tested = 0, bad = 0, scaled = 0;
  for (int attempt = 0; tested < 20000 && attempt < 200000; ++attempt) {
    const Case c = random_case(draw);
    const Int128 a = core::dot(c.ray.direction, c.ray.direction);
    const Int128 num = core::sphere_num(arith, c.ray, a, c.sphere);
    if (num <= 0) continue;
    const Ray out = core::reflect(arith, c.ray, c.sphere, num);
    // Within the Widths table's premises only (the hit point is a ray origin: below 2^25).
    bool inside = true;
    for (int k = 0; k < 3; ++k) inside = inside && out.origin[k] < (Int128{1} << 25) && out.origin[k] > -(Int128{1} << 25);
    if (!inside) continue;
    ++tested;
    Int128 largest = 0;
    for (int k = 0; k < 3; ++k) largest = std::max(largest, out.direction[k] < 0 ? -out.direction[k] : out.direction[k]);
    scaled += largest > (Int128{1} << 19);

    put(top->in_num, raw(num, kNumBits));
    put(top->in_ocx, raw(c.sphere.center.x - c.ray.origin.x, kOcBits));
    put(top->in_ocy, raw(c.sphere.center.y - c.ray.origin.y, kOcBits));
    put(top->in_ocz, raw(c.sphere.center.z - c.ray.origin.z, kOcBits));
    put(top->in_ox, raw(c.ray.origin.x, kOriginBits));
    put(top->in_oy, raw(c.ray.origin.y, kOriginBits));
    put(top->in_oz, raw(c.ray.origin.z, kOriginBits));
    put(top->in_dx, raw(c.ray.direction.x, kDirBits));
    put(top->in_dy, raw(c.ray.direction.y, kDirBits));
    put(top->in_dz, raw(c.ray.direction.z, kDirBits));
    put(top->in_a, static_cast<UInt128>(a));
    top->in_valid = 1;
    const std::int64_t given = cycle;
    tick();
    top->in_valid = 0;
    core::Vec3<Int128> o{}, d{};
    Int128 a_out = 0;
    while (cycle < given + 19) {
      tick();
      if (cycle == given + 11) {
        o = {sign_extend(get(top->ray_ox), kOriginBits), sign_extend(get(top->ray_oy), kOriginBits),
             sign_extend(get(top->ray_oz), kOriginBits)};
      }
      if (cycle == given + 17) {
        d = {sign_extend(get(top->ray_dx), kDirBits), sign_extend(get(top->ray_dy), kDirBits),
             sign_extend(get(top->ray_dz), kDirBits)};
      }
    }
    a_out = static_cast<Int128>(get(top->ray_a));
    const Int128 a_expected = core::dot(out.direction, out.direction);
    bool same = a_out == a_expected;
    for (int k = 0; k < 3; ++k) same = same && o[k] == out.origin[k] && d[k] == out.direction[k];
    if (!same && bad++ == 0) {
      ADD_FAILURE() << "ray o (" << to_string(c.ray.origin.x) << ", " << to_string(c.ray.origin.y) << ", "
                    << to_string(c.ray.origin.z) << ") d (" << to_string(c.ray.direction.x) << ", "
                    << to_string(c.ray.direction.y) << ", " << to_string(c.ray.direction.z) << "), sphere ("
                    << c.sphere.center.x << ", " << c.sphere.center.y << ", " << c.sphere.center.z << ") r "
                    << c.sphere.radius << ", num " << to_string(num) << ": the RTL reflects to p (" << to_string(o.x)
                    << ", " << to_string(o.y) << ", " << to_string(o.z) << ") d (" << to_string(d.x) << ", "
                    << to_string(d.y) << ", " << to_string(d.z) << ") a " << to_string(a_out) << "; the kernel to p ("
                    << to_string(out.origin.x) << ", " << to_string(out.origin.y) << ", " << to_string(out.origin.z)
                    << ") d (" << to_string(out.direction.x) << ", " << to_string(out.direction.y) << ", "
                    << to_string(out.direction.z) << ") a " << to_string(a_expected);
    }
    tick();
  }
  EXPECT_EQ(tested, 20000);
  EXPECT_EQ(bad, 0);
  EXPECT_GT(scaled, 10000) << "too few reflections needed their direction scaled";
}

}  // namespace
}  // namespace tripsitter::rtl

// The hit block's RTL (ts_path_hit.sv) held to the model: artix::hit_point and artix::normal (near and far side) of
// the sphere unit's hits, and the 2^14 roundings trace_path_sample takes (approx::round_shift by 3), bit for bit, a
// hit a cycle and with gaps: random rays from the camera and from anywhere, spheres around them at the formats'
// limits, rays inside spheres for the far side.
#include <cstdint>
#include <deque>
#include <memory>

#include <gtest/gtest.h>

#include "sphere_unit_draw.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_path_hit.h>

#include <tripsitter/device/approx.h>
#include <tripsitter/device/artix_kernel.h>

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;
using namespace sphere_unit;  // the draw and the port helpers (sphere_unit_draw.h)

constexpr int kLatency = 8;

struct Want {
  std::int64_t cycle;
  artix::Vec3i point, normal;
  artix::Vec3i normal14, dir14;
  std::uint32_t tag;
};

artix::Vec3i unpack3(UInt128 v, int bits) {
  artix::Vec3i out{};
  for (std::size_t k = 0; k < 3; ++k)
    out[k] = static_cast<std::int64_t>(sign_extend(v >> (bits * static_cast<int>(k)), bits));
  return out;
}

artix::Vec3i to_unit14(const artix::Vec3i& v) {
  return {device::approx::round_shift(v[0], 3), device::approx::round_shift(v[1], 3),
          device::approx::round_shift(v[2], 3)};
}

TEST(PathHitRtl, HitPointsAndNormalsEqualTheModel) {
  Draw draw(20261208);
  auto top = std::make_unique<Vts_path_hit>();
  top->rst = 1;
  rising_edge(*top);
  top->rst = 0;
  std::deque<Want> want;
  std::int64_t now = 0;
  int checked = 0, far = 0, saturated = 0;
  const auto check = [&] {
    if (top->out_valid == 0) return;
    ASSERT_FALSE(want.empty()) << "a result with no hit in flight, cycle " << now;
    const Want w = want.front();
    want.pop_front();
    EXPECT_EQ(now, w.cycle);
    EXPECT_EQ(top->out_tag, w.tag);
    EXPECT_EQ(unpack3(get(top->out_point), kOriginW), w.point) << "hit " << w.tag;
    EXPECT_EQ(unpack3(get(top->out_normal), kDirW), w.normal) << "hit " << w.tag;
    EXPECT_EQ(unpack3(get(top->out_normal14), 17), w.normal14) << "hit " << w.tag;
    EXPECT_EQ(unpack3(get(top->out_dir14), 17), w.dir14) << "hit " << w.tag;
    ++checked;
  };
  constexpr int kHits = 40000;
  for (int h = 0; h < kHits;) {
    const artix::UnitRay ray = draw.ray();
    const bool inside = draw.below(3) == 0;
    const artix::UnitSphere s = inside ? draw.around_origin(ray) : draw.sphere(ray);
    const artix::Quadratic q = artix::quadratic(ray, s);
    // The near side of a sphere the ray hits, or the far side of one it is inside.
    const std::int64_t td = inside ? artix::far_td(ray, s) : q.td;
    if (q.disc < 0 || td <= 0) continue;
    top->in_valid = 1;
    put(top->in_o, pack3(ray.o, kOriginW));
    put(top->in_d, pack3(ray.d, kDirW));
    put(top->in_td, static_cast<UInt128>(td));
    put(top->in_bd, static_cast<UInt128>(q.bd));
    for (int k = 0; k < 3; ++k) set_bits(top->in_f, k * kFW, kFW, q.f[static_cast<std::size_t>(k)]);  // 144 bits
    put(top->in_s, static_cast<UInt128>(q.s));
    put(top->in_e, static_cast<UInt128>(s.e) & 0x3f);
    put(top->in_rinv, static_cast<UInt128>(s.rinv));
    top->in_far = inside;
    top->in_tag = static_cast<std::uint32_t>(h);
    const artix::Vec3i n = artix::normal(ray, s, inside);
    want.push_back({now + kLatency, artix::hit_point(ray, td), n, to_unit14(n), to_unit14(ray.d),
                    static_cast<std::uint32_t>(h)});
    far += inside;
    for (const auto c : n) saturated += c == artix::kDirectionMax || c == -artix::kDirectionMax;
    ++h;
    check();
    rising_edge(*top);
    ++now;
    top->in_valid = 0;
    for (int gap = draw.below(5) == 0 ? draw.below(12) : 0; gap > 0; --gap) {
      check();
      rising_edge(*top);
      ++now;
    }
  }
  for (int i = 0; i < kLatency + 2; ++i) {
    check();
    rising_edge(*top);
    ++now;
  }
  EXPECT_TRUE(want.empty());
  EXPECT_EQ(checked, kHits);
  EXPECT_GT(far, kHits / 5);
  EXPECT_GT(saturated, 10);
}

}  // namespace
}  // namespace tripsitter::rtl

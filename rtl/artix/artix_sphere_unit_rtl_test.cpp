// The artix sphere unit's RTL (ts_artix_sphere_unit.sv) held to the model's arithmetic, artix::quadratic and
// artix::closest_hit (device/artix_kernel.h), pass by pass, and to the latency the line's schedule counts on
// (DeviceUnits::hit_latency): random rays from the camera and from hit points, spheres around them at the
// formats' limits, passes of 0 to 12 slots with excluded pairs, back to back and with gaps.
#include <algorithm>
#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "sphere_unit_draw.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_artix_sphere_unit.h>

#include <tripsitter/device/artix_kernel.h>
#include <tripsitter/device/preset.h>

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;

using namespace sphere_unit;  // the draw and the port helpers (sphere_unit_draw.h)

constexpr int kSceneReadCycles = 2;

// A pass as the engine sends it: its ray, its slots' spheres (-1: a slot without a pair, the excluded sphere's or
// an idle one), and the model's answer.
struct Pass {
  artix::UnitRay ray;
  std::vector<int> slots;
  artix::Hit hit;
};

class SphereUnit {
 public:
  SphereUnit() : top_(std::make_unique<Vts_artix_sphere_unit>()) {
    top_->rst = 1;
    cycle();
    cycle();
    top_->rst = 0;
  }
  // One cycle with these inputs at the ports; returns whether a result came out in it.
  bool cycle() {
    const bool out = top_->out_valid != 0;
    rising_edge(*top_);
    ++now_;
    return out;
  }
  void slot(const Pass& pass, std::size_t i, const std::vector<artix::UnitSphere>& spheres) {
    const int index = pass.slots[i];
    top_->in_first = i == 0;
    top_->in_pair = index >= 0;
    top_->in_end = i + 1 == pass.slots.size();
    put(top_->in_o, pack3(pass.ray.o, kOriginW));
    put(top_->in_d, pack3(pass.ray.d, kDirW));
    const artix::UnitSphere& s = spheres[static_cast<std::size_t>(std::max(index, 0))];
    put(top_->in_c, pack3(s.c, kCoordW));
    put(top_->in_e, static_cast<UInt128>(s.e) & 0x3f);
    put(top_->in_r2s, static_cast<UInt128>(s.r2s));
    put(top_->in_carry, static_cast<UInt128>(std::max(index, 0)));
  }
  void idle() { top_->in_first = top_->in_pair = top_->in_end = 0; }
  Vts_artix_sphere_unit& top() { return *top_; }
  std::int64_t now() const { return now_; }

 private:
  std::unique_ptr<Vts_artix_sphere_unit> top_;
  std::int64_t now_ = 0;
};

// The model's answer for a pass: the closest hit over its pairs (ascending, as the engine sends them).
artix::Hit model_hit(const Pass& pass, const std::vector<artix::UnitSphere>& spheres) {
  std::vector<int> list;
  for (const int i : pass.slots)
    if (i >= 0) list.push_back(i);
  return artix::closest_hit(pass.ray, spheres, list, -1);
}

TEST(ArtixSphereUnitRtl, LatencyIsTheSchedulesHitLatency) {
  const device::DeviceUnits units;
  // The model's known cycle is hit_latency after the cycle following the pass's last slot; the slot reaches the
  // unit SceneReadCycles after its issue.
  EXPECT_EQ(units.hit_latency + 1 - kSceneReadCycles, 39);
  Draw draw(1);
  std::vector<artix::UnitSphere> spheres;
  const artix::UnitRay ray{{}, artix::camera_direction(320, 240)};
  spheres.push_back(draw.sphere(ray));
  SphereUnit unit;
  Pass pass{ray, {0, -1, -1}, {}};
  std::int64_t end_cycle = 0;
  for (std::size_t i = 0; i < pass.slots.size(); ++i) {
    unit.slot(pass, i, spheres);
    end_cycle = unit.now();
    unit.cycle();
  }
  unit.idle();
  std::vector<std::int64_t> outs;
  for (int i = 0; i < 80; ++i) {
    const std::int64_t now = unit.now();
    if (unit.cycle()) outs.push_back(now);
  }
  ASSERT_EQ(outs.size(), 1u);
  EXPECT_EQ(outs[0] - end_cycle, units.hit_latency + 1 - kSceneReadCycles);
}

TEST(ArtixSphereUnitRtl, PassesEqualTheModel) {
  Draw draw(20261127);
  SphereUnit unit;
  std::deque<std::pair<std::int64_t, artix::Hit>> expected;  // (cycle the result is due, hit) in pass order
  struct Seen {
    int passes = 0, hits = 0, excluded = 0, empty = 0, ties = 0;
  } seen;
  const auto check_output = [&](std::int64_t now) {
    auto& top = unit.top();
    if (top.out_valid == 0) return;
    ASSERT_FALSE(expected.empty()) << "a result with no pass in flight, cycle " << now;
    const auto [due, hit] = expected.front();
    expected.pop_front();
    EXPECT_EQ(now, due);
    ++seen.passes;
    ASSERT_EQ(top.out_hit != 0, hit.index >= 0) << "pass " << seen.passes;
    if (hit.index < 0) return;
    ++seen.hits;
    EXPECT_EQ(static_cast<int>(top.out_carry), hit.index);
    EXPECT_EQ(sign_extend(get(top.out_td), kTdW), hit.td);
  };
  // Each pass's spheres are its own: the quadratic's fields of the winner are checked against the model's.
  std::deque<std::pair<artix::UnitRay, artix::UnitSphere>> winners;
  const auto check_fields = [&]() {
    auto& top = unit.top();
    if (top.out_valid == 0 || top.out_hit == 0) return;
    ASSERT_FALSE(winners.empty());
    const auto [ray, sphere] = winners.front();
    winners.pop_front();
    const artix::Quadratic q = artix::quadratic(ray, sphere);
    EXPECT_EQ(sign_extend(get(top.out_bd), kBdW), q.bd);
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(sign_extend(static_cast<UInt128>(bits_of(top.out_f, k * kFW, kFW)), kFW), q.f[static_cast<std::size_t>(k)]) << k;
    EXPECT_EQ(static_cast<std::int64_t>(top.out_s), q.s);
    EXPECT_EQ(sign_extend(get(top.out_e), kExpW), sphere.e);
  };

  for (int p = 0; p < 3000; ++p) {
    Pass pass;
    pass.ray = draw.ray();
    std::vector<artix::UnitSphere> spheres;
    const int n = draw.below(13);
    // A fifth of the spheres repeat an earlier one: equal t d, where the lower index must win.
    for (int i = 0; i < n; ++i)
      spheres.push_back(i > 0 && draw.below(5) == 0 ? spheres[static_cast<std::size_t>(draw.below(i))]
                                                    : draw.sphere(pass.ray));
    if (spheres.empty()) spheres.push_back(draw.sphere(pass.ray));  // a slot's fields, never a pair
    for (int i = 0; i < n; ++i) {
      const bool excluded = draw.below(10) == 0;
      seen.excluded += excluded;
      pass.slots.push_back(excluded ? -1 : i);
    }
    seen.empty += n == 0;
    while (pass.slots.size() < 3) pass.slots.push_back(-1);
    pass.hit = model_hit(pass, spheres);
    // A tie the pass decides: another pair of the pass hits at the winner's t d.
    for (const int i : pass.slots)
      if (pass.hit.index >= 0 && i > pass.hit.index &&
          artix::quadratic(pass.ray, spheres[static_cast<std::size_t>(i)]).hit() &&
          artix::quadratic(pass.ray, spheres[static_cast<std::size_t>(i)]).td == pass.hit.td) {
        ++seen.ties;
        break;
      }
    if (pass.hit.index >= 0) winners.emplace_back(pass.ray, spheres[static_cast<std::size_t>(pass.hit.index)]);
    for (std::size_t i = 0; i < pass.slots.size(); ++i) {
      unit.slot(pass, i, spheres);
      if (i + 1 == pass.slots.size()) expected.emplace_back(unit.now() + 39, pass.hit);
      check_fields();
      check_output(unit.now());
      unit.cycle();
    }
    unit.idle();
    for (int gap = draw.below(4) == 0 ? draw.below(50) : 0; gap > 0; --gap) {
      check_fields();
      check_output(unit.now());
      unit.cycle();
    }
  }
  for (int i = 0; i < 60; ++i) {
    check_fields();
    check_output(unit.now());
    unit.cycle();
  }
  EXPECT_TRUE(expected.empty());
  EXPECT_EQ(seen.passes, 3000);
  // The draw covers what it should: hits, misses, excluded pairs and passes without pairs.
  EXPECT_GT(seen.hits, 1000);
  EXPECT_LT(seen.hits, 2900);
  EXPECT_GT(seen.excluded, 500);
  EXPECT_GT(seen.empty, 100);
  EXPECT_GT(seen.ties, 100);
}

}  // namespace
}  // namespace tripsitter::rtl

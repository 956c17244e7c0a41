// The path preset's sphere unit (ts_artix_sphere_unit.sv with PATH = 1) held to the model's closest hit of a path
// ray, pass by pass: artix::closest_hit's rule over the pass's spheres in whatever order they come (a tie to the
// lower index), the far side of the sphere the ray is inside (artix::with_far_side), and each hierarchy bound's
// entered (artix::enters), reported in slot order. Random rays from the camera and from anywhere, spheres around
// them, spheres the ray starts inside, bounds; passes back to back and with gaps.
#include <algorithm>
#include <cstdint>
#include <deque>
#include <memory>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "path_slot.h"  // first: it includes verilated.h with its warnings silenced

#include <tripsitter/device/artix_path.h>

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;

using namespace sphere_unit;  // the draw, the port helpers and the slot (sphere_unit_draw.h, path_slot.h)

// The result comes out this many cycles after the pass's end slot was at the ports (HitLatency + 1 -
// SceneReadCycles: ArtixSphereUnitRtl.LatencyIsTheSchedulesHitLatency).
constexpr int kLatency = 39;

struct Pass {
  artix::UnitRay ray;
  std::vector<Slot> slots;
  artix::PathUnitHit hit;      // the model's
  std::vector<bool> entered;  // the model's, a bound slot each in order
};

// The model's answer: the closest hit over the pass's pairs (keep_closest's rule, whatever their order), then the
// far side of the sphere the ray is in, and each bound's entered.
void answer(Pass& pass, const std::vector<artix::UnitSphere>& spheres, const std::vector<artix::UnitSphere>& bounds) {
  std::vector<int> pairs;
  artix::PathUnitRay path{pass.ray, -1, false};
  for (const Slot& s : pass.slots) {
    if (s.kind == Slot::kPair) pairs.push_back(s.index);
    if (s.kind == Slot::kFar) path = {pass.ray, s.index, true};
    if (s.kind == Slot::kBound) pass.entered.push_back(artix::enters(pass.ray, bounds[static_cast<std::size_t>(s.index)]));
  }
  std::sort(pairs.begin(), pairs.end());
  pass.hit = artix::with_far_side(path, artix::closest_hit(pass.ray, spheres, pairs, -1), spheres);
}

class PathSphereUnit {
 public:
  PathSphereUnit() : top_(std::make_unique<Vts_artix_sphere_unit_path>()) {
    top_->rst = 1;
    cycle();
    cycle();
    top_->rst = 0;
  }
  void cycle() {
    rising_edge(*top_);
    ++now_;
  }
  void slot(const Pass& pass, std::size_t i, const std::vector<artix::UnitSphere>& spheres,
            const std::vector<artix::UnitSphere>& bounds) {
    const Slot& s = pass.slots[i];
    const artix::UnitSphere& b = (s.kind == Slot::kBound ? bounds : spheres)[static_cast<std::size_t>(s.index)];
    drive(*top_, s, i == 0, i + 1 == pass.slots.size(), pass.ray, b);
  }
  void idle() { top_->in_first = top_->in_pair = top_->in_end = top_->in_far = top_->in_bound = 0; }
  Vts_artix_sphere_unit_path& top() { return *top_; }
  std::int64_t now() const { return now_; }

 private:
  std::unique_ptr<Vts_artix_sphere_unit_path> top_;
  std::int64_t now_ = 0;
};

TEST(PathSphereUnitRtl, PassesAndBoundsEqualTheModel) {
  Draw draw(20261207);
  PathSphereUnit unit;
  struct Due {
    std::int64_t cycle;
    artix::PathUnitHit hit;
    artix::Quadratic winner;  // the hit sphere's quadratic
    int e = 0;
  };
  std::deque<Due> results;
  std::deque<std::pair<std::int64_t, bool>> reports;  // (cycle due, entered), in slot order
  struct Seen {
    int passes = 0, hits = 0, far_hits = 0, far_pairs = 0, ties = 0, bounds = 0, entered = 0, out_of_order = 0;
    int tangent = 0;  // bounds whose far root is exactly 0
  } seen;
  const auto check = [&] {
    auto& top = unit.top();
    const std::int64_t now = unit.now();
    if (top.out_entered_valid != 0) {
      ASSERT_FALSE(reports.empty()) << "a bound's report with no bound in flight, cycle " << now;
      EXPECT_EQ(now, reports.front().first);
      EXPECT_EQ(top.out_entered != 0, reports.front().second) << "bound " << seen.bounds;
      ++seen.bounds;
      seen.entered += reports.front().second;
      reports.pop_front();
    }
    if (top.out_valid == 0) return;
    ASSERT_FALSE(results.empty()) << "a result with no pass in flight, cycle " << now;
    const Due due = results.front();
    results.pop_front();
    EXPECT_EQ(now, due.cycle);
    ++seen.passes;
    ASSERT_EQ(top.out_hit != 0, due.hit.index >= 0) << "pass " << seen.passes;
    if (due.hit.index < 0) return;
    ++seen.hits;
    seen.far_hits += due.hit.inside;
    EXPECT_EQ(static_cast<int>(top.out_carry), due.hit.index) << "pass " << seen.passes;
    EXPECT_EQ(sign_extend(get(top.out_td), kTdW), due.hit.td) << "pass " << seen.passes;
    EXPECT_EQ(top.out_far != 0, due.hit.inside) << "pass " << seen.passes;
    EXPECT_EQ(sign_extend(get(top.out_bd), kBdW), due.winner.bd);
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(sign_extend(static_cast<UInt128>(bits_of(top.out_f, k * kFW, kFW)), kFW), due.winner.f[static_cast<std::size_t>(k)]) << k;
    EXPECT_EQ(static_cast<std::int64_t>(top.out_s), due.winner.s);
    EXPECT_EQ(sign_extend(get(top.out_e), kExpW), due.e);
  };

  constexpr int kPasses = 4000;
  for (int p = 0; p < kPasses; ++p) {
    Pass pass;
    pass.ray = draw.ray();
    std::vector<artix::UnitSphere> spheres, bounds;
    // A sixteenth of the passes: a ray along an axis from an origin on a bound it leaves tangentially (both roots 0
    // exactly: f = r across the ray, b = 0), the edge of "entered" that random bounds do not reach.
    if (draw.below(16) == 0) {
      const int axis = draw.below(3), across = (axis + 1 + draw.below(2)) % 3;
      pass.ray.d = {};
      pass.ray.d[static_cast<std::size_t>(axis)] = draw.below(2) == 0 ? artix::kDirectionMax : -artix::kDirectionMax;
      artix::UnitSphere b = draw.around_origin(pass.ray);
      b.c = pass.ray.o;
      // Towards the origin of coordinates, so that the centre stays within its 22 bits.
      b.c[static_cast<std::size_t>(across)] += pass.ray.o[static_cast<std::size_t>(across)] > 0 ? -b.r : b.r;
      bounds.push_back(artix::prepare_sphere({{b.c[0], b.c[1], b.c[2]}, b.r}, core::KernelSurface{}));
      pass.slots.push_back({Slot::kBound, 0});
      seen.tangent += artix::far_td(pass.ray, bounds[0]) == 0;
      // The same ball as a sphere: its near root, 0, is not a hit.
      spheres.push_back(bounds[0]);
      pass.slots.push_back({Slot::kPair, 0});
    }
    const int first = static_cast<int>(spheres.size()), n = first + draw.below(11);
    // A fifth of the spheres repeat an earlier one: equal t d, where the lower index must win in any order.
    for (int i = first; i < n; ++i)
      spheres.push_back(i > 0 && draw.below(5) == 0 ? spheres[static_cast<std::size_t>(draw.below(i))]
                                                    : draw.sphere(pass.ray));
    std::vector<int> order(static_cast<std::size_t>(n - first));
    std::iota(order.begin(), order.end(), first);
    std::shuffle(order.begin(), order.end(), std::mt19937(static_cast<unsigned>(p)));
    seen.out_of_order += !std::is_sorted(order.begin(), order.end());
    for (const int i : order) pass.slots.push_back({draw.below(12) == 0 ? Slot::kNone : Slot::kPair, i});
    // Half the rays start inside a sphere they went into: its far side competes.
    if (draw.below(2) == 0) {
      spheres.push_back(draw.around_origin(pass.ray));
      const auto at = pass.slots.begin() + draw.below(static_cast<int>(pass.slots.size()) + 1);
      pass.slots.insert(at, {Slot::kFar, static_cast<int>(spheres.size()) - 1});
      ++seen.far_pairs;
    }
    for (int b = draw.below(5); b > 0; --b) {
      bounds.push_back(draw.below(3) == 0 ? draw.around_origin(pass.ray) : draw.sphere(pass.ray));
      const auto at = pass.slots.begin() + draw.below(static_cast<int>(pass.slots.size()) + 1);
      pass.slots.insert(at, {Slot::kBound, static_cast<int>(bounds.size()) - 1});
    }
    while (pass.slots.size() < 3) pass.slots.push_back({Slot::kNone, 0});
    if (spheres.empty()) spheres.push_back(draw.sphere(pass.ray));  // a slot's fields, never a pair
    if (bounds.empty()) bounds.push_back(draw.sphere(pass.ray));
    answer(pass, spheres, bounds);
    // A tie the pass decides: another pair hits at the winner's t d.
    for (const Slot& s : pass.slots) {
      if (s.kind != Slot::kPair || pass.hit.index < 0 || s.index == pass.hit.index) continue;
      const artix::Quadratic q = artix::quadratic(pass.ray, spheres[static_cast<std::size_t>(s.index)]);
      if (q.hit() && q.td == pass.hit.td) {
        ++seen.ties;
        break;
      }
    }
    std::size_t bound = 0;
    for (std::size_t i = 0; i < pass.slots.size(); ++i) {
      unit.slot(pass, i, spheres, bounds);
      if (pass.slots[i].kind == Slot::kBound) reports.emplace_back(unit.now() + kLatency, pass.entered[bound++]);
      if (i + 1 == pass.slots.size()) {
        Due due{unit.now() + kLatency, pass.hit, {}, 0};
        if (pass.hit.index >= 0) {
          const artix::UnitSphere& s = spheres[static_cast<std::size_t>(pass.hit.index)];
          due.winner = artix::quadratic(pass.ray, s);
          due.e = s.e;
        }
        results.push_back(due);
      }
      check();
      unit.cycle();
    }
    unit.idle();
    for (int gap = draw.below(4) == 0 ? draw.below(50) : 0; gap > 0; --gap) {
      check();
      unit.cycle();
    }
  }
  for (int i = 0; i < 60; ++i) {
    check();
    unit.cycle();
  }
  EXPECT_TRUE(results.empty());
  EXPECT_TRUE(reports.empty());
  EXPECT_EQ(seen.passes, kPasses);
  // The draw covers what it should: hits near and far, ties decided against the order sent, bounds both ways.
  EXPECT_GT(seen.hits, 1500);
  EXPECT_GT(seen.far_hits, 300);
  EXPECT_LT(seen.far_hits, seen.far_pairs);
  EXPECT_GT(seen.ties, 100);
  EXPECT_GT(seen.out_of_order, 2500);
  EXPECT_GT(seen.bounds, 5000);
  EXPECT_GT(seen.entered, 1000);
  EXPECT_LT(seen.entered, seen.bounds - 1000);
  EXPECT_GT(seen.tangent, 100);
}

}  // namespace
}  // namespace tripsitter::rtl

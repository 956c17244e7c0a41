// The hierarchy walker's RTL (ts_path_walk.sv) driving the path preset's sphere unit (ts_artix_sphere_unit.sv,
// PATH = 1), held to the model: every pass's slots in the model's order (artix::walk_closest_hit's levels: the
// nodes' spheres and their children's bounds, the far pair first on a ray that went into the sphere it leaves),
// every pass holding the issue port the cycles artix::unit_finish_cycles counts (WalkLead on a later level), every
// walk's levels as the model's, and every walk's hit, its passes' hits merged, with_far_side's of the model's walk.
// Worlds: the host's two-level hierarchies, and random trees up to 8 levels deep with wide levels; bounced rays
// from the spheres' surfaces, walks interleaved up to the walker's ids, each pass started as soon as the port is
// free. The test bench is the unit around the walker: node memory and scene memory as registered reads.
#include <algorithm>
#include <cstdint>
#include <deque>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "path_slot.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_path_walk.h>

#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/artix_units.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/test_util.h>

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;
using namespace sphere_unit;  // the draw, the port helpers and the slot (sphere_unit_draw.h, path_slot.h)

constexpr int kIds = 8;      // the Verilated walker's (PARAMS IDS=8)
constexpr int kMinPass = 3;  // DeviceUnits::min_pass

// A walk's passes as the model makes them: each level's slots, in order (walk_closest_hit's levels, with the far
// pair and the pads the walker adds; a slot without a pair for the sphere the ray leaves).
std::vector<std::vector<Slot>> model_passes(const artix::UnitRay& ray, const artix::UnitWorld& world, int from,
                                            bool into) {
  std::vector<std::vector<Slot>> passes;
  std::vector<int> level{0};
  while (!level.empty()) {
    std::vector<Slot> slots;
    if (passes.empty() && into) slots.push_back({Slot::kFar, from});
    std::vector<int> next;
    for (const int v : level) {
      const artix::UnitNode& node = world.nodes[static_cast<std::size_t>(v)];
      for (int i = node.first_sphere; i < node.first_sphere + node.spheres; ++i)
        slots.push_back(i == from ? Slot{Slot::kNone, 0} : Slot{Slot::kPair, i});
      for (int c = node.first_child; c < node.first_child + node.children; ++c) {
        slots.push_back({Slot::kBound, c});
        if (artix::enters(ray, world.nodes[static_cast<std::size_t>(c)].bound)) next.push_back(c);
      }
    }
    while (slots.size() < static_cast<std::size_t>(kMinPass)) slots.push_back({Slot::kNone, 0});
    passes.push_back(std::move(slots));
    level = std::move(next);
  }
  return passes;
}

// The smallest ball around `balls` (centre the middle of their box, radius the farthest reach rounded up), with 1
// to spare.
artix::UnitSphere enclosing(const std::vector<artix::UnitSphere>& balls) {
  std::array<std::int64_t, 3> lo{}, hi{};
  for (std::size_t k = 0; k < 3; ++k) {
    lo[k] = balls[0].c[k] - balls[0].r;
    hi[k] = balls[0].c[k] + balls[0].r;
    for (const auto& b : balls) {
      lo[k] = std::min(lo[k], b.c[k] - b.r);
      hi[k] = std::max(hi[k], b.c[k] + b.r);
    }
  }
  core::KernelSphere<std::int64_t> k;
  k.center = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  double reach = 0;
  for (const auto& b : balls) {
    double d2 = 0;
    for (std::size_t j = 0; j < 3; ++j) {
      const double d = static_cast<double>(b.c[j] - k.center[j]);
      d2 += d * d;
    }
    reach = std::max(reach, std::sqrt(d2) + static_cast<double>(b.r));
  }
  k.radius = std::min<std::int64_t>(static_cast<std::int64_t>(reach) + 2, (std::int64_t{1} << 21) - 1);
  return artix::prepare_sphere(k, core::KernelSurface{});
}

// A random tree over the world's spheres, up to 8 levels below the root and at most one node a sphere, nodes
// numbered level by level with up to `fan` children each; every node but the root holds a sphere at least, the
// rest of the spheres spread at random (runs in node order); every bound encloses what lies in it.
void random_tree(artix::UnitWorld& world, std::mt19937_64& rng, int fan) {
  const int n = static_cast<int>(world.spheres.size());
  struct Build {
    int first_child = 0, children = 0, depth = 0, spheres = 0;
  };
  std::vector<Build> nodes(1);
  for (std::size_t v = 0; v < nodes.size(); ++v) {
    const int room = n - static_cast<int>(nodes.size()) + 1;  // nodes more that can each hold a sphere
    const int kids = nodes[v].depth == 8 ? 0 : std::min(room, static_cast<int>(rng() % static_cast<std::uint64_t>(fan + 1)));
    nodes[v].first_child = kids > 0 ? static_cast<int>(nodes.size()) : 0;
    nodes[v].children = kids;
    for (int c = 0; c < kids; ++c) nodes.push_back({0, 0, nodes[v].depth + 1, 1});
  }
  for (int left = n - static_cast<int>(nodes.size()) + 1; left > 0; --left)
    ++nodes[static_cast<std::size_t>(rng() % nodes.size())].spheres;
  world.nodes.assign(nodes.size(), {});
  int next_sphere = 0;
  for (std::size_t v = 0; v < nodes.size(); ++v) {
    world.nodes[v].first_sphere = nodes[v].spheres > 0 ? next_sphere : 0;
    world.nodes[v].spheres = nodes[v].spheres;
    world.nodes[v].first_child = nodes[v].first_child;
    world.nodes[v].children = nodes[v].children;
    next_sphere += nodes[v].spheres;
  }
  // Bounds from the last node up: a node's bound encloses its spheres and its children's bounds.
  for (std::size_t v = nodes.size(); v-- > 1;) {
    artix::UnitNode& u = world.nodes[v];
    std::vector<artix::UnitSphere> inside;
    for (int i = u.first_sphere; i < u.first_sphere + u.spheres; ++i) inside.push_back(world.spheres[static_cast<std::size_t>(i)]);
    for (int c = u.first_child; c < u.first_child + u.children; ++c) inside.push_back(world.nodes[static_cast<std::size_t>(c)].bound);
    u.bound = enclosing(inside);
  }
}

// A bounced ray: from a point on sphere `from`'s surface, in any direction.
artix::UnitRay bounced_ray(Draw& draw, const artix::UnitSphere& from) {
  artix::UnitRay r = draw.ray();  // for its direction
  double u[3], len = 0;
  for (double& x : u) {
    x = draw.uniform(-1, 1);
    len += x * x;
  }
  len = std::sqrt(len);
  for (std::size_t k = 0; k < 3; ++k)
    r.o[k] = draw.clamp_coord(static_cast<double>(from.c[k]) + static_cast<double>(from.r) * u[k] / len);
  return r;
}

struct Walk {
  artix::UnitRay ray;
  int from = 0;
  bool into = false;
  std::vector<std::vector<Slot>> passes;  // the model's
  artix::PathUnitHit want;               // the model's
  artix::PathUnitHit got;                // the passes' hits merged
  std::size_t level = 0;                 // the pass in flight or next
};

struct Pending {
  int id;
  std::int64_t since;
};

// Runs `walks` through the walker and the sphere unit; returns the slots checked.
struct Stats {
  int walks = 0, passes = 0, later_levels = 0, slots = 0, far_hits = 0, hits = 0, wide = 0;
  int max_levels = 0;
};

void run(const artix::UnitWorld& world, std::vector<Walk>& walks, Stats& stats) {
  auto walker = std::make_unique<Vts_path_walk>();
  auto unit = std::make_unique<Vts_artix_sphere_unit_path>();
  const artix::UnitNode& root = world.nodes[0];
  walker->root_first_sphere = static_cast<CData>(root.first_sphere);
  walker->root_spheres = static_cast<CData>(root.spheres);
  walker->root_first_child = static_cast<CData>(root.first_child);
  walker->root_children = static_cast<CData>(root.children);
  walker->rst = unit->rst = 1;
  rising_edge(*walker);
  rising_edge(*unit);
  rising_edge(*walker);
  rising_edge(*unit);
  walker->rst = unit->rst = 0;

  std::vector<int> free_ids;
  for (int i = kIds - 1; i >= 0; --i) free_ids.push_back(i);
  std::vector<std::size_t> walk_of(kIds);  // the walk each id names
  std::size_t next_walk = 0;
  std::deque<Pending> pending;               // passes waiting for the port, oldest first
  std::deque<int> issuing;                   // ids of the passes started whose slots are still to come out
  std::deque<int> in_flight;                 // ids of the passes whose results are still to come, in order
  std::vector<Slot> seen_slots;              // the pass coming out
  bool to_unit_valid = false;               // the slot out last cycle, at the sphere unit this cycle
  Slot to_unit;
  bool to_unit_first = false, to_unit_end = false;
  int to_unit_id = 0;
  int node_read = 0;                         // the node whose record is at the walker's inputs
  std::int64_t started_at = -1, now = 0;
  std::size_t done = 0;

  const auto record = [&](int v) {
    const artix::UnitNode& n = world.nodes[static_cast<std::size_t>(std::clamp(v, 0, static_cast<int>(world.nodes.size()) - 1))];
    walker->node_first_sphere = static_cast<CData>(n.first_sphere);
    walker->node_spheres = static_cast<CData>(n.spheres);
    walker->node_first_child = static_cast<CData>(n.first_child);
    walker->node_children = static_cast<CData>(n.children);
  };

  for (; done < walks.size(); ++now) {
    ASSERT_LT(now, 10'000'000) << "the walks never finished";
    // New walks take free ids; each walk's first pass then waits for the port.
    while (!free_ids.empty() && next_walk < walks.size()) {
      const int id = free_ids.back();
      free_ids.pop_back();
      walk_of[static_cast<std::size_t>(id)] = next_walk++;
      pending.push_back({id, now});
    }
    // The walker's inputs: a pass when the port is free, the node record read last cycle, the sphere unit's
    // reports and result.
    record(node_read);
    walker->start = 0;
    if (walker->ready != 0) {
      if (started_at >= 0) {
        // The pass before held the port from its start to this cycle: the model's count.
        const Walk& w = walks[walk_of[static_cast<std::size_t>(issuing.back())]];
        const std::size_t level = w.level;
        const int tests = static_cast<int>(w.passes[level].size());
        EXPECT_EQ(now - started_at, (level > 0 ? 1 : 0) + std::max(tests, kMinPass)) << "walk level " << level;
        started_at = -1;
      }
      if (!pending.empty()) {
        const Pending p = pending.front();
        pending.pop_front();
        const Walk& w = walks[walk_of[static_cast<std::size_t>(p.id)]];
        walker->start = 1;
        walker->start_root = w.level == 0;
        walker->start_id = static_cast<CData>(p.id);
        walker->start_from = static_cast<CData>(w.from);
        walker->start_into = w.into;
        issuing.push_back(p.id);
        in_flight.push_back(p.id);
        started_at = now;
      }
    }
    walker->entered_valid = unit->out_entered_valid;
    walker->entered = unit->out_entered;
    walker->result_valid = unit->out_valid;
    // The sphere unit's inputs: the slot out last cycle, with its fields.
    unit->in_first = unit->in_pair = unit->in_end = unit->in_far = unit->in_bound = 0;
    if (to_unit_valid) {
      const Walk& w = walks[walk_of[static_cast<std::size_t>(to_unit_id)]];
      const artix::UnitSphere& b = to_unit.kind == Slot::kBound ? world.nodes[static_cast<std::size_t>(to_unit.index)].bound
                                                                  : world.spheres[static_cast<std::size_t>(to_unit.index)];
      drive(*unit, to_unit, to_unit_first, to_unit_end, w.ray, b);
    }
    walker->clk = 0;
    walker->eval();

    // A pass's result: merged into its walk's hit; the walk's next level waits for the port, or the walk is done.
    if (unit->out_valid != 0) {
      ASSERT_FALSE(in_flight.empty());
      const int id = in_flight.front();
      in_flight.pop_front();
      EXPECT_EQ(static_cast<int>(walker->result_id), id);
      Walk& w = walks[walk_of[static_cast<std::size_t>(id)]];
      if (unit->out_hit != 0) {
        const artix::PathUnitHit h{static_cast<int>(unit->out_carry),
                                   static_cast<std::int64_t>(sign_extend(get(unit->out_td), kTdW)),
                                   unit->out_far != 0};
        if (w.got.index < 0 || h.td < w.got.td || (h.td == w.got.td && h.index < w.got.index)) w.got = h;
      }
      ++stats.passes;
      const bool more = w.level + 1 < w.passes.size();
      EXPECT_EQ(walker->result_more != 0, more) << "walk " << walk_of[static_cast<std::size_t>(id)] << " level " << w.level;
      if (more) {
        ++w.level;
        ++stats.later_levels;
        pending.push_back({id, now});
      } else {
        EXPECT_EQ(w.got.index, w.want.index) << "walk " << walk_of[static_cast<std::size_t>(id)];
        EXPECT_EQ(w.got.td, w.want.td) << "walk " << walk_of[static_cast<std::size_t>(id)];
        EXPECT_EQ(w.got.inside, w.want.inside) << "walk " << walk_of[static_cast<std::size_t>(id)];
        stats.hits += w.want.index >= 0;
        stats.far_hits += w.want.inside;
        stats.max_levels = std::max(stats.max_levels, static_cast<int>(w.passes.size()));
        ++stats.walks;
        ++done;
        free_ids.push_back(id);
      }
    }

    // The walker's slot out this cycle goes to the sphere unit next cycle; its node read gives next cycle's record.
    to_unit_valid = false;
    if (walker->slot_valid != 0) {
      ASSERT_FALSE(issuing.empty()) << "a slot out of no pass, cycle " << now;
      const Slot::Kind kind = walker->slot_bound != 0 ? Slot::kBound
                              : walker->slot_far != 0  ? Slot::kFar
                              : walker->slot_pair != 0 ? Slot::kPair
                                                       : Slot::kNone;
      const Slot s{kind, kind == Slot::kNone ? 0 : static_cast<int>(walker->slot_index)};
      if (walker->slot_first != 0) {
        EXPECT_TRUE(seen_slots.empty()) << "cycle " << now;
      }
      seen_slots.push_back(s);
      to_unit = s;
      to_unit_valid = true;
      to_unit_first = walker->slot_first != 0;
      to_unit_end = walker->slot_end != 0;
      to_unit_id = issuing.front();
      if (walker->slot_end != 0) {
        const Walk& w = walks[walk_of[static_cast<std::size_t>(issuing.front())]];
        const std::vector<Slot>& want = w.passes[w.level];
        EXPECT_EQ(seen_slots.size(), want.size()) << "level " << w.level;
        for (std::size_t i = 0; i < std::min(want.size(), seen_slots.size()); ++i)
          EXPECT_EQ(seen_slots[i], want[i]) << "slot " << i << " of level " << w.level << ": "
                                            << describe(seen_slots[i]) << " for " << describe(want[i]);
        stats.slots += static_cast<int>(seen_slots.size());
        stats.wide += seen_slots.size() > 40;
        seen_slots.clear();
        issuing.pop_front();
      }
    }
    node_read = walker->node_addr;
    rising_edge(*walker);
    rising_edge(*unit);
  }
  EXPECT_EQ(walker->overflow, 0);
}

std::vector<Walk> bounced_walks(const artix::UnitWorld& world, Draw& draw, int count) {
  std::vector<Walk> walks;
  for (int k = 0; k < count; ++k) {
    Walk w;
    w.from = draw.below(static_cast<int>(world.spheres.size()));
    w.ray = bounced_ray(draw, world.spheres[static_cast<std::size_t>(w.from)]);
    w.into = draw.below(2) == 0;
    w.passes = model_passes(w.ray, world, w.from, w.into);
    std::vector<int> levels;
    const artix::Hit near = artix::walk_closest_hit(w.ray, world, w.from, levels);
    // The walk's slots are the model's tests, the far pair more on the first.
    EXPECT_EQ(levels.size(), w.passes.size());
    for (std::size_t i = 0; i < std::min(levels.size(), w.passes.size()); ++i)
      EXPECT_EQ(std::max(levels[i] + (i == 0 && w.into ? 1 : 0), kMinPass), static_cast<int>(w.passes[i].size()));
    w.want = artix::with_far_side({w.ray, w.from, w.into}, near, world.spheres);
    walks.push_back(std::move(w));
  }
  return walks;
}

TEST(PathWalkRtl, TheHostsHierarchiesWalkAsTheModel) {
  std::mt19937_64 rng(20261207);
  Draw draw(7);
  const device::DevicePreset p = device::artix_path_preset();
  Stats stats;
  int worlds = 0;
  for (int w = 0; w < 12; ++w) {
    const device::SceneMemory scene = device::testing::with_hierarchy(p, device::testing::random_path_world(p, rng, 64));
    if (scene.hierarchy.empty()) continue;
    ++worlds;
    const artix::UnitWorld world = artix::prepare_world(scene);
    std::vector<Walk> walks = bounced_walks(world, draw, 300);
    run(world, walks, stats);
  }
  EXPECT_GE(worlds, 8);
  EXPECT_EQ(stats.walks, worlds * 300);
  EXPECT_GT(stats.later_levels, stats.walks / 4);
  EXPECT_GT(stats.hits, stats.walks / 5);
  EXPECT_GT(stats.far_hits, 50);
}

TEST(PathWalkRtl, DeepAndWideTreesWalkAsTheModel) {
  std::mt19937_64 rng(77);
  Draw draw(8);
  const device::DevicePreset p = device::artix_path_preset();
  Stats stats;
  for (int w = 0; w < 16; ++w) {
    // A world's spheres and those of the next ones, up to 60 to 250 of them.
    artix::UnitWorld world = artix::prepare_world(device::testing::random_path_world(p, rng, 40));
    const std::size_t want = 60 + rng() % 191;
    while (world.spheres.size() < want) {
      const artix::UnitWorld more = artix::prepare_world(device::testing::random_path_world(p, rng, 40));
      const std::size_t room = want - world.spheres.size();
      world.spheres.insert(world.spheres.end(), more.spheres.begin(),
                           more.spheres.begin() + static_cast<std::ptrdiff_t>(std::min(room, more.spheres.size())));
    }
    random_tree(world, rng, w % 4 == 0 ? 40 : 2 + w % 5);
    std::vector<Walk> walks = bounced_walks(world, draw, 200);
    run(world, walks, stats);
  }
  EXPECT_GT(stats.walks, 2000);
  EXPECT_GE(stats.max_levels, 5);
  EXPECT_GT(stats.wide, 20);
  EXPECT_GT(stats.later_levels, stats.walks);
}

}  // namespace
}  // namespace tripsitter::rtl

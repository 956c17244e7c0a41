// The hierarchy check's RTL (ts_rx_hierarchy.sv) against the model's: link::hierarchy_error and the receiver's
// format check of the bounds (device/receiver.cpp), world by world. The worlds are the host's hierarchies of random
// path worlds (host::build_hierarchy, as the artix path preset's host sends them), each also broken in one of the
// ways the rules name (a child or a sphere out of range, a cycle, a second parent, a node not reached, a sphere in
// two nodes or in none, a bound one unit too small and one exactly large enough, a bound on the root, an empty node,
// a bound outside the formats), and chains of nodes 1 to 10 levels deep (at most 8 allowed).
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_rx_hierarchy.h>

#include "hierarchy_worlds.h"

namespace tripsitter::rtl {
namespace {

using link::World;
using link::WireNode;

struct Answer {
  bool done = false, ok = false;
  std::int64_t cycles = 0;  // from check to done
};

// The world's spheres and node records into the block, as the receiver gives them (a random idle cycle now and
// then), then the check.
Answer run(Vts_rx_hierarchy& top, const World& w, std::mt19937_64& rng) {
  const auto coord = [](std::int32_t c) { return static_cast<IData>(c) & static_cast<IData>(mask(hierarchy::preset().x.total_bits)); };
  top.begin_world = 1;
  rising_edge(top);
  top.begin_world = 0;
  for (const link::WireSphere& b : w.spheres) {
    while (rng() % 4 == 0) rising_edge(top);
    top.sphere_we = 1;
    top.sphere_x = coord(b.x);
    top.sphere_y = coord(b.y);
    top.sphere_z = coord(b.z);
    top.sphere_r = b.radius & static_cast<IData>(mask(hierarchy::preset().radius.total_bits));
    rising_edge(top);
    top.sphere_we = 0;
  }
  for (const WireNode& v : w.nodes) {
    while (rng() % 4 == 0) rising_edge(top);
    top.node_we = 1;
    top.node_x = static_cast<IData>(v.x);
    top.node_y = static_cast<IData>(v.y);
    top.node_z = static_cast<IData>(v.z);
    top.node_radius = v.radius;
    top.node_first_child = v.first_child;
    top.node_children = v.children;
    top.node_sphere_count = v.sphere_count;
    top.node_first_sphere = v.first_sphere;
    rising_edge(top);
    top.node_we = 0;
  }
  top.check = 1;
  Answer r;
  while (r.cycles < 20000) {
    rising_edge(top);
    top.check = 0;
    ++r.cycles;
    if (top.done) {
      r.done = true;
      r.ok = top.ok != 0;
      break;
    }
  }
  return r;
}

TEST(RxHierarchyRtl, AcceptsWhatTheReceiverAcceptsAndRefusesWhatItRefuses) {
  std::mt19937_64 rng(111);
  VerilatedContext context;
  context.randReset(2);
  auto top = std::make_unique<Vts_rx_hierarchy>(&context);
  top->begin_world = top->sphere_we = top->node_we = top->check = 0;  // Verilator starts inputs random too
  top->rst = 1;
  for (int i = 0; i < 3; ++i) rising_edge(*top);
  top->rst = 0;

  int bad = 0, accepted = 0, refused = 0, worlds = 0;
  std::int64_t most_cycles = 0;
  std::size_t most_spheres = 0, most_nodes = 0;
  const auto check = [&](const World& w, const std::string& what) {
    const bool want = hierarchy::accepted(w);
    const Answer got = run(*top, w, rng);
    ++worlds;
    (want ? accepted : refused) += 1;
    if (!got.done) {
      ADD_FAILURE() << what << ": no answer in " << got.cycles << " cycles";
      ++bad;
      return;
    }
    if (got.ok && got.cycles > most_cycles) {
      most_cycles = got.cycles;
      most_spheres = w.spheres.size();
      most_nodes = w.nodes.size();
    }
    if (got.ok != want && ++bad <= 5) {
      const auto problem = link::hierarchy_error(w);
      ADD_FAILURE() << what << " (" << w.spheres.size() << " spheres, " << w.nodes.size() << " nodes): rtl "
                    << (got.ok ? "accepts" : "refuses") << ", model "
                    << (want ? "accepts" : "refuses: " + (problem ? problem->detail : std::string("formats")));
    }
  };

  for (int trial = 0; trial < 60; ++trial) {
    const World w = hierarchy::random_world(rng, trial % 10 == 0);
    check(w, "trial " + std::to_string(trial) + " as built");
    if (w.nodes.size() < 2) continue;
    for (const hierarchy::Damage& d : hierarchy::damages()) {
      World broken = w;
      if (d.apply(broken, rng)) check(broken, "trial " + std::to_string(trial) + ", " + d.name);
    }
  }
  for (int depth = 1; depth <= 10; ++depth) check(hierarchy::chain(depth), "a chain " + std::to_string(depth) + " deep");
  World too_many = hierarchy::chain(1);
  while (too_many.nodes.size() <= hierarchy::preset().max_spheres) too_many.nodes.push_back(too_many.nodes.back());
  check(too_many, "more records than scene memory holds");

  EXPECT_EQ(bad, 0);
  EXPECT_GT(accepted, 60);
  EXPECT_GT(refused, 600);
  std::printf("%d worlds, %d accepted, %d refused; the longest accepted check %lld cycles (%zu spheres, %zu nodes)\n",
              worlds, accepted, refused, static_cast<long long>(most_cycles), most_spheres, most_nodes);
}

}  // namespace
}  // namespace tripsitter::rtl

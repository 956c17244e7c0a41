// The hierarchy check's RTL (ts_path_hierarchy.sv) against the model's: link::hierarchy_error and the receiver's
// format check of the bounds (device/receiver.cpp), world by world. The worlds are the host's hierarchies of random
// path worlds (host::build_hierarchy, as the artix path preset's host sends them), each also broken in one of the
// ways the rules name (a child or a sphere out of range, a cycle, a second parent, a node not reached, a sphere in
// two nodes or in none, a bound one unit too small and one exactly large enough, a bound on the root, an empty node,
// a bound outside the formats), and chains of nodes 1 to 10 levels deep (at most 8 allowed).
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include "path_rtl_util.h"

#include <Vts_path_hierarchy.h>

#include <tripsitter/device/preset.h>
#include <tripsitter/device/test_util.h>
#include <tripsitter/link/frame.h>

namespace tripsitter::rtl {
namespace {

using link::World;
using link::WireNode;

const device::DevicePreset& preset() {
  static const device::DevicePreset p = device::artix_path_preset();
  return p;
}

// What the receiver makes of the world's hierarchy: whether it keeps the wire's rules and fits scene memory.
bool model_ok(const World& w) {
  if (w.nodes.size() > preset().max_spheres) return false;  // the frame's length check
  if (link::hierarchy_error(w)) return false;
  for (std::size_t i = 1; i < w.nodes.size(); ++i) {
    const WireNode& v = w.nodes[i];
    if (!preset().holds_ball(v.x, v.y, v.z, v.radius)) return false;
  }
  return true;
}

struct Answer {
  bool done = false, ok = false;
  std::int64_t cycles = 0;  // from check to done
};

// The world's spheres and node records into the block, as the receiver gives them (a random idle cycle now and
// then), then the check.
Answer run(Vts_path_hierarchy& top, const World& w, std::mt19937_64& rng) {
  const auto coord = [](std::int32_t c) { return static_cast<IData>(c) & static_cast<IData>(mask(preset().x.total_bits)); };
  top.begin_world = 1;
  rising_edge(top);
  top.begin_world = 0;
  for (const link::WireSphere& b : w.spheres) {
    while (rng() % 4 == 0) rising_edge(top);
    top.sphere_we = 1;
    top.sphere_x = coord(b.x);
    top.sphere_y = coord(b.y);
    top.sphere_z = coord(b.z);
    top.sphere_r = b.radius & static_cast<IData>(mask(preset().radius.total_bits));
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

World world_of(const device::SceneMemory& scene) {
  World w;
  w.frac_bits = static_cast<std::uint8_t>(preset().frac_bits());
  w.spheres = device::testing::wire_spheres(scene);
  for (const device::HierarchyNode& v : scene.hierarchy) w.nodes.push_back(device::wire_node(v));
  return w;
}

// The smallest radius of node i's bound that encloses what it holds.
std::uint32_t tight_radius(const World& w, std::size_t i) {
  const WireNode& v = w.nodes[i];
  std::int64_t need = 1;
  const auto take = [&](std::int64_t x, std::int64_t y, std::int64_t z, std::int64_t r) {
    const std::int64_t dx = x - v.x, dy = y - v.y, dz = z - v.z, d2 = dx * dx + dy * dy + dz * dz;
    auto d = static_cast<std::int64_t>(std::sqrt(static_cast<double>(d2)));  // then exactly ceil(sqrt(d2))
    while (d * d < d2) ++d;
    while (d > 0 && (d - 1) * (d - 1) >= d2) --d;
    need = std::max(need, r + d);
  };
  for (std::uint32_t s = v.first_sphere; s < v.first_sphere + v.sphere_count; ++s)
    take(w.spheres[s].x, w.spheres[s].y, w.spheres[s].z, w.spheres[s].radius);
  for (std::uint32_t c = v.first_child; c < std::uint32_t{v.first_child} + v.children; ++c)
    take(w.nodes[c].x, w.nodes[c].y, w.nodes[c].z, w.nodes[c].radius);
  return static_cast<std::uint32_t>(need);
}

// A chain below the root: node k (1..depth) holds sphere k - 1 and node k + 1, each bound inside the one above.
World chain(int depth) {
  World w;
  w.frac_bits = 4;
  w.nodes.push_back({0, 0, 0, 0, 1, 1, 0, 0});
  for (int k = 1; k <= depth; ++k) {
    const std::uint32_t r = 400000u - 10000u * static_cast<std::uint32_t>(k);
    w.spheres.push_back({0, 0, 8000, 100, link::kMaterialLambertian, {}, 0, 4096});
    w.nodes.push_back({0, 0, 8000, r, static_cast<std::uint16_t>(k < depth ? k + 1 : 0),
                       static_cast<std::uint8_t>(k < depth ? 1 : 0), 1, static_cast<std::uint32_t>(k - 1)});
  }
  return w;
}

TEST(PathHierarchyRtl, AcceptsWhatTheReceiverAcceptsAndRefusesWhatItRefuses) {
  std::mt19937_64 rng(111);
  VerilatedContext context;
  context.randReset(2);
  auto top = std::make_unique<Vts_path_hierarchy>(&context);
  top->begin_world = top->sphere_we = top->node_we = top->check = 0;  // Verilator starts inputs random too
  top->rst = 1;
  for (int i = 0; i < 3; ++i) rising_edge(*top);
  top->rst = 0;

  int bad = 0, accepted = 0, refused = 0, worlds = 0;
  std::int64_t most_cycles = 0;
  std::size_t most_spheres = 0, most_nodes = 0;
  const auto check = [&](const World& w, const std::string& what) {
    const bool want = model_ok(w);
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

  using Damage = std::function<bool(World&)>;  // false: the world has no place for this damage
  const auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  const std::vector<std::pair<std::string, Damage>> damages = {
      {"a child out of range", [&](World& w) { return ++w.nodes[0].children, true; }},
      {"a cycle", [&](World& w) {
         WireNode& v = w.nodes[1 + pick(w.nodes.size() - 1)];
         v.first_child = 0, v.children = 1;
         return true;
       }},
      {"a second parent", [&](World& w) {
         WireNode& v = w.nodes[1 + pick(w.nodes.size() - 1)];
         v.first_child = static_cast<std::uint16_t>(1 + pick(w.nodes.size() - 1)), v.children = 1;
         return true;
       }},
      {"a node not reached", [&](World& w) { return --w.nodes[0].children > 0; }},
      {"a sphere beyond the last", [&](World& w) { return ++w.nodes.back().first_sphere, true; }},
      {"a sphere in two nodes", [&](World& w) {
         WireNode& v = w.nodes[1 + pick(w.nodes.size() - 1)];
         return v.sphere_count > 0 && v.first_sphere > 0 ? (--v.first_sphere, true) : false;
       }},
      {"a sphere in no node", [&](World& w) {
         WireNode& v = w.nodes[1 + pick(w.nodes.size() - 1)];
         return v.sphere_count > 1 ? (--v.sphere_count, true) : false;
       }},
      {"a bound one unit too small", [&](World& w) {
         const std::size_t i = 1 + pick(w.nodes.size() - 1);
         w.nodes[i].radius = tight_radius(w, i) - 1;
         return true;
       }},
      {"a bound exactly large enough", [&](World& w) {
         const std::size_t i = 1 + pick(w.nodes.size() - 1);
         w.nodes[i].radius = tight_radius(w, i);
         return true;
       }},
      {"a bound half as large", [&](World& w) { return w.nodes[1 + pick(w.nodes.size() - 1)].radius /= 2, true; }},
      {"a bound on the root", [&](World& w) { return w.nodes[0].z = 1, true; }},
      {"a bound of radius 0", [&](World& w) { return w.nodes.back().radius = 0, true; }},
      {"an empty node", [&](World& w) {  // one more child of the root, holding nothing
         WireNode& root = w.nodes[0];
         if (std::size_t{root.first_child} + root.children != w.nodes.size()) return false;
         ++root.children;
         WireNode empty = w.nodes.back();
         empty.first_child = 0, empty.children = 0, empty.first_sphere = 0, empty.sphere_count = 0;
         w.nodes.push_back(empty);
         return true;
       }},
      {"first_child without children", [&](World& w) { return w.nodes.back().first_child = 1, true; }},
      {"first_sphere without spheres", [&](World& w) {
         WireNode& v = w.nodes[0];
         return v.sphere_count == 0 ? (v.first_sphere = 1, true) : false;
       }},
      {"a radius outside the format", [&](World& w) { return w.nodes.back().radius = 1u << 21, true; }},
      {"a centre outside the format", [&](World& w) {
         WireNode& v = w.nodes.back();
         v.x = rng() % 2 ? (1 << 21) : -(1 << 21) - 1;
         return true;
       }},
      {"a centre on the format's edge", [&](World& w) {
         WireNode& v = w.nodes.back();
         v.x = rng() % 2 ? (1 << 21) - 1 : -(1 << 21);
         v.radius = (1u << 21) - 1;
         return true;
       }},
  };

  for (int trial = 0; trial < 60; ++trial) {
    const std::size_t most = trial % 6 == 0 ? 400 : 20 + pick(100);
    device::SceneMemory scene = device::testing::random_path_world(preset(), rng, most);
    if (trial % 10 == 0) {  // scene memory full: spheres scattered in view
      for (std::size_t i = scene.geometry.size(); i < preset().max_spheres; ++i) {
        const auto z = static_cast<std::int64_t>(2000 + rng() % 60000);
        scene.geometry.push_back({{static_cast<std::int64_t>(rng() % 80000) - 40000,
                                   static_cast<std::int64_t>(rng() % 60000) - 30000, z},
                                  static_cast<std::int64_t>(50 + rng() % 4000)});
        scene.surfaces.push_back(device::testing::random_path_surface(rng));
      }
    }
    if (scene.geometry.size() > preset().max_spheres) {
      scene.geometry.resize(preset().max_spheres);
      scene.surfaces.resize(preset().max_spheres);
    }
    const World w = world_of(device::testing::with_hierarchy(preset(), scene));
    check(w, "trial " + std::to_string(trial) + " as built");
    if (w.nodes.size() < 2) continue;
    for (const auto& [name, damage] : damages) {
      World broken = w;
      if (damage(broken)) check(broken, "trial " + std::to_string(trial) + ", " + name);
    }
  }
  for (int depth = 1; depth <= 10; ++depth) check(chain(depth), "a chain " + std::to_string(depth) + " deep");
  World too_many = chain(1);
  while (too_many.nodes.size() <= preset().max_spheres) too_many.nodes.push_back(too_many.nodes.back());
  check(too_many, "more records than scene memory holds");

  EXPECT_EQ(bad, 0);
  EXPECT_GT(accepted, 60);
  EXPECT_GT(refused, 600);
  std::printf("%d worlds, %d accepted, %d refused; the longest accepted check %lld cycles (%zu spheres, %zu nodes)\n",
              worlds, accepted, refused, static_cast<long long>(most_cycles), most_spheres, most_nodes);
}

}  // namespace
}  // namespace tripsitter::rtl

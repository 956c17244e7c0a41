// The worlds with a hierarchy that the receiver's RTL tests send (rx_hierarchy_rtl_test: the check alone;
// receiver_rtl_test: the whole receiver against device::Receiver): the host's hierarchies of random path worlds in
// the artix path preset's formats, the ways each can be broken (one of the wire's rules each), chains of nodes, and
// what the receiver makes of a world's hierarchy.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <tripsitter/device/preset.h>
#include <tripsitter/device/receiver.h>
#include <tripsitter/device/test_util.h>
#include <tripsitter/link/frame.h>

namespace tripsitter::rtl::hierarchy {

using link::WireNode;
using link::World;

inline const device::DevicePreset& preset() {
  static const device::DevicePreset p = device::artix_path_preset();
  return p;
}

// Whether the receiver takes the world's hierarchy: it keeps the wire's rules (link::hierarchy_error), its bounds
// fit scene memory's formats, and its nodes are no more than the frame's length allows.
inline bool accepted(const World& w) {
  if (w.nodes.size() > preset().max_spheres) return false;
  if (link::hierarchy_error(w)) return false;
  for (std::size_t i = 1; i < w.nodes.size(); ++i) {
    const WireNode& v = w.nodes[i];
    if (!preset().holds_ball(v.x, v.y, v.z, v.radius)) return false;
  }
  return true;
}

// The world the host sends for a random path world (device::testing::random_path_world, or with `full` scene memory
// filled with spheres in view): its spheres in the hierarchy's order and its nodes (none for a small world).
inline World random_world(std::mt19937_64& rng, bool full) {
  const std::size_t most = rng() % 6 == 0 ? 400 : 20 + rng() % 100;
  device::SceneMemory scene = device::testing::random_path_world(preset(), rng, most);
  if (full) {
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
  const device::SceneMemory sent = device::testing::with_hierarchy(preset(), scene);
  World w;
  w.frac_bits = static_cast<std::uint8_t>(preset().frac_bits());
  w.spheres = device::testing::wire_spheres(sent);
  for (const device::HierarchyNode& v : sent.hierarchy) w.nodes.push_back(device::wire_node(v));
  return w;
}

// The smallest radius of node i's bound that encloses what it holds.
inline std::uint32_t tight_radius(const World& w, std::size_t i) {
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
inline World chain(int depth) {
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

// One way to break a world of two nodes or more; apply returns false when the world has no place for it.
struct Damage {
  std::string name;
  std::function<bool(World&, std::mt19937_64&)> apply;
};

inline const std::vector<Damage>& damages() {
  using Rng = std::mt19937_64;
  const auto pick = [](Rng& rng, const World& w) { return 1 + static_cast<std::size_t>(rng() % (w.nodes.size() - 1)); };
  static const std::vector<Damage> list = {
      {"a child out of range", [](World& w, Rng&) { return ++w.nodes[0].children, true; }},
      {"a cycle", [pick](World& w, Rng& rng) {
         WireNode& v = w.nodes[pick(rng, w)];
         v.first_child = 0, v.children = 1;
         return true;
       }},
      {"a second parent", [pick](World& w, Rng& rng) {
         WireNode& v = w.nodes[pick(rng, w)];
         v.first_child = static_cast<std::uint16_t>(pick(rng, w)), v.children = 1;
         return true;
       }},
      {"a node not reached", [](World& w, Rng&) { return --w.nodes[0].children > 0; }},
      {"a sphere beyond the last", [](World& w, Rng&) { return ++w.nodes.back().first_sphere, true; }},
      {"a sphere in two nodes", [pick](World& w, Rng& rng) {
         WireNode& v = w.nodes[pick(rng, w)];
         return v.sphere_count > 0 && v.first_sphere > 0 ? (--v.first_sphere, true) : false;
       }},
      {"a sphere in no node", [pick](World& w, Rng& rng) {
         WireNode& v = w.nodes[pick(rng, w)];
         return v.sphere_count > 1 ? (--v.sphere_count, true) : false;
       }},
      {"a bound one unit too small", [pick](World& w, Rng& rng) {
         const std::size_t i = pick(rng, w);
         w.nodes[i].radius = tight_radius(w, i) - 1;
         return true;
       }},
      {"a bound exactly large enough", [pick](World& w, Rng& rng) {
         const std::size_t i = pick(rng, w);
         w.nodes[i].radius = tight_radius(w, i);
         return true;
       }},
      {"a bound half as large", [pick](World& w, Rng& rng) { return w.nodes[pick(rng, w)].radius /= 2, true; }},
      {"a bound on the root", [](World& w, Rng&) { return w.nodes[0].z = 1, true; }},
      {"a bound of radius 0", [](World& w, Rng&) { return w.nodes.back().radius = 0, true; }},
      {"an empty node", [](World& w, Rng&) {  // one more child of the root, holding nothing
         WireNode& root = w.nodes[0];
         if (std::size_t{root.first_child} + root.children != w.nodes.size()) return false;
         ++root.children;
         WireNode empty = w.nodes.back();
         empty.first_child = 0, empty.children = 0, empty.first_sphere = 0, empty.sphere_count = 0;
         w.nodes.push_back(empty);
         return true;
       }},
      {"first_child without children", [](World& w, Rng&) { return w.nodes.back().first_child = 1, true; }},
      {"first_sphere without spheres", [](World& w, Rng&) {
         WireNode& v = w.nodes[0];
         return v.sphere_count == 0 ? (v.first_sphere = 1, true) : false;
       }},
      {"a radius outside the format", [](World& w, Rng&) { return w.nodes.back().radius = 1u << 21, true; }},
      {"a centre outside the format", [](World& w, Rng& rng) {
         w.nodes.back().x = rng() % 2 ? (1 << 21) : -(1 << 21) - 1;
         return true;
       }},
      {"a centre on the format's edge", [](World& w, Rng& rng) {
         WireNode& v = w.nodes.back();
         v.x = rng() % 2 ? (1 << 21) - 1 : -(1 << 21);
         v.radius = (1u << 21) - 1;
         return true;
       }},
  };
  return list;
}

}  // namespace tripsitter::rtl::hierarchy

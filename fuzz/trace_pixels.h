// Draws a few pixels of a scene memory with the device's worker: any world inside the preset's formats must
// be drawable without an assertion or an overflow (docs/device.md bounds every intermediate).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/device/artix_units.h>
#include <tripsitter/link/frame.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/device/worker.h>

#include "check.h"

namespace tripsitter::fuzz {

// The corners, the centre, and where the first spheres' centres project, with up to core::kMaxBounces
// mirror bounces (more than any preset, as `--bounces 6` allows). A world with a hierarchy (the artix path preset's)
// is also walked by the sphere units for the same pixels' camera rays: a walk ends within the wire's depth, and
// what it hits the units hit.
inline void trace_some_pixels(const device::SceneMemory& m, const device::DevicePreset& p) {
  const device::Worker worker(p.sqrt_iterations, core::kMaxBounces);
  std::vector<std::pair<int, int>> pixels = {{0, 0}, {639, 0}, {0, 479}, {639, 479}, {320, 240}};
  for (std::size_t i = 0; i < std::min<std::size_t>(m.geometry.size(), 4); ++i) {
    const auto& c = m.geometry[i].center;
    if (c.z <= 0) continue;
    const auto project = [&](std::int64_t v, int half, int max) {
      const long double at = half + 320.0L * static_cast<long double>(v) / static_cast<long double>(c.z);
      return static_cast<int>(std::clamp<long double>(at, 0, max));
    };
    pixels.emplace_back(project(c.x, 320, 639), project(c.y, 240, 479));
  }
  for (const auto& [col, row] : pixels) {
    const core::PixelTrace t = worker.trace(col, row, m);
    FUZZ_CHECK(t.bounces >= 0 && t.bounces <= core::kMaxBounces, "a pixel bounced more often than allowed");
  }
  if (m.hierarchy.empty() || !p.units) return;
  const device::artix::UnitWorld world = device::artix::prepare_world(m);
  std::vector<int> passes;
  for (const auto& [col, row] : pixels) {
    const device::artix::UnitRay ray{{}, device::artix::camera_direction(col, row)};
    passes.clear();
    const device::artix::Hit hit = device::artix::walk_closest_hit(ray, world, -1, passes);
    FUZZ_CHECK(!passes.empty() && passes.size() <= link::kMaxHierarchyDepth + 1, "a walk deeper than the wire allows");
    if (hit.index >= 0) {
      const device::artix::Quadratic q =
          device::artix::quadratic(ray, world.spheres[static_cast<std::size_t>(hit.index)]);
      FUZZ_CHECK(q.hit() && q.td == hit.td, "a walk's hit that the units do not confirm");
    }
  }
}

}  // namespace tripsitter::fuzz

// One copy of the device's scene memory: what the workers read while a frame is drawn.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <tripsitter/core/sphere_kernel.h>

namespace tripsitter::device {

// A sphere's surface as stored next to its geometry (the v2 wire's material fields, unchanged).
struct SurfaceWord {
  std::uint8_t material = 0;
  std::array<std::uint8_t, 3> albedo{};
  std::uint16_t fuzz = 0;
  std::uint16_t ior = 0;
  bool operator==(const SurfaceWord&) const = default;
};

// A node of the world's hierarchy of bounding spheres (the v3 wire's node record, docs/link_format.md "The
// hierarchy"), as the artix path preset's walker reads it: its children are nodes first_child .. + children - 1,
// its spheres first_sphere .. + spheres - 1. Node 0, the root, has no bound (all zero) and is never tested.
struct HierarchyNode {
  core::KernelSphere<std::int64_t> bound;  // raw fixed point, the preset's fractional bits
  int first_child = 0;
  int children = 0;
  int first_sphere = 0;
  int spheres = 0;
};

struct SceneMemory {
  bool valid = false;          // false until the first good world arrives
  std::uint32_t sequence = 0;  // the v2 frame's sequence number; for v1, the count of words received
  // CRC-32 of the spheres' fields as received (not the sequence number): the path preset keeps accumulating
  // while a new world's content equals the one shown (docs/device.md, "Frame memory").
  std::uint32_t content = 0;
  // Geometry in raw fixed point (the preset's fractional bits), apart from surfaces so the kernel reads it directly.
  std::vector<core::KernelSphere<std::int64_t>> geometry;
  std::vector<SurfaceWord> surfaces;
  std::vector<HierarchyNode> hierarchy;  // empty when the world carries none
};

}  // namespace tripsitter::device

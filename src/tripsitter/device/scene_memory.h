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

struct SceneMemory {
  bool valid = false;          // false until the first good world arrives
  std::uint32_t sequence = 0;  // the v2 frame's sequence number; for v1, the count of words received
  // CRC-32 of the spheres' fields as received (not the sequence number): the path preset keeps accumulating
  // while a new world's content equals the one shown (docs/device.md, "Frame memory").
  std::uint32_t content = 0;
  // Geometry in raw fixed point (the preset's fractional bits), apart from surfaces so the kernel reads it directly.
  std::vector<core::KernelSphere<std::int64_t>> geometry;
  std::vector<SurfaceWord> surfaces;
};

}  // namespace tripsitter::device

// Helpers shared by the device tests.
#pragma once

#include <cstdint>
#include <vector>

#include <tripsitter/device/device.h>
#include <tripsitter/link/wire_v2.h>

namespace tripsitter::device::testing {

// A v2 frame of spheres given in pixel units, in the preset's format (lambertian grey).
inline std::vector<std::uint8_t> frame_of(const DevicePreset& preset, std::uint32_t sequence,
                                          const std::vector<std::array<double, 4>>& xyzr) {
  link::World w;
  w.sequence = sequence;
  w.frac_bits = static_cast<std::uint8_t>(preset.frac_bits());
  for (const auto& s : xyzr) {
    link::WireSphere ws;
    ws.x = static_cast<std::int32_t>(preset.x.quantize(s[0]).raw);
    ws.y = static_cast<std::int32_t>(preset.y.quantize(s[1]).raw);
    ws.z = static_cast<std::int32_t>(preset.z.quantize(s[2]).raw);
    ws.radius = static_cast<std::uint32_t>(preset.radius.quantize(s[3]).raw);
    ws.albedo = {128, 128, 128};
    ws.ior = 6144;
    w.spheres.push_back(ws);
  }
  return link::encode_v2_frame(w);
}

// The visible pixels of one frame, read straight from the VGA samples by counting clocks from the start
// of vertical blanking (independent of the monitor model).
inline std::vector<core::Rgb444> visible_pixels(Device& device, FrameStats* stats = nullptr) {
  std::vector<core::Rgb444> pixels;
  int clock = 0;
  const FrameStats s = device.run_frame([&](const VgaSample& sample) {
    const int line = (480 + clock / 800) % 525;
    const int col = clock % 800;
    if (line < 480 && col < 640) pixels.push_back(sample.colour);
    ++clock;
  });
  if (stats) *stats = s;
  return pixels;  // rows 0..479 in order, 640 each
}

}  // namespace tripsitter::device::testing

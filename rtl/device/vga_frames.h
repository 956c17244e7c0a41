// Whole VGA frames for the tests that hold an RTL top to the C++ model sample by sample (device_rtl_test,
// board_rtl_test): a frame as the connector carries it, and where two frames first differ.
#pragma once

#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <tripsitter/device/backend.h>
#include <tripsitter/device/device.h>
#include <tripsitter/device/vga.h>

namespace tripsitter::rtl {

// A whole frame, one sample per pixel clock from the start of vertical blanking; the frame's statistics to `stats`.
inline std::vector<device::VgaSample> frame_samples(device::Backend& device, device::FrameStats& stats) {
  std::vector<device::VgaSample> samples;
  samples.reserve(static_cast<std::size_t>(device::kVga640x480.h_total() * device::kVga640x480.v_total()));
  stats = device.run_frame_lines(
      [&](std::span<const device::VgaSample> line) { samples.insert(samples.end(), line.begin(), line.end()); });
  return samples;
}

inline std::string describe(const device::VgaSample& s) {
  std::ostringstream o;
  o << "hsync_n " << s.hsync_n << " vsync_n " << s.vsync_n << " colour 0x" << std::hex << s.colour.packed;
  return o.str();
}

// Empty if the frames are the same; else the first differing sample, with both values (the second frame's under
// `name`).
inline std::string first_difference(const std::vector<device::VgaSample>& model,
                                    const std::vector<device::VgaSample>& other, std::string_view name = "RTL") {
  if (model.size() != other.size()) return "sample counts differ";
  const device::VgaMode& vga = device::kVga640x480;
  for (std::size_t i = 0; i < model.size(); ++i) {
    if (model[i] == other[i]) continue;
    const int line = (static_cast<int>(i) / vga.h_total() + vga.v_visible) % vga.v_total();
    const int col = static_cast<int>(i) % vga.h_total();
    return "line " + std::to_string(line) + " column " + std::to_string(col) + ": model " + describe(model[i]) + ", " +
           std::string(name) + " " + describe(other[i]);
  }
  return "";
}

}  // namespace tripsitter::rtl

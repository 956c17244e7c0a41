// A VGA monitor: it sees only the signal (syncs and colour per pixel clock), locks to the sync pulses and
// captures the visible area as an image. Frames are taken from here, never from the line buffer.
#pragma once

#include <cstdint>
#include <optional>

#include <tripsitter/device/vga_signal.h>
#include <tripsitter/core/image.h>

namespace tripsitter::display {

class VgaMonitor {
 public:
  // The monitor expects this mode (it only uses the widths to place the visible area after each sync).
  explicit VgaMonitor(device::VgaMode mode = device::kVga640x480);

  // One pixel clock of signal.
  void sample(const device::VgaSample& s);

  // The last complete frame (all visible lines seen since a vertical sync), if any; cleared by the call.
  std::optional<core::Image444> take_frame();
  std::uint64_t frames_completed() const { return frames_; }
  // Widths measured from the signal: clocks the last hsync pulse lasted, lines the last vsync pulse lasted.
  int measured_hsync_clocks() const { return hsync_width_; }
  int measured_vsync_lines() const { return vsync_width_lines_; }

 private:
  device::VgaMode mode_;
  // Implementation state; see monitor.cpp.
  bool started_ = false;  // a previous sample exists, so edges can be seen
  bool prev_hsync_n_ = true, prev_vsync_n_ = true;
  bool locked_h_ = false;
  bool capturing_ = false;  // the frame being built has been valid since its vertical sync
  int x_ = 0, y_ = 0;       // position of the last sample, as the monitor believes it
  bool in_hsync_ = false, in_vsync_ = false;  // inside a pulse whose falling edge was seen
  int hsync_count_ = 0, hsync_width_ = 0;
  int vsync_lines_count_ = 0, vsync_width_lines_ = 0;
  core::Image444 building_;
  std::optional<core::Image444> done_;
  std::uint64_t frames_ = 0;
};

}  // namespace tripsitter::display

// The VGA signal's types: the mode's timing and what the connector carries during one pixel clock. The device
// drives it (vga.h) and the display takes it (display/monitor.h, vcd.h): this header is all they share.
#pragma once

#include <tripsitter/core/rgb444.h>

namespace tripsitter::device {

// 640x480 at 60 Hz as the board drove it (SPEC.md section B). Widths in pixel clocks and lines.
struct VgaMode {
  int h_visible = 640, h_front_porch = 16, h_sync = 96, h_back_porch = 48;
  int v_visible = 480, v_front_porch = 10, v_sync = 2, v_back_porch = 33;
  constexpr int h_total() const { return h_visible + h_front_porch + h_sync + h_back_porch; }  // 800
  constexpr int v_total() const { return v_visible + v_front_porch + v_sync + v_back_porch; }  // 525
};

inline constexpr VgaMode kVga640x480{};

// What is on the connector during one pixel clock. Syncs are active low: false during the pulse.
struct VgaSample {
  bool hsync_n = true;
  bool vsync_n = true;
  core::Rgb444 colour;  // black outside the visible area
  bool operator==(const VgaSample&) const = default;
};

}  // namespace tripsitter::device

// The VGA block: a timing generator of two counters driven by the mode's porch and sync widths, and the
// signal it puts on the connector, one sample per pixel clock (25 MHz: 4 device cycles).
#pragma once

#include <cstdint>

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

// Beam position counters. Line 0, column 0 is the first visible pixel; each frame is h_total * v_total clocks.
class VgaTimingGenerator {
 public:
  explicit VgaTimingGenerator(VgaMode mode = kVga640x480) : mode_(mode) {}

  int column() const { return h_; }
  int line() const { return v_; }
  bool visible() const { return h_ < mode_.h_visible && v_ < mode_.v_visible; }
  bool hsync_n() const { return hsync_n_at(h_); }
  bool vsync_n() const;
  // The horizontal sync level at `column` of any line.
  bool hsync_n_at(int column) const {
    const int start = mode_.h_visible + mode_.h_front_porch;
    return !(column >= start && column < start + mode_.h_sync);
  }
  // The sample for the current position, given the colour the line buffer offers there (ignored in blanking).
  VgaSample sample(core::Rgb444 colour) const;
  // Advances one pixel clock, wrapping at the end of a line and of a frame.
  void tick();
  // Advances a whole line (h_total pixel clocks). REQUIRES column() == 0.
  void tick_line();
  const VgaMode& mode() const { return mode_; }

 private:
  VgaMode mode_;
  int h_ = 0;
  int v_ = 0;
};

}  // namespace tripsitter::device

// The VGA block: a timing generator of two counters driven by the mode's porch and sync widths, and the
// signal it puts on the connector, one sample per pixel clock (25 MHz: 4 device cycles).
#pragma once

#include <cstdint>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/device/vga_signal.h>

namespace tripsitter::device {

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

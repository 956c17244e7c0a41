#include <tripsitter/device/vga.h>

namespace tripsitter::device {

// Each pulse starts after the visible area and the front porch, and lasts the sync width (hsync_n_at in vga.h).
bool VgaTimingGenerator::vsync_n() const {
  const int start = mode_.v_visible + mode_.v_front_porch;
  return !(v_ >= start && v_ < start + mode_.v_sync);
}

VgaSample VgaTimingGenerator::sample(core::Rgb444 colour) const {
  return VgaSample{hsync_n(), vsync_n(), visible() ? colour : core::kBlack};
}

void VgaTimingGenerator::tick_line() {
  if (++v_ < mode_.v_total()) return;
  v_ = 0;
}

void VgaTimingGenerator::tick() {
  if (++h_ < mode_.h_total()) return;
  h_ = 0;
  if (++v_ < mode_.v_total()) return;
  v_ = 0;
}

}  // namespace tripsitter::device

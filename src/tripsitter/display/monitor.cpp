// How the monitor follows the signal:
//  - It keeps its own beam position (x_, y_) and advances it one column per sample, wrapping lines at h_total
//    and frames at v_total. It never sees the generator's counters.
//  - An hsync falling edge marks column h_visible + h_front_porch; a vsync falling edge marks the line it falls
//    in as line v_visible + v_front_porch. An edge needs a previous sample, so the first sample never makes one
//    (a monitor switched on in the middle of a pulse does not mistake it for the pulse's start).
//  - A frame is captured from a vsync falling edge seen while locked horizontally up to the last visible pixel.
//    An hsync that arrives where the monitor did not expect it (the signal slipped) abandons the frame being
//    built, so a frame is either complete and exact or not delivered at all.
//  - hsync width is the number of samples the pulse stays low; vsync width is the number of hsync pulses that
//    start while vsync is low, which is how a monitor counts lines.
#include <tripsitter/display/monitor.h>

#include <limits>
#include <utility>

namespace tripsitter::display {
namespace {

void saturating_increment(int& n) {
  if (n < std::numeric_limits<int>::max()) ++n;
}

}  // namespace

VgaMonitor::VgaMonitor(device::VgaMode mode) : mode_(mode), building_(mode.h_visible, mode.v_visible) {}

void VgaMonitor::sample(const device::VgaSample& s) {
  const bool h_fall = started_ && prev_hsync_n_ && !s.hsync_n;
  const bool h_rise = started_ && !prev_hsync_n_ && s.hsync_n;
  const bool v_fall = started_ && prev_vsync_n_ && !s.vsync_n;
  const bool v_rise = started_ && !prev_vsync_n_ && s.vsync_n;
  started_ = true;
  prev_hsync_n_ = s.hsync_n;
  prev_vsync_n_ = s.vsync_n;

  // Where this sample lies if nothing resynchronises us.
  if (++x_ >= mode_.h_total()) {
    x_ = 0;
    if (++y_ >= mode_.v_total()) y_ = 0;
  }

  // Horizontal lock and pulse width.
  if (h_fall) {
    const int sync_x = mode_.h_visible + mode_.h_front_porch;
    if (x_ != sync_x) capturing_ = false;  // first lock, or the signal slipped: the frame in progress is torn
    x_ = sync_x;
    locked_h_ = true;
    in_hsync_ = true;
    hsync_count_ = 0;
  }
  if (h_rise && in_hsync_) {
    hsync_width_ = hsync_count_;
    in_hsync_ = false;
  }
  if (in_hsync_) saturating_increment(hsync_count_);

  // Vertical lock and pulse width (counted in hsync pulses).
  if (v_fall) {
    y_ = mode_.v_visible + mode_.v_front_porch;
    capturing_ = locked_h_;  // a new frame starts here; any unfinished one is abandoned
    in_vsync_ = true;
    vsync_lines_count_ = 0;
  }
  if (v_rise && in_vsync_) {
    vsync_width_lines_ = vsync_lines_count_;
    in_vsync_ = false;
  }
  if (in_vsync_ && h_fall) saturating_increment(vsync_lines_count_);

  // Capture.
  if (!capturing_ || x_ >= mode_.h_visible || y_ >= mode_.v_visible) return;
  building_.at(x_, y_) = s.colour;
  if (x_ == mode_.h_visible - 1 && y_ == mode_.v_visible - 1) {
    // Every visible pixel since the vsync has been written. Reuse the storage of an untaken frame if any.
    if (done_) {
      std::swap(*done_, building_);
    } else {
      done_ = std::move(building_);
      building_ = core::Image444(mode_.h_visible, mode_.v_visible);
    }
    ++frames_;
    capturing_ = false;  // the next frame needs its own vsync
  }
}

std::optional<core::Image444> VgaMonitor::take_frame() { return std::exchange(done_, std::nullopt); }

}  // namespace tripsitter::display

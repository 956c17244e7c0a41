#include <gtest/gtest.h>
#include <tripsitter/display/monitor.h>
#include <tripsitter/device/vga.h>

#include <cstdint>
#include <initializer_list>
#include <random>
#include <vector>

namespace tripsitter::display {
namespace {

using device::VgaMode;
using device::VgaSample;
using device::VgaTimingGenerator;

// A colour that depends on position and frame number, so a misplaced or stale pixel shows.
core::Rgb444 pattern(int x, int y, int frame) {
  return core::Rgb444::from_channels(x % 16, y % 16, (x / 16 + 3 * (y / 16) + frame) % 16);
}

core::Image444 expected_frame(const VgaMode& mode, int frame) {
  core::Image444 image(mode.h_visible, mode.v_visible);
  for (int y = 0; y < mode.v_visible; ++y) {
    for (int x = 0; x < mode.h_visible; ++x) image.at(x, y) = pattern(x, y, frame);
  }
  return image;
}

// A generator showing the pattern; the test may read its counters, the monitor only gets its samples.
struct Source {
  explicit Source(VgaMode mode = device::kVga640x480) : gen(mode) {}
  VgaTimingGenerator gen;
  int frame = 0;

  int column() const { return gen.column(); }
  int line() const { return gen.line(); }
  VgaSample next() {
    const VgaSample s = gen.sample(pattern(gen.column(), gen.line(), frame));
    gen.tick();
    if (gen.column() == 0 && gen.line() == 0) ++frame;
    return s;
  }
  void feed(VgaMonitor& monitor, std::int64_t clocks) {
    for (std::int64_t i = 0; i < clocks; ++i) monitor.sample(next());
  }
};

constexpr std::int64_t kFrameClocks = 800 * 525;
// Last visible pixel (639, 479), counted from the start of a frame.
constexpr std::int64_t kLastVisible = 479 * 800 + 639;

TEST(VgaMonitor, NothingBeforeAnySignal) {
  VgaMonitor monitor;
  EXPECT_EQ(monitor.frames_completed(), 0u);
  EXPECT_FALSE(monitor.take_frame().has_value());
  EXPECT_EQ(monitor.measured_hsync_clocks(), 0);
  EXPECT_EQ(monitor.measured_vsync_lines(), 0);
}

TEST(VgaMonitor, ReproducesThePatternExactly) {
  VgaMonitor monitor;
  Source source;
  // Switched on at the first visible pixel: frame 0 has no vsync before it, so the first frame is frame 1.
  source.feed(monitor, kFrameClocks + kLastVisible);
  EXPECT_EQ(monitor.frames_completed(), 0u);
  EXPECT_FALSE(monitor.take_frame().has_value());
  source.feed(monitor, 1);
  ASSERT_EQ(monitor.frames_completed(), 1u);
  auto frame = monitor.take_frame();
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(frame->width, 640);
  EXPECT_EQ(frame->height, 480);
  EXPECT_EQ(*frame, expected_frame(device::kVga640x480, 1));
  EXPECT_FALSE(monitor.take_frame().has_value()) << "take_frame clears";

  // Frames 2 and 3 complete without being taken: only the latest is kept.
  source.feed(monitor, 2 * kFrameClocks);
  EXPECT_EQ(monitor.frames_completed(), 3u);
  frame = monitor.take_frame();
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(*frame, expected_frame(device::kVga640x480, 3));

  // And the next one after a take.
  source.feed(monitor, kFrameClocks);
  EXPECT_EQ(monitor.frames_completed(), 4u);
  frame = monitor.take_frame();
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(*frame, expected_frame(device::kVga640x480, 4));
}

TEST(VgaMonitor, MeasuresSyncWidths) {
  VgaMonitor monitor;
  Source source;
  source.feed(monitor, 753);  // through column 752, where line 0's hsync pulse (columns 656..751) ends
  EXPECT_EQ(monitor.measured_hsync_clocks(), 96);
  EXPECT_EQ(monitor.measured_vsync_lines(), 0);
  source.feed(monitor, kFrameClocks);
  EXPECT_EQ(monitor.measured_hsync_clocks(), 96);
  EXPECT_EQ(monitor.measured_vsync_lines(), 2);
}

TEST(VgaMonitor, IgnoresPulsesAlreadyUnderWayAtSwitchOn) {
  VgaMonitor monitor;
  Source source;
  // Skip to the middle of line 491 (in vsync) and column 700 (in hsync).
  while (!(source.line() == 491 && source.column() == 700)) source.next();
  source.feed(monitor, 100);  // the hsync pulse ends, but its start was not seen
  EXPECT_EQ(monitor.measured_hsync_clocks(), 0);
  source.feed(monitor, 800);  // the vsync pulse ends, its start not seen either
  EXPECT_EQ(monitor.measured_vsync_lines(), 0);
  EXPECT_EQ(monitor.measured_hsync_clocks(), 96);
}

// Where, counting from switch-on, a monitor must deliver its first frame: the last visible pixel after the first
// vsync falling edge that follows an hsync falling edge (an edge needs a previous sample). Also returns that vsync.
struct FirstFrame {
  std::int64_t vsync_fall = -1;
  std::int64_t complete = -1;
};
FirstFrame first_frame_after(Source source) {  // a copy: the caller's source is not advanced
  FirstFrame r;
  bool started = false, prev_h = true, prev_v = true, h_locked = false;
  for (std::int64_t i = 0;; ++i) {
    const int x = source.column(), y = source.line();
    const VgaSample s = source.next();
    if (started && prev_h && !s.hsync_n) h_locked = true;
    if (started && prev_v && !s.vsync_n && h_locked) r.vsync_fall = i;
    if (r.vsync_fall >= 0 && x == 639 && y == 479) {
      r.complete = i;
      return r;
    }
    started = true;
    prev_h = s.hsync_n;
    prev_v = s.vsync_n;
  }
}

void check_switch_on_at(std::int64_t phase) {
  SCOPED_TRACE(::testing::Message() << "phase " << phase);
  Source source;
  for (std::int64_t i = 0; i < phase; ++i) source.next();
  const FirstFrame first = first_frame_after(source);
  // A whole frame's worth of lines from the vsync to the last visible pixel: no half frames.
  EXPECT_EQ(first.complete - first.vsync_fall, (525 - 490) * 800 + kLastVisible);

  VgaMonitor monitor;
  source.feed(monitor, first.complete);
  ASSERT_EQ(monitor.frames_completed(), 0u);
  ASSERT_FALSE(monitor.take_frame().has_value());
  source.feed(monitor, 1);
  ASSERT_EQ(monitor.frames_completed(), 1u);
  const int shown = source.frame;  // the generator is still in the frame whose last visible pixel that was
  auto frame = monitor.take_frame();
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(*frame, expected_frame(device::kVga640x480, shown));

  source.feed(monitor, kFrameClocks);
  ASSERT_EQ(monitor.frames_completed(), 2u);
  frame = monitor.take_frame();
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(*frame, expected_frame(device::kVga640x480, shown + 1));
  EXPECT_EQ(monitor.measured_hsync_clocks(), 96);
  EXPECT_EQ(monitor.measured_vsync_lines(), 2);
}

TEST(VgaMonitor, SwitchedOnAtChosenPhases) {
  const std::int64_t vsync_start = 490 * 800;
  for (const std::int64_t phase : std::initializer_list<std::int64_t>{
           std::int64_t{1},          // one clock into the first visible line
           kLastVisible,             // the last visible pixel
           kLastVisible + 1,         // blanking just after it
           vsync_start - 1,          // one clock before the vsync edge: the edge is seen
           vsync_start,              // at the vsync edge: no previous sample, so it is not an edge
           vsync_start + 1,          // inside the vsync pulse
           vsync_start + 800 + 700,  // inside both pulses
           489 * 800 + 656,          // on the last hsync edge before vsync
           489 * 800 + 657,          // just after it: no hsync lock when vsync falls
           kFrameClocks - 1,         // the last clock of a frame
       }) {
    check_switch_on_at(phase);
  }
}

TEST(VgaMonitor, SwitchedOnAtRandomPhases) {
  std::mt19937_64 rng(20240611);
  std::uniform_int_distribution<std::int64_t> phase(0, kFrameClocks - 1);
  for (int i = 0; i < 6; ++i) check_switch_on_at(phase(rng));
}

// If the signal slips (clocks lost or repeated), the frame being built is torn and must not be delivered; the
// monitor relocks and the following frame is exact.
void check_slip(int lost, int repeated) {
  SCOPED_TRACE(::testing::Message() << "lost " << lost << " repeated " << repeated);
  VgaMonitor monitor;
  Source source;
  source.feed(monitor, 2 * kFrameClocks);  // frame 1 delivered, frame 2 begun at its first pixel
  ASSERT_EQ(monitor.frames_completed(), 1u);
  monitor.take_frame();

  source.feed(monitor, 200 * 800 + 300);  // into line 200 of frame 2
  for (int i = 0; i < lost; ++i) source.next();
  if (repeated > 0) {
    const VgaSample s = source.next();
    for (int i = 0; i <= repeated; ++i) monitor.sample(s);
  }
  while (source.frame == 2) monitor.sample(source.next());
  EXPECT_EQ(monitor.frames_completed(), 1u) << "a torn frame was delivered";
  EXPECT_FALSE(monitor.take_frame().has_value());

  source.feed(monitor, kFrameClocks);
  ASSERT_EQ(monitor.frames_completed(), 2u);
  const auto frame = monitor.take_frame();
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(*frame, expected_frame(device::kVga640x480, 3));
}

// Each frame needs its own vertical sync: without one the monitor does not guess where a frame starts.
TEST(VgaMonitor, NoFramesWithoutVsync) {
  VgaMonitor monitor;
  Source source;
  source.feed(monitor, 2 * kFrameClocks);  // frame 1 delivered; frame 1's vsync armed frame 2
  ASSERT_EQ(monitor.frames_completed(), 1u);
  for (std::int64_t i = 0; i < 2 * kFrameClocks; ++i) {  // frames 2 and 3 without vsync
    VgaSample s = source.next();
    s.vsync_n = true;
    monitor.sample(s);
  }
  EXPECT_EQ(monitor.frames_completed(), 2u) << "frame 2 only: frame 3 had no vsync before it";
  monitor.take_frame();
  source.feed(monitor, kFrameClocks);  // frame 4's vsync comes after its visible lines
  EXPECT_EQ(monitor.frames_completed(), 2u);
  source.feed(monitor, kFrameClocks);
  EXPECT_EQ(monitor.frames_completed(), 3u);
  const auto frame = monitor.take_frame();
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(*frame, expected_frame(device::kVga640x480, 5));
}

TEST(VgaMonitor, LostClocksTearNoFrame) { check_slip(100, 0); }
TEST(VgaMonitor, RepeatedClocksTearNoFrame) { check_slip(0, 37); }

// The monitor follows the widths of whatever mode it is given.
TEST(VgaMonitor, RandomSmallModes) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> visible(1, 24), porch(0, 5), sync(1, 6);
  for (int trial = 0; trial < 200; ++trial) {
    const VgaMode mode{.h_visible = visible(rng),
                       .h_front_porch = porch(rng),
                       .h_sync = sync(rng),
                       .h_back_porch = porch(rng),
                       .v_visible = visible(rng),
                       .v_front_porch = porch(rng),
                       .v_sync = sync(rng),
                       .v_back_porch = porch(rng)};
    SCOPED_TRACE(::testing::Message() << "trial " << trial << " h " << mode.h_visible << "/" << mode.h_front_porch
                                      << "/" << mode.h_sync << "/" << mode.h_back_porch << " v " << mode.v_visible
                                      << "/" << mode.v_front_porch << "/" << mode.v_sync << "/" << mode.v_back_porch);
    const std::int64_t frame_clocks = std::int64_t{mode.h_total()} * mode.v_total();
    VgaMonitor monitor(mode);
    Source source(mode);
    source.feed(monitor, 3 * frame_clocks);
    ASSERT_EQ(monitor.frames_completed(), 2u);
    const auto frame = monitor.take_frame();
    ASSERT_TRUE(frame.has_value());
    EXPECT_EQ(*frame, expected_frame(mode, 2));
    EXPECT_EQ(monitor.measured_hsync_clocks(), mode.h_sync);
    EXPECT_EQ(monitor.measured_vsync_lines(), mode.v_sync);
  }
}

}  // namespace
}  // namespace tripsitter::display

#include <gtest/gtest.h>
#include <tripsitter/device/vga.h>

#include <vector>

namespace tripsitter::device {
namespace {

constexpr core::Rgb444 kWhite{0xFFF};

// One whole frame of samples from a fresh generator offering white everywhere, indexed [line][column].
std::vector<std::vector<VgaSample>> capture_frame(const VgaMode& mode) {
  VgaTimingGenerator gen(mode);
  std::vector<std::vector<VgaSample>> frame(static_cast<std::size_t>(mode.v_total()));
  for (auto& line : frame) {
    line.reserve(static_cast<std::size_t>(mode.h_total()));
    for (int x = 0; x < mode.h_total(); ++x) {
      line.push_back(gen.sample(kWhite));
      gen.tick();
    }
  }
  return frame;
}

TEST(VgaMode, TotalsOfThe640x480Mode) {
  static_assert(kVga640x480.h_total() == 800);
  static_assert(kVga640x480.v_total() == 525);
  EXPECT_EQ(kVga640x480.h_total() * kVga640x480.v_total(), 420000);
}

TEST(VgaTimingGenerator, StartsAtFirstVisiblePixel) {
  VgaTimingGenerator gen;
  EXPECT_EQ(gen.column(), 0);
  EXPECT_EQ(gen.line(), 0);
  EXPECT_TRUE(gen.visible());
  EXPECT_TRUE(gen.hsync_n());
  EXPECT_TRUE(gen.vsync_n());
}

TEST(VgaTimingGenerator, CountersWrapAfterExactly420000Clocks) {
  VgaTimingGenerator gen;
  int expected_h = 0, expected_v = 0;
  for (int clock = 1; clock <= 420000; ++clock) {
    gen.tick();
    if (++expected_h == 800) {
      expected_h = 0;
      if (++expected_v == 525) expected_v = 0;
    }
    ASSERT_EQ(gen.column(), expected_h) << "clock " << clock;
    ASSERT_EQ(gen.line(), expected_v) << "clock " << clock;
    if (clock < 420000) {
      ASSERT_FALSE(gen.column() == 0 && gen.line() == 0) << "early wrap at clock " << clock;
    }
  }
  EXPECT_EQ(gen.column(), 0);
  EXPECT_EQ(gen.line(), 0);
}

TEST(VgaTimingGenerator, HsyncLowExactlyInColumns656To751OnEveryLine) {
  const auto frame = capture_frame(kVga640x480);
  for (int y = 0; y < 525; ++y) {
    for (int x = 0; x < 800; ++x) {
      const bool in_pulse = x >= 656 && x <= 751;
      ASSERT_EQ(frame[y][x].hsync_n, !in_pulse) << "line " << y << " column " << x;
    }
  }
}

TEST(VgaTimingGenerator, VsyncLowForWholeLines490And491) {
  const auto frame = capture_frame(kVga640x480);
  for (int y = 0; y < 525; ++y) {
    const bool in_pulse = y == 490 || y == 491;
    for (int x = 0; x < 800; ++x) ASSERT_EQ(frame[y][x].vsync_n, !in_pulse) << "line " << y << " column " << x;
  }
}

// Widths and positions measured from the sample stream alone, as a scope would see them.
TEST(VgaTimingGenerator, PulseWidthsAndPeriodsMeasuredFromSamples) {
  VgaTimingGenerator gen;
  std::vector<VgaSample> samples;
  for (int i = 0; i < 2 * 420000; ++i) {
    samples.push_back(gen.sample(kWhite));
    gen.tick();
  }
  std::vector<std::size_t> h_falls, h_rises, v_falls, v_rises;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    if (samples[i - 1].hsync_n && !samples[i].hsync_n) h_falls.push_back(i);
    if (!samples[i - 1].hsync_n && samples[i].hsync_n) h_rises.push_back(i);
    if (samples[i - 1].vsync_n && !samples[i].vsync_n) v_falls.push_back(i);
    if (!samples[i - 1].vsync_n && samples[i].vsync_n) v_rises.push_back(i);
  }
  ASSERT_EQ(h_falls.size(), 2u * 525u);
  ASSERT_EQ(h_rises.size(), 2u * 525u);
  for (std::size_t k = 0; k < h_falls.size(); ++k) {
    EXPECT_EQ(h_falls[k] % 800, 656u);
    EXPECT_EQ(h_rises[k] - h_falls[k], 96u);  // low for 96 clocks
    if (k > 0) {
      EXPECT_EQ(h_falls[k] - h_falls[k - 1], 800u);
    }
  }
  ASSERT_EQ(v_falls.size(), 2u);
  ASSERT_EQ(v_rises.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(v_falls[k] % 420000, 490u * 800u);    // at the start of line 490
    EXPECT_EQ(v_rises[k] - v_falls[k], 2u * 800u);  // low for 2 whole lines
  }
  EXPECT_EQ(v_falls[1] - v_falls[0], 420000u);
}

TEST(VgaTimingGenerator, SyncsAreActiveLow) {
  // Idle (high) most of the time; low only during the pulses.
  const auto frame = capture_frame(kVga640x480);
  int h_low = 0, v_low = 0;
  for (const auto& line : frame) {
    for (const VgaSample& s : line) {
      h_low += s.hsync_n ? 0 : 1;
      v_low += s.vsync_n ? 0 : 1;
    }
  }
  EXPECT_EQ(h_low, 96 * 525);
  EXPECT_EQ(v_low, 2 * 800);
}

TEST(VgaTimingGenerator, ColourOnlyInTheVisibleArea) {
  const auto frame = capture_frame(kVga640x480);
  for (int y = 0; y < 525; ++y) {
    for (int x = 0; x < 800; ++x) {
      const bool visible = x < 640 && y < 480;
      ASSERT_EQ(frame[y][x].colour, visible ? kWhite : core::kBlack) << "line " << y << " column " << x;
    }
  }
}

TEST(VgaTimingGenerator, VisibleMatchesCountersAndSamplePassesColourThrough) {
  VgaTimingGenerator gen;
  for (int i = 0; i < 420000; ++i) {
    const bool visible = gen.column() < 640 && gen.line() < 480;
    ASSERT_EQ(gen.visible(), visible);
    const core::Rgb444 c(static_cast<std::uint16_t>(i * 7));
    const VgaSample s = gen.sample(c);
    ASSERT_EQ(s.colour, visible ? c : core::kBlack);
    ASSERT_EQ(s.hsync_n, gen.hsync_n());
    ASSERT_EQ(s.vsync_n, gen.vsync_n());
    gen.tick();
  }
}

// The counters follow whatever mode they are given, including a zero porch.
TEST(VgaTimingGenerator, SmallCustomMode) {
  const VgaMode mode{.h_visible = 5,
                     .h_front_porch = 0,
                     .h_sync = 2,
                     .h_back_porch = 1,
                     .v_visible = 3,
                     .v_front_porch = 1,
                     .v_sync = 1,
                     .v_back_porch = 0};
  ASSERT_EQ(mode.h_total(), 8);
  ASSERT_EQ(mode.v_total(), 5);
  const auto frame = capture_frame(mode);
  for (int y = 0; y < 5; ++y) {
    for (int x = 0; x < 8; ++x) {
      EXPECT_EQ(frame[y][x].hsync_n, !(x == 5 || x == 6)) << y << "," << x;
      EXPECT_EQ(frame[y][x].vsync_n, y != 4) << y << "," << x;
      EXPECT_EQ(frame[y][x].colour, (x < 5 && y < 3) ? kWhite : core::kBlack) << y << "," << x;
    }
  }
  VgaTimingGenerator gen(mode);
  for (int i = 0; i < 40; ++i) gen.tick();
  EXPECT_EQ(gen.column(), 0);
  EXPECT_EQ(gen.line(), 0);
}

}  // namespace
}  // namespace tripsitter::device

#include <tripsitter/device/preset.h>

#include <string>

#include <gtest/gtest.h>

namespace tripsitter::device {
namespace {

TEST(Preset, BoardCostsFiftyOneCyclesPerPixelWithOneSphere) {
  const DevicePreset p = board_2023_preset();
  EXPECT_EQ(p.finish_cycle(0, 1), 51);
  EXPECT_EQ(p.finish_cycle(57, 1), 58 * 51);
  EXPECT_LE(p.finish_cycle(57, 1), p.lead_cycles);  // the 58th pixel is on time
  EXPECT_GT(p.finish_cycle(58, 1), p.lead_cycles);  // the 59th is not
}

TEST(Preset, WideMeetsEveryLineUpToFortyNineSpheres) {
  const DevicePreset p = wide_preset();
  EXPECT_LE(p.finish_cycle(63, 49), p.lead_cycles);
  EXPECT_GT(p.finish_cycle(63, 50), p.lead_cycles);
}

TEST(Preset, BouncesCostPassesAndReflections) {
  const DevicePreset board = board_2023_preset();
  EXPECT_EQ(board.max_bounces, 0);  // the board had no reflections
  EXPECT_EQ(board.drain_cycles(), 0);
  EXPECT_EQ(board.pixel_occupancy(1, 0), 51);
  // Not pipelined: 2 + (k + 1) * spheres * 45 + k * 10 + 4.
  EXPECT_EQ(board.pixel_occupancy(1, 1), 2 + 2 * 45 + 10 + 4);
  EXPECT_EQ(board.pixel_occupancy(7, 3), 2 + 4 * 7 * 45 + 3 * 10 + 4);
  const DevicePreset wide = wide_preset();
  EXPECT_EQ(wide.max_bounces, 3);
  EXPECT_EQ(wide.costs.reflect, 10);
  // Pipelined: each pass issues `spheres` pairs; a reflected pass waits 31 cycles for the previous pass's hit
  // (2 + 12 + 16 + 1) and 10 for the reflection; the colour is ready 35 cycles after the last pass issued.
  EXPECT_EQ(wide.drain_cycles(), 35);
  EXPECT_EQ(wide.pixel_occupancy(49, 0), 49);
  EXPECT_EQ(wide.pixel_occupancy(20, 1), 2 * 20 + 41);
  EXPECT_EQ(wide.pixel_occupancy(20, 3), 4 * 20 + 3 * 41);
  // The no-reflection schedule is unchanged.
  EXPECT_EQ(wide.finish_cycle(63, 49), 64 * 49 + 35);
}

TEST(Preset, NamesResolveAndValidate) {
  for (const auto& name : preset_names()) {
    const auto p = preset_by_name(name);
    ASSERT_TRUE(p.has_value()) << name;
    EXPECT_EQ(p->name, name);
    EXPECT_FALSE(p->validate().has_value()) << name << ": " << *p->validate();
  }
  EXPECT_FALSE(preset_by_name("nope").has_value());
}

TEST(Preset, ValidateNamesTheProblem) {
  DevicePreset p = wide_preset();
  p.workers = 0;
  EXPECT_TRUE(p.validate().has_value());
  p = wide_preset();
  p.y.frac_bits = 5;
  EXPECT_TRUE(p.validate().has_value());
  p = wide_preset();
  p.lead_cycles = 3201;
  EXPECT_TRUE(p.validate().has_value());
  p = wide_preset();
  p.sqrt_iterations = 31;
  EXPECT_TRUE(p.validate().has_value());
  p = wide_preset();
  p.max_bounces = core::kMaxBounces + 1;
  EXPECT_TRUE(p.validate().has_value());
  p.max_bounces = -1;
  EXPECT_TRUE(p.validate().has_value());
  p.max_bounces = core::kMaxBounces;
  EXPECT_FALSE(p.validate().has_value());
}

// The shipped presets model the hardware: late pixels untraced, the path preset's frame memory in external memory.
TEST(Preset, ShippedPresetsTraceNoLatePixelsAndKeepFrameMemoryOutside) {
  for (const std::string& name : preset_names()) {
    const DevicePreset p = *preset_by_name(name);
    EXPECT_FALSE(p.trace_late_pixels) << name;
    if (p.path) {
      EXPECT_EQ(p.path->frame_memory, FrameMemoryPlace::kExternal) << name;
    }
    DevicePreset traced = p;
    traced.trace_late_pixels = true;
    EXPECT_FALSE(traced.validate().has_value()) << name;
  }
}

// The path presets (path, artix-path) path-trace on the framed wires only; the others never do.
TEST(Preset, OnlyThePathPresetsOnAFramedWireTracePaths) {
  for (const std::string& name : preset_names()) {
    const DevicePreset p = *preset_by_name(name);
    const bool path = name == "path" || name == "artix-path";
    EXPECT_FALSE(traces_paths(p, link::WireVersion::kV1)) << name;
    EXPECT_EQ(traces_paths(p, link::WireVersion::kV2), path) << name;
    EXPECT_EQ(traces_paths(p, link::WireVersion::kV3), path) << name;
  }
}

}  // namespace
}  // namespace tripsitter::device

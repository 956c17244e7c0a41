#include <tripsitter/device/preset.h>

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
}

}  // namespace
}  // namespace tripsitter::device

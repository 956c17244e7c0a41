#include <tripsitter/explore/sweep.h>

#include <gtest/gtest.h>

namespace tripsitter::explore {
namespace {

std::vector<std::string> values_of(const Sweep& s, const std::string& name) {
  for (const auto& p : s.parameters)
    if (p.name == name) return p.values;
  return {};
}

// The offset a bad specification is pointed at, or npos when it parses.
std::size_t error_offset(const std::string& spec) {
  try {
    parse_sweep(spec);
  } catch (const SweepError& e) {
    return e.offset();
  }
  return std::string::npos;
}

TEST(Sweep, ListsAndRangesRunOnUntilTheNextName) {
  const Sweep s = parse_sweep("workers=1..4,fracbits=3,4,8,preset=board-2023,wide");
  ASSERT_EQ(s.parameters.size(), 3u);
  EXPECT_EQ(values_of(s, "workers"), (std::vector<std::string>{"1", "2", "3", "4"}));
  EXPECT_EQ(values_of(s, "fracbits"), (std::vector<std::string>{"3", "4", "8"}));
  EXPECT_EQ(values_of(s, "preset"), (std::vector<std::string>{"board-2023", "wide"}));
}

TEST(Sweep, RangeWithStepAndDecimals) {
  EXPECT_EQ(values_of(parse_sweep("workers=1..10:4"), "workers"), (std::vector<std::string>{"1", "5", "9"}));
  EXPECT_EQ(values_of(parse_sweep("spi=0.5,12.5,25"), "spi"), (std::vector<std::string>{"0.5", "12.5", "25"}));
}

TEST(Sweep, BadSpecificationsPointAtTheOffendingPart) {
  //                    0         1         2
  //                    0123456789012345678901234
  EXPECT_EQ(error_offset("workers=1..64,fracbits=3,x"), 25u);  // not a number
  EXPECT_EQ(error_offset("workers=1..64,colour=3"), 14u);       // unknown name
  EXPECT_EQ(error_offset("workers=0..4"), 8u);                  // out of range
  EXPECT_EQ(error_offset("workers=4..1"), 8u);                  // empty range
  EXPECT_EQ(error_offset("workers=1..4:0"), 13u);               // bad step
  EXPECT_EQ(error_offset("workers=1,,2"), 10u);                 // empty value
  EXPECT_EQ(error_offset("3,workers=1"), 0u);                   // a value before any name
  EXPECT_EQ(error_offset("workers=1,workers=2"), 10u);          // named twice
  EXPECT_EQ(error_offset("workers=1,1"), 10u);                  // listed twice
  EXPECT_EQ(error_offset("preset=board-2024"), 7u);             // unknown word
  EXPECT_EQ(error_offset("workers=1..640,sqrt=1..30"), 15u);    // too many combinations
  EXPECT_EQ(error_offset(""), 0u);
  EXPECT_EQ(error_offset("workers=1..64,fracbits=3,4,8"), std::string::npos);
}

TEST(Sweep, PointedMessageHasACaretUnderTheOffset) {
  try {
    parse_sweep("workers=1,fracbits=z");
    FAIL() << "parsed";
  } catch (const SweepError& e) {
    EXPECT_EQ(e.pointed(), std::string(e.what()) + "\n  workers=1,fracbits=z\n" + std::string(2 + 19, ' ') + "^");
  }
}

TEST(Sweep, ExpandIsEveryCombinationPerSceneInOrder) {
  const auto configs = expand({parse_sweep("preset=board-2023,workers=1,2,sqrt=8,16")}, {"demo", "cluster"});
  ASSERT_EQ(configs.size(), 8u);
  EXPECT_EQ(configs[0].scene, "demo");
  EXPECT_EQ(configs[0].workers, 1);
  EXPECT_EQ(configs[0].sqrt_iterations, 8);
  EXPECT_EQ(configs[1].sqrt_iterations, 16);  // the last parameter varies fastest
  EXPECT_EQ(configs[2].workers, 2);
  EXPECT_EQ(configs[4].scene, "cluster");
  // What the sweep does not name keeps the preset's value.
  EXPECT_EQ(configs[0].frac_bits, 3);
  EXPECT_EQ(configs[0].capacity, 64);
  EXPECT_EQ(configs[0].wire, "v3");
}

TEST(Sweep, ExpandRunsAConfigurationMetTwiceOnce) {
  const auto configs = expand({parse_sweep("preset=wide,workers=10"), parse_sweep("preset=wide")}, {"demo"});
  EXPECT_EQ(configs.size(), 1u);  // wide has 10 workers
}

TEST(Sweep, ExpandRefusesParametersOfTheOtherKindOfPreset) {
  try {
    expand({parse_sweep("preset=board-2023,spp=1,2")}, {"demo"});
    FAIL() << "expanded";
  } catch (const SweepError& e) {
    EXPECT_EQ(e.offset(), 18u);
    EXPECT_NE(std::string(e.what()).find("path preset"), std::string::npos) << e.what();
  }
  EXPECT_THROW(expand({parse_sweep("preset=path,bounces=1")}, {"demo"}), SweepError);
  EXPECT_THROW(expand({parse_sweep("memory=bram")}, {"demo"}), SweepError);  // wide by default
}

TEST(Sweep, ExpandRefusesDevicesTheModelCannotRunAtTheValue) {
  // wide's 24-bit formats with 12 more fractional bits are 36 bits wide: more than the v2 wire's 32.
  try {
    expand({parse_sweep("preset=wide,workers=1,2,fracbits=4,16")}, {"demo"});
    FAIL() << "expanded";
  } catch (const SweepError& e) {
    EXPECT_EQ(e.offset(), 35u) << e.pointed();
    EXPECT_NE(std::string(e.what()).find("32 bits"), std::string::npos) << e.what();
  }
}

TEST(Sweep, SetupKeepsEachFormatsIntegerBits) {
  Configuration c = preset_configuration("demo", "board-2023");
  c.frac_bits = 5;
  c.workers = 7;
  const DeviceSetup s = setup_of(c);
  EXPECT_EQ(s.preset.x.frac_bits, 5);
  const device::DevicePreset board = device::board_2023_preset();
  EXPECT_EQ(board.x.frac_bits, 3);
  EXPECT_EQ(s.preset.x.total_bits, board.x.total_bits + 2);
  EXPECT_EQ(s.preset.radius.total_bits, board.radius.total_bits + 2);
  EXPECT_EQ(s.preset.z.total_bits, board.z.total_bits + 2);
  EXPECT_EQ(s.preset.workers, 7);
  EXPECT_TRUE(s.preset.trace_late_pixels);
  EXPECT_FALSE(s.preset.validate());
}

TEST(Sweep, DefaultSweepsParseAndExpand) {
  std::vector<Sweep> sweeps;
  for (const auto& spec : default_sweeps()) ASSERT_NO_THROW(sweeps.push_back(parse_sweep(spec))) << spec;
  const auto configs = expand(sweeps, default_scenes());
  EXPECT_GT(configs.size(), 50u);
  EXPECT_LT(configs.size(), 1000u);
}

}  // namespace
}  // namespace tripsitter::explore

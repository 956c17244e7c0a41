#include <tripsitter/host/key_script.h>

#include <string>

#include <gtest/gtest.h>

#include <tripsitter/scene/builtin.h>

namespace tripsitter::host {
namespace {

const link::SceneFormats kWideFormats{{24, 4, true}, {24, 4, true}, {24, 4, true}, {24, 4, false}, 4096};

struct Good {
  const char* text;
  std::optional<Key> key;
  std::int64_t duration_us;
  std::int64_t ticks;
};

TEST(KeyScript, GoodLines) {
  const Good cases[] = {
      {"W 500ms", Key::kW, 500'000, 30},
      {"w 500ms", Key::kW, 500'000, 30},
      {"J 0.5s", Key::kJ, 500'000, 30},
      {"L 0.25S", Key::kL, 250'000, 15},
      {"D 100", Key::kD, 100'000, 6},
      {"A 100MS", Key::kA, 100'000, 6},
      {"S 2s", Key::kS, 2'000'000, 120},
      {"I 1.5", Key::kI, 1'500, 0 + 1},            // 0.09 ticks rounds to 0; a key lasts at least one tick
      {"K 25ms", Key::kK, 25'000, 2},              // 1.5 ticks rounds up
      {"Q 3600s", Key::kQ, 3'600'000'000, 216'000},  // exactly the one-hour limit
      {"E", Key::kE, 0, 1},                        // a tap
      {"R", Key::kR, 0, 1},
      {"r 1s", Key::kR, 1'000'000, 60},
      {"wait 1s", std::nullopt, 1'000'000, 60},
      {"WAIT 5ms", std::nullopt, 5'000, 0},        // a wait may round to no tick at all
      {"wait 0", std::nullopt, 0, 0},
      {"\t  W\t 500ms  ", Key::kW, 500'000, 30},
      {"W 500ms # forward", Key::kW, 500'000, 30},
      {"W 500ms#forward", Key::kW, 500'000, 30},
      {"W 500ms\r", Key::kW, 500'000, 30},       // CRLF line endings
      {"W 007.50ms", Key::kW, 7'500, 0 + 0 + 1},
  };
  for (const Good& c : cases) {
    auto r = parse_key_script(c.text);
    ASSERT_TRUE(r.ok()) << c.text << ": " << r.error().to_string("script");
    ASSERT_EQ(r.value().size(), 1u) << c.text;
    const KeyAction& a = r.value()[0];
    EXPECT_EQ(a.key, c.key) << c.text;
    EXPECT_EQ(a.duration_us, c.duration_us) << c.text;
    EXPECT_EQ(a.ticks, c.ticks) << c.text;
    EXPECT_EQ(a.line, 1) << c.text;
  }
}

TEST(KeyScript, BlankLinesAndCommentsAreSkippedAndLinesCounted) {
  auto r = parse_key_script("# a script\n\n   \nW 500ms\n  # more\nJ 200ms\nD 100ms");
  ASSERT_TRUE(r.ok()) << r.error().to_string("s");
  ASSERT_EQ(r.value().size(), 3u);
  EXPECT_EQ(r.value()[0], (KeyAction{Key::kW, 500'000, 30, 4}));
  EXPECT_EQ(r.value()[1], (KeyAction{Key::kJ, 200'000, 12, 6}));
  EXPECT_EQ(r.value()[2], (KeyAction{Key::kD, 100'000, 6, 7}));
  EXPECT_EQ(total_ticks(r.value()), 48);
  EXPECT_TRUE(parse_key_script("").value().empty());
  EXPECT_TRUE(parse_key_script("\n# nothing\n\n").value().empty());
}

struct Bad {
  const char* text;
  int line, column;
  const char* message_part;
};

TEST(KeyScript, BadLinesSayWhereAndWhy) {
  const Bad cases[] = {
      {"X 500ms", 1, 1, "unknown key 'X'"},
      {"W 500ms\n  Z", 2, 3, "unknown key 'Z'"},
      {"WA 1s", 1, 1, "unknown key 'WA'"},
      {"W500ms", 1, 1, "unknown key 'W500ms'"},
      {"\xC3\xA9 1s", 1, 1, "unknown key '\\xC3\\xA9'"},
      {"W 5min", 1, 3, "bad duration '5min'"},
      {"W ms", 1, 3, "bad duration 'ms'"},
      {"W .5s", 1, 3, "bad duration '.5s'"},
      {"W 5.s", 1, 3, "bad duration '5.s'"},
      {"W 1e3", 1, 3, "bad duration '1e3'"},
      {"W +5ms", 1, 3, "bad duration '+5ms'"},
      {"W 0x10", 1, 3, "bad duration '0x10'"},
      {"W -5ms", 1, 3, "negative duration '-5ms'"},
      {"\n\n  J   -0.5s", 3, 7, "negative duration '-0.5s'"},
      {"W -abc", 1, 3, "bad duration '-abc'"},
      {"W 3600.001s", 1, 3, "longer than one hour"},
      {"W 3600001", 1, 3, "longer than one hour"},
      {"W 2h", 1, 3, "bad duration '2h'"},
      {"W 99999999999999999999999999999999999999999999999999s", 1, 3, "longer than one hour"},
      {"W 500ms forward", 1, 9, "unexpected 'forward' after the duration"},
      {"W 5 ms", 1, 5, "unexpected 'ms'"},
      {"wait", 1, 5, "wait needs a duration"},
      {"  wait  # nothing", 1, 7, "wait needs a duration"},
      {"wait soon", 1, 6, "bad duration 'soon'"},
  };
  for (const Bad& c : cases) {
    auto r = parse_key_script(c.text);
    ASSERT_FALSE(r.ok()) << c.text;
    EXPECT_EQ(r.error().line, c.line) << c.text;
    EXPECT_EQ(r.error().column, c.column) << c.text;
    EXPECT_NE(r.error().message.find(c.message_part), std::string::npos) << c.text << " -> " << r.error().message;
  }
}

TEST(KeyScript, ErrorsPrintAsSourceLineColumn) {
  auto r = parse_key_script("W 1s\nJ 1 s\n");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().to_string("keys.txt"),
            "keys.txt:2:5: unexpected 's' after the duration; one action per line ('#' starts a comment)");
  EXPECT_EQ((KeyScriptError{0, 0, "too big"}.to_string("keys.txt")), "keys.txt: too big");
}

TEST(KeyScript, LimitsAreEnforced) {
  const std::string too_big(kMaxScriptBytes + 1, '\n');
  auto big = parse_key_script(too_big);
  ASSERT_FALSE(big.ok());
  EXPECT_EQ(big.error().line, 0);
  EXPECT_NE(big.error().message.find("limit"), std::string::npos);

  std::string many;
  for (std::size_t i = 0; i < kMaxScriptActions; ++i) many += "E\n";
  ASSERT_TRUE(parse_key_script(many).ok());
  auto too_many = parse_key_script(many + "  Q\n");
  ASSERT_FALSE(too_many.ok());
  EXPECT_EQ(too_many.error().line, static_cast<int>(kMaxScriptActions) + 1);
  EXPECT_EQ(too_many.error().column, 3);
  EXPECT_NE(too_many.error().message.find("100000 actions"), std::string::npos);

  std::string long_script;
  for (int i = 0; i < 24; ++i) long_script += "wait 3600s\n";
  ASSERT_TRUE(parse_key_script(long_script).ok());
  auto too_long = parse_key_script(long_script + "W\n");
  ASSERT_FALSE(too_long.ok());
  EXPECT_EQ(too_long.error().line, 25);
  EXPECT_NE(too_long.error().message.find("24 hours"), std::string::npos);
}

TEST(KeyScriptPlayer, StepsOneTickAtATimeThroughApplyHeldKey) {
  const scene::Scene scene = *scene::builtin("demo");
  Host played(scene, kWideFormats, link::WireVersion::kV2);
  Host expected(scene, kWideFormats, link::WireVersion::kV2);
  KeyScriptPlayer player(parse_key_script("W 100ms\nwait 50ms\nJ\nwait 0\nD 50ms\n").value());
  int ticks = 0;
  while (player.step(played)) ++ticks;
  EXPECT_EQ(ticks, 6 + 3 + 1 + 3);
  EXPECT_EQ(player.ticks_played(), ticks);
  EXPECT_TRUE(player.done());
  EXPECT_FALSE(player.step(played));
  for (int i = 0; i < 6; ++i) apply_held_key(expected.camera(), Key::kW, 1.0 / 60);
  apply_held_key(expected.camera(), Key::kJ, 1.0 / 60);
  for (int i = 0; i < 3; ++i) apply_held_key(expected.camera(), Key::kD, 1.0 / 60);
  EXPECT_EQ(played.camera().position(), expected.camera().position());
  EXPECT_EQ(played.camera().yaw_deg(), expected.camera().yaw_deg());
}

TEST(KeyScriptPlayer, RResetsWorldAndCamera) {
  const scene::Scene scene = *scene::builtin("demo");
  Host host(scene, kWideFormats, link::WireVersion::kV2);
  const core::Vec3d start = host.camera().position();
  KeyScriptPlayer player(parse_key_script("W 1s\nL 1s\nR\n").value());
  for (int i = 0; i < 120; ++i) ASSERT_TRUE(player.step(host));
  EXPECT_NE(host.camera().position(), start);
  ASSERT_TRUE(player.step(host));
  EXPECT_EQ(host.camera().position(), start);
  EXPECT_EQ(host.camera().yaw_deg(), 0.0);
  EXPECT_TRUE(player.done());
}

TEST(KeyScriptPlayer, AnEmptyScriptIsDoneAtOnce) {
  Host host(*scene::builtin("demo"), kWideFormats, link::WireVersion::kV2);
  KeyScriptPlayer player(parse_key_script("# nothing\nwait 1ms\n").value());
  EXPECT_TRUE(player.done());
  EXPECT_FALSE(player.step(host));
}

}  // namespace
// Regression (found while fuzzing, fuzz/regressions/key_script): a duration of many dashes recursed once per
// dash and built a message each time, overflowing the stack.
TEST(KeyScript, ManyDashesAreOneBadDuration) {
  for (const std::size_t dashes : {std::size_t{2}, std::size_t{20000}, std::size_t{500000}}) {
    const std::string script = "W " + std::string(dashes, '-') + "5ms";
    const auto result = parse_key_script(script);
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.error().line, 1);
    EXPECT_EQ(result.error().column, 3);
    EXPECT_EQ(result.error().message.rfind("bad duration", 0), 0u);
  }
}

}  // namespace tripsitter::host

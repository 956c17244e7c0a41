// The command line as a user meets it: exit codes, messages, files written or not.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <tripsitter/display/exr.h>
#include <tripsitter/display/png.h>
#include <tripsitter/host/rom_image.h>
#include <tripsitter/link/frame.h>

#include "command_test_util.h"

namespace {

namespace fs = std::filesystem;

using tripsitter::cmd::test::Result;
using tripsitter::cmd::test::slurp;

class Cli : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = tripsitter::cmd::test::scratch_dir("tripsitter_cli_"); }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Runs tripsitter with `args` (shell words) and optional stdin file.
  Result run(const std::string& args, const std::string& stdin_file = "/dev/null") const {
    return tripsitter::cmd::test::run_shell(std::string(TRIPSITTER_BIN) + " " + args + " <" + stdin_file, dir_);
  }

  fs::path dir_;
};

TEST_F(Cli, HelpTellsTheSubcommandsAndExitsZero) {
  const Result r = run("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* word : {"render", "link", "bench"}) EXPECT_NE(r.out.find(word), std::string::npos) << word;
  const Result rr = run("render --help");
  EXPECT_EQ(rr.exit_code, 0);
  for (const char* flag : {"--scene", "--mode", "--preset", "--workers", "--wire", "--width", "--height", "--out",
                           "--vcd", "--lines", "--link-input"})
    EXPECT_NE(rr.out.find(flag), std::string::npos) << flag;
}

TEST_F(Cli, RenderWritesTheDemoFrame) {
  const Result r = run("render --out " + path("demo.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("demo.png"), std::string::npos);
  const auto img = tripsitter::display::read_png(path("demo.png"));
  ASSERT_TRUE(img.ok());
  EXPECT_EQ(img.value().at(320, 240), tripsitter::core::Rgb444(0x770));
}

// --quiet leaves out the summary (device, link, host) in every mode: what is left on stderr is the file written.
TEST_F(Cli, QuietRenderSaysOnlyWhatItWrote) {
  for (const char* mode : {"hw", "normal"}) {
    const Result r = run("render --quiet --scene cluster --mode " + std::string(mode) + " --out " + path("q.png"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "wrote " + path("q.png") + " (640x480)\n") << mode;
  }
}

TEST_F(Cli, NormalModeRendersOtherSizesAndComparesWithHw) {
  Result r = run("render --mode normal --width 320 --height 200 --out " + path("small.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto img = tripsitter::display::read_png(path("small.png"));
  ASSERT_TRUE(img.ok());
  EXPECT_EQ(img.value().width, 320);
  EXPECT_EQ(img.value().height, 200);
  EXPECT_EQ(img.value().at(160, 100), tripsitter::core::Rgb444(0x770));
  r = run("render --compare --out " + path("hw.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("vs float reference: 0 of 307200 pixels differ"), std::string::npos) << r.out;
}

TEST_F(Cli, BadInputExitsTwoWithAMessageAndWritesNothing) {
  struct Case {
    std::string args, message;
  };
  std::ofstream(path("broken.json")) << "{\n  \"spheres\": [\n    {\"center\": [0, 0], \"radius\": 1}\n  ]\n}\n";
  const std::vector<Case> cases = {
      {"render --mode nope --out " + path("x.png"), "--mode"},
      {"render --preset nope --out " + path("x.png"), "unknown preset"},
      {"render --wire v4 --out " + path("x.png"), "unknown wire"},
      {"render --workers 0 --out " + path("x.png"), "workers"},
      {"render --width 320 --out " + path("x.png"), "640x480"},
      {"render --scene nosuchscene --out " + path("x.png"), "nosuchscene"},
      {"render --scene " + path("broken.json") + " --out " + path("x.png"), "broken.json:3:"},
      {"render --link-input " + path("missing.bin") + " --out " + path("x.png"), "missing.bin"},
      {"render --frobnicate", "frobnicate"},
      {"render --out " + path("no/such/dir/x.png"), "no/such/dir"},
      {"", "subcommand"},
  };
  for (const auto& c : cases) {
    const Result r = run(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(path("x.png"))) << c.args;
  }
}

TEST_F(Cli, LinkEncodeDecodeRoundTripAndRejection) {
  const std::string bin = path("world.bin");
  Result r = run("link encode --scene cluster --wire v2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  fs::copy_file(path("stdout"), bin, fs::copy_options::overwrite_existing);
  r = run("link decode --wire v2", bin);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("8 spheres"), std::string::npos) << r.out;
  // One flipped bit: rejected with the reason, exit code 2.
  std::string bytes = slurp(bin);
  bytes[40] = static_cast<char>(bytes[40] ^ 1);
  std::ofstream(path("bad.bin"), std::ios::binary) << bytes;
  r = run("link decode --wire v2", path("bad.bin"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("CRC"), std::string::npos) << r.err;
}

TEST_F(Cli, LinkInputDrivesTheDevice) {
  Result r = run("link encode --scene demo --wire v1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  fs::copy_file(path("stdout"), path("demo.v1"));
  r = run("render --link-input " + path("demo.v1") + " --wire v1 --preset board-2023 --out " + path("v1.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto img = tripsitter::display::read_png(path("v1.png"));
  ASSERT_TRUE(img.ok());
  EXPECT_EQ(img.value().at(320, 240), tripsitter::core::Rgb444(0x770));
  EXPECT_EQ(img.value().at(600, 240), tripsitter::core::kBlack);  // the board's strip
  std::ofstream(path("garbage.bin"), std::ios::binary) << "this is not a world";
  r = run("render --link-input " + path("garbage.bin") + " --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("no intact world"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("x.png")));
}

// link encode --worlds N writes a stream of numbered worlds; link decode --json says what a device makes of it.
class CliLink : public Cli {
 protected:
  // The cluster scene's 8 spheres in one v3 frame.
  static constexpr std::size_t kWorldBytes =
      tripsitter::link::kV3HeaderBytes + 8 * tripsitter::link::kSphereBytes + tripsitter::link::kFrameTrailerBytes;

  // The bytes `link encode ARGS` writes; fails the test if it does not exit 0.
  std::string encode(const std::string& args) const {
    const Result r = run("link encode --scene cluster " + args);
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
    return r.out;
  }

  // `link decode --json ARGS` of `bytes`: its result, and the JSON it printed.
  std::pair<Result, nlohmann::json> decode_json(const std::string& bytes, const std::string& args = "--wire v3") const {
    std::ofstream(path("in.bin"), std::ios::binary) << bytes;
    const Result r = run("link decode --json " + args, path("in.bin"));
    return {r, nlohmann::json::parse(r.out)};
  }

  static std::vector<std::uint32_t> accepted(const nlohmann::json& doc) {
    return doc["accepted"].get<std::vector<std::uint32_t>>();
  }
};

TEST_F(CliLink, EncodedWorldsOfAnOrbitDecodeInOrder) {
  const Result enc = run("link encode --scene cluster --wire v3 --worlds 5 --session 77");
  ASSERT_EQ(enc.exit_code, 0) << enc.err;
  EXPECT_NE(enc.err.find("encoded 5 worlds of 8 spheres as " + std::to_string(5 * kWorldBytes) + " bytes (v3, "
                         "session 77, numbered 1 to 5"),
            std::string::npos)
      << enc.err;
  const std::string stream = enc.out;
  ASSERT_EQ(stream.size(), 5 * kWorldBytes);
  EXPECT_EQ(stream.substr(8, 8), std::string("\0\0\0\x4d\0\0\0\x01", 8));  // session 77, sequence 1
  // The camera moves between worlds: the spheres' bytes differ.
  const std::size_t payload = tripsitter::link::kV3HeaderBytes;
  EXPECT_NE(stream.substr(payload, 8 * 24), stream.substr(kWorldBytes + payload, 8 * 24));

  const auto [r, doc] = decode_json(stream);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(accepted(doc), (std::vector<std::uint32_t>{1, 2, 3, 4, 5})) << r.out;
  for (const char* key : {"missing", "rejected", "replayed", "garbage_runs", "bytes_dropped"})
    EXPECT_EQ(doc[key], 0) << key << "\n" << r.out;
  EXPECT_EQ(doc["sessions"], 1) << r.out;
  EXPECT_EQ(doc["wire"], "v3") << r.out;
  EXPECT_EQ(doc["bytes"], stream.size()) << r.out;

  std::ofstream(path("five.bin"), std::ios::binary) << stream;
  const Result human = run("link decode", path("five.bin"));  // v3 is the default
  EXPECT_EQ(human.exit_code, 0) << human.err;
  for (const char* line : {"wire: v3", "world 1: sequence 1, session 77, 4 fractional bits, 8 spheres, a new session\n",
                           "world 5: sequence 5, session 77, 4 fractional bits, 8 spheres\n", "  sphere 7: centre (",
                           "shown 5, rejected 0, replayed 0, missing 0, garbage runs 0, bytes dropped 0\n"})
    EXPECT_NE(human.out.find(line), std::string::npos) << line << "\n" << human.out;
  EXPECT_EQ(human.err, "");

  // Without --session, a random one: two hosts that start differ (but for a chance of 2^-32).
  EXPECT_NE(encode("--wire v3").substr(8, 4), encode("--wire v3").substr(8, 4));
}

TEST_F(CliLink, ALostWorldIsMissingAndADamagedOneRejected) {
  const std::string stream = encode("--wire v3 --worlds 5 --session 9");
  ASSERT_EQ(stream.size(), 5 * kWorldBytes);
  const std::size_t third = 2 * kWorldBytes;

  // World 3 never arrived: its number is missing, every byte that came is shown.
  std::string lost = stream;
  lost.erase(third, kWorldBytes);
  auto [r, doc] = decode_json(lost);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(accepted(doc), (std::vector<std::uint32_t>{1, 2, 4, 5})) << r.out;
  EXPECT_EQ(doc["missing"], 1) << r.out;
  EXPECT_EQ(doc["rejected"], 0) << r.out;

  // A flipped bit in world 3's sequence number: its header CRC refuses it, its other bytes are skipped, the
  // next world is shown, and world 3 counts as missing. The JSON comes with exit code 2.
  std::string damaged = stream;
  damaged[third + 15] = static_cast<char>(damaged[third + 15] ^ 0x04);
  std::tie(r, doc) = decode_json(damaged);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(accepted(doc), (std::vector<std::uint32_t>{1, 2, 4, 5})) << r.out;
  EXPECT_EQ(doc["rejected"], 1) << r.out;
  EXPECT_EQ(doc["garbage_runs"], 1) << r.out;
  EXPECT_EQ(doc["bytes_dropped"], kWorldBytes) << r.out;
  EXPECT_EQ(doc["missing"], 1) << r.out;
  EXPECT_EQ(doc["problems"][0]["error"], "bad header CRC") << r.out;
  EXPECT_EQ(doc["problems"][0]["offset"], third + 24) << r.out;
  EXPECT_NE(r.err.find("<stdin>: byte " + std::to_string(third + 24) + ": bad header CRC: "),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("(1 byte dropped)"), std::string::npos) << r.err;

  // The same in human words.
  std::ofstream(path("damaged.bin"), std::ios::binary) << damaged;
  const Result human = run("link decode --wire v3", path("damaged.bin"));
  EXPECT_EQ(human.exit_code, 2);
  EXPECT_NE(human.out.find("world 3: sequence 4, session 9, 4 fractional bits, 8 spheres, 1 missing before it"),
            std::string::npos)
      << human.out;
  EXPECT_NE(human.out.find("shown 4, rejected 1, replayed 0, missing 1, garbage runs 1, bytes dropped " +
                           std::to_string(kWorldBytes) + "\n"),
            std::string::npos)
      << human.out;
}

TEST_F(CliLink, ReplaysAreNotShownAndANewSessionIs) {
  const std::string first = encode("--wire v3 --worlds 5 --session 9");
  const std::string second = encode("--wire v3 --worlds 2 --session 10");
  const std::string world2 = first.substr(kWorldBytes, kWorldBytes);

  // World 2 again after world 5: a replay, not shown; exit code 2.
  auto [r, doc] = decode_json(first + world2);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(accepted(doc), (std::vector<std::uint32_t>{1, 2, 3, 4, 5})) << r.out;
  EXPECT_EQ(doc["replayed"], 1) << r.out;
  EXPECT_EQ(doc["rejected"], 0) << r.out;
  EXPECT_EQ(doc["bytes_dropped"], kWorldBytes) << r.out;  // as the device counts a replay's bytes
  EXPECT_EQ(doc["problems"][0]["error"], "replay") << r.out;
  EXPECT_NE(r.err.find(": byte " + std::to_string(5 * kWorldBytes) + ": replay: world 2 of session 9 is not newer "
                       "than the last one of its session (" + std::to_string(kWorldBytes) + " bytes dropped, not shown)"),
            std::string::npos)
      << r.err;

  // A host that restarts with another session is shown from its first world; the old session has ended.
  std::tie(r, doc) = decode_json(first + second + world2);
  EXPECT_EQ(accepted(doc), (std::vector<std::uint32_t>{1, 2, 3, 4, 5, 1, 2})) << r.out;
  EXPECT_EQ(doc["sessions"], 2) << r.out;
  EXPECT_EQ(doc["replayed"], 1) << r.out;
  EXPECT_EQ(doc["missing"], 0) << r.out;
  EXPECT_NE(r.err.find("replay: world 2 of session 9 belongs to a session that has ended"), std::string::npos) << r.err;
}

TEST_F(CliLink, EarlierWiresStillDecode) {
  const Result enc = run("link encode --scene cluster --wire v2 --worlds 3");
  ASSERT_EQ(enc.exit_code, 0) << enc.err;
  EXPECT_NE(enc.err.find("(v2, numbered 1 to 3, "), std::string::npos) << enc.err;
  auto [r, doc] = decode_json(enc.out, "--wire v2");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(accepted(doc), (std::vector<std::uint32_t>{1, 2, 3})) << r.out;
  EXPECT_EQ(doc["wire"], "v2");
  const Result human = run("link decode --wire v2", path("in.bin"));
  EXPECT_EQ(human.exit_code, 0) << human.err;
  EXPECT_NE(human.out.find("wire: v2 (TripSitter's earlier framed wire, still decoded)"), std::string::npos)
      << human.out;
  EXPECT_NE(human.out.find("world 3: sequence 3, 4 fractional bits, 8 spheres\n"), std::string::npos) << human.out;

  // v2 bytes read as v3: no frame at all, one garbage run.
  std::tie(r, doc) = decode_json(enc.out, "--wire v3");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(accepted(doc), std::vector<std::uint32_t>{}) << r.out;
  EXPECT_EQ(doc["garbage_runs"], 1) << r.out;
  EXPECT_EQ(doc["bytes_dropped"], enc.out.size()) << r.out;

  // v1: each word is a world; a partial word at the end is rejected.
  const std::string words = encode("--wire v1 --worlds 2");
  ASSERT_EQ(words.size(), 2 * 8 * 8u);
  std::tie(r, doc) = decode_json(words + "abc", "--wire v1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(accepted(doc).size(), 16u) << r.out;
  EXPECT_EQ(doc["rejected"], 1) << r.out;
  EXPECT_EQ(doc["bytes_dropped"], 3) << r.out;
}

TEST_F(CliLink, BadEncodeOptionsExitTwo) {
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {"link encode --session 0", "--session"},
      {"link encode --session 4294967296", "--session"},
      {"link encode --session -3", "--session"},
      {"link encode --wire v2 --session 5", "--session"},
      {"link encode --worlds 0", "--worlds"},
      {"link encode --worlds -2", "--worlds"},
      {"link encode --worlds many", "--worlds"},
      {"link encode --orbit 1e9", "--orbit"},
  };
  for (const auto& c : cases) {
    const Result r = run(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_EQ(r.out, "") << c.args;
  }
  const Result help = run("link decode --help");
  for (const char* text : {"--json", "Exit 0 when every byte was in a world the device shows", "replay"})
    EXPECT_NE(help.out.find(text), std::string::npos) << text << "\n" << help.out;
}

TEST_F(Cli, VcdHasTheSignals) {
  const Result r = run("render --vcd " + path("vga.vcd") + " --lines 50 --out " + path("f.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string vcd = slurp(dir_ / "vga.vcd");
  for (const char* word : {"$timescale", "hsync", "vsync", "$enddefinitions"})
    EXPECT_NE(vcd.find(word), std::string::npos) << word;
}

TEST_F(Cli, AnimationWritesNumberedFramesOfAnOrbit) {
  const Result r = run("render --scene cluster --frames 3 --orbit 90 --out " + path("f_%02d.png") + " --video " +
                       path("orbit.mp4"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"f_00.png", "f_01.png", "f_02.png"}) EXPECT_TRUE(fs::exists(path(name))) << name;
  EXPECT_FALSE(fs::exists(path("f_03.png")));
  EXPECT_NE(slurp(dir_ / "f_00.png"), slurp(dir_ / "f_01.png"));
  if (std::system("command -v ffmpeg >/dev/null 2>&1") == 0) {
    EXPECT_TRUE(fs::exists(path("orbit.mp4")));
  } else {
    EXPECT_NE(r.err.find("ffmpeg is not installed"), std::string::npos) << r.err;
  }
  const Result bad = run("render --frames 2 --out " + path("no_pattern.png"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("%d"), std::string::npos) << bad.err;
  EXPECT_EQ(run("render --orbit 30 --out " + path("x.png")).exit_code, 2);
}

// Malformed scene files through the command line: one message naming the file and place, exit code 2,
// no output file.
TEST_F(Cli, MalformedSceneFilesAreRejectedWithAPlaceAndNoOutput) {
  struct Case {
    std::string name, text, expected;  // expected: a piece of the message, after "FILE:"
  };
  const std::string ok_sphere = R"({"center": [0, 0, 0], "radius": 1})";
  std::string deep(100000, '[');
  std::string garbage("\x00\x01\xff\xfe{\x80\x81", 8);
  const std::vector<Case> cases = {
      {"empty", "", "1:1:"},
      {"not_json", "hello", "1:1:"},
      {"binary", garbage, "1:"},
      {"trailing_comma", "{\"spheres\": [" + ok_sphere + ",]}", "1:"},
      {"unclosed", "{\"spheres\": [" + ok_sphere, "1:"},
      {"top_array", "[]", "1:1:"},
      {"deep", deep, "1:1:"},
      {"no_spheres", "{}", "1:1:"},
      {"spheres_object", "{\"spheres\": {}}", "1:13:"},
      {"wrong_type_vfov", "{\"camera\": {\"vfov\": \"wide\"}, \"spheres\": []}", "1:21:"},
      {"vfov_zero", "{\"camera\": {\"vfov\": 0}, \"spheres\": []}", "1:21:"},
      {"vfov_180", "{\"camera\": {\"vfov\": 180}, \"spheres\": []}", "1:21:"},
      {"lookfrom_is_lookat", "{\"camera\": {\"lookfrom\": [0,0,0], \"lookat\": [0,0,0]}, \"spheres\": []}", "1:"},
      {"vup_parallel", "{\"camera\": {\"vup\": [0,0,1]}, \"spheres\": []}", "1:"},
      {"focus_negative", "{\"camera\": {\"focus_dist\": -1}, \"spheres\": []}", "1:"},
      {"huge_number", "{\"spheres\": [{\"center\": [0, 1e999, 0], \"radius\": 1}]}", "1:"},
      {"radius_zero", "{\"spheres\": [{\"center\": [0, 0, 0], \"radius\": 0}]}", "1:"},
      {"radius_negative", "{\"spheres\": [{\"center\": [0, 0, 0], \"radius\": -2}]}", "1:"},
      {"center_two", "{\"spheres\": [{\"center\": [0, 0], \"radius\": 1}]}", "1:"},
      {"center_string", "{\"spheres\": [{\"center\": \"origin\", \"radius\": 1}]}", "1:"},
      {"missing_radius", "{\"spheres\": [{\"center\": [0, 0, 0]}]}", "1:"},
      {"missing_center", "{\"spheres\": [{\"radius\": 1}]}", "1:"},
      {"unknown_material", "{\"spheres\": [{\"center\": [0,0,0], \"radius\": 1, \"material\": {\"type\": \"wood\"}}]}", "1:"},
      {"albedo_two", "{\"spheres\": [{\"center\": [0,0,0], \"radius\": 1, \"material\": {\"type\": \"metal\", \"albedo\": [2, 0, 0]}}]}", "1:"},
      {"fuzz_negative", "{\"spheres\": [{\"center\": [0,0,0], \"radius\": 1, \"material\": {\"type\": \"metal\", \"fuzz\": -0.5}}]}", "1:"},
      {"ior_zero", "{\"spheres\": [{\"center\": [0,0,0], \"radius\": 1, \"material\": {\"type\": \"dielectric\", \"ior\": 0}}]}", "1:"},
      {"unknown_key", "{\"spheres\": [], \"camra\": {}}", "1:"},
      {"width_zero", "{\"render\": {\"width\": 0}, \"spheres\": []}", "1:"},
      {"width_absurd", "{\"render\": {\"width\": 100000}, \"spheres\": []}", "1:"},
      {"spp_fraction", "{\"render\": {\"spp\": 1.5}, \"spheres\": []}", "1:"},
      {"depth_negative", "{\"render\": {\"max_depth\": -1}, \"spheres\": []}", "1:"},
      {"units_zero", "{\"units_per_world\": 0, \"spheres\": []}", "1:"},
      {"second_line", "{\n  \"spheres\": [\n    {\"center\": [0, 0, 0], \"radius\": \"big\"}\n  ]\n}\n", "3:"},
  };
  ASSERT_GE(cases.size(), 30u);
  for (const auto& c : cases) {
    const std::string file = path(c.name + ".json");
    std::ofstream(file, std::ios::binary) << c.text;
    for (const char* mode : {"hw", "path"}) {
      const Result r = run("render --mode " + std::string(mode) + " --quiet --scene " + file + " --out " + path("x.png"));
      EXPECT_EQ(r.exit_code, 2) << c.name << " " << mode << "\n" << r.err;
      EXPECT_NE(r.err.find(file + ":" + c.expected), std::string::npos) << c.name << "\n" << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.name << ": one message\n" << r.err;
      EXPECT_FALSE(fs::exists(path("x.png"))) << c.name;
    }
  }
}

// The path-tracing device against the float path tracer of its own rays: the text, and the JSON object.
TEST_F(Cli, PathPresetComparesFrameMemoryWithTheFloatPathTracer) {
  // The text is checked for its form only, so a reference of 4 samples per pixel does (the reference was most of
  // this command's time; the JSON below, whose bias is checked, keeps 16).
  Result r = run("render --mode hw --preset path --scene cluster --spp 2 --depth 3 --accumulate 2 --compare "
                 "--reference-spp 4 --threads 2 --out " + path("p.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("vs float path tracer of the device's rays (same sky, 3 rays per path, 4 samples per pixel, "
                       "seed 1):"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("mean relative bias "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("relative MSE "), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("device: 4 samples per pixel accumulated in frame memory over 2 frames"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(path("p.png")));

  r = run("render --mode hw --preset path --scene cluster --compare --json --reference-spp 16 --threads 2 --quiet --out " +
          path("q.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  for (const char* key : {"mean_relative_bias", "relmse", "device_spp", "reference_spp", "depth", "late_pixels",
                          "pixels_compared", "pixels_without_samples"})
    EXPECT_TRUE(doc.contains(key)) << key << "\n" << r.out;
  EXPECT_EQ(doc["device_spp"], 1);
  EXPECT_EQ(doc["reference_spp"], 16);
  EXPECT_EQ(doc["depth"], 4);
  EXPECT_EQ(doc["pixels_compared"].get<int>() + doc["pixels_without_samples"].get<int>(), 640 * 480);
  EXPECT_LT(std::abs(doc["mean_relative_bias"].get<double>()), 0.02) << r.out;
  int parts = 0;
  for (const char* part : {"sky", "lambertian", "metal", "dielectric"}) parts += doc["by_first_hit"][part]["pixels"].get<int>();
  EXPECT_EQ(parts, doc["pixels_compared"].get<int>()) << r.out;

  // Presets that trace one ray per pixel: the same figures as the text, as JSON.
  r = run("render --compare --json --out " + path("w.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto wide = nlohmann::json::parse(r.out);
  EXPECT_EQ(wide["differing"], 0) << r.out;
  EXPECT_EQ(wide["pixels"], 640 * 480) << r.out;
}

TEST_F(Cli, CompareJsonAndAccumulateMisusedExitTwo) {
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {"render --json", "--json"},
      {"render --mode hw --preset path --json", "--json"},
      {"render --compare --reference-spp 64", "--reference-spp"},
      {"render --mode hw --preset path --reference-spp 64", "--reference-spp"},
      {"render --accumulate 4", "--accumulate"},
      {"render --mode path --accumulate 4", "--accumulate"},
      {"render --mode hw --preset path --wire v1 --accumulate 4", "--accumulate"},
      {"render --mode hw --preset path --accumulate 4 --frames 2 --out " + path("f_%d.png"), "--accumulate"},
      {"render --mode hw --preset path --spp 256", "samples per pixel must be 1 to 255"},
      {"render --mode hw --preset path --depth 17", "path depth must be 1 to 16"},
      {"run --mode normal --depth 3", "--depth"},
      {"run --mode path --spp 3", "--spp"},
      {"run --spp 3", "--spp"},  // the wide preset traces one ray per pixel
      {"device --listen 127.0.0.1:0 --headless --out-dir " + path("d") + " --spp 2", "--spp"},
      {"device --listen 127.0.0.1:0 --headless --out-dir " + path("d") + " --preset path --spp 0", "--spp"},
      {"bench --preset path", "--preset"},
      {"bench --scene demo --mode normal --preset path", "--preset"},
      {"bench --scene demo --mode hw --preset nope", "unknown preset"},
      {"bench --scene demo --mode path --row-step 2", "--row-step"},  // the window's, for the suite
      {"bench --row-step 9", "--row-step"},
  };
  for (const auto& c : cases) {
    const Result r = run(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_EQ(r.out, "") << c.args;
  }
}

TEST_F(Cli, HelpTellsTheTruthAboutThePathPreset) {
  const Result render = run("render --help");
  for (const char* text : {"--preset path or artix-path: samples per pixel the device adds to frame memory each frame",
                           "rays per path on the device, 1..16 (default 4)", "--reference-spp", "--accumulate",
                           "mean_relative_bias", "pixels late in every frame have none"})
    EXPECT_NE(render.out.find(text), std::string::npos) << text;
  const Result run_help = run("run --help");
  for (const char* text : {"--spp", "--depth", "accumulates samples while the camera is still"})
    EXPECT_NE(run_help.out.find(text), std::string::npos) << text;
  const Result device = run("device --help");
  for (const char* text : {"--spp", "--depth", "--preset path"})
    EXPECT_NE(device.out.find(text), std::string::npos) << text;
  const Result bench = run("bench --help");
  EXPECT_NE(bench.out.find("hw_path_fps_64"), std::string::npos);
}

// One scene measured in each mode: the JSON has the machine, the timings apart and the figure on the threads asked.
TEST_F(Cli, BenchMeasuresOneSceneAsJson) {
  for (const char* mode : {"hw", "normal", "path"}) {
    const Result r = run(std::string("bench --scene demo --mode ") + mode + " --threads 1 --seconds 0 --runs 1 --json");
    ASSERT_EQ(r.exit_code, 0) << mode << "\n" << r.err;
    const auto doc = nlohmann::json::parse(r.out);
    EXPECT_TRUE(doc.contains("machine")) << r.out;
    EXPECT_EQ(doc["scene"]["spheres"], 1) << r.out;
    const std::string figure = std::string(mode) == "hw" ? "hw_fps" : (std::string(mode) == "normal" ? "primary_mrays" : "path_msamples");
    ASSERT_TRUE(doc.contains(figure)) << r.out;
    EXPECT_GT(doc[figure]["threads_1"].get<double>(), 0.0) << r.out;
    EXPECT_FALSE(doc[figure].contains("threads_2")) << r.out;
    if (std::string(mode) != "hw") {
      EXPECT_TRUE(doc.contains("build_seconds")) << r.out;
      // Where Embree is built in, primary rays and the path tracer are measured over it too.
      EXPECT_EQ(doc[figure].contains("embree_threads_1"), !doc["machine"]["embree"].is_null()) << r.out;
    }
  }
  // hw with the path preset.
  const Result path_hw = run("bench --scene demo --mode hw --preset path --threads 1 --seconds 0 --runs 1 --json");
  ASSERT_EQ(path_hw.exit_code, 0) << path_hw.err;
  const auto doc = nlohmann::json::parse(path_hw.out);
  EXPECT_EQ(doc["preset"]["name"], "path") << path_hw.out;
  EXPECT_EQ(doc["preset"]["spp"], 1) << path_hw.out;
  EXPECT_GT(doc["hw_fps"]["threads_1"].get<double>(), 0.0) << path_hw.out;
  // A scene that does not load: its error alone, nothing on stdout.
  const Result bad = run("bench --scene " + path("missing.json") + " --mode hw");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(bad.out, "");
}

// Bad flags of every subcommand: exit code 2, a message naming the flag, nothing written.
TEST_F(Cli, BadFlagsExitTwoAndNameTheFlag) {
  struct Case {
    std::string args, expected;
  };
  const std::vector<Case> cases = {
      {"render --spp 0 --mode path", "--spp"},
      {"render --spp 100000000 --mode path", "--spp"},
      {"render --depth 0 --mode path", "--depth"},
      {"render --width 0 --mode normal", "--width"},
      {"render --height 99999 --mode normal", "--height"},
      {"render --threads 0 --mode path", "--threads"},
      {"render --spp 4", "--spp"},  // hw traces one ray per pixel
      {"render --bounces 7", "--bounces"},
      {"render --lines 0 --vcd " + path("v.vcd"), "--lines"},
      {"render --transfer-bytes 0", "--transfer-bytes"},
      {"render --spi-hz 0", "--spi-hz"},
      {"render --frames 0 --out " + path("f_%d.png"), "--frames"},
      {"render --orbit 10", "--orbit"},
      {"render --mode normal --vcd " + path("v.vcd"), "--vcd"},
      {"render --compare --mode normal", "--compare"},
      {"render --denoise", "--denoise"},                   // hw pictures are not noisy
      {"render --mode normal --aov " + path(""), "--aov"},
      {"render --mode path --sampler halton", "--sampler"},
      {"render --mode path --aov " + path("missing-dir"), "missing-dir"},
      {"render --mode path --exr-pixel double", "--exr-pixel"},
      {"render --mode path --frames 2 --aov " + path(""), "--aov"},
      {"run --no-denoise", "--no-denoise"},                // hw has no denoiser
      {"run --mode path --row-step 0", "--row-step"},
      {"run --scale 0", "--scale"},
      {"run --mode sideways", "--mode"},
      {"link decode --wire v9", "wire"},
      {"bench --runs 0", "--runs"},
      {"bench --mode path", "--mode"},                       // --mode is for --scene
      {"bench --scene demo --mode sideways", "--mode"},
      {"bench --scene " + path("missing.json") + " --mode path", "missing.json"},
      {"bench --scene demo --threads 0", "--threads"},
      {"host --connect nowhere", "nowhere"},
  };
  for (const auto& c : cases) {
    const Result r = run(c.args + " --out " + path("x.png"));
    const Result plain = run(c.args);
    for (const Result* res : {&r, &plain}) {
      EXPECT_EQ(res->exit_code, 2) << c.args << "\n" << res->err;
    }
    EXPECT_NE(plain.err.find(c.expected), std::string::npos) << c.args << "\n" << plain.err;
    EXPECT_FALSE(fs::exists(path("x.png"))) << c.args;
    EXPECT_FALSE(fs::exists(path("v.vcd"))) << c.args;
  }
}

TEST_F(Cli, PathStillWritesExrWithLayersAndAovPngs) {
  const Result r = run("render --scene field --mode path --width 40 --height 24 --spp 4 --denoise --threads 2 --quiet --out " +
                       path("f.exr") + " --aov " + path(""));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto exr = tripsitter::display::read_exr(path("f.exr"));
  ASSERT_TRUE(exr) << exr.error().message;
  EXPECT_EQ(exr.value().width, 40);
  EXPECT_EQ(exr.value().height, 24);
  for (const char* name : {"R", "G", "B", "albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z", "Z"})
    EXPECT_NE(tripsitter::display::find_channel(exr.value(), name), nullptr) << name;
  EXPECT_EQ(tripsitter::display::find_channel(exr.value(), "Z")->pixel, tripsitter::display::ExrPixel::kFloat);
  EXPECT_EQ(tripsitter::display::find_channel(exr.value(), "R")->pixel, tripsitter::display::ExrPixel::kHalf);
  for (const char* name : {"albedo.png", "normal.png", "depth.png"}) {
    const auto png = tripsitter::display::read_png(path(name));
    ASSERT_TRUE(png) << name;
    EXPECT_EQ(png.value().width, 40) << name;
  }
}

// tripsitter rom: the board's ROM image. Run with its defaults it writes, byte for byte, the image checked in beside
// the board's top (rtl/boards/arty_a7/), so that image cannot go stale; its worlds are the wire's frames, in order.
TEST_F(Cli, RomWritesTheBoardsCheckedInImage) {
  const Result r = run("rom -o " + path("rom.mem"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("32 worlds of 8 spheres"), std::string::npos) << r.err;
  const std::string written = slurp(dir_ / "rom.mem");
  EXPECT_EQ(written, slurp(fs::path(TRIPSITTER_SOURCE_DIR) / "rtl/boards/arty_a7/ts_arty_rom.mem"))
      << "rtl/boards/arty_a7/ts_arty_rom.mem is not what `tripsitter rom` writes: write it again with "
         "`tripsitter rom -o rtl/boards/arty_a7/ts_arty_rom.mem`";
  // The bytes, one a line after the comments, hold the table and the 32 worlds, each a frame numbered 1..32.
  std::vector<std::uint8_t> bytes;
  std::istringstream lines(written);
  for (std::string line; std::getline(lines, line);)
    if (!line.starts_with("//")) bytes.push_back(static_cast<std::uint8_t>(std::stoul(line, nullptr, 16)));
  const auto worlds = tripsitter::host::rom_worlds(bytes);
  ASSERT_TRUE(worlds.ok()) << worlds.error();
  ASSERT_EQ(worlds.value().size(), 32u);
  for (std::size_t k = 0; k < worlds.value().size(); ++k) {
    const auto w = tripsitter::link::decode_frame(tripsitter::link::WireVersion::kV2, worlds.value()[k], 256);
    ASSERT_TRUE(w.ok()) << "world " << k;
    EXPECT_EQ(w.value().sequence, k + 1);
  }
  EXPECT_LE(bytes.size(), 8192u);
}

TEST_F(Cli, RomRefusesBadInputAndWritesNothing) {
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {"rom --worlds 0", "--worlds"},
      {"rom --worlds 64", "more than the ROM's 8192"},
      {"rom --orbit 90 --walk 2", "excludes"},
      {"rom --scene nope", "nope"},
      {"rom --preset path", "--preset path"},
      {"rom --preset nope", "nope"},
      {"rom --capacity 8", "--capacity"},
  };
  for (const auto& c : cases) {
    const Result r = run(c.args + " -o " + path("rom.mem"));
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(path("rom.mem"))) << c.args;
  }
  const Result no_out = run("rom");
  EXPECT_EQ(no_out.exit_code, 2);
  EXPECT_NE(no_out.err.find("--out"), std::string::npos) << no_out.err;
  const Result nowhere = run("rom -o " + path("no/such/dir/rom.mem"));
  EXPECT_EQ(nowhere.exit_code, 2);
  EXPECT_NE(nowhere.err.find("no/such/dir/rom.mem"), std::string::npos) << nowhere.err;
  EXPECT_FALSE(fs::exists(dir_ / "no")) << "no folder is made";
  const Result help = run("rom --help");
  for (const char* text : {"--scene", "--worlds", "--orbit", "--walk", "--capacity", "$readmemh", "wire v2"})
    EXPECT_NE(help.out.find(text), std::string::npos) << text << "\n" << help.out;
}

}  // namespace

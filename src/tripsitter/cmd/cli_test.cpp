// The command line as a user meets it: exit codes, messages, files written or not.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include <tripsitter/display/png.h>

namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code = -1;
  std::string out, err;
};

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("tripsitter_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }

  // Runs tripsitter with `args` (shell words) and optional stdin file.
  Result run(const std::string& args, const std::string& stdin_file = "/dev/null") const {
    const std::string cmd = std::string(TRIPSITTER_BIN) + " " + args + " <" + stdin_file + " >" + path("stdout") +
                            " 2>" + path("stderr");
    const int status = std::system(cmd.c_str());
    Result r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(dir_ / "stdout");
    r.err = slurp(dir_ / "stderr");
    return r;
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
      {"render --wire v3 --out " + path("x.png"), "unknown wire"},
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

}  // namespace

// `--device rtl` as a user meets it: the built tripsitter program, its picture against the C++ model's, its errors, its
// VCD.
#include <string>

#include <gtest/gtest.h>

#include <tripsitter/cmd/command_test_util.h>

namespace tripsitter::cmd::test {
namespace {

const std::string kBin = TRIPSITTER_BIN;

Result render(const std::string& args, const fs::path& dir, const std::string& log) {
  return run_shell(kBin + " render " + args, dir / log);
}

// A world through host, link, the RTL's pins (SCLK at its fastest, 12.5 MHz) and the monitor: the same PNG file as the
// model's, byte for byte.
TEST(RtlCli, RenderDrawsWhatTheModelDraws) {
  const fs::path dir = scratch_dir("rtl_cli_");
  const std::string board = "--scene cluster --preset board-2023 --wire v2 --workers 1 --out ";
  const Result model = render(board + (dir / "model.png").string(), dir, "model");
  ASSERT_EQ(model.exit_code, 0) << model.err;
  const Result rtl = render("--device rtl --spi-hz 12500000 " + board + (dir / "rtl.png").string(), dir, "rtl");
  ASSERT_EQ(rtl.exit_code, 0) << rtl.err;
  EXPECT_NE(rtl.err.find("device (RTL): simulated in"), std::string::npos) << rtl.err;
  EXPECT_EQ(slurp(dir / "model.png"), slurp(dir / "rtl.png"));
  EXPECT_FALSE(slurp(dir / "rtl.png").empty());
}

// The board as the report shipped it: board-2023 with its 10 workers on the v1 wire. The demo sphere's word through
// the RTL's pins: the model's PNG file byte for byte, with the report's 60 late pixels on every line (a sphere
// costs each of the 64 pixels of a worker's line 51 cycles, 3,264 of the 3,000).
TEST(RtlCli, RenderTheBoardAsItShipped) {
  const fs::path dir = scratch_dir("rtl_cli_");
  const std::string board = "--scene demo --preset board-2023 --wire v1 --out ";
  const Result model = render(board + (dir / "model.png").string(), dir, "model");
  ASSERT_EQ(model.exit_code, 0) << model.err;
  const Result rtl = render("--device rtl --spi-hz 12500000 " + board + (dir / "rtl.png").string(), dir, "rtl");
  ASSERT_EQ(rtl.exit_code, 0) << rtl.err;
  EXPECT_EQ(slurp(dir / "model.png"), slurp(dir / "rtl.png"));
  EXPECT_FALSE(slurp(dir / "rtl.png").empty());
  const std::string late = "device: 28800 late pixels on 480 lines";
  EXPECT_NE(model.err.find(late), std::string::npos) << model.err;
  EXPECT_NE(rtl.err.find(late), std::string::npos) << rtl.err;
}

// The artix device with one sphere unit on `cluster` (8 spheres, mirrors): the model's PNG file byte for byte.
TEST(RtlCli, RenderTheArtixDevice) {
  const fs::path dir = scratch_dir("rtl_cli_");
  const std::string artix = "--scene cluster --preset artix --workers 1 --out ";
  const Result model = render(artix + (dir / "model.png").string(), dir, "model");
  ASSERT_EQ(model.exit_code, 0) << model.err;
  const Result rtl = render("--device rtl --spi-hz 12500000 " + artix + (dir / "rtl.png").string(), dir, "rtl");
  ASSERT_EQ(rtl.exit_code, 0) << rtl.err;
  EXPECT_EQ(slurp(dir / "model.png"), slurp(dir / "rtl.png"));
  EXPECT_FALSE(slurp(dir / "rtl.png").empty());
}

// A link file fed to the device alone: the same picture and the same receiver counts.
TEST(RtlCli, LinkInputAsTheModel) {
  const fs::path dir = scratch_dir("rtl_cli_");
  const Result link = run_shell(kBin + " link encode --scene cluster --preset board-2023 --wire v2 | tee " +
                                    (dir / "world.bin").string(), dir / "link");
  ASSERT_EQ(link.exit_code, 0) << link.err;
  const std::string args =
      "--link-input " + (dir / "world.bin").string() + " --preset board-2023 --wire v2 --workers 1 --out ";
  const Result model = render(args + (dir / "model.png").string(), dir, "model");
  const Result rtl = render("--device rtl " + args + (dir / "rtl.png").string(), dir, "rtl");
  ASSERT_EQ(model.exit_code, 0) << model.err;
  ASSERT_EQ(rtl.exit_code, 0) << rtl.err;
  EXPECT_EQ(slurp(dir / "model.png"), slurp(dir / "rtl.png"));
  const auto receiver_line = [](const std::string& err) { return err.substr(0, err.find('\n')); };
  EXPECT_EQ(receiver_line(rtl.err), receiver_line(model.err));
}

TEST(RtlCli, BadInputSaysWhatIsBuilt) {
  const fs::path dir = scratch_dir("rtl_cli_");
  const Result workers = render("--device rtl --preset wide --workers 3 --out " + (dir / "a.png").string(), dir, "w");
  EXPECT_EQ(workers.exit_code, 2);
  EXPECT_NE(workers.err.find("the RTL is built for board-2023 with 10 workers on wire v2"), std::string::npos)
      << workers.err;
  EXPECT_FALSE(fs::exists(dir / "a.png"));
  const Result mode = render("--device rtl --mode normal --out " + (dir / "b.png").string(), dir, "m");
  EXPECT_EQ(mode.exit_code, 2);
  EXPECT_NE(mode.err.find("--device rtl needs --mode hw"), std::string::npos) << mode.err;
  const Result name = render("--device fpga --out " + (dir / "c.png").string(), dir, "n");
  EXPECT_EQ(name.exit_code, 2);
  EXPECT_NE(name.err.find("--device fpga: expected model or rtl"), std::string::npos) << name.err;
  const Result worker = render("--vcd-worker 2 --out " + (dir / "d.png").string(), dir, "v");
  EXPECT_EQ(worker.exit_code, 2);
  EXPECT_NE(worker.err.find("--vcd-worker"), std::string::npos) << worker.err;
  const Result spi = render("--device rtl --preset board-2023 --wire v2 --spi-hz 20000000 --out " +
                                (dir / "e.png").string(), dir, "s");
  EXPECT_EQ(spi.exit_code, 2);
  EXPECT_NE(spi.err.find("SPI clock"), std::string::npos) << spi.err;
}

// --vcd with the RTL: Verilator's trace of the pins, and with --vcd-worker of that worker's signals.
TEST(RtlCli, VcdOfTheRtl) {
  const fs::path dir = scratch_dir("rtl_cli_");
  const Result r = render("--device rtl --scene cluster --preset board-2023 --wire v2 --workers 1 --vcd " +
                              (dir / "rtl.vcd").string() + " --vcd-worker 0 --lines 3 --out " + (dir / "a.png").string(),
                          dir, "vcd");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string vcd = slurp(dir / "rtl.vcd");
  EXPECT_NE(vcd.find("$scope module g_worker[0] $end"), std::string::npos);
  EXPECT_NE(vcd.find(" spi_mosi "), std::string::npos);
  // Reset, the world's transfer and three lines: not the frame the device passes on its way to the world's first.
  EXPECT_LT(vcd.size(), 20u << 20);
  EXPECT_NE(r.err.find("wrote " + (dir / "rtl.vcd").string()), std::string::npos) << r.err;
}

}  // namespace
}  // namespace tripsitter::cmd::test

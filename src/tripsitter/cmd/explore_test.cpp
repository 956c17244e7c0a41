// tripsitter explore as a user runs it: its points against `render`'s own report of the same configuration, bad
// sweeps, and Ctrl-C keeping the points finished.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "command_test_util.h"

namespace tripsitter::cmd::test {
namespace {

const std::string kBin = TRIPSITTER_BIN;

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(slurp(p)); }

// The points of points.json, by index.
nlohmann::json explore_points(const std::string& args, const fs::path& dir) {
  const Result r = run_shell(kBin + " explore --quiet " + args + " --out " + (dir / "report").string(), dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return read_json(dir / "report" / "points.json")["points"];
}

TEST(Explore, MirrorPointMatchesRendersReport) {
  const fs::path dir = scratch_dir("explore_");
  const nlohmann::json points = explore_points("--scene cluster --sweep preset=board-2023,workers=10,24", dir);
  ASSERT_EQ(points.size(), 2u);
  for (const auto& p : points) {
    const Result r = run_shell(kBin + " render --scene cluster --mode hw --preset board-2023 --workers " +
                                   std::to_string(p["workers"].get<int>()) + " --compare --json --out " +
                                   (dir / "render.png").string(),
                               dir / "render");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json render = nlohmann::json::parse(r.out);
    EXPECT_EQ(p["late_pixels"], render["late_pixels"]);
    EXPECT_EQ(p["late_lines"], render["late_lines"]);
    EXPECT_EQ(p["differing"], render["differing"]);
    EXPECT_EQ(p["over_one_level"], render["over_one_level"]);
    EXPECT_EQ(p["max_levels"], render["max_level_difference"]);
    EXPECT_EQ(p["pixels"], render["pixels"]);
  }
  EXPECT_GT(points[0]["late_lines"].get<int>(), 0);  // 10 workers are late on cluster; the test compares both kinds
}

TEST(Explore, PathPointMatchesRendersReport) {
  const fs::path dir = scratch_dir("explore_");
  const nlohmann::json points =
      explore_points("--scene demo --sweep preset=path,spp=2,depth=3 --reference-spp 8 --seed 5", dir);
  ASSERT_EQ(points.size(), 1u);
  const Result r = run_shell(kBin + " render --scene demo --mode hw --preset path --spp 2 --depth 3 --compare --json "
                                    "--reference-spp 8 --seed 5 --out " + (dir / "render.png").string(),
                             dir / "render");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json render = nlohmann::json::parse(r.out);
  const nlohmann::json& p = points[0];
  EXPECT_EQ(p["late_pixels"], render["late_pixels"]);
  EXPECT_EQ(p["late_lines"], render["late_lines"]);
  EXPECT_DOUBLE_EQ(p["relmse"].get<double>(), render["relmse"].get<double>());
  EXPECT_DOUBLE_EQ(p["bias"].get<double>(), render["mean_relative_bias"].get<double>());
  EXPECT_EQ(p["reference_spp"], render["reference_spp"]);
  EXPECT_EQ(p["pixels"], render["pixels_compared"]);
}

TEST(Explore, BadSweepExitsTwoPointingAtTheOffendingPartAndWritesNothing) {
  const fs::path dir = scratch_dir("explore_");
  const Result r = run_shell(kBin + " explore --sweep workers=1..64,fracbits=3,x --out " + (dir / "report").string(), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("'x' is not an integer"), std::string::npos) << r.err;
  // Built with append: GCC 12 at -O3 warns (-Warray-bounds, falsely) on "literal" + std::string here.
  const std::string caret = std::string("  workers=1..64,fracbits=3,x\n").append(2 + 25, ' ').append("^");
  EXPECT_NE(r.err.find(caret), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "report"));
  const Result scene = run_shell(kBin + " explore --scene no-such-scene.json --out " + (dir / "report").string(), dir);
  EXPECT_EQ(scene.exit_code, 2);
  EXPECT_NE(scene.err.find("no-such-scene.json"), std::string::npos) << scene.err;
}

TEST(Explore, InterruptedSweepKeepsThePointsFinished) {
  const fs::path dir = scratch_dir("explore_");
  const fs::path report = dir / "report";
  // Enough points that the sweep is still running when it is interrupted: about 50 ms each.
  const fs::path err = dir / "stderr";
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::FILE* log = std::freopen(err.c_str(), "w", stderr);
    if (log == nullptr) ::_exit(126);
    const std::string out = report.string();
    ::execl(kBin.c_str(), kBin.c_str(), "explore", "--threads", "1", "--scene", "cluster", "--sweep",
            "preset=board-2023,workers=1..640", "--out", out.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Interrupt once the sweep has said it started (its handler is in place by then), bounded at 60 s.
  for (int i = 0; i < 600 && slurp(err).find("Ctrl-C stops") == std::string::npos; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ::kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const nlohmann::json doc = read_json(report / "points.json");
  EXPECT_TRUE(doc["sweep"]["interrupted"].get<bool>());
  EXPECT_EQ(doc["sweep"]["points_planned"], 640);
  EXPECT_LT(doc["points"].size(), 640u);
  EXPECT_EQ(doc["points"].size(), doc["sweep"]["points_done"].get<std::size_t>());
  EXPECT_TRUE(fs::exists(report / "index.html"));
  EXPECT_TRUE(fs::exists(report / "points.csv"));
}

}  // namespace
}  // namespace tripsitter::cmd::test

// index.html as a person sees it: a report of synthetic points covering every chart, opened from file:// in
// headless Chromium (Debian's chromium) with every host name unresolvable, must say it drew each chart it made
// (the page's self-check: body's data-ready, data-charts-expected, data-charts-drawn) and screenshot to a picture
// that is not one colour. Skipped, saying so, where no Chromium is installed. Chromium runs in its own process
// group, killed if it takes longer than kTimeout, so the test cannot hang.
//
// TRIPSITTER_KEEP_REPORT=DIR keeps a copy of the report and its screenshot (DIR/shot.png), to look at.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include <tripsitter/core/image.h>
#include <tripsitter/display/png.h>
#include <tripsitter/explore/report.h>

#include "report_test_util.h"

extern char** environ;

namespace tripsitter::explore {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

constexpr auto kTimeout = std::chrono::seconds(60);

// The first of Chromium's usual names on PATH, or "".
std::string find_chromium() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path != nullptr ? path : "/usr/bin:/bin");
  std::vector<std::string> folders;
  for (std::string d; std::getline(dirs, d, ':');) folders.push_back(d.empty() ? "." : d);
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    for (const std::string& d : folders) {
      const fs::path candidate = fs::path(d) / name;
      if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    }
  }
  return "";
}

struct Outcome {
  bool timed_out = false;
  int exit_code = -1;
  std::string out, err;
};

// Runs argv with HOME (and XDG's folders) in `home`, stdout and stderr to files there, in a process group of its
// own that is killed whole if it outlives kTimeout and, after it exits, to end any helper it left.
Outcome run(const std::vector<std::string>& args, const fs::path& home, const std::string& tag) {
  Outcome result;
  const fs::path out = home / (tag + ".out"), err = home / (tag + ".err");
  std::vector<std::string> env_text;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string kv = *e;
    if (kv.rfind("HOME=", 0) == 0 || kv.rfind("XDG_CONFIG_HOME=", 0) == 0 || kv.rfind("XDG_CACHE_HOME=", 0) == 0) continue;
    env_text.push_back(kv);
  }
  env_text.push_back("HOME=" + home.string());
  env_text.push_back("XDG_CONFIG_HOME=" + (home / ".config").string());
  env_text.push_back("XDG_CACHE_HOME=" + (home / ".cache").string());
  std::vector<char*> env, argv;
  for (std::string& kv : env_text) env.push_back(kv.data());
  env.push_back(nullptr);
  std::vector<std::string> arg_text = args;
  for (std::string& a : arg_text) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&files, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&files, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attr, 0);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &files, &attr, argv.data(), env.data());
  posix_spawn_file_actions_destroy(&files);
  posix_spawnattr_destroy(&attr);
  if (rc != 0) {
    result.err = "cannot start " + args[0] + ": " + std::to_string(rc);
    return result;
  }

  const auto deadline = std::chrono::steady_clock::now() + kTimeout;
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(-pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      result.timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ::kill(-pid, SIGKILL);  // Chromium's helpers, if any outlived it (the group is ours alone)
  if (!result.timed_out && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  result.out = test::slurp(out);
  result.err = test::slurp(err);
  return result;
}

// A 160x120 frame: a shaded sphere on a dark sky, tinted by `hue`.
std::vector<std::uint8_t> frame(int hue) {
  core::ImageRgb8 image(160, 120);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      std::uint8_t* px = &image.pixels[3 * static_cast<std::size_t>(y * image.width + x)];
      const double dx = (x - 80) / 45.0, dy = (y - 60) / 45.0, r2 = dx * dx + dy * dy;
      if (r2 < 1) {
        const double shade = 0.25 + 0.75 * std::max(0.0, -0.5 * dx - 0.6 * dy + 0.62 * std::sqrt(1 - r2));
        px[0] = static_cast<std::uint8_t>(255 * shade * (hue == 0 ? 1.0 : 0.4));
        px[1] = static_cast<std::uint8_t>(255 * shade * 0.7);
        px[2] = static_cast<std::uint8_t>(255 * shade * (hue == 0 ? 0.3 : 1.0));
      } else {
        px[0] = 10;
        px[1] = static_cast<std::uint8_t>(20 + y / 4);
        px[2] = static_cast<std::uint8_t>(40 + y / 2);
      }
    }
  }
  auto png = display::encode_png(image);
  return png.ok() ? png.value() : std::vector<std::uint8_t>{};
}

// Twenty points: board-2023 on two scenes over workers and fractional bits, the path preset over spp and
// workers, a few late, a few too big for the board.
Report synthetic_report() {
  Report r;
  int index = 0;
  const auto mirror = [&](const std::string& scene, int workers, int frac_bits, double load) {
    Point p;
    p.index = index++;
    p.config = {.scene = scene, .preset = "board-2023", .workers = workers, .frac_bits = frac_bits,
                .sqrt_iterations = 8, .bounces = 1, .spi_hz = 10'000'000, .transfer_bytes = 64,
                .frame_memory = "", .wire = "v1"};
    const double line_load = load / workers;
    p.m.line_load = line_load;
    p.m.late_lines = line_load <= 1 ? 0 : static_cast<int>(std::min(480.0, 480 * (1 - 1 / line_load) * 1.3));
    p.m.late_pixels = p.m.late_lines * 210;
    p.m.fps = line_load <= 1 ? 59.94 : 59.94 / line_load;
    p.m.link_bits = 2'000;
    p.m.link_ms = 0.2;
    p.m.pixels = 307'200;
    p.m.differing = static_cast<std::uint64_t>(307'200 * 0.2 / (1 << (frac_bits - 8)));
    p.m.over_one_level = p.m.differing / 10;
    p.m.max_levels = frac_bits < 12 ? 3 : 1;
    p.m.dsp_per_worker = 9 + (frac_bits - 10) / 2;
    p.m.dsp_shared = 6;
    p.m.dsp = p.m.dsp_per_worker * workers + p.m.dsp_shared;
    p.m.bram_kbit = 1'368;
    p.m.multiplies = 21;
    p.m.additions = 30;
    p.m.square_roots = 1;
    p.m.divisions = 1;
    r.points.push_back(p);
  };
  for (const int w : {2, 4, 8, 16}) {
    for (const int f : {10, 14}) mirror("cluster", w, f, 11.0);
  }
  for (const int w : {2, 4, 8}) {
    for (const int f : {10, 14}) mirror("demo", w, f, 3.5);
  }
  for (const int w : {8, 16}) {
    for (const int spp : {1, 4, 16}) {
      Point p;
      p.index = index++;
      p.config = {.scene = "cluster", .preset = "path", .workers = w, .frac_bits = 12, .sqrt_iterations = 10,
                  .spp = spp, .depth = 3, .frames = 8, .spi_hz = 20'000'000, .transfer_bytes = 256,
                  .frame_memory = "external", .wire = "v2"};
      p.m.line_load = 0.9 * spp * 8 / w;
      p.m.late_lines = p.m.line_load <= 1 ? 0 : 480;
      p.m.fps = std::min(59.94, 59.94 / p.m.line_load);
      p.m.pixels = 307'200;
      p.m.relmse = 0.8 / (spp * 8) * (w == 8 ? 1.0 : 1.05);
      p.m.bias = 0.004;
      p.m.reference_spp = 1024;
      p.m.random_draws = 6.0 * spp;
      p.m.dsp_per_worker = 18;
      p.m.dsp_shared = 10;
      p.m.dsp = 18 * w + 10;
      p.m.bram_kbit = 2'100;
      p.m.sram_bits_per_cycle = 1.5 * spp;
      r.points.push_back(p);
    }
  }
  r.points[0].thumbnail_png = frame(0);
  r.points[6].thumbnail_png = frame(0);
  r.points[18].thumbnail_png = frame(1);
  r.summary = Json::parse(R"({
    "cheapest_on_time": [{"scene": "cluster", "preset": "board-2023", "point": 6},
                         {"scene": "demo", "preset": "board-2023", "point": 10},
                         {"scene": "cluster", "preset": "path", "point": 14}],
    "sixty_hz": [{"scene": "cluster", "point": 6}, {"scene": "demo", "point": null}],
    "thumbnails": [{"point": 0, "caption": "cluster, board-2023, 2 workers: 422 late lines"},
                   {"point": 6, "caption": "cluster, board-2023, 16 workers: on time"},
                   {"point": 18, "caption": "cluster, path, 16 workers, 4 spp"}]})");
  r.sweep = Json::parse(R"({"command": "tripsitter explore --scene cluster --scene demo --preset board-2023 --preset path --sweep workers=2,4,8,16 --sweep frac_bits=10,14 --sweep spp=1,4,16 --out report",
    "scenes": ["cluster", "demo"], "sweeps": ["workers=2,4,8,16", "frac_bits=10,14", "spp=1,4,16"],
    "points_planned": 20, "points_done": 20, "interrupted": false, "seconds": 83.2})");
  return r;
}

class ReportInABrowser : public test::ScratchDirTest {
 protected:
  std::vector<std::string> chromium_args(const std::string& chromium, const std::string& profile) const {
    return {chromium,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-dev-shm-usage",
            "--no-first-run",
            "--no-default-browser-check",
            "--disable-extensions",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
            "--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE localhost",
            "--user-data-dir=" + (dir_ / profile).string(),
            "--virtual-time-budget=5000"};
  }
};

TEST_F(ReportInABrowser, DrawsEveryChartAndShowsAPicture) {
  const std::string chromium = find_chromium();
  if (chromium.empty()) {
    GTEST_SKIP() << "no Chromium on PATH (chromium, chromium-browser or google-chrome): install Debian's chromium "
                    "to test the report's page in a browser";
  }
  const fs::path report_dir = dir_ / "report";
  const auto written = write_report(report_dir, synthetic_report());
  ASSERT_TRUE(written.ok()) << written.error().message;
  const std::string url = "file://" + (report_dir / "index.html").string();

  // The DOM once the page's script has run: its self-check on <body>.
  std::vector<std::string> args = chromium_args(chromium, "profile-dom");
  args.push_back("--dump-dom");
  args.push_back(url);
  const Outcome dom = run(args, dir_, "dom");
  ASSERT_FALSE(dom.timed_out) << "Chromium took longer than " << kTimeout.count() << " s\n" << dom.err;
  ASSERT_EQ(dom.exit_code, 0) << dom.err;
  const std::string tag = test::first_tag(dom.out, "<body");
  ASSERT_FALSE(tag.empty()) << dom.out.substr(0, 2000) << dom.err;
  EXPECT_EQ(tag.find("data-error"), std::string::npos) << tag;
  EXPECT_NE(tag.find("data-ready=\"1\""), std::string::npos) << tag << "\n" << dom.err;
  const std::optional<int> expected_count = test::number_attribute(tag, "data-charts-expected");
  const std::optional<int> drawn_count = test::number_attribute(tag, "data-charts-drawn");
  ASSERT_TRUE(expected_count && drawn_count) << tag;
  const int expected = *expected_count, drawn = *drawn_count;
  // Two scenes' late lines, error for mirror and path, fps, fps against the SPI clock, and three Pareto fronts (2
  // scenes mirror, 1 path).
  EXPECT_EQ(expected, 9);
  EXPECT_EQ(drawn, expected);
  EXPECT_NE(dom.out.find("id=\"point-19\""), std::string::npos) << "the table of all points";
  // Every element the page has, the script's included: src and href are data: URLs or #anchors. (Chart.js's text
  // is skipped: a script's content is not markup.)
  std::string markup = dom.out;
  for (std::size_t open; (open = markup.find("<script")) != std::string::npos;) {
    const std::size_t close = markup.find("</script>", open);
    ASSERT_NE(close, std::string::npos);
    markup.erase(open, close + 9 - open);
  }
  int images = 0, anchors = 0;
  for (const test::Attribute& a : test::link_attributes(markup)) {
    EXPECT_TRUE(a.value.rfind("data:image/png;base64,", 0) == 0 || a.value.rfind("#", 0) == 0) << a.value.substr(0, 80);
    ++(a.name == "src" ? images : anchors);
  }
  EXPECT_EQ(images, 3) << "the three thumbnails";
  EXPECT_GE(anchors, 12) << "navigation, and links to points from the tables and frames";

  // A screenshot: not one colour, and not nearly all white.
  const fs::path shot = dir_ / "shot.png";
  args = chromium_args(chromium, "profile-shot");
  args.push_back("--screenshot=" + shot.string());
  args.push_back("--window-size=1280,2400");
  args.push_back(url);
  const Outcome screenshot = run(args, dir_, "shot");
  ASSERT_FALSE(screenshot.timed_out) << "Chromium took longer than " << kTimeout.count() << " s\n" << screenshot.err;
  ASSERT_EQ(screenshot.exit_code, 0) << screenshot.err;
  const auto image = display::read_png(shot.string());
  ASSERT_TRUE(image.ok()) << image.error().message << "\n" << screenshot.err;
  EXPECT_EQ(image.value().width, 1280);
  EXPECT_EQ(image.value().height, 2400);
  std::set<std::uint16_t> colours;
  std::size_t white = 0;
  for (const core::Rgb444 p : image.value().pixels) {
    colours.insert(p.packed);
    if (p.packed == 0xFFF) ++white;
  }
  EXPECT_GT(colours.size(), 20u) << "the screenshot is (nearly) one colour";
  EXPECT_LT(static_cast<double>(white), 0.97 * static_cast<double>(image.value().pixels.size()));
  if (const char* keep = std::getenv("TRIPSITTER_KEEP_REPORT"); keep != nullptr && *keep != '\0') {
    std::error_code ec;
    fs::create_directories(keep, ec);
    fs::copy(report_dir, keep, fs::copy_options::overwrite_existing | fs::copy_options::recursive, ec);
    if (!ec) fs::copy_file(shot, fs::path(keep) / "shot.png", fs::copy_options::overwrite_existing, ec);
    EXPECT_FALSE(ec) << "cannot keep the report in " << keep << ": " << ec.message();
  }
}

}  // namespace
}  // namespace tripsitter::explore

// tripsitter bench: frames per second of the board model and of the float reference.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <thread>
#include <vector>

#include <tripsitter/board/board.h>
#include <tripsitter/render/normal.h>
#include <tripsitter/scene/builtin.h>

#include "commands.h"
#include "common.h"

namespace tripsitter::cmd {
namespace {

struct BenchOptions {
  double seconds = 1.0;  // per figure, at least
  int runs = 3;          // the median of these is reported
};

// Median frames per second of `frame` over `runs` runs of at least `seconds` each.
template <class F>
double median_fps(const BenchOptions& o, F&& frame) {
  std::vector<double> fps;
  for (int run = 0; run < o.runs; ++run) {
    const auto start = std::chrono::steady_clock::now();
    int frames = 0;
    double elapsed = 0;
    do {
      frame();
      ++frames;
      elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    } while (elapsed < o.seconds);
    fps.push_back(frames / elapsed);
  }
  std::sort(fps.begin(), fps.end());
  return fps[fps.size() / 2];
}

int run_bench(const BenchOptions& o) {
  std::printf("machine: %u hardware threads; hw computes a frame's lines on all of them, normal uses one;\n"
              "median of %d runs of at least %.1f s\n",
              std::thread::hardware_concurrency(), o.runs, o.seconds);
  std::printf("%-28s %12s\n", "figure", "frames/s");
  for (int n : {1, 16, 64}) {
    board::Board b(scene::random_spheres(n, 1), {});
    const double fps = median_fps(o, [&] { b.show(); });
    std::printf("%-28s %12.2f\n", ("hw_fps_" + std::to_string(n)).c_str(), fps);
  }
  for (int n : {1, 16, 64}) {
    host::Host h(scene::random_spheres(n, 1), board::formats_of(device::wide_preset()), link::WireVersion::kV2);
    const auto& world = h.update();
    const int bounces = device::wide_preset().max_bounces;
    const double fps = median_fps(o, [&] { render::render_normal(world.view_spheres, 640, 480, bounces); });
    std::printf("%-28s %12.2f\n", ("normal_fps_" + std::to_string(n)).c_str(), fps);
  }
  return kExitOk;
}

}  // namespace

void add_bench_command(CLI::App& app, Action& run) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench", "Frames per second at 640x480: the board model (hw) and the float reference (normal), 1/16/64 spheres");
  cmd->add_option("--seconds", o->seconds, "Minimum time per run")->capture_default_str()->check(CLI::Range(0.0, 600.0));
  cmd->add_option("--runs", o->runs, "Runs per figure; the median is reported")->capture_default_str()->check(CLI::Range(1, 101));
  cmd->callback([o, &run] { run = [o] { return run_bench(*o); }; });
}

}  // namespace tripsitter::cmd

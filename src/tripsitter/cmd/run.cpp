// tripsitter run: the board in a window, driven by the keyboard.
#include <cstdio>
#include <iostream>
#include <memory>

#include <tripsitter/device/preset.h>
#include <tripsitter/frontend/run.h>
#include <tripsitter/scene/scene.h>

#include "commands.h"
#include "common.h"
#include "options.h"
#include "device_choice.h"

namespace tripsitter::cmd {
namespace {

// The window's settings as the options give them (app: the mode, wire, seed, threads, denoiser, reuse, row step
// and screenshot directory), and what run_run makes of the rest: the scene, the preset, the device, the depth.
struct RunCommandOptions {
  frontend::AppConfig app;
  std::string scene = "demo";
  std::string preset = "wide";
  int workers = 0;
  int scale = 1;
  std::uint64_t frames = 0;
  int spp = 0;    // 0: not given
  int depth = 0;
  DeviceChoice device;
};

// Options that contradict each other; throws InputError before any work.
void check_options(const RunCommandOptions& o) {
  const modes::SourceConfig& s = o.app.source;
  if (s.mode == modes::Mode::kNormal && (o.spp != 0 || o.depth != 0))
    throw InputError("--spp and --depth need --mode hw with --preset path or artix-path, or --mode path (normal traces one ray per pixel)");
  if (s.mode == modes::Mode::kPath && o.spp != 0)
    throw InputError("--spp: the window's --mode path adds one sample per pixel per frame while the camera is still; "
                     "--spp sets the device's samples per frame with --mode hw and a path preset");
  if (s.mode != modes::Mode::kPath && (!s.denoise || !s.reuse || s.row_step != 1))
    throw InputError("--no-denoise, --no-reuse and --row-step need --mode path");
  if (wants_rtl(o.device) && s.mode != modes::Mode::kHw)
    throw InputError("--device rtl needs --mode hw (the RTL is the device)");
}

int run_run(const RunCommandOptions& o) {
  check_options(o);
  frontend::AppConfig c = o.app;
  modes::SourceConfig& s = c.source;
  const bool hw = s.mode == modes::Mode::kHw;
  s.board.preset = load_preset(o.preset, o.workers, -1, hw ? o.spp : 0, hw ? o.depth : 0);
  if (hw) s.board.make_device = device_maker(o.device, s.board.preset, s.board.wire);
  if (!hw) s.max_depth = o.depth;
  c.scene = load_scene(o.scene);
  const frontend::LatencyStats latency = frontend::run_window(std::move(c), {o.scale, o.frames});
  if (latency.samples > 0)
    std::fprintf(stderr, "key-to-photon latency: mean %.1f ms, max %.1f ms over %d key presses\n", latency.mean_ms,
                 latency.max_ms, latency.samples);
  return kExitOk;
}

}  // namespace

void add_run_command(CLI::App& app, Action& run) {
  auto o = std::make_shared<RunCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "run",
      "Open a window that shows the board's VGA monitor live; the keyboard drives the host's camera.\n"
      "Keys: W/S forward/back, A/D left/right, I/K look up/down, J/L look left/right, Q/E orbit the target,\n"
      "R reset, Tab figures, H help, N denoiser on/off (path mode), F12 screenshot (PNG in --screenshot-dir), Esc or\n"
      "closing the window quits. Tab shows frames per second and frame time; in hw mode late lines, link bytes and\n"
      "saturations, and with a path preset the samples per pixel accumulated and the device's workers; in path mode\n"
      "samples per pixel and whether the denoiser is on. Path mode keeps earlier frames while the camera moves\n"
      "(reprojected through the depth buffer) and filters the picture (docs/denoiser.md).");
  add_scene_option(*cmd, o->scene);
  add_mode_option(*cmd, o->app.source.mode,
                  "hw: every camera change goes host -> link -> device -> VGA capture (with a path preset the\n"
                  "device accumulates samples while the camera is still); normal: the float reference;\n"
                  "path: the float path tracer, refining while the camera is still");
  add_preset_option(*cmd, o->preset, "hw; path path-traces, and accumulates in frame memory while the camera is still");
  cmd->add_option("--spp", o->spp,
                  "--mode hw --preset path or artix-path: samples per pixel the device adds each frame, 1..255 (default 1; a pixel "
                  "stops at 255)")
      ->check(CLI::Range(1, 255));
  cmd->add_option("--depth", o->depth,
                  "--mode hw --preset path or artix-path: rays per path on the device, 1..16 (default 4); --mode path: most bounces "
                  "along one path (default: the scene's render.max_depth)")
      ->check(CLI::Range(1, scene::kMaxDepth));
  cmd->add_option("--workers", o->workers,
                  "Number of device workers (the artix preset's sphere units; default: the preset's)")
      ->check(CLI::Range(1, 640));
  add_wire_option(*cmd, o->app.source.board.wire);
  add_device_option(*cmd, o->device);
  cmd->add_option("--scale", o->scale, "Window size as a multiple of 640x480")->capture_default_str()->check(CLI::Range(1, 8));
  cmd->add_option("--screenshot-dir", o->app.screenshot_dir, "Where F12 writes tripsitter-N.png")->capture_default_str();
  cmd->add_option("--seed", o->app.source.seed, "path: random seed")->capture_default_str();
  cmd->add_option("--threads", o->app.source.threads, "normal and path modes: worker threads (default: all)")->check(CLI::Range(1, 1024));
  cmd->add_option("--frames", o->frames, "Quit after this many frames (default: run until Esc)");
  cmd->add_flag("!--no-denoise", o->app.source.denoise, "path: start with the denoiser off (N turns it on)");
  cmd->add_flag("!--no-reuse", o->app.source.reuse, "path: start over at every camera move instead of reprojecting earlier frames");
  cmd->add_option("--row-step", o->app.source.row_step,
                  "path: trace paths on 1 row of every N per frame, the rest carried by earlier frames (faster frames, "
                  "more lag)")
      ->capture_default_str()->check(CLI::Range(1, 8));
  cmd->callback([o, &run] { run = [o] { return run_run(*o); }; });
}

}  // namespace tripsitter::cmd

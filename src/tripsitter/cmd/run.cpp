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

struct RunCommandOptions {
  std::string scene = "demo";
  std::string mode = "hw";
  std::string preset = "wide";
  int workers = 0;
  link::WireVersion wire = link::WireVersion::kV3;
  int scale = 1;
  std::string screenshot_dir = ".";
  std::uint64_t seed = 1;
  int threads = 0;
  std::uint64_t frames = 0;
  int spp = 0;    // 0: not given
  int depth = 0;
  bool denoise = true;
  bool reuse = true;
  int row_step = 1;
  DeviceChoice device;
};

int run_run(const RunCommandOptions& o) {
  frontend::AppConfig c;
  c.mode = parse_mode(o.mode);
  c.wire = o.wire;
  const bool hw = c.mode == modes::Mode::kHw;
  if (c.mode == modes::Mode::kNormal && (o.spp != 0 || o.depth != 0))
    throw InputError("--spp and --depth need --mode hw with --preset path, or --mode path (normal traces one ray per pixel)");
  if (c.mode == modes::Mode::kPath && o.spp != 0)
    throw InputError("--spp: the window's --mode path adds one sample per pixel per frame while the camera is still; "
                     "--spp sets the device's samples per frame with --mode hw --preset path");
  if (c.mode != modes::Mode::kPath && (!o.denoise || !o.reuse || o.row_step != 1))
    throw InputError("--no-denoise, --no-reuse and --row-step need --mode path");
  if (wants_rtl(o.device) && !hw) throw InputError("--device rtl needs --mode hw (the RTL is the device)");
  c.preset = load_preset(o.preset, o.workers, -1, hw ? o.spp : 0, hw ? o.depth : 0);
  if (hw) c.make_device = device_maker(o.device, c.preset, c.wire);
  if (!hw) c.max_depth = o.depth;
  c.scene = load_scene(o.scene);
  c.screenshot_dir = o.screenshot_dir;
  c.seed = o.seed;
  c.threads = o.threads;
  c.denoise = o.denoise;
  c.reuse = o.reuse;
  c.row_step = o.row_step;
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
      "saturations, and with --preset path the samples per pixel accumulated and the device's workers; in path mode\n"
      "samples per pixel and whether the denoiser is on. Path mode keeps earlier frames while the camera moves\n"
      "(reprojected through the depth buffer) and filters the picture (docs/denoiser.md).");
  add_scene_option(*cmd, o->scene);
  cmd->add_option("--mode", o->mode,
                  "hw: every camera change goes host -> link -> device -> VGA capture (with --preset path the\n"
                  "device accumulates samples while the camera is still); normal: the float reference;\n"
                  "path: the float path tracer, refining while the camera is still")
      ->capture_default_str();
  add_preset_option(*cmd, o->preset, "hw; path path-traces, and accumulates in frame memory while the camera is still");
  cmd->add_option("--spp", o->spp,
                  "--mode hw --preset path: samples per pixel the device adds each frame, 1..255 (default 1; a pixel "
                  "stops at 255)")
      ->check(CLI::Range(1, 255));
  cmd->add_option("--depth", o->depth,
                  "--mode hw --preset path: rays per path on the device, 1..16 (default 4); --mode path: most bounces "
                  "along one path (default: the scene's render.max_depth)")
      ->check(CLI::Range(1, scene::kMaxDepth));
  cmd->add_option("--workers", o->workers,
                  "Number of device workers (the artix preset's sphere units; default: the preset's)")
      ->check(CLI::Range(1, 640));
  add_wire_option(*cmd, o->wire);
  add_device_option(*cmd, o->device);
  cmd->add_option("--scale", o->scale, "Window size as a multiple of 640x480")->capture_default_str()->check(CLI::Range(1, 8));
  cmd->add_option("--screenshot-dir", o->screenshot_dir, "Where F12 writes tripsitter-N.png")->capture_default_str();
  cmd->add_option("--seed", o->seed, "path: random seed")->capture_default_str();
  cmd->add_option("--threads", o->threads, "normal and path modes: worker threads (default: all)")->check(CLI::Range(1, 1024));
  cmd->add_option("--frames", o->frames, "Quit after this many frames (default: run until Esc)");
  cmd->add_flag("!--no-denoise", o->denoise, "path: start with the denoiser off (N turns it on)");
  cmd->add_flag("!--no-reuse", o->reuse, "path: start over at every camera move instead of reprojecting earlier frames");
  cmd->add_option("--row-step", o->row_step,
                  "path: trace paths on 1 row of every N per frame, the rest carried by earlier frames (faster frames, "
                  "more lag)")
      ->capture_default_str()->check(CLI::Range(1, 8));
  cmd->callback([o, &run] { run = [o] { return run_run(*o); }; });
}

}  // namespace tripsitter::cmd

// tripsitter device: the FPGA and its monitor as a program, fed by a host over TCP.
#include <chrono>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <memory>

#include <tripsitter/device/device.h>
#include <tripsitter/display/png.h>
#include <tripsitter/frontend/window.h>
#include <tripsitter/transport/stream.h>

#include "commands.h"
#include "common.h"
#include "options.h"
#include "device_choice.h"
#include "device_loop.h"

namespace tripsitter::cmd {
namespace {

struct DeviceOptions {
  std::string listen;
  bool headless = false;
  std::string out_dir;
  std::string preset = "wide";
  int workers = 0;
  int spp = 0;    // path-tracing preset: 0 not given
  int depth = 0;
  link::WireVersion wire = link::WireVersion::kV3;
  std::uint64_t frames = 0;
  int scale = 1;
  double host_timeout_s = std::chrono::duration<double>(transport::StreamPort::kDefaultStallTimeout).count();
  DeviceChoice device;
};

// The monitor as a window. The keyboard belongs to the host program; here Esc or closing the window stops
// the device, Tab shows the device's figures and F12 saves the frame shown.
class WindowFrameSink : public FrameSink {
 public:
  explicit WindowFrameSink(int scale) : window_("TripSitter device", scale) {}

  bool show(const core::Image444& image, const FrameInfo& info) override {
    for (const frontend::PolledInput& p : window_.poll()) {
      switch (p.input.kind) {
        case frontend::Input::Kind::kQuit: return false;
        case frontend::Input::Kind::kToggleOverlay: overlay_ = !overlay_; break;
        case frontend::Input::Kind::kScreenshot: screenshot(image); break;
        default: break;
      }
    }
    std::vector<std::string> lines;
    if (overlay_) {
      lines.push_back("frame " + std::to_string(info.frame));
      lines.push_back(info.stats.has_world ? "world " + std::to_string(info.stats.sequence) : "no world yet");
      lines.push_back("late lines " + std::to_string(info.stats.late_lines));
      // A path-tracing device accumulates while the host sends worlds of the same content.
      if (info.stats.samples_per_pixel > 0)
        lines.push_back(std::to_string(info.stats.samples_per_pixel) + " samples per pixel");
    }
    window_.present(core::to_rgb8(image), ++serial_, lines);
    return true;
  }

 private:
  void screenshot(const core::Image444& image) {
    std::filesystem::path path;
    do {
      path = "tripsitter-device-" + std::to_string(++screenshots_) + ".png";
    } while (std::filesystem::exists(path));
    const auto written = display::write_png(path.string(), image);
    std::cerr << (written ? "screenshot written to " + path.string() : written.error().message) << "\n";
  }

  frontend::Window window_;
  bool overlay_ = false;
  std::uint64_t serial_ = 0;
  int screenshots_ = 0;
};

volatile std::sig_atomic_t g_stop = 0;

extern "C" void on_stop_signal(int) { g_stop = 1; }

// SIGINT and SIGTERM end the loop after the frame being drawn; SIGPIPE never ends the program.
void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: a sleeping poll() wakes up
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
}

void print_receiver(const device::ReceiverStats& rx) {
  std::cerr << rx.worlds_accepted << " worlds accepted, " << rx.worlds_missing << " missing (lost on the link), "
            << rx.worlds_replayed << " replayed, " << rx.frames_rejected << " rejected, " << rx.garbage_runs
            << " runs of garbage, " << rx.bytes_dropped << " bytes dropped";
  if (!rx.last_error.empty()) std::cerr << " (last error: " << rx.last_error << ")";
}

int run_device(const DeviceOptions& o) {
  if (o.headless && o.out_dir.empty()) throw InputError("--headless needs --out-dir DIR, where the frames go");
  if (!o.headless && !o.out_dir.empty()) throw InputError("--out-dir goes with --headless (the window shows the frames)");
  const link::WireVersion wire = o.wire;
  const device::DevicePreset preset = load_preset(o.preset, o.workers, -1, o.spp, o.depth);
  auto address = transport::parse_stream_address(o.listen);
  if (!address) throw InputError("--listen: " + address.error().message);
  if (o.headless) {
    std::error_code ec;
    std::filesystem::create_directories(o.out_dir, ec);
    if (ec || !std::filesystem::is_directory(o.out_dir))
      throw InputError("--out-dir " + o.out_dir + ": cannot create the directory" + (ec ? ": " + ec.message() : ""));
  }

  const auto make_rtl = device_maker(o.device, preset, wire);
  const std::unique_ptr<device::Backend> device = make_rtl ? make_rtl() : std::make_unique<device::Device>(preset, wire);
  device::Backend& dev = *device;
  auto port = transport::StreamPort::listen(address.value(), [&dev](const transport::StreamPortEvent& e) {
    using Kind = transport::StreamPortEvent::Kind;
    switch (e.kind) {
      case Kind::kConnected:
        std::cerr << "device: host " << e.peer << " connected\n";
        break;
      case Kind::kDisconnected:
        std::cerr << "device: host " << e.peer << " went away (" << e.detail << ") after " << e.bytes << " bytes; "
                  << (dev.has_world() || !dev.ready() ? "the last good world stays on screen" : "no world yet")
                  << "; receiver so far: ";
        print_receiver(dev.receiver_stats());
        std::cerr << "\n";
        break;
      case Kind::kRefused:
        std::cerr << "device: refused host " << e.peer << ": " << e.detail << " (one host at a time)\n";
        break;
      case Kind::kError:
        std::cerr << "device: " << e.detail << "\n";
        break;
    }
  }, std::chrono::milliseconds(static_cast<std::int64_t>(o.host_timeout_s * 1000)));
  if (!port) throw InputError(port.error().message);
  install_signal_handlers();
  std::cerr << "listening on " << port.value().address().to_string() << std::endl;
  std::cerr << "device: preset " << preset.name;
  if (preset.path)
    std::cerr << " (" << preset.path->spp << " samples per pixel per frame, " << preset.path->depth
              << " rays per path, accumulated while the world's content stays the same)";
  std::cerr << ", wire " << link::wire_name(o.wire) << ", " << 1.0 / kVgaFrameSeconds << " frames/s; "
            << (o.headless ? "writing each frame that shows a new world to " +
                                 (std::filesystem::path(o.out_dir) / "frame_NNNNNN.png").string()
                           : std::string("showing the frames in a window"))
            << "\n";

  std::unique_ptr<PngFrameSink> png;
  std::unique_ptr<WindowFrameSink> window;
  FrameSink* sink = nullptr;
  if (o.headless) {
    sink = (png = std::make_unique<PngFrameSink>(o.out_dir)).get();
  } else {
    try {
      sink = (window = std::make_unique<WindowFrameSink>(o.scale)).get();
    } catch (const std::runtime_error& e) {
      throw InputError(std::string(e.what()) + " (without a display, use --headless --out-dir DIR)");
    }
  }
  const auto started = std::chrono::steady_clock::now();
  const DeviceLoopResult r = run_device_loop(dev, port.value(), *sink, {o.frames, kVgaFrameSeconds}, g_stop);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::cerr << "device: " << r.frames << " frames drawn (" << r.late_frames << " late) in " << seconds << " s ("
            << (seconds > 0 ? static_cast<double>(r.frames) / seconds : 0.0) << " frames/s), " << r.new_worlds
            << " new worlds shown";
  if (png) std::cerr << ", " << png->written() << " files written";
  std::cerr << "; receiver: ";
  print_receiver(dev.receiver_stats());
  std::cerr << "; hosts: " << port.value().stats().hosts_served << " served, " << port.value().stats().hosts_refused
            << " refused\n";
  if (png && !png->error().empty()) {
    std::cerr << "tripsitter: " << png->error() << "\n";
    return kExitInternal;
  }
  return kExitOk;
}

}  // namespace

void add_device_command(CLI::App& app, Action& run) {
  auto o = std::make_shared<DeviceOptions>();
  CLI::App* cmd = app.add_subcommand("device", "The device (FPGA) and its monitor as a program, fed by a host over TCP");
  cmd->footer(
      "Listens for one host at a time and draws frames at the VGA rate (59.5 frames/s) in real time. A host\n"
      "that goes away leaves its last good world on screen; a second host while one is served is refused (it\n"
      "is told the device is busy); one that sends bytes but completes no world for --host-timeout seconds is\n"
      "dropped. Stops cleanly (exit 0) on SIGINT or SIGTERM, or after --frames. The protocol:\n"
      "docs/link_format.md, \"Over a byte stream\".\n"
      "With --preset path or artix-path the device path-traces the host's worlds and accumulates them in frame memory while the\n"
      "worlds the host sends keep the same content (a host sends its view every tick, so a still camera\n"
      "refines); a world of other content starts over. Headless, each frame that shows a new world is\n"
      "written: while a host with a still camera runs (a script's 'wait'), the files show the samples growing.");
  cmd->add_option("--listen", o->listen, "Address to listen on, HOST:PORT (port 0: any free port; the port is "
                                         "printed on stderr as 'listening on HOST:PORT')")
      ->required();
  cmd->add_flag("--headless", o->headless,
                "No window: write each frame that shows a new world to --out-dir as frame_NNNNNN.png, NNNNNN "
                "the frame number");
  cmd->add_option("--out-dir", o->out_dir, "Directory for the frames (--headless); created if missing");
  add_preset_option(*cmd, o->preset);
  cmd->add_option("--workers", o->workers,
                  "Number of device workers (the artix preset's sphere units), 1..640 (default: the preset's)")
      ->check(CLI::Range(1, 640));
  add_device_option(*cmd, o->device);
  cmd->add_option("--spp", o->spp,
                  "--preset path or artix-path: samples per pixel added to frame memory each frame, 1..255 (default 1; a pixel "
                  "stops at 255)")
      ->check(CLI::Range(1, 255));
  cmd->add_option("--depth", o->depth, "--preset path or artix-path: rays per path, 1..16 (default 4)")->check(CLI::Range(1, 16));
  add_wire_option(*cmd, o->wire, "the one the host speaks");
  cmd->add_option("--frames", o->frames, "Stop after this many frames (default: run until SIGINT or SIGTERM)");
  cmd->add_option("--host-timeout", o->host_timeout_s,
                  "Seconds a host may send bytes without completing a world before it is dropped and the next "
                  "host served (a host sending one byte a second, or bytes of another wire)")
      ->capture_default_str()->check(CLI::Range(0.1, 3600.0));
  cmd->add_option("--scale", o->scale, "Window size as a multiple of 640x480 (without --headless)")
      ->capture_default_str()->check(CLI::Range(1, 8));
  cmd->callback([o, &run] { run = [o] { return run_device(*o); }; });
}

}  // namespace tripsitter::cmd

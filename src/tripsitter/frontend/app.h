// The interactive board: what `tripsitter run` shows and how the keyboard drives it, apart from SDL so
// that tests can drive it with synthetic input. The window (window.h) only turns SDL events into Input
// and puts frame() on the screen.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <tripsitter/core/image.h>
#include <tripsitter/host/controls.h>
#include <tripsitter/modes/frame_source.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::frontend {

using modes::Mode;

// The window's frame source before any option: the denoiser on (N toggles it) and the scene's depth.
modes::SourceConfig window_source();

struct AppConfig {
  scene::Scene scene;
  // The mode, the board (hw), threads, and in path mode the seed, the denoiser, reuse and row_step. App always
  // draws 640x480, progressively; a max_depth of 0 is the scene's render.max_depth.
  modes::SourceConfig source = window_source();
  std::string screenshot_dir = ".";
  host::ControlSpeeds speeds;
};

struct Input {
  enum class Kind { kKeyDown, kKeyUp, kScreenshot, kToggleOverlay, kToggleHelp, kToggleDenoise, kQuit };
  Kind kind;
  host::Key key = host::Key::kW;  // for key events
};

// Figures for the overlay (Tab).
struct FrameInfo {
  double fps = 0;            // frames made per second over the last half second
  double frame_ms = 0;       // time to produce the last frame
  std::size_t spheres = 0;
  int late_lines = 0;        // hw: lines of the last frame with late pixels
  std::size_t link_bytes = 0;
  double link_ms = 0;        // at the SPI clock
  std::uint64_t saturations = 0;
  int samples = 0;           // path, and hw with a path-tracing device: samples per pixel accumulated in the frame shown
                             // (path: frames since the camera last moved)
  double mean_samples = 0;   // path: samples per pixel in the picture, mean (reprojected history included)
  bool denoise = false;      // path: the denoiser is on
  bool device_path = false;  // hw: the device path-traces (a path-tracing preset fed v2 worlds)
  int workers = 0;           // hw: the device's workers
};

class App {
 public:
  explicit App(AppConfig config);

  void handle(const Input& input);
  // Moves the camera by `dt_s` seconds of the keys held, and makes the next frame when the camera changed, or
  // while the picture still refines (path: one more sample per pixel while the camera is still).
  void advance(double dt_s);

  // The frame on screen, 640x480, 8 bits per channel (12-bit frames expanded).
  const core::ImageRgb8& frame() const;
  const FrameInfo& info() const { return info_; }
  bool quit() const { return quit_; }
  bool overlay() const { return overlay_; }
  bool help() const { return help_; }
  // Where the last F12 wrote, or why it could not; cleared by the call.
  std::optional<std::string> take_message();
  // Increases every time the frame changes (so the window knows when to upload it).
  std::uint64_t frame_serial() const { return serial_; }

  static constexpr int kWidth = 640;
  static constexpr int kHeight = 480;

 private:
  void render_frame();
  void screenshot();

  AppConfig config_;
  std::unique_ptr<modes::FrameSource> source_;  // owns the host camera the keys move
  const modes::Frame* shown_ = nullptr;         // the source's last frame
  std::array<bool, 11> held_{};
  bool dirty_ = true;   // the camera or world changed since the last frame
  bool quit_ = false, overlay_ = false, help_ = false;
  core::ImageRgb8 expanded_;                    // hw and normal: the 12-bit frame in 8 bits per channel
  std::uint64_t serial_ = 0;
  int screenshots_ = 0;
  std::optional<std::string> message_;
  FrameInfo info_;
  double fps_window_s_ = 0;
  int frames_in_window_ = 0;
};

}  // namespace tripsitter::frontend

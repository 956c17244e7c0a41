#include <tripsitter/frontend/app.h>

#include <chrono>
#include <filesystem>

#include <tripsitter/display/png.h>

namespace tripsitter::frontend {
namespace {

double ms_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

App::App(AppConfig config) : config_(std::move(config)) {
  modes::SourceConfig c;
  c.mode = config_.mode;
  c.preset = config_.preset;
  c.wire = config_.wire;
  c.make_device = config_.make_device;
  c.width = kWidth;
  c.height = kHeight;
  c.threads = config_.threads;
  c.max_depth = config_.max_depth > 0 ? config_.max_depth : config_.scene.render.max_depth;
  c.seed = config_.seed;
  c.progressive = true;
  c.denoise = config_.denoise;
  c.reuse = config_.reuse;
  c.row_step = config_.row_step;
  source_ = modes::make_frame_source(config_.scene, c);
  info_.spheres = config_.scene.spheres.size();
  info_.device_path = config_.mode == Mode::kHw && device::traces_paths(config_.preset, config_.wire);
  info_.workers = config_.preset.workers;
  render_frame();
}

void App::handle(const Input& input) {
  switch (input.kind) {
    case Input::Kind::kKeyDown:
      if (input.key == host::Key::kR) {
        source_->reset();
        dirty_ = true;
      } else {
        held_[static_cast<std::size_t>(input.key)] = true;
      }
      break;
    case Input::Kind::kKeyUp: held_[static_cast<std::size_t>(input.key)] = false; break;
    case Input::Kind::kScreenshot: screenshot(); break;
    case Input::Kind::kToggleOverlay: overlay_ = !overlay_; break;
    case Input::Kind::kToggleHelp: help_ = !help_; break;
    case Input::Kind::kToggleDenoise:
      // Only a source with a denoiser (path mode) takes it; the picture is redrawn with or without.
      if (source_->set_denoise(!source_->denoise())) dirty_ = true;
      break;
    case Input::Kind::kQuit: quit_ = true; break;
  }
}

void App::advance(double dt_s) {
  for (std::size_t k = 0; k < held_.size(); ++k) {
    if (!held_[k]) continue;
    host::apply_held_key(source_->steer(), static_cast<host::Key>(k), dt_s, config_.speeds);
    dirty_ = true;
  }
  if (dirty_ || source_->refining()) {
    render_frame();
    ++frames_in_window_;
  }
  // Frames made per second, over windows of half a second (0 while nothing changes).
  fps_window_s_ += dt_s;
  if (fps_window_s_ >= 0.5) {
    info_.fps = frames_in_window_ / fps_window_s_;
    fps_window_s_ = 0;
    frames_in_window_ = 0;
  }
}

void App::render_frame() {
  const auto start = std::chrono::steady_clock::now();
  const modes::Frame& frame = source_->draw();
  shown_ = &frame;
  if (!frame.vga.pixels.empty()) expanded_ = core::to_rgb8(frame.vga);
  info_.late_lines = frame.device.late_lines;
  info_.link_bytes = frame.link_bytes;
  info_.link_ms = frame.link_seconds * 1e3;
  info_.saturations = frame.saturations.total();
  info_.samples = frame.samples;
  info_.mean_samples = frame.mean_samples;
  info_.denoise = source_->denoise();
  dirty_ = false;
  ++serial_;
  info_.frame_ms = ms_since(start);
}

void App::screenshot() {
  namespace fs = std::filesystem;
  fs::path path;
  do {
    path = fs::path(config_.screenshot_dir) / ("tripsitter-" + std::to_string(++screenshots_) + ".png");
  } while (fs::exists(path));
  const auto written = modes::write_png(path.string(), *shown_);
  message_ = written ? "screenshot written to " + path.string() : written.error().message;
}

std::optional<std::string> App::take_message() { return std::exchange(message_, std::nullopt); }

}  // namespace tripsitter::frontend

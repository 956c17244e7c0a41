#include <tripsitter/frontend/app.h>

#include <chrono>
#include <filesystem>

#include <tripsitter/display/png.h>

namespace tripsitter::frontend {
namespace {

double ms_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// The overlay's figures of an hw frame: the device's late lines, the link's cost, the host's saturations and,
// with a path-tracing preset, the samples in frame memory.
void take_figures(const modes::HwFrame& f, FrameInfo& info) {
  info.late_lines = f.device.late_lines;
  info.link_bytes = f.link_bytes;
  info.link_ms = f.link_seconds * 1e3;
  info.saturations = f.saturations.total();
  info.samples = f.samples;
}

// The overlay's figures of a path frame: its samples per pixel.
void take_figures(const modes::PathFrame& f, FrameInfo& info) {
  info.samples = f.samples;
  info.mean_samples = f.mean_samples;
}

}  // namespace

modes::SourceConfig window_source() {
  modes::SourceConfig c;
  c.denoise = true;
  c.max_depth = 0;
  return c;
}

App::App(AppConfig config) : config_(std::move(config)) {
  modes::SourceConfig c = config_.source;
  c.width = kWidth;
  c.height = kHeight;
  if (c.max_depth == 0) c.max_depth = config_.scene.render.max_depth;
  c.progressive = true;
  source_ = modes::make_frame_source(config_.scene, c);
  const board::BoardConfig& board = c.board;
  info_.spheres = config_.scene.spheres.size();
  info_.device_path = c.mode == Mode::kHw && device::traces_paths(board.preset, board.wire);
  info_.workers = board.preset.workers;
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

const core::ImageRgb8& App::frame() const {
  if (const auto* path = std::get_if<modes::PathFrame>(shown_)) return path->rgb;
  return expanded_;
}

void App::render_frame() {
  const auto start = std::chrono::steady_clock::now();
  const modes::Frame& frame = source_->draw();
  shown_ = &frame;
  if (const auto* hw = std::get_if<modes::HwFrame>(&frame)) take_figures(*hw, info_);
  if (const auto* path = std::get_if<modes::PathFrame>(&frame))
    take_figures(*path, info_);
  else
    expanded_ = modes::rgb8(frame);
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
  const auto written = modes::write_image(path.string(), *shown_);
  message_ = written ? "screenshot written to " + path.string() : written.error().message;
}

std::optional<std::string> App::take_message() { return std::exchange(message_, std::nullopt); }

}  // namespace tripsitter::frontend

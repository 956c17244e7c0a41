#include <tripsitter/frontend/app.h>

#include <chrono>
#include <filesystem>

#include <tripsitter/display/png.h>
#include <tripsitter/render/normal.h>

namespace tripsitter::frontend {
namespace {

constexpr int kMaxPathSamples = 1024;  // path mode stops refining a still picture here

double ms_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

App::App(AppConfig config)
    : config_(std::move(config)), board_(config_.scene, {config_.preset, config_.wire, {}}) {
  if (config_.mode == Mode::kPath) path_scene_ = std::make_unique<render::PathScene>(config_.scene.spheres);
  info_.spheres = config_.scene.spheres.size();
  render_frame();
}

void App::handle(const Input& input) {
  switch (input.kind) {
    case Input::Kind::kKeyDown:
      if (input.key == host::Key::kR) {
        board_.host().reset();
        dirty_ = true;
      } else {
        held_[static_cast<std::size_t>(input.key)] = true;
      }
      break;
    case Input::Kind::kKeyUp: held_[static_cast<std::size_t>(input.key)] = false; break;
    case Input::Kind::kScreenshot: screenshot(); break;
    case Input::Kind::kToggleOverlay: overlay_ = !overlay_; break;
    case Input::Kind::kToggleHelp: help_ = !help_; break;
    case Input::Kind::kQuit: quit_ = true; break;
  }
}

void App::advance(double dt_s) {
  for (std::size_t k = 0; k < held_.size(); ++k) {
    if (!held_[k]) continue;
    host::apply_held_key(board_.host().camera(), static_cast<host::Key>(k), dt_s, config_.speeds);
    dirty_ = true;
  }
  if (dirty_ || (config_.mode == Mode::kPath && accumulated_spp_ < kMaxPathSamples)) {
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
  switch (config_.mode) {
    case Mode::kHw: {
      // Every camera change travels host -> link -> device -> VGA signal -> monitor.
      const board::ShownFrame shown = board_.show();
      frame444_ = shown.image;
      info_.late_lines = shown.device.late_lines;
      info_.link_bytes = shown.link_bytes;
      info_.link_ms = shown.link_seconds * 1e3;
      info_.saturations = shown.saturations.total();
      frame_ = core::to_rgb8(frame444_);
      break;
    }
    case Mode::kNormal: {
      const host::ReadyWorld& world = board_.host().update();
      frame444_ = render::render_normal_fast(world.view_spheres, kWidth, kHeight, config_.preset.max_bounces,
                                             config_.threads);
      info_.saturations = world.saturations.total();
      frame_ = core::to_rgb8(frame444_);
      break;
    }
    case Mode::kPath: {
      if (dirty_ || accumulated_spp_ == 0) {
        accumulated_ = {kWidth, kHeight, std::vector<render::Vec3f>(static_cast<std::size_t>(kWidth) * kHeight)};
        accumulated_spp_ = 0;
      }
      scene::CameraSettings cam = config_.scene.camera;
      cam.lookfrom = board_.host().camera().position();
      cam.lookat = board_.host().camera().target();
      render::PathSettings s{.width = kWidth, .height = kHeight, .spp = 1,
                             .max_depth = config_.scene.render.max_depth,
                             .seed = config_.seed + static_cast<std::uint64_t>(accumulated_spp_),
                             .threads = config_.threads, .sky = {}};
      if (pass_.pixels.size() != accumulated_.pixels.size()) pass_ = accumulated_;
      if (frame_.width != kWidth || frame_.height != kHeight) frame_ = core::ImageRgb8(kWidth, kHeight);
      ++accumulated_spp_;
      const float scale = 1.0f / static_cast<float>(accumulated_spp_);
      // Each row is added to the sum and encoded by the thread that traced it, while it is in cache.
      render::render_path_rows(*path_scene_, render::ThinLensCamera(cam, kWidth, kHeight), s, 0, 1, pass_, [&](int row) {
        const std::size_t first = static_cast<std::size_t>(row) * kWidth;
        for (std::size_t i = first; i < first + kWidth; ++i) accumulated_.pixels[i] += pass_.pixels[i];
        render::encode_srgb8(&accumulated_.pixels[first], kWidth, scale, &frame_.pixels[3 * first]);
      });
      info_.samples = accumulated_spp_;
      break;
    }
  }
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
  const auto written = config_.mode == Mode::kPath ? display::write_png(path.string(), frame_)
                                                   : display::write_png(path.string(), frame444_);
  message_ = written ? "screenshot written to " + path.string() : written.error().message;
}

std::optional<std::string> App::take_message() { return std::exchange(message_, std::nullopt); }

}  // namespace tripsitter::frontend

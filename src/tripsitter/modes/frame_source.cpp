#include <tripsitter/modes/frame_source.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

#include <tripsitter/board/board.h>
#include <tripsitter/core/colour.h>
#include <tripsitter/display/png.h>
#include <tripsitter/host/view.h>
#include <tripsitter/render/camera.h>
#include <tripsitter/render/denoise.h>
#include <tripsitter/render/normal.h>

namespace tripsitter::modes {
namespace {

host::Camera initial_camera(const scene::CameraSettings& c) { return host::Camera(c.lookfrom, c.lookat, c.vup); }

// hw: every frame travels host -> link -> device -> VGA signal -> monitor.
class HwSource final : public FrameSource {
 public:
  HwSource(const scene::Scene& scene, const SourceConfig& c)
      : FrameSource(Mode::kHw),
        board_(scene, c.board),
        probe_(c.probe),
        accumulates_(device::traces_paths(c.board.preset, c.board.wire)),
        spp_(c.board.preset.path ? c.board.preset.path->spp : 0) {}

  const host::Camera& camera() const override { return board_.host().camera(); }
  host::Camera& steer() override { return board_.host().camera(); }
  void reset() override { board_.host().reset(); }

  const Frame& draw() override {
    board::ShownFrame shown = board_.show(probe_);
    HwFrame& f = std::get<HwFrame>(frame_);
    f.vga = std::move(shown.image);
    f.device = shown.device;
    f.saturations = shown.saturations;
    f.link_bytes = shown.link_bytes;
    f.link_seconds = shown.link_seconds;
    f.spheres_dropped = shown.spheres_dropped;
    f.samples = shown.device.samples_per_pixel;
    f.scene_memory = board_.device().scene_memory();
    f.frame_memory = board_.device().frame_memory();
    return frame_;
  }
  // The path preset accumulates while the host sends worlds of the same content, until frame memory is full.
  bool refining() const override {
    const HwFrame& f = std::get<HwFrame>(frame_);
    return accumulates_ && f.device.has_world && f.samples + spp_ <= device::kMaxSamples;
  }

 private:
  board::Board board_;
  std::function<void(const device::VgaSample&)> probe_;
  const bool accumulates_;  // a path-tracing preset fed v2 worlds (v1 words are normal-shaded)
  const int spp_;           // samples per pixel per frame
  Frame frame_ = HwFrame{};
};

// normal: the host's view of the world the device would hold, in double, nothing encoded.
class NormalSource final : public FrameSource {
 public:
  NormalSource(const scene::Scene& scene, const SourceConfig& c)
      : FrameSource(Mode::kNormal),
        scene_(scene),
        camera_(initial_camera(scene.camera)),
        units_per_world_(host::units_per_world(scene)),
        carried_(host::spheres_carried(scene.spheres.size(), board::formats_of(c.board.preset), c.board.wire)),
        config_(c) {}

  const host::Camera& camera() const override { return camera_; }
  host::Camera& steer() override { return camera_; }
  void reset() override { camera_ = initial_camera(scene_.camera); }

  const Frame& draw() override {
    const std::vector<scene::Sphere> view =
        host::view_spheres(std::span(scene_.spheres).first(carried_), camera_, units_per_world_);
    std::get<NormalFrame>(frame_).vga =
        render::render_normal_fast(view, config_.width, config_.height, config_.board.preset.max_bounces, config_.threads);
    return frame_;
  }

 private:
  const scene::Scene scene_;
  host::Camera camera_;
  double units_per_world_;
  std::size_t carried_;
  SourceConfig config_;
  Frame frame_ = NormalFrame{};
};

// path: the path tracer from the scene's camera, or from the host camera once it has been steered. Two sources
// share this: the window's progressive one and the stills' one.
class PathSource : public FrameSource {
 public:
  const host::Camera& camera() const override { return camera_; }
  host::Camera& steer() override {
    steered_ = true;
    return camera_;
  }
  void reset() override {
    camera_ = initial_camera(camera_settings_);
    steered_ = false;
  }
  bool set_denoise(bool on) override {
    config_.denoise = on;
    return true;
  }
  bool denoise() const override { return config_.denoise; }

 protected:
  PathSource(const scene::Scene& scene, const SourceConfig& c)
      : FrameSource(Mode::kPath),
        path_scene_(scene.spheres),
        config_(c),
        camera_settings_(scene.camera),
        camera_(initial_camera(scene.camera)) {}

  render::ThinLensCamera lens() const {
    scene::CameraSettings c = camera_settings_;
    if (steered_) {
      c.lookfrom = camera_.position();
      c.lookat = camera_.target();
    }
    return render::ThinLensCamera(c, config_.width, config_.height);
  }
  PathFrame& path_frame() { return std::get<PathFrame>(frame_); }
  const PathFrame& path_frame() const { return std::get<PathFrame>(frame_); }

  const render::PathScene path_scene_;
  SourceConfig config_;
  Frame frame_ = PathFrame{};

 private:
  const scene::CameraSettings camera_settings_;
  host::Camera camera_;
  bool steered_ = false;  // the picture is seen from camera_, not from the scene's camera
};

// The window refines a still picture for this many frames after the camera stops.
constexpr int kMaxProgressiveSamples = 1024;

// The window's path source: each draw is one more pass of render/interactive.h's loop, samples reprojected
// while the camera moves, accumulated while it is still, and filtered.
class ProgressivePathSource final : public PathSource {
 public:
  ProgressivePathSource(const scene::Scene& scene, const SourceConfig& c)
      : PathSource(scene, c), interactive_(path_scene_, path_settings(c), interactive_settings(c)) {}

  host::Camera& steer() override {
    moved_ = true;
    return PathSource::steer();
  }
  void reset() override {
    PathSource::reset();
    moved_ = true;
    interactive_.restart();
  }
  bool set_denoise(bool on) override {
    interactive_.set_denoise(on);
    return PathSource::set_denoise(on);
  }
  bool refining() const override { return path_frame().samples < kMaxProgressiveSamples; }

  const Frame& draw() override {
    PathFrame& f = path_frame();
    f.linear = interactive_.frame(lens());
    f.rgb = core::to_srgb8(f.linear);
    f.aovs = &interactive_.aovs();
    still_frames_ = moved_ ? 1 : std::min(still_frames_ + 1, kMaxProgressiveSamples);
    moved_ = false;
    f.samples = still_frames_;
    f.mean_samples = interactive_.mean_samples();
    return frame_;
  }

 private:
  static render::InteractiveSettings interactive_settings(const SourceConfig& c) {
    render::InteractiveSettings s;
    s.denoise = c.denoise;
    s.reuse = c.reuse;
    s.row_step = c.row_step;
    return s;
  }

  bool moved_ = true;     // the camera moved since the last draw
  int still_frames_ = 0;  // draws since the camera last moved
  render::InteractivePath interactive_;
};

// The stills' path source (render, animations): each draw is a whole picture at config.spp samples per pixel,
// filtered with its own feature buffers when asked (render::denoised_still).
class StillPathSource final : public PathSource {
 public:
  StillPathSource(const scene::Scene& scene, const SourceConfig& c) : PathSource(scene, c) {}

  const Frame& draw() override {
    const render::PathSettings s = path_settings(config_);
    const bool keeps_aovs = config_.aovs || config_.denoise;
    if (keeps_aovs) aovs_ = render::Aovs(s.width, s.height);
    PathFrame& f = path_frame();
    if (config_.denoise) {
      f.linear = render::denoised_still(s, [this](const render::PathSettings& part, render::Aovs* aovs) {
        return trace(part, aovs);
      }, denoiser_, aovs_);
    } else {
      f.linear = trace(s, keeps_aovs ? &aovs_ : nullptr);
    }
    f.rgb = core::to_srgb8(f.linear);
    f.aovs = keeps_aovs ? &aovs_ : nullptr;
    f.samples = s.spp;
    f.mean_samples = s.spp;
    return frame_;
  }

 private:
  core::ImageRgbF trace(const render::PathSettings& s, render::Aovs* aovs) const {
    return config_.trace ? config_.trace(path_scene_, lens(), s, config_.on_samples, aovs)
                         : render::render_path(path_scene_, lens(), s, config_.on_samples, aovs);
  }

  render::Denoiser denoiser_;  // kept, so that an animation's frames reuse its scratch planes
  render::Aovs aovs_;
};

// The 12-bit picture of an hw or a normal frame.
const core::Image444& picture_444(const Frame& frame) {
  if (const auto* hw = std::get_if<HwFrame>(&frame)) return hw->vga;
  return std::get<NormalFrame>(frame).vga;
}

}  // namespace

render::PathSettings path_settings(const SourceConfig& c) {
  render::PathSettings s{.width = c.width, .height = c.height, .spp = c.spp, .max_depth = c.max_depth, .seed = c.seed,
                         .threads = c.threads, .sky = {}};
  s.sampler = c.sampler;
  return s;
}

core::ImageRgb8 rgb8(const Frame& frame) {
  if (const auto* path = std::get_if<PathFrame>(&frame)) return path->rgb;
  return core::to_rgb8(picture_444(frame));
}

PictureSize picture_size(const Frame& frame) {
  if (const auto* path = std::get_if<PathFrame>(&frame)) return {path->rgb.width, path->rgb.height};
  const core::Image444& vga = picture_444(frame);
  return {vga.width, vga.height};
}

core::Result<bool, display::IoError> write_image(const std::string& path, const Frame& frame, display::ExrPixel pixel) {
  const auto* f = std::get_if<PathFrame>(&frame);
  if (f == nullptr && display::is_exr(path))
    return display::IoError{"cannot write EXR '" + path + "': a 12-bit picture has no linear light"};
  if (f == nullptr) return display::write_png(path, picture_444(frame));
  display::ImageLayers layers{.rgb = f->rgb, .linear = f->linear};
  if (f->aovs != nullptr) {
    layers.albedo = f->aovs->albedo;
    layers.normal = f->aovs->normal;
    layers.depth = f->aovs->depth;
  }
  return display::write_image(path, layers, pixel);
}

std::unique_ptr<FrameSource> make_frame_source(const scene::Scene& scene, const SourceConfig& config) {
  switch (config.mode) {
    case Mode::kHw: return std::make_unique<HwSource>(scene, config);
    case Mode::kNormal: return std::make_unique<NormalSource>(scene, config);
    case Mode::kPath:
      if (config.progressive) return std::make_unique<ProgressivePathSource>(scene, config);
      return std::make_unique<StillPathSource>(scene, config);
  }
  throw std::invalid_argument("unknown mode");
}

}  // namespace tripsitter::modes

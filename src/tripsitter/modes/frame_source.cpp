#include <tripsitter/modes/frame_source.h>

#include <stdexcept>
#include <vector>

#include <tripsitter/board/board.h>
#include <tripsitter/display/png.h>
#include <tripsitter/host/view.h>
#include <tripsitter/render/camera.h>
#include <tripsitter/render/normal.h>

namespace tripsitter::modes {
namespace {

host::Camera initial_camera(const scene::CameraSettings& c) { return host::Camera(c.lookfrom, c.lookat, c.vup); }

// hw: every frame travels host -> link -> device -> VGA signal -> monitor.
class HwSource final : public FrameSource {
 public:
  HwSource(const scene::Scene& scene, const SourceConfig& c)
      : FrameSource(Mode::kHw),
        board_(scene, {c.preset, c.wire, c.spi, c.device_threads}),
        probe_(c.probe),
        accumulates_(c.preset.path.has_value() && c.wire != link::WireVersion::kV1),
        spp_(c.preset.path ? c.preset.path->spp : 0) {}

  const host::Camera& camera() const override { return board_.host().camera(); }
  host::Camera& steer() override { return board_.host().camera(); }
  void reset() override { board_.host().reset(); }

  const Frame& draw() override {
    board::ShownFrame shown = board_.show(probe_);
    frame_.vga = std::move(shown.image);
    frame_.device = shown.device;
    frame_.saturations = shown.saturations;
    frame_.link_bytes = shown.link_bytes;
    frame_.link_seconds = shown.link_seconds;
    frame_.spheres_dropped = shown.spheres_dropped;
    frame_.samples = shown.device.samples_per_pixel;
    frame_.scene_memory = &board_.device().scene();
    frame_.frame_memory = board_.device().frame_memory();
    return frame_;
  }
  // The path preset accumulates while the host sends worlds of the same content, until frame memory is full.
  bool refining() const override {
    return accumulates_ && frame_.device.has_world && frame_.samples + spp_ <= device::kMaxSamples;
  }

 private:
  board::Board board_;
  std::function<void(const device::VgaSample&)> probe_;
  const bool accumulates_;  // a path-tracing preset fed v2 worlds (v1 words are normal-shaded)
  const int spp_;           // samples per pixel per frame
  Frame frame_;
};

// normal: the host's view of the world the device would hold, in double, nothing encoded.
class NormalSource final : public FrameSource {
 public:
  NormalSource(const scene::Scene& scene, const SourceConfig& c)
      : FrameSource(Mode::kNormal),
        scene_(scene),
        camera_(initial_camera(scene.camera)),
        units_per_world_(host::units_per_world(scene)),
        carried_(host::spheres_carried(scene.spheres.size(), board::formats_of(c.preset), c.wire)),
        config_(c) {}

  const host::Camera& camera() const override { return camera_; }
  host::Camera& steer() override { return camera_; }
  void reset() override { camera_ = initial_camera(scene_.camera); }

  const Frame& draw() override {
    const std::vector<scene::Sphere> view =
        host::view_spheres(std::span(scene_.spheres).first(carried_), camera_, units_per_world_);
    frame_.vga = render::render_normal_fast(view, config_.width, config_.height, config_.preset.max_bounces,
                                            config_.threads);
    return frame_;
  }

 private:
  const scene::Scene scene_;
  host::Camera camera_;
  double units_per_world_;
  std::size_t carried_;
  SourceConfig config_;
  Frame frame_;
};

// The window refines a still picture up to this many samples per pixel.
constexpr int kMaxProgressiveSamples = 1024;

// path: the path tracer from the scene's camera, or from the host camera once it has been steered.
class PathSource final : public FrameSource {
 public:
  PathSource(const scene::Scene& scene, const SourceConfig& c)
      : FrameSource(Mode::kPath),
        camera_settings_(scene.camera),
        camera_(initial_camera(scene.camera)),
        path_scene_(scene.spheres),
        config_(c) {}

  const host::Camera& camera() const override { return camera_; }
  host::Camera& steer() override {
    steered_ = true;
    restart_ = true;
    return camera_;
  }
  void reset() override {
    camera_ = initial_camera(camera_settings_);
    steered_ = false;
    restart_ = true;
  }

  const Frame& draw() override { return config_.progressive ? refine() : trace(); }
  bool refining() const override { return config_.progressive && frame_.samples < kMaxProgressiveSamples; }

 private:
  render::ThinLensCamera lens() const {
    scene::CameraSettings c = camera_settings_;
    if (steered_) {
      c.lookfrom = camera_.position();
      c.lookat = camera_.target();
    }
    return render::ThinLensCamera(c, config_.width, config_.height);
  }
  // A whole picture at config.spp samples per pixel.
  const Frame& trace() {
    const render::PathSettings s = path_settings(config_);
    const render::ImageRgbF image = config_.trace ? config_.trace(path_scene_, lens(), s, config_.on_samples)
                                                  : render::render_path(path_scene_, lens(), s, config_.on_samples);
    frame_.rgb = render::to_srgb8(image);
    frame_.samples = s.spp;
    return frame_;
  }

  // One more sample per pixel added to the sum, which starts over when the camera moved. Each row is added to
  // the sum and encoded by the thread that traced it, while it is in cache.
  const Frame& refine() {
    const int w = config_.width, h = config_.height;
    const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    if (restart_ || frame_.samples == 0) {
      sum_ = {w, h, std::vector<render::Vec3f>(pixels)};
      frame_.samples = 0;
      restart_ = false;
    }
    if (pass_.pixels.size() != pixels) pass_ = sum_;
    if (frame_.rgb.width != w || frame_.rgb.height != h) frame_.rgb = core::ImageRgb8(w, h);
    render::PathSettings s = path_settings(config_);
    s.spp = 1;
    s.seed = config_.seed + static_cast<std::uint64_t>(frame_.samples);
    ++frame_.samples;
    const float scale = 1.0f / static_cast<float>(frame_.samples);
    render::render_path_rows(path_scene_, lens(), s, 0, 1, pass_, [&](int row) {
      const std::size_t first = static_cast<std::size_t>(row) * static_cast<std::size_t>(w);
      for (std::size_t i = first; i < first + static_cast<std::size_t>(w); ++i) sum_.pixels[i] += pass_.pixels[i];
      render::encode_srgb8(&sum_.pixels[first], static_cast<std::size_t>(w), scale, &frame_.rgb.pixels[3 * first]);
    });
    return frame_;
  }

  const scene::CameraSettings camera_settings_;
  host::Camera camera_;
  bool steered_ = false;  // the picture is seen from camera_, not from the scene's camera
  bool restart_ = false;  // progressive: the camera moved since the last draw
  const render::PathScene path_scene_;
  SourceConfig config_;
  render::ImageRgbF sum_;   // progressive: the sum of the samples so far
  render::ImageRgbF pass_;  // progressive: the draw's new sample per pixel
  Frame frame_;
};

}  // namespace

render::PathSettings path_settings(const SourceConfig& c) {
  return {.width = c.width, .height = c.height, .spp = c.spp, .max_depth = c.max_depth, .seed = c.seed,
          .threads = c.threads, .sky = {}};
}

core::Result<bool, display::IoError> write_png(const std::string& path, const Frame& frame) {
  return frame.vga.pixels.empty() ? display::write_png(path, frame.rgb) : display::write_png(path, frame.vga);
}

std::unique_ptr<FrameSource> make_frame_source(const scene::Scene& scene, const SourceConfig& config) {
  switch (config.mode) {
    case Mode::kHw: return std::make_unique<HwSource>(scene, config);
    case Mode::kNormal: return std::make_unique<NormalSource>(scene, config);
    case Mode::kPath: return std::make_unique<PathSource>(scene, config);
  }
  throw std::invalid_argument("unknown mode");
}

}  // namespace tripsitter::modes

#include <tripsitter/modes/frame_source.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include <tripsitter/board/board.h>
#include <tripsitter/core/colour.h>
#include <tripsitter/display/png.h>
#include <tripsitter/host/view.h>
#include <tripsitter/render/camera.h>
#include <tripsitter/render/normal.h>

namespace tripsitter::modes {
namespace {

host::Camera initial_camera(const scene::CameraSettings& c) { return host::Camera(c.lookfrom, c.lookat, c.vup); }

board::BoardConfig board_config(const SourceConfig& c) {
  board::BoardConfig b;
  b.preset = c.preset;
  b.wire = c.wire;
  b.spi = c.spi;
  b.device_threads = c.device_threads;
  b.make_device = c.make_device;
  return b;
}

// hw: every frame travels host -> link -> device -> VGA signal -> monitor.
class HwSource final : public FrameSource {
 public:
  HwSource(const scene::Scene& scene, const SourceConfig& c)
      : FrameSource(Mode::kHw),
        board_(scene, board_config(c)),
        probe_(c.probe),
        accumulates_(device::traces_paths(c.preset, c.wire)),
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
    frame_.scene_memory = board_.device().scene_memory();
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

// The window refines a still picture for this many frames after the camera stops.
constexpr int kMaxProgressiveSamples = 1024;

// path: the path tracer from the scene's camera, or from the host camera once it has been steered.
class PathSource final : public FrameSource {
 public:
  PathSource(const scene::Scene& scene, const SourceConfig& c)
      : FrameSource(Mode::kPath),
        camera_settings_(scene.camera),
        camera_(initial_camera(scene.camera)),
        path_scene_(scene.spheres),
        config_(c),
        interactive_(path_scene_, path_settings(c), interactive_settings(c)) {}

  const host::Camera& camera() const override { return camera_; }
  host::Camera& steer() override {
    steered_ = true;
    moved_ = true;
    return camera_;
  }
  void reset() override {
    camera_ = initial_camera(camera_settings_);
    steered_ = false;
    moved_ = true;
    interactive_.restart();
  }

  const Frame& draw() override { return config_.progressive ? refine() : trace(); }
  bool refining() const override { return config_.progressive && frame_.samples < kMaxProgressiveSamples; }
  bool set_denoise(bool on) override {
    config_.denoise = on;
    interactive_.set_denoise(on);
    return true;
  }
  bool denoise() const override { return config_.denoise; }

 private:
  static render::InteractiveSettings interactive_settings(const SourceConfig& c) {
    render::InteractiveSettings s;
    s.denoise = c.denoise;
    s.reuse = c.reuse;
    s.row_step = c.row_step;
    return s;
  }
  render::ThinLensCamera lens() const {
    scene::CameraSettings c = camera_settings_;
    if (steered_) {
      c.lookfrom = camera_.position();
      c.lookat = camera_.target();
    }
    return render::ThinLensCamera(c, config_.width, config_.height);
  }
  // A whole picture at config.spp samples per pixel, filtered with its own feature buffers when asked.
  const Frame& trace() {
    const render::PathSettings s = path_settings(config_);
    render::Aovs* aovs = config_.aovs || config_.denoise ? &aovs_ : nullptr;
    if (aovs != nullptr) aovs_ = render::Aovs(s.width, s.height);
    if (config_.denoise && s.spp >= 2) {
      denoised_halves(s);
    } else {
      frame_.linear = trace_samples(s, aovs);
      if (config_.denoise) {
        // One sample per pixel says nothing of its own spread: the variance comes from the neighbours.
        std::vector<float> variance(frame_.linear.pixels.size());
        denoiser_.estimate_variance({.width = s.width, .height = s.height, .color = frame_.linear.pixels,
                                     .variance = {}, .aovs = &aovs_},
                                    render::DenoiseSettings{}.variance_radius, s.threads, variance);
        denoise(s, variance);
      }
    }
    frame_.rgb = core::to_srgb8(frame_.linear);
    frame_.aovs = aovs;
    frame_.samples = s.spp;
    frame_.mean_samples = s.spp;
    return frame_;
  }

  core::ImageRgbF trace_samples(const render::PathSettings& s, render::Aovs* aovs) {
    return config_.trace ? config_.trace(path_scene_, lens(), s, config_.on_samples, aovs)
                         : render::render_path(path_scene_, lens(), s, config_.on_samples, aovs);
  }

  // --denoise with two or more samples: the samples traced in two halves (the first and the second half of each
  // pixel's sequence), whose difference gives each pixel's own variance, so that what the samples agree on
  // (a sharp reflection, say) is kept, where a variance from the neighbours would count it as noise.
  void denoised_halves(const render::PathSettings& s) {
    render::PathSettings first = s, second = s;
    first.spp = s.spp / 2;
    second.spp = s.spp - first.spp;
    second.first_sample = s.first_sample + static_cast<std::uint32_t>(first.spp);
    render::Aovs other(s.width, s.height);
    const core::ImageRgbF a = trace_samples(first, &aovs_);
    const core::ImageRgbF b = trace_samples(second, &other);
    const float wa = static_cast<float>(first.spp) / static_cast<float>(s.spp), wb = 1 - wa;
    frame_.linear = {s.width, s.height, std::vector<render::Vec3f>(a.pixels.size())};
    std::vector<float> variance(a.pixels.size());
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
      frame_.linear.pixels[i] = a.pixels[i] * wa + b.pixels[i] * wb;
      // Two estimates of the mean, each of about half the samples: the variance of their mean is about
      // (a - b)^2 / 4 (a noisy estimate of it, which the denoiser smooths before use).
      const float d = core::luminance(a.pixels[i]) - core::luminance(b.pixels[i]);
      variance[i] = d * d / 4;
      aovs_.albedo[i] = aovs_.albedo[i] * wa + other.albedo[i] * wb;
      aovs_.normal[i] = aovs_.normal[i] * wa + other.normal[i] * wb;
      const float da = aovs_.depth[i], db = other.depth[i];
      aovs_.depth[i] = std::isinf(da) ? db : std::isinf(db) ? da : da * wa + db * wb;
    }
    denoise(s, variance);
  }

  void denoise(const render::PathSettings& s, const std::vector<float>& variance) {
    render::DenoiseSettings settings;
    settings.threads = s.threads;
    denoiser_.denoise({.width = s.width, .height = s.height, .color = frame_.linear.pixels, .variance = variance,
                       .aovs = &aovs_},
                      settings, frame_.linear.pixels);
  }

  // One more pass of the window's loop (render/interactive.h): samples reprojected while the camera moves,
  // accumulated while it is still, and filtered.
  const Frame& refine() {
    frame_.linear = interactive_.frame(lens());
    frame_.rgb = core::to_srgb8(frame_.linear);
    frame_.aovs = &interactive_.aovs();
    still_frames_ = moved_ ? 1 : std::min(still_frames_ + 1, kMaxProgressiveSamples);
    moved_ = false;
    frame_.samples = still_frames_;
    frame_.mean_samples = interactive_.mean_samples();
    return frame_;
  }

  const scene::CameraSettings camera_settings_;
  host::Camera camera_;
  bool steered_ = false;  // the picture is seen from camera_, not from the scene's camera
  bool moved_ = true;     // progressive: the camera moved since the last draw
  int still_frames_ = 0;  // progressive: draws since the camera last moved
  const render::PathScene path_scene_;
  SourceConfig config_;
  render::InteractivePath interactive_;  // progressive
  render::Denoiser denoiser_;            // stills
  render::Aovs aovs_;                    // stills
  Frame frame_;
};

}  // namespace

render::PathSettings path_settings(const SourceConfig& c) {
  render::PathSettings s{.width = c.width, .height = c.height, .spp = c.spp, .max_depth = c.max_depth, .seed = c.seed,
                         .threads = c.threads, .sky = {}};
  s.sampler = c.sampler;
  return s;
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

#include <tripsitter/modes/path_quality.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include <tripsitter/core/colour.h>
#include <tripsitter/display/exr.h>
#include <tripsitter/display/png.h>

namespace tripsitter::modes {
namespace {

using Clock = std::chrono::steady_clock;

std::vector<render::Vec3f> layer(const display::ExrImage& image, const std::string& name) {
  const display::ExrChannel* c[3] = {display::find_channel(image, name + ".R"), display::find_channel(image, name + ".G"),
                                     display::find_channel(image, name + ".B")};
  std::vector<render::Vec3f> out;
  if (c[0] == nullptr || c[1] == nullptr || c[2] == nullptr) return out;
  out.resize(c[0]->values.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {c[0]->values[i], c[1]->values[i], c[2]->values[i]};
  return out;
}

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

}  // namespace

PathQuality::PathQuality(scene::Scene scene, QualitySettings settings)
    : scene_(std::move(scene)), settings_(std::move(settings)) {}

SourceConfig PathQuality::config() const {
  SourceConfig c;
  c.mode = Mode::kPath;
  c.width = settings_.width;
  c.height = settings_.height;
  c.threads = settings_.threads;
  c.max_depth = settings_.max_depth;
  return c;
}

Reference PathQuality::render_reference(int orbit_steps, int spp) {
  char name[160];
  std::snprintf(name, sizeof name, "%s-%dx%d-depth%d-spp%d-orbit%d-%.4fdeg-v1.exr", scene_.name.c_str(),
                settings_.width, settings_.height, settings_.max_depth, spp, orbit_steps, settings_.orbit_deg_per_frame);
  const std::filesystem::path path = settings_.cache_dir.empty() ? std::filesystem::path()
                                                                 : std::filesystem::path(settings_.cache_dir) / name;
  Reference ref;
  std::vector<render::Vec3f> a, b;
  if (!path.empty() && std::filesystem::exists(path)) {
    auto read = display::read_exr(path.string());
    if (read && read.value().width == settings_.width && read.value().height == settings_.height) {
      a = layer(read.value(), "a");
      b = layer(read.value(), "b");
      ref.cached = !a.empty() && !b.empty();
    }
  }
  if (!ref.cached) {
    if (settings_.say) settings_.say("rendering the reference " + std::string(name) + " (kept for later runs)");
    for (int half = 0; half < 2; ++half) {
      SourceConfig c = config();
      c.spp = spp / 2;
      c.seed = 1000003 + static_cast<std::uint64_t>(half);  // not a seed the measured pictures use
      const std::unique_ptr<FrameSource> source = make_frame_source(scene_, c);
      for (int k = 0; k < orbit_steps; ++k) source->steer().orbit(settings_.orbit_deg_per_frame);
      (half == 0 ? a : b) = std::get<PathFrame>(source->draw()).linear.pixels;
    }
    if (!path.empty()) {
      std::filesystem::create_directories(path.parent_path());
      display::ExrImage image{settings_.width, settings_.height, {}};
      display::add_rgb(image, "a", a);
      display::add_rgb(image, "b", b);
      auto written = display::write_exr(path.string(), image, display::ExrPixel::kFloat);
      if (!written && settings_.say) settings_.say("could not keep the reference: " + written.error().message);
    }
  }
  ref.image = {settings_.width, settings_.height, std::vector<render::Vec3f>(a.size())};
  for (std::size_t i = 0; i < a.size(); ++i) ref.image.pixels[i] = (a[i] + b[i]) * 0.5f;
  ref.noise_relmse = render::image_error(a, b, settings_.width, settings_.height).relmse / 4;
  return ref;
}

const Reference& PathQuality::reference() {
  if (!have_still_) {
    still_ = render_reference(0, settings_.reference_spp);
    have_still_ = true;
    keep("reference", still_.image);
  }
  return still_;
}

const Reference& PathQuality::orbit_reference(int frame) {
  const std::size_t k = static_cast<std::size_t>(frame / settings_.orbit_every - 1);
  while (orbit_.size() <= k) {
    const int f = static_cast<int>(orbit_.size() + 1) * settings_.orbit_every;
    orbit_.push_back(render_reference(f, settings_.orbit_reference_spp));
  }
  return orbit_[k];
}

double PathQuality::orbit_noise_relmse() {
  double worst = 0;
  for (int f = settings_.orbit_every; f <= settings_.orbit_frames; f += settings_.orbit_every)
    worst = std::max(worst, orbit_reference(f).noise_relmse);
  return worst;
}

void PathQuality::keep(const std::string& name, const core::ImageRgbF& picture) const {
  if (settings_.pictures_dir.empty() || name.empty()) return;
  std::filesystem::create_directories(settings_.pictures_dir);
  const std::string path = (std::filesystem::path(settings_.pictures_dir) / (name + ".png")).string();
  auto written = display::write_png(path, core::to_srgb8(picture));
  if (settings_.say) settings_.say(written ? "wrote " + path : written.error().message);
}

QualityFigure PathQuality::still(bool denoise, int frames, double seconds, const std::string& name) {
  const Reference& ref = reference();
  SourceConfig c = config();
  c.progressive = true;
  c.denoise = denoise;
  c.row_step = denoise ? settings_.row_step : 1;  // the plain tracer's figures trace every row
  const std::unique_ptr<FrameSource> source = make_frame_source(scene_, c);
  QualityFigure f;
  const auto start = Clock::now();
  const PathFrame* frame = nullptr;
  do {
    frame = &std::get<PathFrame>(source->draw());
    ++f.frames;
    f.seconds = seconds_since(start);
  } while (frames > 0 ? f.frames < frames : f.seconds < seconds);
  f.error = render::image_error(frame->linear.pixels, ref.image.pixels, settings_.width, settings_.height);
  f.mean_samples = frame->mean_samples;
  keep(name, frame->linear);
  return f;
}

QualityFigure PathQuality::orbit(bool denoise, bool reuse, const std::string& name) {
  for (int k = settings_.orbit_every; k <= settings_.orbit_frames; k += settings_.orbit_every) orbit_reference(k);
  SourceConfig c = config();
  c.progressive = true;
  c.denoise = denoise;
  c.reuse = reuse;
  c.row_step = denoise ? settings_.row_step : 1;
  const std::unique_ptr<FrameSource> source = make_frame_source(scene_, c);
  QualityFigure f;
  double samples = 0;
  int compared = 0;
  const auto start = Clock::now();
  source->draw();  // the still first frame the orbit starts from
  for (int k = 1; k <= settings_.orbit_frames; ++k) {
    source->steer().orbit(settings_.orbit_deg_per_frame);
    const PathFrame& frame = std::get<PathFrame>(source->draw());
    if (k % settings_.orbit_every != 0) continue;
    const double drawing = seconds_since(start);
    const render::ImageError e =
        render::image_error(frame.linear.pixels, orbit_reference(k).image.pixels, settings_.width, settings_.height);
    f.error.relmse += e.relmse;
    f.error.bias += e.bias;
    f.error.block_relmse += e.block_relmse;
    samples += frame.mean_samples;
    ++compared;
    if (k == settings_.orbit_frames) {
      keep(name, frame.linear);
      keep(name + "-reference", orbit_reference(k).image);
    }
    f.seconds = drawing;
  }
  f.frames = settings_.orbit_frames + 1;
  f.error.relmse /= compared;
  f.error.bias /= compared;
  f.error.block_relmse /= compared;
  f.mean_samples = samples / compared;
  return f;
}

QualityFigure PathQuality::plain(int spp, render::SamplerKind sampler, const std::string& name) {
  const Reference& ref = reference();
  SourceConfig c = config();
  c.spp = spp;
  c.sampler = sampler;
  const auto start = Clock::now();
  const std::unique_ptr<FrameSource> source = make_frame_source(scene_, c);  // owns the frame
  const PathFrame& frame = std::get<PathFrame>(source->draw());
  QualityFigure f;
  f.seconds = seconds_since(start);
  f.frames = 1;
  f.mean_samples = spp;
  f.error = render::image_error(frame.linear.pixels, ref.image.pixels, settings_.width, settings_.height);
  keep(name, frame.linear);
  return f;
}

}  // namespace tripsitter::modes

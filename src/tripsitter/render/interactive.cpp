#include <tripsitter/render/interactive.h>

#include <algorithm>
#include <cmath>

#include <tripsitter/core/parallel.h>
#include <tripsitter/render/primary.h>

namespace tripsitter::render {
namespace {

bool same_view(const ThinLensCamera::Pinhole& a, const ThinLensCamera::Pinhole& b) {
  return a.origin == b.origin && a.pixel00 == b.pixel00 && a.du == b.du && a.dv == b.dv;
}

}  // namespace

InteractivePath::InteractivePath(const PathScene& scene, const PathSettings& path, const InteractiveSettings& settings)
    : scene_(scene), path_(path), settings_(settings), history_(settings.temporal) {
  path_.spp = 1;
  settings_.temporal.threads = path.threads;
  settings_.denoiser.threads = path.threads;
  history_ = TemporalAccumulator(settings_.temporal);
  const std::size_t n = Aovs::pixels(path.width, path.height);
  pass_ = {path.width, path.height, std::vector<Vec3f>(n)};
  picture_ = pass_;
  variance_.resize(n);
  spatial_.resize(n);
}

void InteractivePath::restart() { restart_ = true; }

const core::ImageRgbF& InteractivePath::frame(const ThinLensCamera& camera) {
  const int w = path_.width, h = path_.height;
  const ThinLensCamera::Pinhole view = camera.pinhole();
  if (!settings_.reuse && frames_ > 0 && !same_view(view, view_)) restart_ = true;
  if (restart_) {
    history_.reset();
    frames_ = 0;
    restart_ = false;
  }
  view_ = view;
  const int step = settings_.row_step;
  const int first = static_cast<int>(frames_ % static_cast<std::uint64_t>(step));
  const PrimarySettings primary{.width = w, .height = h, .threads = path_.threads};
  if (settings_.denoise)
    render_primary_guides(scene_, camera, primary, settings_.guides, aovs_, guides_);
  else
    render_primary_aovs(scene_, camera, primary, aovs_);
  PathSettings s = path_;
  // A pixel's k-th sample is sample k of its sequence (the rows take turns: one sample per `step` frames).
  s.first_sample = static_cast<std::uint32_t>(frames_ / static_cast<std::uint64_t>(step));
  render_path_rows(scene_, camera, s, first, step, pass_);
  history_.add(pass_.pixels, aovs_, view, first, step);
  ++frames_;

  // The picture: each pixel's mean; a pixel with no sample yet (rows not traced since it came into view) takes
  // the mean of the nearest pixels above and below that have one.
  const std::span<const Vec3f> sum = history_.sum();
  const std::span<const float> count = history_.count();
  // Per row: its samples, and whether it has a pixel without any (a hole) or with too few to know its own
  // variance (a young one).
  struct RowTally {
    double samples = 0;
    bool holes = false, young = false;
  };
  std::vector<RowTally> rows(static_cast<std::size_t>(h));
  const float young_below = settings_.spatial_variance_below;
  core::parallel_for(0, h, path_.threads, [&](int row) {
    RowTally t;
    for (int col = 0; col < w; ++col) {
      const std::size_t i = static_cast<std::size_t>(row) * static_cast<std::size_t>(w) + static_cast<std::size_t>(col);
      const float n = count[i];
      t.samples += n;
      t.holes |= !(n > 0);
      t.young |= n < young_below;
      picture_.pixels[i] = n > 0 ? sum[i] * (1.0f / n) : Vec3f{};
    }
    rows[static_cast<std::size_t>(row)] = t;
  });
  double total = 0;
  bool holes = false, young = false;
  for (const RowTally& t : rows) {
    total += t.samples;
    holes |= t.holes;
    young |= t.young;
  }
  mean_samples_ = total / static_cast<double>(Aovs::pixels(w, h));
  if (holes) {
    for (int row = 0; row < h; ++row) {
      for (int col = 0; col < w; ++col) {
        const std::size_t i = static_cast<std::size_t>(row) * static_cast<std::size_t>(w) + static_cast<std::size_t>(col);
        if (count[i] > 0) continue;
        Vec3f fill{};
        float found = 0;
        for (int d = 1; d <= step && found == 0; ++d) {
          for (int r : {row - d, row + d}) {
            if (r < 0 || r >= h) continue;
            const std::size_t j = static_cast<std::size_t>(r) * static_cast<std::size_t>(w) + static_cast<std::size_t>(col);
            if (count[j] > 0) {
              fill += sum[j] * (1.0f / count[j]);
              found += 1;
            }
          }
        }
        if (found > 0) picture_.pixels[i] = fill * (1.0f / found);
      }
    }
  }
  if (!settings_.denoise) return picture_;

  // Each pixel's variance from its own samples where it has enough of them, else from its neighbours'.
  history_.mean_variance(variance_);
  if (young) {
    denoiser_.estimate_variance({.width = w, .height = h, .color = picture_.pixels, .variance = {}, .aovs = &guides_},
                                settings_.denoiser.variance_radius, path_.threads, spatial_);
    core::parallel_for(0, h, path_.threads, [&](int row) {
      const std::size_t first = static_cast<std::size_t>(row) * static_cast<std::size_t>(w);
      for (std::size_t i = first; i < first + static_cast<std::size_t>(w); ++i)
        if (count[i] < young_below) variance_[i] = spatial_[i];
    });
  }
  // The luminance term stops the filter more sharply as samples gather (InteractiveSettings).
  DenoiseSettings filter = settings_.denoiser;
  const float samples = static_cast<float>(std::max(mean_samples_, 1.0));
  filter.sigma_luminance = std::max(settings_.sigma_luminance_min, settings_.sigma_luminance_1spp / std::sqrt(samples));
  denoiser_.denoise({.width = w, .height = h, .color = picture_.pixels, .variance = variance_, .aovs = &guides_},
                    filter, picture_.pixels);
  return picture_;
}

}  // namespace tripsitter::render

#include <tripsitter/render/temporal.h>

#include <algorithm>
#include <cmath>

#include <tripsitter/core/parallel.h>

namespace tripsitter::render {
namespace {

bool same_view(const ThinLensCamera::Pinhole& a, const ThinLensCamera::Pinhole& b) {
  return a.origin == b.origin && a.pixel00 == b.pixel00 && a.du == b.du && a.dv == b.dv;
}

// Where directions from a view's eye cross its image, in pixel coordinates (pixel centres at whole numbers):
// the view's terms computed once for every pixel that asks.
class Projection {
 public:
  explicit Projection(const ThinLensCamera::Pinhole& view)
      : forward_(core::cross(view.du, view.dv)),  // du right, dv down: their cross product looks ahead
        plane_(core::dot(view.pixel00 - view.origin, forward_)),
        corner_(view.origin - view.pixel00),
        du_(view.du * (1.0f / core::dot(view.du, view.du))),
        dv_(view.dv * (1.0f / core::dot(view.dv, view.dv))) {}

  // False when d does not point into the half-space in front of the eye.
  bool operator()(const Vec3f& d, float& x, float& y) const {
    const float along = core::dot(d, forward_);
    if (!(along > 0)) return false;
    const Vec3f on_plane = d * (plane_ / along) + corner_;
    x = core::dot(on_plane, du_);
    y = core::dot(on_plane, dv_);
    return std::isfinite(x) && std::isfinite(y);
  }

 private:
  Vec3f forward_;
  float plane_;   // the image plane's distance along forward_, times |forward_|
  Vec3f corner_;  // from pixel 0's centre to the eye
  Vec3f du_, dv_;  // du / |du|^2, dv / |dv|^2
};

}  // namespace

void TemporalAccumulator::add(std::span<const Vec3f> pass, const Aovs& aovs, const ThinLensCamera::Pinhole& view,
                              int first_row, int row_step) {
  const auto traced = [&](int row) { return row % row_step == first_row; };
  const int w = aovs.width, h = aovs.height;
  const std::size_t n = Aovs::pixels(w, h);
  const bool fresh = width_ != w || height_ != h;
  const bool still = !fresh && same_view(view, view_);
  reprojected_ = 0;
  if (fresh) {
    width_ = w;
    height_ = h;
    sum_.assign(n, {});
    square_sum_.assign(n, 0);
    count_.assign(n, 0);
    next_sum_.assign(n, {});
    next_square_sum_.assign(n, 0);
    next_count_.assign(n, 0);
  }
  if (fresh || still) {
    // Plain accumulation: every pixel adds its sample to its own sums (a fresh pixel's sums are zero).
    core::parallel_for(0, h, settings_.threads, [&](int row) {
      if (!traced(row)) return;
      const std::size_t first = static_cast<std::size_t>(row) * static_cast<std::size_t>(w);
      for (std::size_t i = first; i < first + static_cast<std::size_t>(w); ++i) {
        const float l = luminance(pass[i]);
        sum_[i] += pass[i];
        square_sum_[i] += l * l;
        count_[i] += 1;
      }
    });
  } else {
    const ThinLensCamera::Pinhole before = view_;
    const Projection project(before);
    const float cosine2 = settings_.normal_cosine * settings_.normal_cosine;
    std::vector<std::size_t> carried(static_cast<std::size_t>(h));
    core::parallel_for(0, h, settings_.threads, [&](int row) {
      std::size_t row_carried = 0;
      for (int col = 0; col < w; ++col) {
        const std::size_t i = static_cast<std::size_t>(row) * static_cast<std::size_t>(w) + static_cast<std::size_t>(col);
        const Vec3f ray = core::normalize(view.pixel00 + view.du * static_cast<float>(col) +
                                          view.dv * static_cast<float>(row) - view.origin);
        const float normal2 = core::dot(aovs.normal[i], aovs.normal[i]);
        const float depth = aovs.depth[i];
        const bool sky = std::isinf(depth);
        // The pixel's surface point, seen from the previous eye; a sky pixel keeps its direction.
        const Vec3f from_before = sky ? ray : view.origin + ray * depth - before.origin;
        const float expected = sky ? 0.0f : core::length(from_before);
        const Vec3f& normal = aovs.normal[i];
        Vec3f mean{};
        float square_mean = 0, samples = 0, weight = 0;
        float x, y;
        if (project(from_before, x, y)) {
          const float fx = std::floor(x), fy = std::floor(y);
          const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
          const float ax = x - fx, ay = y - fy;
          for (int k = 0; k < 4; ++k) {
            const int tx = x0 + (k & 1), ty = y0 + (k >> 1);
            if (tx < 0 || ty < 0 || tx >= w || ty >= h) continue;
            const std::size_t j = static_cast<std::size_t>(ty) * static_cast<std::size_t>(w) + static_cast<std::size_t>(tx);
            if (!(count_[j] > 0)) continue;
            const float d = depth_[j];
            if (sky != std::isinf(d)) continue;
            if (!sky) {
              if (std::fabs(d - expected) > settings_.depth_tolerance * expected) continue;
              // cos >= normal_cosine, squared (both sides non-negative): no square root per tap.
              const Vec3f& m = normal_[j];
              const float dot = core::dot(m, normal);
              if (!(dot > 0 && dot * dot >= cosine2 * core::dot(m, m) * normal2)) continue;
            }
            const float tap = ((k & 1) ? ax : 1 - ax) * ((k >> 1) ? ay : 1 - ay);
            const float inv = tap / count_[j];
            mean += sum_[j] * inv;
            square_mean += square_sum_[j] * inv;
            samples += count_[j] * tap;
            weight += tap;
          }
        }
        // The new sample, or nothing on a row this pass did not trace.
        const bool sampled = traced(row);
        const Vec3f sample = sampled ? pass[i] : Vec3f{};
        const float l = luminance(sample);
        if (weight > 1e-3f) {
          // Each tap's mean, weighted; the history counts for at most max_history_moving samples.
          const float kept = std::min(samples / weight, settings_.max_history_moving);
          next_sum_[i] = mean * (kept / weight) + sample;
          next_square_sum_[i] = square_mean * (kept / weight) + l * l;
          next_count_[i] = kept + (sampled ? 1.0f : 0.0f);
          ++row_carried;
        } else {
          next_sum_[i] = sample;
          next_square_sum_[i] = l * l;
          next_count_[i] = sampled ? 1.0f : 0.0f;
        }
      }
      carried[static_cast<std::size_t>(row)] = row_carried;
    });
    sum_.swap(next_sum_);
    square_sum_.swap(next_square_sum_);
    count_.swap(next_count_);
    for (std::size_t c : carried) reprojected_ += c;
  }
  view_ = view;
  normal_.assign(aovs.normal.begin(), aovs.normal.end());
  depth_.assign(aovs.depth.begin(), aovs.depth.end());
}

void TemporalAccumulator::mean_variance(std::span<float> out) const {
  for (std::size_t i = 0; i < count_.size(); ++i) {
    const float n = count_[i];
    if (!(n > 1)) {
      out[i] = 0;
      continue;
    }
    const float l = luminance(sum_[i] / n);
    out[i] = std::max(0.0f, square_sum_[i] / n - l * l) / n;
  }
}

}  // namespace tripsitter::render

#include <tripsitter/render/temporal.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <tripsitter/core/colour.h>
#include <tripsitter/core/parallel.h>
#include <tripsitter/render/simd8.h>

namespace tripsitter::render {
namespace {

bool same_view(const ThinLensCamera::Pinhole& a, const ThinLensCamera::Pinhole& b) {
  return a.origin == b.origin && a.pixel00 == b.pixel00 && a.du == b.du && a.dv == b.dv;
}

// Where each pixel's surface point of the new view lies in the previous view's image (pixel centres at whole
// numbers), eight pixels at a time: the square roots and divisions of reprojection, done once per pixel (the taps
// in add() are then loads and comparisons).
class Projection {
 public:
  Projection(const ThinLensCamera::Pinhole& now, const ThinLensCamera::Pinhole& before)
      : now_(now),
        before_origin_(before.origin),
        forward_(core::cross(before.du, before.dv)),  // du right, dv down: their cross product looks ahead
        plane_(core::dot(before.pixel00 - before.origin, forward_)),
        corner_(before.origin - before.pixel00),
        du_(before.du * (1.0f / core::dot(before.du, before.du))),
        dv_(before.dv * (1.0f / core::dot(before.dv, before.dv))) {}

  // For the `width` pixels of `row` with their depths: x, y in the previous image (NaN where the point was behind
  // the previous eye or the projection is not finite) and `expected`, the distance from the previous eye to the
  // surface point (0 for the sky, whose pixels keep their direction). x, y and expected hold width rounded up to
  // a multiple of 8.
  void row(int row, int width, const float* depth, float* x, float* y, float* expected) const {
    using simd::F8;
    const F8 inf = F8::set1(std::numeric_limits<float>::infinity());
    const F8 nan = F8::set1(std::numeric_limits<float>::quiet_NaN());
    const F8 zero = F8::set1(0), one = F8::set1(1);
    const F8 magnitude = F8::set1(-0.0f);  // andnot(magnitude, x): |x|
    const Vec3f start = now_.pixel00 + now_.dv * static_cast<float>(row) - now_.origin;
    const Vec3f eye = now_.origin - before_origin_;
    const auto splat = [](const Vec3f& v) { return std::array<F8, 3>{F8::set1(v.x), F8::set1(v.y), F8::set1(v.z)}; };
    const auto [sx, sy, sz] = splat(start);
    const auto [ux, uy, uz] = splat(now_.du);
    const auto [ex, ey, ez] = splat(eye);
    const auto [wx, wy, wz] = splat(forward_);
    const auto [cx, cy, cz] = splat(corner_);
    const auto [dux, duy, duz] = splat(du_);
    const auto [dvx, dvy, dvz] = splat(dv_);
    const F8 plane = F8::set1(plane_);
    const F8 eight = F8::set1(8);
    alignas(32) float lanes[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    F8 c = F8::load(lanes);  // the group's columns (whole numbers, exact in float)
    for (int col = 0; col < width; col += 8, c = c + eight) {
      F8 d;
      if (col + 8 <= width) {
        d = F8::loadu(depth + col);
      } else {
        // The last group reaches past the row: its extra lanes see the sky, and are not read.
        for (int k = 0; k < 8; ++k) lanes[k] = col + k < width ? depth[col + k] : std::numeric_limits<float>::infinity();
        d = F8::load(lanes);
      }
      const F8 rx = sx + ux * c, ry = sy + uy * c, rz = sz + uz * c;
      const F8 inv = one / sqrt(rx * rx + ry * ry + rz * rz);
      const F8 sky = d == inf;
      // From the previous eye to the point; on the sky, the unit direction itself.
      const F8 t = select(sky, inv, d * inv);
      const F8 fx = andnot(sky, ex) + rx * t, fy = andnot(sky, ey) + ry * t, fz = andnot(sky, ez) + rz * t;
      andnot(sky, sqrt(fx * fx + fy * fy + fz * fz)).storeu(expected + col);
      const F8 along = fx * wx + fy * wy + fz * wz;
      const F8 scale = plane / along;
      const F8 px = fx * scale + cx, py = fy * scale + cy, pz = fz * scale + cz;
      const F8 u = px * dux + py * duy + pz * duz;
      const F8 v = px * dvx + py * dvy + pz * dvz;
      const F8 ok = (along > zero) & (andnot(magnitude, u) < inf) & (andnot(magnitude, v) < inf);
      select(ok, u, nan).storeu(x + col);
      select(ok, v, nan).storeu(y + col);
    }
  }

 private:
  ThinLensCamera::Pinhole now_;
  Vec3f before_origin_;
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
        const float l = core::luminance(pass[i]);
        sum_[i] += pass[i];
        square_sum_[i] += l * l;
        count_[i] += 1;
      }
    });
  } else {
    const Projection project(view, view_);
    const float cosine2 = settings_.normal_cosine * settings_.normal_cosine;
    const float low = 1 - settings_.depth_tolerance, high = 1 + settings_.depth_tolerance;
    // The previous pass's means per sample: one division per pixel here rather than one per tap below.
    inverse_count_.resize(n);
    core::parallel_for(0, h, settings_.threads, [&](int row) {
      const std::size_t first = static_cast<std::size_t>(row) * static_cast<std::size_t>(w);
      for (std::size_t j = first; j < first + static_cast<std::size_t>(w); ++j)
        inverse_count_[j] = count_[j] > 0 ? 1.0f / count_[j] : 0.0f;
    });
    std::vector<std::size_t> carried(static_cast<std::size_t>(h));
    core::parallel_for(0, h, settings_.threads, [&](int row) {
      thread_local std::vector<float> scratch;
      const int padded = (w + 7) / 8 * 8;
      scratch.resize(3 * static_cast<std::size_t>(padded));
      float* const xs = scratch.data();
      float* const ys = xs + padded;
      float* const expecteds = ys + padded;
      const std::size_t first = static_cast<std::size_t>(row) * static_cast<std::size_t>(w);
      project.row(row, w, aovs.depth.data() + first, xs, ys, expecteds);
      std::size_t row_carried = 0;
      for (int col = 0; col < w; ++col) {
        const std::size_t i = first + static_cast<std::size_t>(col);
        const Vec3f& normal = aovs.normal[i];
        const float normal2 = core::dot(normal, normal);
        const float x = xs[col], y = ys[col], expected = expecteds[col];
        const bool sky = std::isinf(aovs.depth[i]);
        Vec3f mean{};
        float square_mean = 0, samples = 0, weight = 0;
        // A NaN position fails both comparisons: no tap.
        if (x > -1 && y > -1 && x < static_cast<float>(w) && y < static_cast<float>(h)) {
          const float fx = std::floor(x), fy = std::floor(y);
          const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
          const float ax = x - fx, ay = y - fy;
          for (int k = 0; k < 4; ++k) {
            const int tx = x0 + (k & 1), ty = y0 + (k >> 1);
            if (tx < 0 || ty < 0 || tx >= w || ty >= h) continue;
            const std::size_t j = static_cast<std::size_t>(ty) * static_cast<std::size_t>(w) + static_cast<std::size_t>(tx);
            const float inverse = inverse_count_[j];
            if (!(inverse > 0)) continue;
            const float d = depth_[j];
            if (sky) {
              if (!std::isinf(d)) continue;
            } else {
              // Within depth_tolerance of the expected distance (false for the sky's infinite depth) ...
              if (!(d >= low * expected && d <= high * expected)) continue;
              // ... and cos >= normal_cosine, squared (both sides non-negative): no square root per tap.
              const Vec3f& m = normal_[j];
              const float dot = core::dot(m, normal);
              if (!(dot > 0 && dot * dot >= cosine2 * core::dot(m, m) * normal2)) continue;
            }
            const float tap = ((k & 1) ? ax : 1 - ax) * ((k >> 1) ? ay : 1 - ay);
            const float share = tap * inverse;
            mean += sum_[j] * share;
            square_mean += square_sum_[j] * share;
            samples += count_[j] * tap;
            weight += tap;
          }
        }
        // The new sample, or nothing on a row this pass did not trace.
        const bool sampled = traced(row);
        const Vec3f sample = sampled ? pass[i] : Vec3f{};
        const float l = core::luminance(sample);
        if (weight > 1e-3f) {
          // Each tap's mean, weighted; the history counts for at most max_history_moving samples.
          const float kept = std::min(samples / weight, settings_.max_history_moving);
          const float scale = kept / weight;
          next_sum_[i] = mean * scale + sample;
          next_square_sum_[i] = square_mean * scale + l * l;
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
  normal_.resize(n);
  depth_.resize(n);
  core::parallel_for(0, h, settings_.threads, [&](int row) {
    const std::size_t first = static_cast<std::size_t>(row) * static_cast<std::size_t>(w);
    std::copy_n(aovs.normal.data() + first, w, normal_.data() + first);
    std::copy_n(aovs.depth.data() + first, w, depth_.data() + first);
  });
}

void TemporalAccumulator::mean_variance(std::span<float> out) const {
  core::parallel_for(0, height_, settings_.threads, [&](int row) {
    const std::size_t first = static_cast<std::size_t>(row) * static_cast<std::size_t>(width_);
    for (std::size_t i = first; i < first + static_cast<std::size_t>(width_); ++i) {
      const float n = count_[i];
      if (!(n > 1)) {
        out[i] = 0;
        continue;
      }
      const float l = core::luminance(sum_[i] / n);
      out[i] = std::max(0.0f, square_sum_[i] / n - l * l) / n;
    }
  });
}

}  // namespace tripsitter::render

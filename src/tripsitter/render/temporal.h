// Reuse of earlier frames while the camera moves: each pixel keeps the sum of the samples it has gathered, and
// when the view changes that history is reprojected into the new view through the depth buffer, where it still
// shows the same surface. A still camera adds every pass to the sum, exactly as plain accumulation does.
#pragma once

#include <span>
#include <vector>

#include <tripsitter/render/aov.h>
#include <tripsitter/render/camera.h>

namespace tripsitter::render {

struct TemporalSettings {
  // After a move, a pixel keeps at most this many samples' worth of its history, so that what the history got
  // wrong (resampling blur, light that changed with the view: reflections) fades within that many frames; the
  // denoiser, fed the reprojected history, does the rest. docs/denoiser.md has the measurements that chose 1.
  float max_history_moving = 1;
  // A tap of the previous frame is the same surface when its depth is within this fraction of the distance
  // expected from the previous camera to the pixel's surface point ...
  float depth_tolerance = 0.05f;
  // ... and its normal's cosine with the pixel's normal is at least this (both as means over samples, so
  // silhouettes, whose normals are shorter, reject more easily).
  float normal_cosine = 0.8f;
  int threads = 0;  // 0: all hardware threads
};

class TemporalAccumulator {
 public:
  explicit TemporalAccumulator(TemporalSettings settings = {}) : settings_(settings) {}

  // Forgets every history: the next pass starts afresh.
  void reset() { width_ = 0; }

  // Adds one sample per pixel, `pass`, seen from `view`, with the feature buffers of those samples.
  // - The first pass (or the first after reset(), or after a change of size) starts every pixel at this sample.
  // - The same view as the previous pass: every pixel adds the sample to its sums (plain accumulation).
  // - Another view: each pixel first takes the previous pass's history at the point where its surface was seen
  //   (bilinear over the previous pixels that show the same surface: depth and normal agree), capped at
  //   max_history_moving samples, then adds the sample. A pixel whose surface was not visible before (it was
  //   disoccluded, left the screen or lay behind the camera) starts at this sample.
  // Only rows first_row, first_row + row_step, ... have a new sample (a frame that traces a fraction of the
  // image); the other pixels take their history alone, and one without history has none (count 0).
  // REQUIRES pass and aovs sized aovs.width x aovs.height, 0 <= first_row < row_step.
  void add(std::span<const Vec3f> pass, const Aovs& aovs, const ThinLensCamera::Pinhole& view, int first_row = 0,
           int row_step = 1);

  int width() const { return width_; }
  int height() const { return height_; }
  // Per pixel: the sum of its samples' radiance, the sum of their luminances' squares (core::luminance, Rec.
  // 709), and their number (not a whole number after a move: the reprojected share of earlier samples).
  std::span<const Vec3f> sum() const { return sum_; }
  std::span<const float> luminance_square_sum() const { return square_sum_; }
  std::span<const float> count() const { return count_; }
  // The variance of each pixel's mean luminance, (E[l^2] - E[l]^2) / n, from its sums; 0 where n <= 1 (one sample
  // says nothing of its variance: the caller estimates it from the neighbours then).
  void mean_variance(std::span<float> out) const;
  // How many pixels of the last add() carried history over a move (0 for a still camera).
  std::size_t reprojected() const { return reprojected_; }

 private:
  TemporalSettings settings_;
  int width_ = 0, height_ = 0;
  ThinLensCamera::Pinhole view_{};
  std::vector<Vec3f> sum_, next_sum_;
  std::vector<float> square_sum_, next_square_sum_;
  std::vector<float> count_, next_count_;
  std::vector<Vec3f> normal_;  // the previous pass's feature buffers: where its history lies
  std::vector<float> depth_;
  std::vector<float> inverse_count_;  // 1 / count_, 0 where count_ is 0 (scratch of add())
  std::size_t reprojected_ = 0;
};

}  // namespace tripsitter::render

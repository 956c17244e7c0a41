// The window's path tracer: each frame traces one pass of paths, adds it to every pixel's history (reprojected
// when the camera moved: temporal.h) and filters the result (denoise.h), so that a moving camera shows a
// clean picture rather than one sample per pixel of grain, and a still one keeps converging to what plain
// accumulation gives. docs/denoiser.md describes the whole loop.
#pragma once

#include <cstdint>

#include <tripsitter/render/aov.h>
#include <tripsitter/render/camera.h>
#include <tripsitter/render/denoise.h>
#include <tripsitter/render/path_tracer.h>
#include <tripsitter/render/primary.h>
#include <tripsitter/render/temporal.h>

namespace tripsitter::render {

struct InteractiveSettings {
  bool denoise = true;  // filter the picture (the window's N key)
  bool reuse = true;    // reproject the history when the camera moves; off: a move starts over
  // Paths per frame: one per pixel on 1 row of every `row_step` (1: every pixel every frame). The rows take
  // turns, so a still camera gives every pixel one sample per row_step frames.
  int row_step = 1;
  // Where a pixel's history holds fewer samples than this, its variance is estimated from its neighbours
  // (too few samples say little about their own spread).
  float spatial_variance_below = 4;
  // The filter's luminance term by the samples gathered: each frame's sigma_luminance (DenoiseSettings) is
  // sigma_luminance_1spp / sqrt(mean samples per pixel), at least sigma_luminance_min. With few samples the
  // filter has to smooth hard to hide the noise; with many, the picture itself is mostly right and a sharper
  // stop keeps its detail (docs/denoiser.md has the figures this was chosen by).
  float sigma_luminance_1spp = 4;
  float sigma_luminance_min = 0.5f;
  TemporalSettings temporal;
  DenoiseSettings denoiser;  // its sigma_luminance is set each frame, as above
  GuideSettings guides;  // the denoiser's guides look into mirrors (render_primary_guides)
};

class InteractivePath {
 public:
  // `path` gives size, depth, seed, sampler and threads (spp and first_sample are the loop's own: one sample per
  // traced pixel per frame). REQUIRES the scene to outlive this.
  InteractivePath(const PathScene& scene, const PathSettings& path, const InteractiveSettings& settings);

  // Forgets every pixel's history: the next frame starts afresh (the window's R key, a new world).
  void restart();
  void set_denoise(bool on) { settings_.denoise = on; }
  bool denoise() const { return settings_.denoise; }

  // The next frame seen from `camera` (made for the settings' size): linear radiance per pixel, valid until the
  // next call. A camera other than the last frame's is a move (without reuse, it starts over).
  const core::ImageRgbF& frame(const ThinLensCamera& camera);

  // Frames since the last restart.
  std::uint64_t frames() const { return frames_; }
  // The mean over pixels of the samples their picture holds (after a move, the reprojected share too).
  double mean_samples() const { return mean_samples_; }
  // The frame's feature buffers (the pixel-centre rays' first hits, render_primary_aovs), and the denoiser's
  // guides (what mirrors show: render_primary_guides; filled only while the denoiser is on).
  const Aovs& aovs() const { return aovs_; }
  const Aovs& guides() const { return guides_; }

 private:
  const PathScene& scene_;
  PathSettings path_;
  InteractiveSettings settings_;
  TemporalAccumulator history_;
  Denoiser denoiser_;
  Aovs aovs_, guides_;
  core::ImageRgbF pass_;     // the frame's new samples (on the rows it traced)
  core::ImageRgbF picture_;  // what frame() returns
  std::vector<float> variance_, spatial_;
  std::uint64_t frames_ = 0;
  double mean_samples_ = 0;
  bool restart_ = true;
  ThinLensCamera::Pinhole view_{};  // the last frame's camera
};

}  // namespace tripsitter::render

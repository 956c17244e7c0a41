// How clean the window's path mode is, against a converged reference: the figures `tripsitter bench` reports as
// path_relmse_field_* (docs/denoiser.md). Every picture here comes from the mode's own frame source, the one the
// window draws with (render/interactive.h), so what is measured is what a person sees.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <tripsitter/core/image.h>
#include <tripsitter/modes/frame_source.h>
#include <tripsitter/render/image_error.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::modes {

struct QualitySettings {
  int width = 640;
  int height = 480;
  int threads = 0;                   // 0: all
  int max_depth = 50;
  int row_step = 1;                  // the window loop's (SourceConfig::row_step) in the figures with the denoiser on
  int reference_spp = 2048;          // of the still camera's reference
  int orbit_reference_spp = 512;     // of each orbit frame's reference
  int orbit_frames = 60;             // frames of the scripted orbit
  double orbit_deg_per_frame = 0.75; // the window's Q/E at 45 degrees per second, at 60 frames per second
  int orbit_every = 10;              // frames 10, 20, ... of the orbit are compared with their references
  std::string cache_dir;             // references are kept here (created if missing); empty: not kept
  std::function<void(const std::string&)> say;  // progress of long work (rendering a reference), may be empty
  std::string pictures_dir;          // non-empty: every measured picture and its reference written here as PNG
};

// A reference rendered as two halves of its samples with different seeds: their mean is the reference, and
// their difference tells how noisy it still is.
struct Reference {
  core::ImageRgbF image;
  // The reference's own expected relMSE against the converged image, estimated as relMSE(half a, half b) / 4:
  // the floor under every figure measured against it.
  double noise_relmse = 0;
  bool cached = false;  // read from the cache rather than rendered
};

struct QualityFigure {
  render::ImageError error;
  int frames = 0;          // frames drawn
  double seconds = 0;      // wall time they took
  double mean_samples = 0; // samples per pixel in the last picture (mean)
};

class PathQuality {
 public:
  // REQUIRES the scene's camera valid.
  PathQuality(scene::Scene scene, QualitySettings settings);

  // The still camera's reference, rendered once and kept in the cache.
  const Reference& reference();
  // The window's loop (denoise and reuse as given) from a fresh start with a still camera: after `frames`
  // frames, or after the first frame that ends `seconds` or more after the start (frames 0).
  QualityFigure still(bool denoise, int frames, double seconds, const std::string& name = "");
  // The scripted orbit: orbit_deg_per_frame every frame, the mean of the errors at every orbit_every-th frame
  // against that frame's reference.
  QualityFigure orbit(bool denoise, bool reuse, const std::string& name = "");
  // The path tracer alone (no window loop, no denoiser): one picture at `spp` samples per pixel.
  // Pictures named `name` go to pictures_dir as name.png (when both are given).
  QualityFigure plain(int spp, render::SamplerKind sampler, const std::string& name = "");
  // The largest orbit reference noise (each frame's reference has its own).
  double orbit_noise_relmse();

 private:
  SourceConfig config() const;
  Reference render_reference(int orbit_steps, int spp);
  const Reference& orbit_reference(int frame);
  void keep(const std::string& name, const core::ImageRgbF& picture) const;

  scene::Scene scene_;
  QualitySettings settings_;
  Reference still_;
  bool have_still_ = false;
  std::vector<Reference> orbit_;  // orbit_[k]: the reference of frame (k + 1) * orbit_every
};

}  // namespace tripsitter::modes

// Feature buffers (AOVs, "arbitrary output variables") of the path tracer: what each pixel's camera rays hit
// first. The denoiser (denoise.h) is guided by them, the window's reprojection (temporal.h) finds a pixel's
// surface in the previous frame with them, and `render --aov DIR` and `--out FILE.exr` write them out.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include <tripsitter/core/image.h>
#include <tripsitter/core/vec.h>

namespace tripsitter::render {

using Vec3f = core::Vec3f;

// Per pixel, row-major, the mean over the pixel's samples:
//   albedo  the first hit's material albedo (dielectrics: their albedo, white unless given); a sample that
//           leaves the scene counts as white, so that colour / albedo is the sky's radiance there;
//   normal  the first hit's unit normal, facing the camera ray; a sample that leaves the scene counts as 0, so
//           the mean is shorter than 1 at silhouettes and 0 on the sky;
//   depth   the distance from the camera ray's origin to the first hit along its unit direction, averaged over
//           the samples that hit; infinity where none did.
struct Aovs {
  int width = 0;
  int height = 0;
  std::vector<Vec3f> albedo;
  std::vector<Vec3f> normal;
  std::vector<float> depth;

  Aovs() = default;
  Aovs(int w, int h)
      : width(w),
        height(h),
        albedo(pixels(w, h)),
        normal(pixels(w, h)),
        depth(pixels(w, h), std::numeric_limits<float>::infinity()) {}

  static std::size_t pixels(int w, int h) { return static_cast<std::size_t>(w) * static_cast<std::size_t>(h); }
};

// The buffers as 8-bit pictures (`render --aov DIR`):
//   albedo  sRGB-encoded, as the path tracer's colours are;
//   normal  each component n mapped to 255 (n + 1) / 2 (render/primary.h's normal colours; the sky is grey);
//   depth   grey by inverse depth: white at the nearest hit, black at the farthest and on the sky.
core::ImageRgb8 albedo_image(const Aovs& aovs);
core::ImageRgb8 normal_image(const Aovs& aovs);
core::ImageRgb8 depth_image(const Aovs& aovs);

}  // namespace tripsitter::render

// The denoised path-traced still (denoise.h): its samples traced in two halves, merged, and filtered.
#include <cmath>

#include <tripsitter/core/colour.h>
#include <tripsitter/render/denoise.h>

namespace tripsitter::render {
namespace {

// The still traced in the first and the second half of each pixel's sequence, merged, with each pixel's variance.
core::ImageRgbF trace_halves(const PathSettings& s, const TraceStill& trace, Aovs& aovs, std::span<float> variance) {
  PathSettings first = s, second = s;
  first.spp = s.spp / 2;
  second.spp = s.spp - first.spp;
  second.first_sample = s.first_sample + static_cast<std::uint32_t>(first.spp);
  Aovs other(s.width, s.height);
  const core::ImageRgbF a = trace(first, &aovs);
  const core::ImageRgbF b = trace(second, &other);
  return merge_halves(a, aovs, b, other, static_cast<float>(first.spp) / static_cast<float>(s.spp), variance);
}

}  // namespace

core::ImageRgbF merge_halves(const core::ImageRgbF& a, Aovs& aovs_a, const core::ImageRgbF& b, const Aovs& aovs_b,
                             float weight_a, std::span<float> variance) {
  const float wa = weight_a, wb = 1 - weight_a;
  core::ImageRgbF merged{a.width, a.height, std::vector<Vec3f>(a.pixels.size())};
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    merged.pixels[i] = a.pixels[i] * wa + b.pixels[i] * wb;
    const float d = core::luminance(a.pixels[i]) - core::luminance(b.pixels[i]);
    variance[i] = d * d / 4;
    aovs_a.albedo[i] = aovs_a.albedo[i] * wa + aovs_b.albedo[i] * wb;
    aovs_a.normal[i] = aovs_a.normal[i] * wa + aovs_b.normal[i] * wb;
    const float da = aovs_a.depth[i], db = aovs_b.depth[i];
    aovs_a.depth[i] = std::isinf(da) ? db : std::isinf(db) ? da : da * wa + db * wb;
  }
  return merged;
}

core::ImageRgbF denoised_still(const PathSettings& s, const TraceStill& trace, Denoiser& denoiser, Aovs& aovs) {
  core::ImageRgbF image;
  std::vector<float> variance(Aovs::pixels(s.width, s.height));
  if (s.spp >= 2) {
    image = trace_halves(s, trace, aovs, variance);
  } else {
    image = trace(s, &aovs);
    denoiser.estimate_variance({.width = s.width, .height = s.height, .color = image.pixels, .variance = {}, .aovs = &aovs},
                               DenoiseSettings{}.variance_radius, s.threads, variance);
  }
  DenoiseSettings filter;
  filter.threads = s.threads;
  denoiser.denoise({.width = s.width, .height = s.height, .color = image.pixels, .variance = variance, .aovs = &aovs},
                   filter, image.pixels);
  return image;
}

}  // namespace tripsitter::render

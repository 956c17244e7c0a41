#include <tripsitter/render/aov.h>

#include <algorithm>
#include <cmath>

#include <tripsitter/core/colour.h>
#include <tripsitter/render/primary.h>

namespace tripsitter::render {

core::ImageRgb8 albedo_image(const Aovs& aovs) {
  core::ImageRgb8 out(aovs.width, aovs.height);
  core::encode_srgb8(aovs.albedo.data(), aovs.albedo.size(), 1.0f, out.pixels.data());
  return out;
}

core::ImageRgb8 normal_image(const Aovs& aovs) {
  core::ImageRgb8 out(aovs.width, aovs.height);
  for (std::size_t i = 0; i < aovs.normal.size(); ++i) normal_to_rgb8(aovs.normal[i], &out.pixels[3 * i]);
  return out;
}

core::ImageRgb8 depth_image(const Aovs& aovs) {
  core::ImageRgb8 out(aovs.width, aovs.height);
  // Grey by inverse depth: a ground plane reaching the horizon would leave linear depth no range for the rest.
  float nearest = INFINITY, farthest = 0;
  for (float d : aovs.depth) {
    if (!std::isfinite(d)) continue;
    nearest = std::min(nearest, d);
    farthest = std::max(farthest, d);
  }
  const float near_inv = 1.0f / nearest, far_inv = 1.0f / farthest;
  const float span = near_inv > far_inv ? near_inv - far_inv : 1.0f;
  for (std::size_t i = 0; i < aovs.depth.size(); ++i) {
    const float d = aovs.depth[i];
    const float grey = std::isfinite(d) ? 255.0f * (1.0f / d - far_inv) / span : 0.0f;
    const auto level = static_cast<std::uint8_t>(std::lround(std::clamp(grey, 0.0f, 255.0f)));
    std::fill_n(&out.pixels[3 * i], 3, level);
  }
  return out;
}

}  // namespace tripsitter::render

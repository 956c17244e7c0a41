// Primary rays: one ray per pixel from the camera's eye through the pixel's centre, shaded by the normal of
// what it hits (black where it hits nothing). The float renderer that `tripsitter bench` measures as
// primary_mrays_N and compares with Embree.
#pragma once

#include <cstdint>

#include <tripsitter/core/image.h>
#include <tripsitter/render/aov.h>
#include <tripsitter/render/camera.h>
#include <tripsitter/render/path_tracer.h>

namespace tripsitter::render {

struct PrimarySettings {
  int width = 640;
  int height = 480;
  int threads = 0;  // 0: all hardware threads
};

// The colour of a unit normal: each component n mapped to 255 (n + 1) / 2, rounded down.
inline void normal_to_rgb8(const Vec3f& n, std::uint8_t* rgb) {
  const float c[3] = {n.x, n.y, n.z};
  for (int k = 0; k < 3; ++k) {
    const float v = 127.5f * (c[k] + 1.0f);
    rgb[k] = static_cast<std::uint8_t>(v < 0.0f ? 0.0f : (v > 255.0f ? 255.0f : v));
  }
}

// The pixel's colour for a ray and its closest hit, the same for every tracer the benchmark compares.
inline void shade_primary(const PathScene& scene, const Ray& ray, const SphereHit& hit, std::uint8_t* rgb) {
  normal_to_rgb8(core::normalize(ray.at(hit.t) - scene.center(hit.sphere)), rgb);
}

// Renders width x height pixels (REQUIRES the camera made for that size).
core::ImageRgb8 render_primary(const PathScene& scene, const ThinLensCamera& camera, const PrimarySettings& settings);

// The feature buffers (aov.h) of the same rays, one per pixel through its centre from the lens centre: a sharp
// G-buffer, the same from frame to frame for a still camera, where the path tracer's own buffers average jittered
// samples. The window's path mode reprojects and denoises with it. `aovs` is resized to the settings' size.
void render_primary_aovs(const PathScene& scene, const ThinLensCamera& camera, const PrimarySettings& settings,
                         Aovs& aovs);

}  // namespace tripsitter::render

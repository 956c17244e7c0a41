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

// Which surfaces the denoiser's guides look into (render_primary_guides).
struct GuideSettings {
  // Metal at most this fuzzy is a mirror: its reflection is sharp enough to have edges worth keeping. Negative:
  // no surface is, and the guides are the first hits everywhere.
  float max_fuzz = 0.1f;
  int max_bounces = 4;  // mirrors followed at most, one after another
};

// render_primary_aovs's buffers in `first_hits`, and in `guides` the same except where the centre ray first hits
// a mirror (GuideSettings): there the ray is reflected, from mirror to mirror, until it meets a surface of another
// kind or the sky, and the guides are that surface's normal (facing the ray; 0 on the sky), the length of the
// whole chain as depth (infinity on the sky), and its albedo times every mirror's tint on the way (the sky
// counts as white, as in Aovs). A reflection then has the edges and the paint of what it shows, so the denoiser
// keeps it sharp and demodulates it as it does the surface itself; with the first hits alone the mirror is one
// smooth surface to the filter, and the reflected spheres blur away. Glass is not looked through: measured on
// `field`, following the refracted (or, above a Fresnel reflectance of one half, reflected) ray made the window's
// pictures worse (docs/denoiser.md). Both buffers are resized to the settings' size.
void render_primary_guides(const PathScene& scene, const ThinLensCamera& camera, const PrimarySettings& settings,
                           const GuideSettings& guide, Aovs& first_hits, Aovs& guides);

}  // namespace tripsitter::render

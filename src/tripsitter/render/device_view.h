// The float path tracer in the device's view (SPEC.md section B): the reference for the device's fixed-point path
// tracer, tracing the device's own rays so that the two images compare pixel for pixel.
#pragma once

#include <cstdint>
#include <functional>
#include <span>

#include <tripsitter/render/path_tracer.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::render {

// The device's view: spheres in view space (camera at the origin, x right, y down, z ahead, pixel units); the camera
// ray of pixel (col, row) on the 640 x 480 screen is exactly core::device_ray: origin 0, direction
// (col - 320, row - 240, 320), no jitter, no lens. The light is the path tracer's Sky as a function of direction
// with "up" being -y of view space: the device has no up vector on its wire, so its sky is fixed to the view.
// The reference traces the view scaled down by this (it is the same image at any scale: every ray starts at the
// camera, and directions, normals and the sky do not change), because the path tracer's kRayEpsilon (10^-3) is
// meant for world units: at the device's own scale, a floor of radius 10^4 pixels 10^4 pixels away, a float hit
// point is good to about 10^-3 and bounced rays meet the surface they leave again (black speckles). At 1/256 the
// coordinates of a device's world stay below about 50.
inline constexpr float kDeviceViewPixelsPerUnit = 256;

struct DeviceViewSettings {
  int spp = 64;        // >= 1
  int max_depth = 4;   // rays per path, as PathSettings::max_depth and trace_path; >= 1
  std::uint64_t seed = 1;
  int threads = 0;     // 0: every core (core::parallel_for)
  Sky sky;
};

// Renders 640 x 480 linear radiance: each pixel the mean of spp paths of trace_path along its device ray. The same
// seed gives the same image whatever the thread count: pixel (col, row) draws from its own stream,
// RngStreams(seed).stream(row * 640 + col), as in the path tracer. `on_row(row)` is called, from the worker thread
// that traced it, as each row is written.
core::ImageRgbF render_device_view(std::span<const scene::Sphere> view_spheres, const DeviceViewSettings& settings,
                                   const std::function<void(int row)>& on_row = {});

// A linear comparison of an image against a reference of the same size, over every pixel and channel.
struct LinearComparison {
  double mean_relative_bias = 0;  // (mean of x - mean of ref) / mean of ref; 0 when the reference's mean is 0
  double relmse = 0;              // mean of (x - ref)^2 / (ref^2 + 0.01)
};
// Throws std::invalid_argument when the sizes differ. Two empty images compare as {0, 0}.
LinearComparison compare_linear(const core::ImageRgbF& image, const core::ImageRgbF& reference);

}  // namespace tripsitter::render

// A device's frame against the float renderers (`tripsitter render --mode hw --compare`, and each point of
// `tripsitter explore`): compare_device decides how. A normal-shaded frame is compared level by level with the
// float renderer's frame of the same world from the same camera. A path-traced picture (the path preset on a
// framed wire), what the device accumulated in frame memory as linear light, is compared with
// render::render_device_view of the world in its scene memory, under the same sky and with the same number of
// rays per path.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <variant>
#include <vector>

#include <tripsitter/core/image.h>
#include <tripsitter/device/frame_memory.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/modes/frame_source.h>
#include <tripsitter/render/device_view.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::modes {

// The world in scene memory as the float renderers take it: view space in the device's pixel units (centre and
// radius raw / 2^frac_bits), albedo byte / 255, fuzz / 65535, ior / 4096, the wire's material code as the
// material type (an unknown code, which the receiver never accepts, reads as lambertian).
std::vector<scene::Sphere> scene_memory_spheres(const device::SceneMemory& memory, int frac_bits);

// Frame memory as linear light: each pixel's mean (device::entry_mean). Pixels without a sample (count 0: late in
// every frame, or never traced) are black in `mean` and 0 in `counts`.
//
// Frame memory does not say which entries belong to the world shown: an entry left from an earlier world by a
// pixel late ever since reads as that world's. The board must have shown worlds of one content since its reset
// (as `render` does) for the image to be the world's alone.
struct AccumulatedImage {
  core::ImageRgbF mean;            // 640 x 480
  std::vector<std::uint8_t> counts;  // samples per pixel, row by row
  std::size_t without_samples = 0;   // pixels of count 0
  int min_count = 0;                 // over the pixels with samples (0 when there are none)
  int max_count = 0;
};
AccumulatedImage accumulated_image(const device::FrameMemory& memory);

struct PathComparisonSettings {
  int reference_spp = 0;   // 0: max(256, 4 x the device's samples per pixel)
  std::uint64_t seed = 1;  // the reference's
  int threads = 0;         // the reference's (0: every core)
  std::function<void(int row)> on_row;  // the reference's progress, from its worker threads
  // The reference rendered already (device_path_reference of a frame of the same world, with the same settings), for callers
  // that compare many frames of one world; null: rendered here.
  const core::ImageRgbF* reference = nullptr;
};

// The figures over a subset of the pixels with samples.
struct PartComparison {
  std::size_t pixels = 0;
  render::LinearComparison figures;  // {0, 0} when there are no pixels
};

struct PathComparison {
  render::LinearComparison figures;   // over the pixels with samples, every channel
  // The same by what the pixel's camera ray meets first in the float world (the sky, or a sphere of each material),
  // so that a bias of one material is not drowned by the sky around it. Indexed by scene::MaterialType.
  PartComparison sky;
  std::array<PartComparison, 3> material;
  int device_spp = 0;                 // FrameStats::samples_per_pixel: what each pixel on time in every frame has
  int min_spp = 0, max_spp = 0;       // the counts in frame memory, over the pixels with samples
  int reference_spp = 0;
  int depth = 0;                      // rays per path, the device's and the reference's
  std::size_t pixels = 0;             // 640 x 480
  std::size_t pixels_compared = 0;
  std::size_t pixels_without_samples = 0;  // left out of the figures
  int late_pixels = 0, late_lines = 0;     // of the last frame
  std::size_t spheres = 0;            // in scene memory
};

// The default reference: max(256, 4 x device_spp) samples per pixel.
int default_reference_spp(int device_spp);

// The float path tracer's picture compare_device_path compares the frame with: render_device_view of the world in
// its scene memory at settings.reference_spp (0: the default for the frame's samples) and the preset's depth.
core::ImageRgbF device_path_reference(const HwFrame& frame, const device::DevicePreset& preset,
                                        const PathComparisonSettings& settings);

// Compares an hw frame of a path-tracing preset (frame.frame_memory set; the frame's world in frame.scene_memory)
// with render_device_view of its scene memory at settings.reference_spp samples per pixel and the preset's depth.
// Throws std::invalid_argument for a frame without frame memory or a preset without path.
PathComparison compare_device_path(const HwFrame& frame, const device::DevicePreset& preset,
                                   const PathComparisonSettings& settings);

// The comparison `--compare` makes of an hw frame drawn from `scene` with `config` (the frame source's): on a
// preset and wire that trace paths (device::traces_paths) compare_device_path with `path_settings`, otherwise the
// frame's VGA image against normal mode's frame of the same world and camera.
using DeviceComparison = std::variant<core::ImageDiff, PathComparison>;
DeviceComparison compare_device(const scene::Scene& scene, const SourceConfig& config, const HwFrame& frame,
                                const PathComparisonSettings& path_settings);

}  // namespace tripsitter::modes

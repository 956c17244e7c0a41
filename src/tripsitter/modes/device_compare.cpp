#include <tripsitter/modes/device_compare.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <tripsitter/core/screen.h>
#include <tripsitter/link/frame.h>

namespace tripsitter::modes {

std::vector<scene::Sphere> scene_memory_spheres(const device::SceneMemory& memory, int frac_bits) {
  const double unit = std::ldexp(1.0, -frac_bits);
  std::vector<scene::Sphere> out;
  out.reserve(memory.geometry.size());
  for (std::size_t i = 0; i < memory.geometry.size(); ++i) {
    const auto& g = memory.geometry[i];
    scene::Sphere s;
    s.center = {static_cast<double>(g.center.x) * unit, static_cast<double>(g.center.y) * unit,
                static_cast<double>(g.center.z) * unit};
    s.radius = static_cast<double>(g.radius) * unit;
    if (i < memory.surfaces.size()) {
      const device::SurfaceWord& w = memory.surfaces[i];
      switch (w.material) {
        case link::kMaterialMetal: s.material.type = scene::MaterialType::kMetal; break;
        case link::kMaterialDielectric: s.material.type = scene::MaterialType::kDielectric; break;
        default: s.material.type = scene::MaterialType::kLambertian; break;
      }
      s.material.albedo = {w.albedo[0] / 255.0, w.albedo[1] / 255.0, w.albedo[2] / 255.0};
      s.material.fuzz = w.fuzz / link::kFuzzScale;
      s.material.ior = w.ior / link::kIorScale;
    }
    out.push_back(s);
  }
  return out;
}

AccumulatedImage accumulated_image(const device::FrameMemory& memory) {
  constexpr int kW = core::kScreenWidth, kH = core::kScreenHeight;
  AccumulatedImage out;
  out.mean = {kW, kH, std::vector<render::Vec3f>(std::size_t{kW} * std::size_t{kH})};
  const std::span<const device::AccumEntry> entries = memory.entries();
  out.counts.resize(entries.size());
  int lo = device::kMaxSamples + 1, hi = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const device::AccumEntry& e = entries[i];
    out.counts[i] = e.count;
    if (e.count == 0) {
      ++out.without_samples;
      continue;
    }
    lo = std::min<int>(lo, e.count);
    hi = std::max<int>(hi, e.count);
    const std::array<double, 3> m = device::entry_mean(e);
    out.mean.pixels[i] = {static_cast<float>(m[0]), static_cast<float>(m[1]), static_cast<float>(m[2])};
  }
  if (hi > 0) {
    out.min_count = lo;
    out.max_count = hi;
  }
  return out;
}

int default_reference_spp(int device_spp) { return std::max(256, 4 * device_spp); }

core::ImageRgbF device_path_reference(const HwFrame& frame, const device::DevicePreset& preset,
                                        const PathComparisonSettings& settings) {
  if (!preset.path) throw std::invalid_argument("device_path_reference: preset " + preset.name + " does not path-trace");
  if (frame.scene_memory == nullptr)
    throw std::invalid_argument("device_path_reference: the frame carries no scene memory (not an hw frame)");
  render::DeviceViewSettings s;
  s.spp = settings.reference_spp > 0 ? settings.reference_spp : default_reference_spp(frame.device.samples_per_pixel);
  s.max_depth = preset.path->depth;
  s.seed = settings.seed;
  s.threads = settings.threads;
  return render::render_device_view(scene_memory_spheres(*frame.scene_memory, preset.frac_bits()), s, settings.on_row);
}

PathComparison compare_device_path(const HwFrame& frame, const device::DevicePreset& preset,
                                   const PathComparisonSettings& settings) {
  if (!preset.path) throw std::invalid_argument("compare_device_path: preset " + preset.name + " does not path-trace");
  if (frame.frame_memory == nullptr || frame.scene_memory == nullptr)
    throw std::invalid_argument("compare_device_path: the frame carries no frame memory (not an hw frame of a path preset)");
  PathComparison out;
  const AccumulatedImage device_image = accumulated_image(*frame.frame_memory);
  const std::vector<scene::Sphere> view = scene_memory_spheres(*frame.scene_memory, preset.frac_bits());
  out.device_spp = frame.device.samples_per_pixel;
  out.min_spp = device_image.min_count;
  out.max_spp = device_image.max_count;
  out.reference_spp = settings.reference_spp > 0 ? settings.reference_spp : default_reference_spp(out.device_spp);
  out.depth = preset.path->depth;
  out.pixels = device_image.counts.size();
  out.pixels_without_samples = device_image.without_samples;
  out.pixels_compared = out.pixels - out.pixels_without_samples;
  out.late_pixels = frame.device.late_pixels;
  out.late_lines = frame.device.late_lines;
  out.spheres = view.size();

  const core::ImageRgbF rendered = settings.reference != nullptr ? core::ImageRgbF{}
                                                                   : device_path_reference(frame, preset, settings);
  const core::ImageRgbF& reference = settings.reference != nullptr ? *settings.reference : rendered;

  // Each part's pixels with samples, in both images, as one row each: compare_linear over them alone. Part 0 is
  // every pixel, 1 the sky, 2 + t the spheres of material type t met first by the camera ray.
  constexpr std::size_t kParts = 5;
  std::array<core::ImageRgbF, kParts> part_image, part_reference;
  const render::PathScene world(view);
  for (std::size_t i = 0; i < device_image.counts.size(); ++i) {
    if (device_image.counts[i] == 0) continue;
    const int col = static_cast<int>(i % core::kScreenWidth), row = static_cast<int>(i / core::kScreenWidth);
    const render::Vec3f d = core::device_ray<float>(col, row);
    render::SphereHit hit;
    const bool met = world.intersect({{0, 0, 0}, d}, 0.0f, INFINITY, hit);
    const std::size_t part = met ? 2 + static_cast<std::size_t>(view[hit.sphere].material.type) : 1;
    for (std::size_t p : {std::size_t{0}, part}) {
      part_image[p].pixels.push_back(device_image.mean.pixels[i]);
      part_reference[p].pixels.push_back(reference.pixels[i]);
    }
  }
  std::array<PartComparison, kParts> parts;
  for (std::size_t p = 0; p < kParts; ++p) {
    for (auto* image : {&part_image[p], &part_reference[p]}) {
      image->width = static_cast<int>(image->pixels.size());
      image->height = 1;
    }
    parts[p] = {part_image[p].pixels.size(), render::compare_linear(part_image[p], part_reference[p])};
  }
  out.figures = parts[0].figures;
  out.sky = parts[1];
  for (std::size_t t = 0; t < out.material.size(); ++t) out.material[t] = parts[2 + t];
  return out;
}

DeviceComparison compare_device(const scene::Scene& scene, const SourceConfig& config, const HwFrame& frame,
                                const PathComparisonSettings& path_settings) {
  if (device::traces_paths(config.board.preset, config.board.wire))
    return compare_device_path(frame, config.board.preset, path_settings);
  SourceConfig reference = config;
  reference.mode = Mode::kNormal;
  reference.probe = {};
  reference.board.make_device = {};
  return core::diff(frame.vga, std::get<NormalFrame>(make_frame_source(scene, reference)->draw()).vga);
}

}  // namespace tripsitter::modes

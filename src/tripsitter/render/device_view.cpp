#include <tripsitter/render/device_view.h>

#include <stdexcept>
#include <vector>

#include <tripsitter/core/parallel.h>
#include <tripsitter/core/screen.h>

namespace tripsitter::render {
namespace {

// View space has y down and the device's sky has up = -y, where Sky's up is +y. Mirroring the scene and the rays in
// y maps one onto the other exactly: a mirror is an isometry, so every hit, normal and material (whose scattering
// is the same in distribution under any isometry) behaves as in the unmirrored view, and Sky then applies unchanged.
// The spheres are also scaled by 1 / kDeviceViewPixelsPerUnit (a similarity about the camera: the same image).
std::vector<scene::Sphere> mirrored_in_y(std::span<const scene::Sphere> spheres) {
  std::vector<scene::Sphere> mirrored(spheres.begin(), spheres.end());
  const double scale = 1.0 / kDeviceViewPixelsPerUnit;
  for (auto& s : mirrored) {
    s.center = {s.center.x * scale, -s.center.y * scale, s.center.z * scale};
    s.radius *= scale;
  }
  return mirrored;
}

}  // namespace

core::ImageRgbF render_device_view(std::span<const scene::Sphere> view_spheres, const DeviceViewSettings& settings,
                                   const std::function<void(int row)>& on_row) {
  constexpr int kWidth = core::kScreenWidth, kHeight = core::kScreenHeight;
  const PathScene scene(mirrored_in_y(view_spheres));
  core::ImageRgbF image{kWidth, kHeight, std::vector<Vec3f>(std::size_t{kWidth} * std::size_t{kHeight})};
  const RngStreams streams(settings.seed);
  const float inv_spp = 1.0f / static_cast<float>(settings.spp);
  core::parallel_for(0, kHeight, settings.threads, [&](int row) {
    for (int col = 0; col < kWidth; ++col) {
      const auto pixel = static_cast<std::size_t>(row) * kWidth + static_cast<std::size_t>(col);
      Rng rng = streams.stream(pixel);
      // The device's ray unnormalised, as on the device (trace_path accepts any length; the Sky normalises).
      const Vec3f d = core::device_ray<float>(col, row);
      const Ray ray{{0, 0, 0}, {d.x, -d.y, d.z}};
      Vec3f sum{0, 0, 0};
      for (int s = 0; s < settings.spp; ++s) sum += trace_path(scene, ray, settings.max_depth, settings.sky, rng);
      image.pixels[pixel] = sum * inv_spp;
    }
    if (on_row) on_row(row);
  });
  return image;
}

LinearComparison compare_linear(const core::ImageRgbF& image, const core::ImageRgbF& reference) {
  if (image.width != reference.width || image.height != reference.height ||
      image.pixels.size() != reference.pixels.size())
    throw std::invalid_argument("compare_linear: the image and the reference differ in size");
  if (image.pixels.empty()) return {};
  double sum = 0, sum_ref = 0, sum_rel = 0;
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const double x = image.pixels[i][k], ref = reference.pixels[i][k];
      sum += x;
      sum_ref += ref;
      sum_rel += (x - ref) * (x - ref) / (ref * ref + 0.01);
    }
  }
  // The means share their count, so the bias is a ratio of sums.
  const double n = 3.0 * static_cast<double>(image.pixels.size());
  return {sum_ref != 0 ? (sum - sum_ref) / sum_ref : 0.0, sum_rel / n};
}

}  // namespace tripsitter::render

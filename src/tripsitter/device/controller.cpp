#include <tripsitter/device/controller.h>

namespace tripsitter::device {

Controller::Controller(const DevicePreset& preset) : preset_(preset), worker_(preset.sqrt_iterations) {}

int Controller::pixels_in_time(std::int64_t spheres) const {
  const int per_worker = (kLineWidth + preset_.workers - 1) / preset_.workers;
  int k = 0;
  while (k < per_worker && preset_.finish_cycle(k, spheres) <= preset_.lead_cycles) ++k;
  return k;
}

LineResult Controller::render_line(int row, const SceneMemory& scene, std::span<core::Rgb444> line) const {
  LineResult result;
  const int in_time = pixels_in_time(static_cast<std::int64_t>(scene.geometry.size()));
  for (int w = 0; w < preset_.workers; ++w) {
    int k = 0;
    for (int col = w; col < kLineWidth; col += preset_.workers, ++k) {
      if (k < in_time) {
        line[static_cast<std::size_t>(col)] = worker_.shade(col, row, scene);
      } else {
        line[static_cast<std::size_t>(col)] = core::kBlack;
        ++result.late_pixels;
      }
    }
  }
  return result;
}

}  // namespace tripsitter::device

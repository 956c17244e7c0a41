#include <tripsitter/device/controller.h>

namespace tripsitter::device {

Controller::Controller(const DevicePreset& preset) : preset_(preset), worker_(preset) {}

int Controller::pixels_in_time(std::int64_t spheres) const {
  const int per_worker = (kLineWidth + preset_.workers - 1) / preset_.workers;
  int k = 0;
  while (k < per_worker && preset_.finish_cycle(k, spheres) <= preset_.lead_cycles) ++k;
  return k;
}

LineResult Controller::render_line(int row, const SceneMemory& scene, std::span<core::Rgb444> line) const {
  LineResult result;
  const auto spheres = static_cast<std::int64_t>(scene.geometry.size());
  const std::int64_t drain = preset_.drain_cycles();
  for (int w = 0; w < preset_.workers; ++w) {
    std::int64_t busy = 0;  // cycles from the start of the line until the worker may start its next pixel
    bool late = false;      // once one pixel is late, every later pixel of the worker is too
    for (int col = w; col < kLineWidth; col += preset_.workers) {
      core::Rgb444& slot = line[static_cast<std::size_t>(col)];
      if (!late) {
        const core::PixelTrace t = worker_.trace(col, row, scene);
        busy += preset_.pixel_occupancy(spheres, t.bounces);
        late = busy + drain > preset_.lead_cycles;
        if (!late) {
          slot = t.colour;
          result.reflections += t.bounces;
          continue;
        }
      }
      slot = core::kBlack;
      ++result.late_pixels;
    }
  }
  return result;
}

}  // namespace tripsitter::device

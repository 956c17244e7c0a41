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
  return schedule_line(preset_, static_cast<std::int64_t>(scene.geometry.size()), line,
                       [&](int col) { return worker_.trace(col, row, scene); });
}

}  // namespace tripsitter::device

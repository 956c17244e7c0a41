#include <tripsitter/device/controller.h>

#include <tripsitter/device/artix_units.h>

namespace tripsitter::device {

Controller::Controller(const DevicePreset& preset) : preset_(preset), worker_(preset) {}

int Controller::pixels_in_time(std::int64_t spheres) const {
  const int per_worker = (kLineWidth + preset_.workers - 1) / preset_.workers;
  int k = 0;
  while (k < per_worker && preset_.finish_cycle(k, spheres) <= preset_.lead_cycles) ++k;
  return k;
}

LineResult Controller::render_line(int row, const SceneMemory& scene, std::span<core::Rgb444> line) const {
  if (preset_.units) return artix::render_line(preset_, artix::prepare_world(scene), row, line, artix::Search::kAll);
  return schedule_line(preset_, static_cast<std::int64_t>(scene.geometry.size()), line,
                       [&](int col) { return worker_.trace(col, row, scene); });
}

LineResult Controller::render_path_line(int row, const SceneMemory& scene, const PathFrame& frame,
                                        std::span<AccumEntry> memory, std::span<core::Rgb444> line,
                                        PathCounters& counters) const {
  if (preset_.units)
    return artix::render_path_line(preset_, artix::prepare_world(scene), row, frame, memory, line, counters,
                                   artix::Search::kAll);
  const std::span<const core::KernelSphere<std::int64_t>> spheres(scene.geometry);
  const FixedArith& arith = worker_.arith();
  const auto closest = [&](const PathRay& path) {
    return with_far_side(arith, path, core::closest_hit(arith, path.ray, spheres, path.from), spheres);
  };
  return schedule_path_line(preset_, static_cast<std::int64_t>(spheres.size()), line, memory, [&](int col) {
    return trace_path_pixel(arith, col, row, memory[static_cast<std::size_t>(col)], spheres, frame, counters, closest);
  });
}

}  // namespace tripsitter::device

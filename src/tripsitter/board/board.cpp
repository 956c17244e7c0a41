#include <tripsitter/board/board.h>

#include <stdexcept>

namespace tripsitter::board {

link::SceneFormats formats_of(const device::DevicePreset& preset) {
  return {preset.x, preset.y, preset.z, preset.radius, preset.max_spheres};
}

Board::Board(scene::Scene scene, BoardConfig config)
    : config_(config),
      host_(std::move(scene), formats_of(config.preset), config.wire),
      link_(config.spi),
      device_(config.preset, config.wire, config.device_threads, config.device_model) {}

ShownFrame Board::show(const std::function<void(const device::VgaSample&)>& probe) {
  const host::ReadyWorld& world = host_.update();
  link_.submit(world.bytes);
  const auto run = [&] {
    return device_.run_frame_lines([&](std::span<const device::VgaSample> line) {
      for (const device::VgaSample& s : line) monitor_.sample(s);
      if (probe)
        for (const device::VgaSample& s : line) probe(s);
    });
  };
  // A device still holding an earlier world for its next blanking lowers ready: let it show that one first.
  for (int tries = 0; !link_.pump(device_); ++tries) {
    if (tries == 2) throw std::logic_error("device never raised its ready line");
    run();
    monitor_.take_frame();
  }
  ShownFrame shown;
  shown.device = run();
  auto frame = monitor_.take_frame();
  if (!frame) throw std::logic_error("monitor did not capture a frame");
  shown.image = std::move(*frame);
  shown.saturations = world.saturations;
  shown.link_bytes = world.bytes.size();
  shown.link_seconds = link_.seconds_for(world.bytes.size());
  shown.spheres_dropped = world.spheres_dropped;
  return shown;
}

}  // namespace tripsitter::board

#include <tripsitter/board/board.h>

#include <stdexcept>

#include <tripsitter/board/capture.h>
#include <tripsitter/device/path_kernel.h>

namespace tripsitter::board {

link::SceneFormats formats_of(const device::DevicePreset& preset) {
  link::SceneFormats f{preset.x, preset.y, preset.z, preset.radius, preset.max_spheres};
  if (preset.path) {
    f.ior_min = device::kPathIorMin;
    f.ior_max = device::kPathIorMax;
  }
  f.hierarchy = preset.walks_hierarchy();
  return f;
}

Board::Board(scene::Scene scene, BoardConfig config)
    : config_(config),
      host_(std::move(scene), formats_of(config.preset), config.wire),
      link_(config.spi, link::Numbering(config.wire, config.session)),
      device_(config.make_device ? config.make_device()
                                 : std::make_unique<device::Device>(config.preset, config.wire, config.device_threads,
                                                                    config.device_model)) {}

ShownFrame Board::show(const std::function<void(const device::VgaSample&)>& probe) {
  const host::ReadyWorld& world = host_.update();
  link_.submit(world.bytes);
  // A device still holding an earlier world for its next blanking lowers ready: let it show that one first.
  for (int tries = 0; !link_.pump(*device_); ++tries) {
    if (tries == 2) throw std::logic_error("device never raised its ready line");
    capture_frame(*device_, monitor_, probe);
  }
  CapturedFrame captured = capture_frame(*device_, monitor_, probe);
  ShownFrame shown;
  shown.device = captured.stats;
  shown.image = std::move(captured.image);
  shown.saturations = world.saturations;
  shown.link_bytes = world.bytes.size();
  shown.link_seconds = link_.seconds_for(world.bytes.size());
  shown.spheres_dropped = world.spheres_dropped;
  return shown;
}

}  // namespace tripsitter::board

#include <tripsitter/board/capture.h>

#include <stdexcept>

namespace tripsitter::board {

CapturedFrame capture_frame(device::Backend& device, display::VgaMonitor& monitor,
                            const std::function<void(const device::VgaSample&)>& probe) {
  CapturedFrame captured;
  captured.stats = device.run_frame_lines([&](std::span<const device::VgaSample> line) {
    for (const device::VgaSample& s : line) monitor.sample(s);
    if (probe)
      for (const device::VgaSample& s : line) probe(s);
  });
  auto frame = monitor.take_frame();
  if (!frame) throw std::logic_error("the monitor did not capture the device's frame");
  captured.image = std::move(*frame);
  return captured;
}

}  // namespace tripsitter::board

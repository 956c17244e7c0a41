// The ray-tracing controller: hands the 640 pixels of the next line to N workers, interleaved (worker i
// takes columns i, i + N, i + 2N, ...), and collects their colours into the back line buffer within the
// line's cycle budget. A pixel not finished in time stays black, as on the board.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/device/worker.h>

namespace tripsitter::device {

struct LineResult {
  int late_pixels = 0;  // pixels whose worker had not finished them when the line was due
};

class Controller {
 public:
  explicit Controller(const DevicePreset& preset);

  // Fills `line` (640 pixels) with row `row` of the image of `scene`. Each worker clears a pixel's slot
  // when it starts it, so late pixels are black.
  LineResult render_line(int row, const SceneMemory& scene, std::span<core::Rgb444> line) const;

  // How many pixels each worker finishes within the lead time, with `spheres` spheres (0..64 per worker).
  int pixels_in_time(std::int64_t spheres) const;

 private:
  DevicePreset preset_;
  Worker worker_;  // the workers are identical and stateless between pixels, so one model serves all N
};

}  // namespace tripsitter::device

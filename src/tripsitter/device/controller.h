// The ray-tracing controller: hands the 640 pixels of the next line to N workers, interleaved (worker i
// takes columns i, i + N, i + 2N, ...), and collects their colours into the back line buffer within the
// line's cycle budget. A pixel not finished in time stays black, as on the board. The schedule depends on
// the data: a pixel that reflects off metals costs its worker more passes over the spheres.
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
  int reflections = 0;  // reflections traced for the pixels that were on time
};

class Controller {
 public:
  explicit Controller(const DevicePreset& preset);

  // Fills `line` (640 pixels) with row `row` of the image of `scene`. Each worker clears a pixel's slot
  // when it starts it, so late pixels are black. A worker's pixel k is ready after the occupancies of its
  // pixels 0..k (each from its own bounce count) plus the drain (DevicePreset::pixel_occupancy); it is
  // late when that exceeds the lead time, and so are all the worker's later pixels.
  LineResult render_line(int row, const SceneMemory& scene, std::span<core::Rgb444> line) const;

  // How many pixels each worker finishes within the lead time, with `spheres` spheres, when no pixel
  // reflects (0..64 per worker with 10 workers).
  int pixels_in_time(std::int64_t spheres) const;

 private:
  DevicePreset preset_;
  Worker worker_;  // the workers are identical and stateless between pixels, so one model serves all N
};

}  // namespace tripsitter::device

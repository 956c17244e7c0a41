// The ray-tracing controller: hands the 640 pixels of the next line to N workers, interleaved (worker i
// takes columns i, i + N, i + 2N, ...), and collects their colours into the back line buffer within the
// line's cycle budget. A pixel not finished in time stays black, as on the board. The schedule depends on
// the data: a pixel that reflects off metals costs its worker more passes over the spheres.
#pragma once

#include <array>
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

// The controller's schedule of one line, whatever computes the pixels: trace(col) returns the
// core::PixelTrace of column col (its colour and bounce count), and is called in each worker's order for
// the pixels that start on time only. Each worker clears a pixel's slot when it starts it, so late pixels
// are black. A worker's pixel k is ready after the occupancies of its pixels 0..k (each from its own bounce
// count) plus the drain (DevicePreset::pixel_occupancy); it is late when that exceeds the lead time, and
// so are all the worker's later pixels.
template <class Trace>
LineResult schedule_line(const DevicePreset& preset, std::int64_t spheres, std::span<core::Rgb444> line,
                         const Trace& trace) {
  LineResult result;
  const std::int64_t drain = preset.drain_cycles();
  std::array<std::int64_t, core::kMaxBounces + 1> occupancy{};  // by bounce count
  for (int k = 0; k <= core::kMaxBounces; ++k) occupancy[static_cast<std::size_t>(k)] = preset.pixel_occupancy(spheres, k);
  for (int w = 0; w < preset.workers; ++w) {
    std::int64_t busy = 0;  // cycles from the start of the line until the worker may start its next pixel
    bool late = false;      // once one pixel is late, every later pixel of the worker is too
    for (int col = w; col < kLineWidth; col += preset.workers) {
      core::Rgb444& slot = line[static_cast<std::size_t>(col)];
      if (!late) {
        const core::PixelTrace t = trace(col);
        busy += occupancy[static_cast<std::size_t>(t.bounces)];
        late = busy + drain > preset.lead_cycles;
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

class Controller {
 public:
  explicit Controller(const DevicePreset& preset);

  // Fills `line` (640 pixels) with row `row` of the image of `scene`: the worker's pixels on
  // schedule_line's schedule.
  LineResult render_line(int row, const SceneMemory& scene, std::span<core::Rgb444> line) const;

  // How many pixels each worker finishes within the lead time, with `spheres` spheres, when no pixel
  // reflects (0..64 per worker with 10 workers).
  int pixels_in_time(std::int64_t spheres) const;

 private:
  DevicePreset preset_;
  Worker worker_;  // the workers are identical and stateless between pixels, so one model serves all N
};

}  // namespace tripsitter::device

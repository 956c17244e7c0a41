// The ray-tracing controller: hands the 640 pixels of the next line to N workers, interleaved (worker i
// takes columns i, i + N, i + 2N, ...), and collects their colours into the back line buffer within the
// line's cycle budget. A pixel not finished in time stays black, as on the board. The schedule depends on
// the data: a pixel that reflects off metals costs its worker more passes over the spheres.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/device/frame_memory.h>
#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/device/worker.h>

namespace tripsitter::device {

struct LineResult {
  int late_pixels = 0;  // pixels whose worker had not finished them when the line was due
  int reflections = 0;  // reflections traced for the pixels that were on time (mirror model)
  int rays = 0;         // rays traced for the pixels that were on time (path preset)
  // The line's demand: cycles from the start of its work until its busiest worker has the colour of its last
  // pixel (the occupancies of all the worker's pixels plus the drain), on time or not. Exact when no pixel is
  // late (then at most the lead time) or when DevicePreset::demand_exact(); otherwise a lower bound above the
  // lead time (schedule_pixels).
  std::int64_t demand_cycles = 0;
};

// What schedule_pixels found for a line.
struct LineSchedule {
  int late_pixels = 0;
  std::int64_t demand_cycles = 0;  // LineResult::demand_cycles
};

// The controller's schedule of one line, whatever computes the pixels: work(col) computes column col's pixel,
// occupancy(pixel) is the cycles it keeps its worker from starting the next one, and on_time(col, pixel) returns
// the colour of a pixel finished in time (and takes whatever else the pixel leaves behind). work is called in
// each worker's order for the pixels that start on time, and with `trace_late` for the late ones too. Each worker
// clears a pixel's slot when it starts it, so late pixels are black. A worker's pixel k is ready after the
// occupancies of its pixels 0..k plus the drain; it is late when that exceeds the lead time, and so are all the
// worker's later pixels.
//
// The demand (LineResult::demand_cycles) is the largest over the workers of their occupancies over all their
// pixels plus the drain. With `trace_late` every pixel is computed and it is exact. Without, a late worker's
// pixels from its first late one on are not known: each counts `least` (the smallest occupancy a pixel can
// have), and the worker at least lead_cycles + 1 (it is late). That bound needs nothing of the late pixels, so
// every model gives the same one whether it computes them or skips them (FastTracer), and it is exact when
// every late pixel would have taken `least`.
template <class Work, class Occupancy, class OnTime>
LineSchedule schedule_pixels(int workers, int lead_cycles, std::int64_t drain, std::int64_t least, bool trace_late,
                             std::span<core::Rgb444> line, const Work& work, const Occupancy& occupancy,
                             const OnTime& on_time) {
  LineSchedule result;
  for (int w = 0; w < workers; ++w) {
    std::int64_t busy = 0;          // cycles from the start of the line until the worker may start its next pixel
    std::int64_t on_time_busy = 0;  // the same after its last pixel on time
    int late = 0;                   // the worker's late pixels: once one is late, every later one is too
    for (int col = w; col < kLineWidth; col += workers) {
      core::Rgb444& slot = line[static_cast<std::size_t>(col)];
      if (late == 0 || trace_late) {
        const auto pixel = work(col);
        busy += occupancy(pixel);
        if (late == 0 && busy + drain <= lead_cycles) {
          slot = on_time(col, pixel);
          on_time_busy = busy;
          continue;
        }
      }
      slot = core::kBlack;
      ++late;
    }
    result.late_pixels += late;
    const std::int64_t demand = late == 0 || trace_late
                                    ? busy + drain
                                    : std::max<std::int64_t>(std::int64_t{lead_cycles} + 1,
                                                             on_time_busy + late * least + drain);
    result.demand_cycles = std::max(result.demand_cycles, demand);
  }
  return result;
}

// The mirror model's line: trace(col) returns the core::PixelTrace of column col (its colour and bounce count),
// which sets its occupancy (DevicePreset::pixel_occupancy).
template <class Trace>
LineResult schedule_line(const DevicePreset& preset, std::int64_t spheres, std::span<core::Rgb444> line,
                         const Trace& trace) {
  LineResult result;
  std::array<std::int64_t, core::kMaxBounces + 1> occupancy{};  // by bounce count
  for (int k = 0; k <= core::kMaxBounces; ++k) occupancy[static_cast<std::size_t>(k)] = preset.pixel_occupancy(spheres, k);
  const LineSchedule schedule = schedule_pixels(
      preset.workers, preset.lead_cycles, preset.drain_cycles(), occupancy[0], preset.trace_late_pixels, line, trace,
      [&](const core::PixelTrace& t) { return occupancy[static_cast<std::size_t>(t.bounces)]; },
      [&](int, const core::PixelTrace& t) {
        result.reflections += t.bounces;
        return t.colour;
      });
  result.late_pixels = schedule.late_pixels;
  result.demand_cycles = schedule.demand_cycles;
  return result;
}

// The path preset's line: trace(col) returns column col's PathPixel, whose rays and bounces set its occupancy
// (DevicePreset::path_occupancy); a pixel on time writes its entry to `memory`, the row's frame memory.
template <class Trace>
LineResult schedule_path_line(const DevicePreset& preset, std::int64_t spheres, std::span<core::Rgb444> line,
                              std::span<AccumEntry> memory, const Trace& trace) {
  LineResult result;
  // The least a pixel can take is a converged one's, which traces nothing.
  const LineSchedule schedule = schedule_pixels(
      preset.workers, preset.lead_cycles, preset.path_drain_cycles(), preset.path_occupancy(spheres, 0, {0, 0, 0}),
      preset.trace_late_pixels, line, trace,
      [&](const PathPixel& p) {
        return preset.path_occupancy(spheres, p.rays, {p.bounces.lambertian, p.bounces.metal, p.bounces.dielectric});
      },
      [&](int col, const PathPixel& p) {
        memory[static_cast<std::size_t>(col)] = p.entry;
        result.rays += p.rays;
        return p.colour;
      });
  result.late_pixels = schedule.late_pixels;
  result.demand_cycles = schedule.demand_cycles;
  return result;
}

class Controller {
 public:
  explicit Controller(const DevicePreset& preset);

  // Fills `line` (640 pixels) with row `row` of the image of `scene`: the worker's pixels on
  // schedule_line's schedule.
  LineResult render_line(int row, const SceneMemory& scene, std::span<core::Rgb444> line) const;
  // The path preset's row `row` of `frame`: reads and writes the row's frame memory (`memory`, 640 entries) and
  // adds what its workers did to `counters` (every pixel traced, late or not: the workers did the work; with
  // DevicePreset::trace_late_pixels that is every pixel of the line).
  LineResult render_path_line(int row, const SceneMemory& scene, const PathFrame& frame, std::span<AccumEntry> memory,
                              std::span<core::Rgb444> line, PathCounters& counters) const;

  // How many pixels each worker finishes within the lead time, with `spheres` spheres, when no pixel
  // reflects (0..64 per worker with 10 workers).
  int pixels_in_time(std::int64_t spheres) const;

 private:
  DevicePreset preset_;
  Worker worker_;  // the workers are identical and stateless between pixels, so one model serves all N
};

}  // namespace tripsitter::device

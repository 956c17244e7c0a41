// The lines of a frame computed ahead of the beam with the fast model (FastTracer): from the start of
// vertical blanking, helper threads compute the frame's lines in order, while the device draws; a line the
// device needs before a helper has done it, the device computes itself (or the next undone one, until it
// is there). So drawing the VGA signal and tracing share the cores.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/device/fast_tracer.h>
#include <tripsitter/device/frame_memory.h>
#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/scene_memory.h>

namespace tripsitter::device {

class FrameLines {
 public:
  struct Line {
    std::array<core::Rgb444, kLineWidth> pixels{};
    int late_pixels = 0;
    int reflections = 0;             // mirror model: reflections of the pixels on time
    std::int64_t demand_cycles = 0;  // LineResult::demand_cycles
    int rays = 0;                    // path preset: rays of the pixels on time
    PathCounters counters;           // path preset: what the line's workers did
  };

  // `threads` as Device's: 0 for every core; helpers are the threads beyond the caller's.
  FrameLines(const DevicePreset& preset, int threads);
  ~FrameLines();  // waits for the helpers
  FrameLines(const FrameLines&) = delete;
  FrameLines& operator=(const FrameLines&) = delete;

  // Starts computing the frame of (a copy of) `scene`, once the previous frame's helpers are done. With `path`
  // (a path preset's frame; its surfaces are copied too), the lines read and write `memory`, which must stay
  // untouched by others until every line has been taken.
  void start(const SceneMemory& scene, const PathFrame* path = nullptr, FrameMemory* memory = nullptr);
  // Row `row` (0..479) of the frame started last, computed by now. Valid until the next start().
  const Line& line(int row);

 private:
  void compute(int row);
  void helper();
  void join();

  FastTracer fast_;
  int helpers_;
  SceneMemory scene_;
  std::optional<PathFrame> path_;
  std::vector<PathSurface> surfaces_;  // path_->surfaces views these
  FrameMemory* memory_ = nullptr;
  std::vector<Line> lines_;
  std::unique_ptr<std::atomic<bool>[]> done_;  // done_[row]: lines_[row] is written (release)
  std::atomic<int> next_{0};                   // the next row no one has taken
  std::vector<std::thread> threads_;
};

}  // namespace tripsitter::device

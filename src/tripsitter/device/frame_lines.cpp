#include <tripsitter/device/frame_lines.h>

#include <tripsitter/core/screen.h>

#include <tripsitter/core/parallel.h>

namespace tripsitter::device {
namespace {

constexpr int kRows = core::kScreenHeight;

}  // namespace

FrameLines::FrameLines(const DevicePreset& preset, int threads)
    : fast_(preset),
      helpers_(core::thread_count(threads) - 1),
      lines_(kRows),
      done_(std::make_unique<std::atomic<bool>[]>(kRows)) {}

FrameLines::~FrameLines() { join(); }

void FrameLines::join() {
  for (auto& t : threads_) t.join();
  threads_.clear();
}

void FrameLines::start(const SceneMemory& scene, const PathFrame* path, FrameMemory* memory) {
  join();  // the previous frame's rows have all been taken; its helpers are finishing or done
  scene_ = scene;
  path_.reset();
  memory_ = memory;
  if (path) {
    surfaces_.assign(path->surfaces.begin(), path->surfaces.end());
    path_ = *path;
    path_->surfaces = surfaces_;
  }
  fast_.load(scene_);
  for (int row = 0; row < kRows; ++row) done_[row].store(false, std::memory_order_relaxed);
  next_.store(0, std::memory_order_relaxed);
  for (int t = 0; t < helpers_; ++t) threads_.emplace_back([this] { helper(); });
}

void FrameLines::compute(int row) {
  Line& line = lines_[static_cast<std::size_t>(row)];
  line.counters = {};
  const LineResult r = path_ ? fast_.render_path_line(row, *path_, memory_->row(row), line.pixels, line.counters)
                             : fast_.render_line(row, line.pixels);
  line.late_pixels = r.late_pixels;
  line.reflections = r.reflections;
  line.demand_cycles = r.demand_cycles;
  line.rays = r.rays;
  done_[row].store(true, std::memory_order_release);
  done_[row].notify_all();
}

void FrameLines::helper() {
  for (int row = next_.fetch_add(1); row < kRows; row = next_.fetch_add(1)) compute(row);
}

const FrameLines::Line& FrameLines::line(int row) {
  while (!done_[row].load(std::memory_order_acquire)) {
    const int mine = next_.fetch_add(1);
    if (mine < kRows) {
      compute(mine);
    } else {
      done_[row].wait(false, std::memory_order_acquire);  // a helper has it in hand
    }
  }
  return lines_[static_cast<std::size_t>(row)];
}

}  // namespace tripsitter::device

// The device (the report's FPGA): receiver, scene memory (two copies), controller with its workers,
// two line buffers and the VGA block, advanced one pixel clock (four device cycles) at a time.
//
// Time: the device comes out of reset at the start of vertical blanking (line 480, column 0), so the first
// full frame it sends is the first one after reset. At column 0 of line 480 a waiting world is swapped into
// scene memory. At column 0 of every line the controller starts on the next visible line, which the
// workers write into the back line buffer; at the end of each line the buffers swap.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/device/backend.h>
#include <tripsitter/device/controller.h>
#include <tripsitter/device/frame_lines.h>
#include <tripsitter/device/frame_memory.h>
#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/receiver.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/device/vga.h>
#include <tripsitter/link/spi.h>
#include <tripsitter/link/wire.h>

namespace tripsitter::device {

struct FrameStats {
  std::uint32_t sequence = 0;   // the world this frame shows
  bool has_world = false;       // false before the first good world
  int late_pixels = 0;
  int late_lines = 0;
  // The largest demand of the frame's visible lines (LineResult::demand_cycles): the cycles its slowest line
  // needed from the start of its work to its last colour. At most the lead time when no line is late; above it a
  // lower bound unless DevicePreset::demand_exact(), then exact.
  std::int64_t worst_line_cycles = 0;
  bool demand_known = true;  // false where no one counts it: the RTL's pins say which pixels are late, not when
  // The mirror model (zero otherwise): reflections traced for the pixels on time.
  std::uint64_t reflections = 0;
  // The path preset (zero otherwise): samples each pixel on time in every frame has accumulated (at most
  // kMaxSamples), rays traced for the pixels on time, and what the workers did (PathCounters: every pixel traced,
  // the late ones too with DevicePreset::trace_late_pixels).
  int samples_per_pixel = 0;
  std::uint64_t rays = 0;
  PathCounters path;
};

// Which model computes the pixels. Both show the same pixels and count the same late pixels, bit for bit.
enum class DeviceModel {
  kPlain,  // each line when the controller starts it, pixel by pixel with Worker::trace: the reference
  kFast,   // the fast model (FastTracer), a frame's lines computed ahead of the beam (FrameLines)
};

class Device final : public Backend {
 public:
  // REQUIRES preset.validate() is empty. The model only changes how fast the device runs, never what it
  // shows. kFast computes a frame's lines ahead of the beam from vertical blanking on, on `threads`
  // threads counting the caller's (0: every core; 1: the caller alone, each line when it is needed).
  // kPlain ignores `threads`.
  Device(const DevicePreset& preset, link::WireVersion wire, int threads = 0, DeviceModel model = DeviceModel::kFast);

  // Backend: the ready line, one SPI transfer (taken at once), the host's end.
  bool ready() const override { return receiver_.ready(); }
  void transfer(std::span<const std::uint8_t> bytes) override { receiver_.receive(bytes); }
  void end_of_stream() override { receiver_.end_of_stream(); }

  // One pixel clock: what the VGA connector carries during it.
  VgaSample tick();
  // One whole frame of 800 x 525 pixel clocks, from the start of vertical blanking to the end of the last
  // visible line; every sample goes to `sink`. Returns the statistics of the frame drawn.
  // REQUIRES the device to be at the start of vertical blanking (as after reset or run_frame).
  FrameStats run_frame(const std::function<void(const VgaSample&)>& sink);
  // The same frame a line at a time: `line_sink` gets each line's h_total samples, in order.
  FrameStats run_frame_lines(const std::function<void(std::span<const VgaSample>)>& line_sink) override;

  // Statistics of the frame being drawn since the last vertical blanking.
  const FrameStats& current_frame() const { return building_; }
  std::uint64_t total_late_pixels() const { return total_late_pixels_; }
  std::uint64_t total_late_lines() const { return total_late_lines_; }
  const ReceiverStats& receiver_stats() const override { return receiver_.stats(); }
  bool has_world() const override { return scene_.valid; }
  const DevicePreset& preset() const { return preset_; }
  const SceneMemory& scene() const { return scene_; }
  const SceneMemory* scene_memory() const override { return &scene_; }
  // The path preset's frame memory as the last frame left it (null for other presets).
  const FrameMemory* frame_memory() const override { return memory_.get(); }

 private:
  void start_line(int line);
  // The path preset at vertical blanking: a world of new content starts a new epoch in frame memory.
  void next_path_frame(bool swapped);
  bool path_traced() const { return traces_paths(preset_, wire_) && scene_.valid; }

  DevicePreset preset_;
  link::WireVersion wire_;
  Receiver receiver_;
  Controller controller_;
  SceneMemory scene_;
  VgaTimingGenerator vga_;
  std::array<std::array<core::Rgb444, kLineWidth>, 2> line_buffers_{};
  std::unique_ptr<FrameLines> ahead_;  // the fast model's lines, null for the plain model
  int front_ = 0;  // index of the line buffer the VGA block reads
  // The path preset: frame memory, the surfaces of the world in scene memory and the frame being drawn of it.
  std::unique_ptr<FrameMemory> memory_;
  std::vector<PathSurface> surfaces_;
  PathFrame path_frame_;
  std::optional<std::uint32_t> shown_content_;  // content of the world accumulated in frame memory
  FrameStats building_;
  std::uint64_t total_late_pixels_ = 0;
  std::uint64_t total_late_lines_ = 0;
};

}  // namespace tripsitter::device

#include "device_loop.h"

#include <chrono>
#include <cstdio>
#include <stdexcept>

#include <tripsitter/board/capture.h>
#include <tripsitter/display/monitor.h>
#include <tripsitter/display/png.h>

namespace tripsitter::cmd {

std::string PngFrameSink::file_name(std::uint64_t frame) {
  char name[40];
  std::snprintf(name, sizeof name, "frame_%06llu.png", static_cast<unsigned long long>(frame));
  return name;
}

bool PngFrameSink::show(const core::Image444& image, const FrameInfo& info) {
  if (!info.new_world || !info.stats.has_world) return true;
  auto written = display::write_png((dir_ / file_name(info.frame)).string(), image);
  if (!written) {
    error_ = written.error().message;
    return false;
  }
  ++written_;
  return true;
}

DeviceLoopResult run_device_loop(device::Backend& device, transport::StreamPort& port, FrameSink& sink,
                                 const DeviceLoopConfig& config, const volatile std::sig_atomic_t& stop) {
  using Clock = transport::StreamClock;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(config.frame_seconds));
  DeviceStreamEndpoint endpoint(device);
  display::VgaMonitor monitor;
  DeviceLoopResult result;
  auto due = Clock::now();
  while (stop == 0 && (config.max_frames == 0 || result.frames < config.max_frames)) {
    port.service(endpoint);
    FrameInfo info;
    info.frame = result.frames;
    info.new_world = !device.ready();  // a world waits: the frame's vertical blanking swaps it in
    board::CapturedFrame captured = board::capture_frame(device, monitor);
    info.stats = captured.stats;
    ++result.frames;
    if (info.new_world) ++result.new_worlds;
    if (!sink.show(captured.image, info)) break;
    port.service(endpoint);  // only now may the credit say the world was taken
    due += period;
    const auto now = Clock::now();
    if (now > due) {
      // The model is slower than the VGA signal: draw the next frame at once, and do not try to catch up.
      if (period.count() > 0) ++result.late_frames;
      due = now;
      continue;
    }
    while (stop == 0 && Clock::now() < due) {
      port.wait(due);
      port.service(endpoint);
    }
  }
  return result;
}

}  // namespace tripsitter::cmd

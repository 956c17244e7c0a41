// The device as a program (`tripsitter device`): the device model run at the VGA frame rate in real time,
// its monitor, and its end of the stream link. What the monitor captures goes to a FrameSink: PNG files
// when headless, the window otherwise.
#pragma once

#include <csignal>
#include <cstdint>
#include <filesystem>
#include <string>

#include <tripsitter/core/image.h>
#include <tripsitter/device/backend.h>
#include <tripsitter/device/device.h>
#include <tripsitter/link/stream_protocol.h>
#include <tripsitter/transport/stream.h>

namespace tripsitter::cmd {

// What the loop knows about a frame it hands to the sink.
struct FrameInfo {
  std::uint64_t frame = 0;      // frames drawn since the device started, from 0
  device::FrameStats stats;     // the world it shows (sequence, has_world) and its late pixels and lines
  bool new_world = false;       // a world was swapped into scene memory at this frame's vertical blanking
};

// Where the monitor's frames go. Called once per frame, in order, from the loop's thread.
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // Returns false to stop the device (the window was closed, or the sink failed).
  virtual bool show(const core::Image444& image, const FrameInfo& info) = 0;
};

// Headless: each frame that shows a newly swapped-in world becomes `dir`/frame_NNNNNN.png, NNNNNN the
// frame number (at least six digits). Frames before the first world, and repeats of a world, are not written.
class PngFrameSink : public FrameSink {
 public:
  explicit PngFrameSink(std::filesystem::path dir) : dir_(std::move(dir)) {}
  bool show(const core::Image444& image, const FrameInfo& info) override;

  static std::string file_name(std::uint64_t frame);
  std::uint64_t written() const { return written_; }
  // Why the sink stopped the device, empty if it did not.
  const std::string& error() const { return error_; }

 private:
  std::filesystem::path dir_;
  std::uint64_t written_ = 0;
  std::string error_;
};

// The device as its stream port sees it.
class DeviceStreamEndpoint : public link::StreamEndpoint {
 public:
  explicit DeviceStreamEndpoint(device::Backend& device) : device_(device) {}
  bool ready() const override { return device_.ready(); }
  void transfer(std::span<const std::uint8_t> bytes) override { device_.transfer(bytes); }
  void end_of_stream() override { device_.end_of_stream(); }
  std::uint64_t worlds_accepted() const override { return device_.receiver_stats().worlds_accepted; }
  // A replayed world ends its credit like a rejected one: it is not shown.
  std::uint64_t worlds_rejected() const override {
    return device_.receiver_stats().frames_rejected + device_.receiver_stats().worlds_replayed;
  }

 private:
  device::Backend& device_;
};

// The VGA frame period: 800 x 525 pixel clocks at 25 MHz, 16.8 ms (59.52 frames/s).
inline constexpr double kVgaFrameSeconds = 800.0 * 525.0 / 25e6;

struct DeviceLoopConfig {
  std::uint64_t max_frames = 0;               // stop after this many frames; 0: until stopped
  double frame_seconds = kVgaFrameSeconds;    // real time per frame; 0: as fast as the model runs
};

struct DeviceLoopResult {
  std::uint64_t frames = 0;      // drawn
  std::uint64_t new_worlds = 0;  // frames that showed a newly swapped-in world
  std::uint64_t late_frames = 0; // frames the model took longer than frame_seconds to draw
};

// Runs the device until `stop` becomes non-zero (a signal handler sets it), the sink returns false, or
// max_frames frames have been drawn. Each frame: the port hands the host's bytes to the device, the
// device draws a whole frame (a waiting world is swapped in at its vertical blanking), the monitor's
// capture goes to the sink, and only then may the port send the credit that tells the host its world
// was taken; so a host that has seen its last world taken knows the sink already has a frame of it.
// Between frames the loop sleeps until the next frame is due, serving the port meanwhile.
DeviceLoopResult run_device_loop(device::Backend& device, transport::StreamPort& port, FrameSink& sink,
                                 const DeviceLoopConfig& config, const volatile std::sig_atomic_t& stop);

}  // namespace tripsitter::cmd

// The device's receiver: reassembles link bytes into worlds, checks them against the device's formats
// and writes the back copy of scene memory. The back copy becomes the front copy only during vertical
// blanking (Device calls swap_if_pending), so a frame never mixes two worlds. Anything damaged is counted
// and dropped; the last good world stays on screen.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include <tripsitter/device/preset.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/link/wire.h>
#include <tripsitter/link/wire_v1.h>
#include <tripsitter/link/wire_v2.h>

namespace tripsitter::device {

struct ReceiverStats {
  std::uint64_t worlds_accepted = 0;   // complete, checked worlds written to the back copy
  std::uint64_t worlds_replaced = 0;   // accepted while an earlier one still waited for the swap
  std::uint64_t frames_rejected = 0;   // damaged or unacceptable frames (or v1 words) dropped
  std::uint64_t garbage_runs = 0;      // runs of bytes between frames that were no frame at all
  std::uint64_t bytes_dropped = 0;     // in both
  // v2 only: sequence numbers skipped between consecutive accepted worlds, so worlds the host numbered that
  // never reached scene memory: lost on the link, rejected, or replaced at the host before they went out.
  // A sequence number at or below the previous accepted one (a repeat, a host that started again) skips
  // nothing. docs/link_format.md, "What the receiver counts".
  std::uint64_t worlds_missing = 0;
  std::string last_error;              // why the last frame was rejected
};

class Receiver {
 public:
  Receiver(const DevicePreset& preset, link::WireVersion wire);

  // The ready line: high while no accepted world waits for the next vertical blanking.
  bool ready() const { return !pending_; }
  void receive(std::span<const std::uint8_t> bytes);
  // The host went away: a partial frame is dropped and counted.
  void end_of_stream();

  // Vertical blanking: if a new world is waiting, it becomes `front` and the ready line rises.
  bool swap_if_pending(SceneMemory& front);

  const ReceiverStats& stats() const { return stats_; }

 private:
  void accept_v1(const link::V1Sphere& word);
  void accept_v2(link::World&& world);
  void reject(const std::string& why, std::size_t bytes);
  void skip_garbage(std::size_t bytes);

  DevicePreset preset_;
  link::WireVersion wire_;
  link::V1StreamDecoder v1_;
  link::V2StreamDecoder v2_;
  SceneMemory back_;
  bool pending_ = false;
  std::uint32_t v1_words_ = 0;
  std::optional<std::uint32_t> last_sequence_;  // of the last accepted v2 world
  ReceiverStats stats_;
};

}  // namespace tripsitter::device

// The device's receiver: reassembles link bytes into worlds, checks them against the device's formats
// and writes the back copy of scene memory. The back copy becomes the front copy only during vertical
// blanking (Device calls swap_if_pending), so a frame never mixes two worlds. Anything damaged is counted
// and dropped; the last good world stays on screen.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>

#include <tripsitter/device/preset.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/link/wire.h>
#include <tripsitter/link/wire_v1.h>
#include <tripsitter/link/frame.h>
#include <tripsitter/link/sequence.h>

namespace tripsitter::device {

struct ReceiverStats {
  std::uint64_t worlds_accepted = 0;   // complete, checked worlds written to the back copy
  std::uint64_t worlds_replaced = 0;   // accepted while an earlier one still waited for the swap
  std::uint64_t frames_rejected = 0;   // damaged or unacceptable frames (or v1 words) dropped
  std::uint64_t garbage_runs = 0;      // runs of bytes between frames that were no frame at all
  std::uint64_t bytes_dropped = 0;     // in both, and in replays
  // v2 and v3: sequence numbers skipped, so worlds a host sent that never arrived intact: what the link lost
  // (docs/link_format.md, "Sessions and sequence numbers"). Worlds that arrived intact and were rejected for
  // their content are in frames_rejected, not here.
  std::uint64_t worlds_missing = 0;
  // v3: intact worlds not newer than the last one of their session, or of a session that has ended; never
  // shown (a duplicated transfer, an old frame sent again).
  std::uint64_t worlds_replayed = 0;
  std::uint64_t sessions = 0;          // v2 and v3: host sessions begun (v2: the first world only)
  std::string last_error;              // why the last frame was rejected
};

// What the receiver did with one piece of the stream. Events come in stream order and every byte received is
// in exactly one, so a listener that adds up `bytes` knows where each piece began.
struct ReceiverEvent {
  enum class Kind {
    kAccepted,  // a world went to the back copy
    kReplayed,  // v3: an intact world the sequence rules refused
    kRejected,  // a damaged frame, or a world (or v1 word) refused for its content
    kGarbage,   // bytes skipped looking for a frame
  };
  Kind kind = Kind::kAccepted;
  std::size_t bytes = 0;
  std::optional<std::size_t> found_at;  // stream offset at which the decoder found the problem, if it says
  std::string error;                    // a short name: "bad CRC", "truncated", "rejected", "replay", ...
  std::string detail;                   // a sentence for people
  const link::World* world = nullptr;    // kAccepted, v2 and v3
  const link::V1Sphere* word = nullptr;  // kAccepted, v1
  link::SequenceCheck check;             // kAccepted, v2 and v3
};

// A node of the v3 wire's hierarchy as scene memory holds it, and back: the same fields (scene_memory.h). REQUIRES
// for wire_node a node in the wire's ranges (as every node the receiver accepted is).
HierarchyNode hierarchy_node(const link::WireNode& v);
link::WireNode wire_node(const HierarchyNode& v);

class Receiver {
 public:
  // A preset that walks no hierarchy (DevicePreset::walks_hierarchy) refuses a v3 world that carries one at its
  // header, as the RTL receiver does (its content byte is not 0).
  Receiver(const DevicePreset& preset, link::WireVersion wire);

  // Tools that explain a stream (`link decode`) listen; the device itself does not.
  void set_listener(std::function<void(const ReceiverEvent&)> listener) { listener_ = std::move(listener); }

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
  void accept_frame(link::World&& world);
  // The sequence rules for a frame of `bytes` bytes that arrived intact; false if it must not be shown (a
  // replay, whose bytes are dropped).
  std::optional<link::SequenceCheck> admit(std::uint32_t session, std::uint32_t sequence, std::size_t bytes);
  // A world (or v1 word) refused for its content.
  void reject(const std::string& why, std::size_t bytes);
  // A problem the decoder reported: a damaged or cut frame, a bad sphere, or (kBadMagic) garbage.
  void report(const std::string& error, const std::string& detail, std::size_t bytes,
              std::optional<std::size_t> found_at);
  // Events are built only when a listener is set: the device's receiver pays nothing for them.
  static ReceiverEvent event(ReceiverEvent::Kind kind, std::size_t bytes, std::string error, std::string detail);
  void emit(const ReceiverEvent& event) const;

  DevicePreset preset_;
  link::WireVersion wire_;
  link::V1StreamDecoder v1_;
  link::FrameStreamDecoder frames_;   // v2 and v3
  link::SequenceRules sequence_;
  SceneMemory back_;
  bool pending_ = false;
  std::uint32_t v1_words_ = 0;
  ReceiverStats stats_;
  std::function<void(const ReceiverEvent&)> listener_;
};

}  // namespace tripsitter::device

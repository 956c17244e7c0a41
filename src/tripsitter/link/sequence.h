// Which worlds are new: the host's numbering of the worlds it sends, and the receiver's rules that turn
// those numbers into "show", "replay" and a count of worlds the link lost (docs/link_format.md, "Sessions
// and sequence numbers").
//
// On v3 a host numbers the worlds it sends 1, 2, ... within a session, a number it chooses at random when
// it starts (or reconnects), so a restarted host is told apart from an old frame replayed. On v2 there is
// no session: any world is shown, and only a step forward counts missing numbers. v1 words carry no number.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include <tripsitter/link/wire.h>

namespace tripsitter::link {

// The host's side: gives each world the next number as it starts to go out, so a number is spent only on a
// world that was sent. After 2^32 - 1 worlds the session moves on to the next number and counting starts
// again at 1 (the receiver sees a new session, never a step back).
class Numbering {
 public:
  // REQUIRES session != 0 on v3 (0 is what a v2 frame's missing session reads as).
  Numbering(WireVersion wire, std::uint32_t session);

  // Stamps the next number (and, on v3, the session) into a whole encoded frame, fixing its CRCs. v1 bytes
  // are left as they are.
  void stamp(std::span<std::uint8_t> world_bytes);

  std::uint32_t session() const { return session_; }
  std::uint32_t last_sequence() const { return last_; }  // 0 before the first world

 private:
  WireVersion wire_;
  std::uint32_t session_;
  std::uint32_t last_ = 0;
};

// A session for a host that is starting: random, never 0.
std::uint32_t random_session();

enum class SequenceVerdict {
  kShow,    // a newer world: take it
  kReplay,  // an older or repeated world, or one of a session that has ended: never shown
};

struct SequenceCheck {
  SequenceVerdict verdict = SequenceVerdict::kShow;
  std::uint64_t missing = 0;  // numbers skipped before this world: worlds the link lost
  bool new_session = false;   // the world begins a host session this receiver had not seen
  bool ended_session = false; // a replay because its session has ended (not because its number is old)
};

// The receiver's side. Every frame that arrived intact goes through check(), whether the device then takes
// it or rejects it for its content, so a number it has seen is never counted missing.
class SequenceRules {
 public:
  // How many ended sessions are remembered, so that their frames, replayed, are refused.
  static constexpr std::size_t kRetiredSessions = 16;

  // REQUIRES wire != kV1.
  explicit SequenceRules(WireVersion wire);

  // v3: a world of the current session is shown if its number is above the last one's, and counts the
  // numbers between as missing; a number at or below it is a replay. A world of another session that has
  // not ended starts that session (the host restarted): it is shown, and the numbers below its own count as
  // missing. A world of an ended session is a replay.
  // v2: every world is shown; a number above the last counts the numbers between as missing, anything else
  // (a repeat, a host numbering from 1 again) counts nothing.
  SequenceCheck check(std::uint32_t session, std::uint32_t sequence);

 private:
  bool retired(std::uint32_t session) const;

  WireVersion wire_;
  std::optional<std::uint32_t> session_;  // the current session (v2: always 0 once a world was seen)
  std::uint32_t last_ = 0;                // the last number seen in it
  std::array<std::uint32_t, kRetiredSessions> retired_{};
  std::size_t retired_count_ = 0;
  std::size_t retired_next_ = 0;  // ring position
};

}  // namespace tripsitter::link

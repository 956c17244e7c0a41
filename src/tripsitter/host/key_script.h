// Key scripts: the board's keyboard, written down. One action per line, played in ticks of 1/60 s of
// script time (docs/key_script.md):
//
//   # comment                     blank lines and comments are ignored; a comment may follow an action
//   W 500ms                       hold W for 500 ms (30 ticks)
//   j 0.25s                       keys in either case; durations in ms, s, or a bare number of ms
//   L                             no duration: a tap, one tick
//   R                             reset world and camera
//   wait 1s                       no key for 1 s
//
// Durations round to the nearest tick; a key lasts at least one tick, a wait may round to none.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <tripsitter/core/result.h>
#include <tripsitter/host/controls.h>
#include <tripsitter/host/host.h>

namespace tripsitter::host {

inline constexpr int kScriptTicksPerSecond = 60;                          // one tick is 1/60 s of script time
inline constexpr std::int64_t kMaxActionMicros = 3600LL * 1'000'000;      // one action lasts at most one hour
inline constexpr std::int64_t kMaxScriptTicks = 24LL * 3600 * kScriptTicksPerSecond;  // a script, 24 hours
inline constexpr std::size_t kMaxScriptBytes = 1 << 20;                   // 1 MiB of text
inline constexpr std::size_t kMaxScriptActions = 100'000;

struct KeyAction {
  std::optional<Key> key;        // the key held for the whole action; nothing for `wait`
  std::int64_t duration_us = 0;  // as written (a tap: 0)
  std::int64_t ticks = 0;        // what the action lasts, in ticks: >= 1 for a key, >= 0 for a wait
  int line = 0;                  // 1-based line of the script
  bool operator==(const KeyAction&) const = default;
};

struct KeyScriptError {
  int line = 0;    // 1-based; 0 when the error has no place (the whole text)
  int column = 0;  // 1-based, the first character of the offending word
  std::string message;

  // "source:line:column: message", or "source: message" without a place.
  std::string to_string(std::string_view source) const;
};

// Parses a whole script. The first error stops the parse.
core::Result<std::vector<KeyAction>, KeyScriptError> parse_key_script(std::string_view text);

// Ticks the whole script lasts.
std::int64_t total_ticks(const std::vector<KeyAction>& actions);

// Plays a script one tick at a time: a held key moves the host's camera by 1/60 s of apply_held_key,
// R resets the host's world and camera (on every tick it is held).
class KeyScriptPlayer {
 public:
  explicit KeyScriptPlayer(std::vector<KeyAction> actions, ControlSpeeds speeds = {});

  // Applies the next tick to `host`. Returns false, changing nothing, when the script is over.
  bool step(Host& host);
  bool done() const { return action_ >= actions_.size(); }
  std::int64_t ticks_played() const { return ticks_played_; }

 private:
  void skip_empty();

  std::vector<KeyAction> actions_;
  ControlSpeeds speeds_;
  std::size_t action_ = 0;
  std::int64_t tick_in_action_ = 0;
  std::int64_t ticks_played_ = 0;
};

}  // namespace tripsitter::host

// The host's key-script parser (host/key_script.h, docs/key_script.md).
//
// Input: the text of a key script.
//
// Checks:
//   - a failure has a place (1-based line that exists, column from 1 to just past the line's end) and a
//     message; only a script over 1 MiB fails without a place;
//   - a script that parses keeps the limits: at most 100,000 actions, each at most one hour, the whole at
//     most 24 hours of ticks; lines increase; a key lasts its duration rounded to the nearest tick (halves
//     up) and at least one tick, a wait its rounded duration;
//   - line endings and letter case do not matter: the script with \n turned into \r\n, and the script in
//     lower case, give the same actions (or fail at the same place).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <tripsitter/host/key_script.h>

#include "check.h"

namespace {

namespace host = tripsitter::host;

using ScriptResult = decltype(host::parse_key_script(std::string_view{}));

// Length of each line of the text, in bytes (without the '\n').
std::vector<std::size_t> line_lengths(std::string_view text) {
  std::vector<std::size_t> out;
  std::size_t at = 0;
  while (true) {
    const std::size_t end = text.find('\n', at);
    out.push_back((end == std::string_view::npos ? text.size() : end) - at);
    if (end == std::string_view::npos) return out;
    at = end + 1;
  }
}

std::int64_t rounded_ticks(std::int64_t micros) {
  return (micros * host::kScriptTicksPerSecond + 500'000) / 1'000'000;
}

void check_result(std::string_view text, const ScriptResult& result) {
  if (!result.ok()) {
    const host::KeyScriptError& e = result.error();
    FUZZ_CHECK(!e.message.empty(), "an error without a message");
    if (text.size() > host::kMaxScriptBytes) {
      FUZZ_CHECK(e.line == 0, "a script over the size limit failed at a place");
      return;
    }
    const std::vector<std::size_t> lengths = line_lengths(text);
    FUZZ_CHECK(e.line >= 1 && static_cast<std::size_t>(e.line) <= lengths.size(), "an error on a line that does not exist");
    FUZZ_CHECK(e.column >= 1 && static_cast<std::size_t>(e.column) <= lengths[e.line - 1] + 1,
               "an error column outside its line");
    FUZZ_CHECK(e.to_string("k").starts_with("k:" + std::to_string(e.line) + ":" + std::to_string(e.column) + ": "),
               "to_string() is not source:line:column: message");
    return;
  }
  const std::vector<host::KeyAction>& actions = result.value();
  FUZZ_CHECK(actions.size() <= host::kMaxScriptActions, "more actions than the limit");
  FUZZ_CHECK(host::total_ticks(actions) <= host::kMaxScriptTicks, "a script longer than 24 hours");
  const std::size_t lines = line_lengths(text).size();
  int previous_line = 0;
  for (const host::KeyAction& a : actions) {
    FUZZ_CHECK(a.line > previous_line && static_cast<std::size_t>(a.line) <= lines, "action lines do not increase");
    previous_line = a.line;
    FUZZ_CHECK(a.duration_us >= 0 && a.duration_us <= host::kMaxActionMicros, "a duration out of 0..1 hour");
    const std::int64_t ticks = rounded_ticks(a.duration_us);
    if (a.key) {
      FUZZ_CHECK(a.ticks == std::max<std::int64_t>(ticks, 1), "a key's ticks are not its rounded duration (>= 1)");
    } else {
      FUZZ_CHECK(a.ticks == ticks, "a wait's ticks are not its rounded duration");
    }
  }
}

// The same parse, up to the place of an error.
bool same_outcome(const ScriptResult& a, const ScriptResult& b) {
  if (a.ok() != b.ok()) return false;
  if (a.ok()) return a.value() == b.value();
  return a.error().line == b.error().line && a.error().column == b.error().column;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const ScriptResult result = host::parse_key_script(text);
  check_result(text, result);

  if (text.find('\r') == std::string_view::npos) {
    std::string crlf;
    for (const char c : text) crlf += c == '\n' ? std::string_view("\r\n") : std::string_view(&c, 1);
    if (crlf.size() <= host::kMaxScriptBytes) {
      FUZZ_CHECK(same_outcome(result, host::parse_key_script(crlf)), "\\r\\n line endings change the parse");
    }
  }
  std::string lower(text);
  for (char& c : lower) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  FUZZ_CHECK(same_outcome(result, host::parse_key_script(lower)), "letter case changes the parse");
  return 0;
}

#include <tripsitter/host/key_script.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace tripsitter::host {
namespace {

constexpr std::int64_t kMicrosPerSecond = 1'000'000;

// A word of a line and its 1-based column.
struct Word {
  std::string_view text;
  int column = 0;
};

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// The words of one line, up to a '#' comment.
std::vector<Word> split_words(std::string_view line) {
  std::vector<Word> words;
  std::size_t i = 0;
  while (i < line.size()) {
    if (is_blank(line[i])) {
      ++i;
      continue;
    }
    if (line[i] == '#') break;
    const std::size_t start = i;
    while (i < line.size() && !is_blank(line[i]) && line[i] != '#') ++i;
    words.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
  }
  return words;
}

// The word in quotes, with anything unprintable escaped, for messages.
std::string quoted(std::string_view s) {
  std::string out = "'";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", u);
      out += buf;
    }
  }
  return out + "'";
}

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

bool ends_with_icase(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && iequals(s.substr(s.size() - suffix.size()), suffix);
}

// "digits" or "digits.digits"
bool is_decimal(std::string_view s) {
  const std::size_t dot = s.find('.');
  const auto all_digits = [](std::string_view d) {
    return !d.empty() && std::all_of(d.begin(), d.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (dot == std::string_view::npos) return all_digits(s);
  return all_digits(s.substr(0, dot)) && all_digits(s.substr(dot + 1));
}

// An unsigned duration word in microseconds, or nothing (too long: the reason).
core::Result<std::int64_t, std::string> parse_magnitude(std::string_view word, bool& well_formed) {
  std::string_view number = word;
  double micros_per_unit = 1000.0;  // a bare number is milliseconds
  if (ends_with_icase(word, "ms")) {
    number.remove_suffix(2);
  } else if (ends_with_icase(word, "s")) {
    number.remove_suffix(1);
    micros_per_unit = 1e6;
  }
  well_formed = false;
  if (!is_decimal(number)) return std::string();
  double value = 0;
  const auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), value);
  if (end != number.data() + number.size()) return std::string();
  well_formed = true;
  const double micros = ec == std::errc::result_out_of_range ? HUGE_VAL : value * micros_per_unit;
  if (!(micros <= static_cast<double>(kMaxActionMicros)))
    return "duration " + quoted(word) + " is longer than one hour, the most one action may last";
  return static_cast<std::int64_t>(std::llround(micros));
}

// A duration word in microseconds, or the reason it is not one. Linear in the word's length.
core::Result<std::int64_t, std::string> parse_duration(std::string_view word) {
  const auto bad = [&] {
    return "bad duration " + quoted(word) +
           ": expected a number of milliseconds or seconds, like 500ms, 0.5s or 500 (milliseconds)";
  };
  const bool negative = !word.empty() && word[0] == '-';
  bool well_formed = false;
  auto magnitude = parse_magnitude(negative ? word.substr(1) : word, well_formed);
  if (negative) {
    if (magnitude.ok()) return "negative duration " + quoted(word);
    return bad();
  }
  if (!well_formed) return bad();
  return magnitude;
}

std::int64_t ticks_for(std::int64_t micros) {
  return (micros * kScriptTicksPerSecond + kMicrosPerSecond / 2) / kMicrosPerSecond;
}

}  // namespace

std::string KeyScriptError::to_string(std::string_view source) const {
  std::string out(source);
  if (line > 0) {
    out += ':';
    out += std::to_string(line);
    out += ':';
    out += std::to_string(column);
  }
  out += ": ";
  out += message;
  return out;
}

core::Result<std::vector<KeyAction>, KeyScriptError> parse_key_script(std::string_view text) {
  if (text.size() > kMaxScriptBytes)
    return KeyScriptError{0, 0,
                          "the script has " + std::to_string(text.size()) + " bytes; the limit is " +
                              std::to_string(kMaxScriptBytes)};
  std::vector<KeyAction> actions;
  std::int64_t ticks = 0;
  int line_number = 0;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view line = text.substr(at, end - at);
    at = end + 1;
    ++line_number;
    const std::vector<Word> words = split_words(line);
    if (words.empty()) continue;
    const auto fail = [&](const Word& w, std::string message) {
      return KeyScriptError{line_number, w.column, std::move(message)};
    };

    KeyAction action;
    action.line = line_number;
    const bool is_wait = iequals(words[0].text, "wait");
    if (!is_wait) {
      action.key = key_by_name(words[0].text);
      if (!action.key)
        return fail(words[0], "unknown key " + quoted(words[0].text) +
                                  "; the keys are W A S D I K J L Q E R (either case), or wait DURATION");
    }
    if (words.size() >= 2) {
      auto duration = parse_duration(words[1].text);
      if (!duration) return fail(words[1], duration.error());
      action.duration_us = duration.value();
      action.ticks = ticks_for(action.duration_us);
    } else if (is_wait) {
      return KeyScriptError{line_number, static_cast<int>(words[0].column + words[0].text.size()),
                            "wait needs a duration, like wait 500ms"};
    }
    if (action.key) action.ticks = std::max<std::int64_t>(action.ticks, 1);  // a tap is one tick
    if (words.size() >= 3)
      return fail(words[2], "unexpected " + quoted(words[2].text) +
                                " after the duration; one action per line ('#' starts a comment)");
    if (actions.size() == kMaxScriptActions)
      return fail(words[0], "more than " + std::to_string(kMaxScriptActions) + " actions; that is the limit");
    ticks += action.ticks;
    if (ticks > kMaxScriptTicks) return fail(words[0], "the script lasts more than 24 hours; that is the limit");
    actions.push_back(action);
  }
  return actions;
}

std::int64_t total_ticks(const std::vector<KeyAction>& actions) {
  std::int64_t n = 0;
  for (const auto& a : actions) n += a.ticks;
  return n;
}

KeyScriptPlayer::KeyScriptPlayer(std::vector<KeyAction> actions, ControlSpeeds speeds)
    : actions_(std::move(actions)), speeds_(speeds) {
  skip_empty();
}

void KeyScriptPlayer::skip_empty() {
  while (action_ < actions_.size() && tick_in_action_ >= actions_[action_].ticks) {
    ++action_;
    tick_in_action_ = 0;
  }
}

bool KeyScriptPlayer::step(Host& host) {
  if (done()) return false;
  const KeyAction& a = actions_[action_];
  if (a.key == Key::kR) {
    host.reset();
  } else if (a.key) {
    apply_held_key(host.camera(), *a.key, 1.0 / kScriptTicksPerSecond, speeds_);
  }
  ++tick_in_action_;
  ++ticks_played_;
  skip_empty();
  return true;
}

}  // namespace tripsitter::host

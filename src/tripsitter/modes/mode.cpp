#include <tripsitter/modes/mode.h>

namespace tripsitter::modes {

std::optional<Mode> mode_by_name(std::string_view name) {
  for (Mode m : {Mode::kHw, Mode::kNormal, Mode::kPath})
    if (name == mode_name(m)) return m;
  return std::nullopt;
}

std::string_view mode_name(Mode mode) {
  switch (mode) {
    case Mode::kHw: return "hw";
    case Mode::kNormal: return "normal";
    case Mode::kPath: return "path";
  }
  return "?";
}

}  // namespace tripsitter::modes

#include <tripsitter/modes/mode.h>

namespace tripsitter::modes {

std::string_view mode_name(Mode mode) {
  switch (mode) {
    case Mode::kHw: return "hw";
    case Mode::kNormal: return "normal";
    case Mode::kPath: return "path";
  }
  return "?";
}

}  // namespace tripsitter::modes

#include <tripsitter/host/controls.h>

#include <cctype>

namespace tripsitter::host {

std::optional<Key> key_by_name(std::string_view name) {
  if (name.size() != 1) return std::nullopt;
  switch (std::toupper(static_cast<unsigned char>(name[0]))) {
    case 'W': return Key::kW;
    case 'A': return Key::kA;
    case 'S': return Key::kS;
    case 'D': return Key::kD;
    case 'I': return Key::kI;
    case 'K': return Key::kK;
    case 'J': return Key::kJ;
    case 'L': return Key::kL;
    case 'Q': return Key::kQ;
    case 'E': return Key::kE;
    case 'R': return Key::kR;
    default: return std::nullopt;
  }
}

const char* key_name(Key key) {
  static constexpr const char* kNames[] = {"W", "A", "S", "D", "I", "K", "J", "L", "Q", "E", "R"};
  return kNames[static_cast<int>(key)];
}

void apply_held_key(Camera& camera, Key key, double seconds, const ControlSpeeds& speeds) {
  const double move = speeds.move_units_per_s * seconds;
  const double look = speeds.look_deg_per_s * seconds;
  const double orbit = speeds.orbit_deg_per_s * seconds;
  switch (key) {
    case Key::kW: camera.move(move); break;
    case Key::kS: camera.move(-move); break;
    case Key::kA: camera.strafe(-move); break;
    case Key::kD: camera.strafe(move); break;
    case Key::kI: camera.look(0, look); break;
    case Key::kK: camera.look(0, -look); break;
    case Key::kJ: camera.look(-look, 0); break;
    case Key::kL: camera.look(look, 0); break;
    case Key::kQ: camera.orbit(-orbit); break;
    case Key::kE: camera.orbit(orbit); break;
    case Key::kR: break;
  }
}

}  // namespace tripsitter::host

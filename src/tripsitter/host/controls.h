// The board's keyboard controls (SPEC.md section B) as actions on the host's camera, shared by the window
// and by key scripts. Movement is continuous while a key is held; speeds are per second of hold, so the
// result does not depend on the frame rate.
#pragma once

#include <optional>
#include <string_view>

#include <tripsitter/host/camera.h>

namespace tripsitter::host {

enum class Key { kW, kA, kS, kD, kI, kK, kJ, kL, kQ, kE, kR };

struct ControlSpeeds {
  double move_units_per_s = 4.0;   // W/S and A/D, world units per second
  double look_deg_per_s = 60.0;    // I/K and J/L
  double orbit_deg_per_s = 45.0;   // Q/E
};

// "W", "a", ... (either case); nothing for other names.
std::optional<Key> key_by_name(std::string_view name);
const char* key_name(Key key);

// Applies `seconds` of holding `key` to the camera. R (reset) is not a camera motion: the host resets
// world and camera (Host::reset), so this does nothing for it.
void apply_held_key(Camera& camera, Key key, double seconds, const ControlSpeeds& speeds = {});

}  // namespace tripsitter::host

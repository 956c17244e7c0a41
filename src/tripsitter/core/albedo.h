// The albedo byte: a surface's albedo channel in [0, 1] as the v2 wire carries it (0..255 stands for 0..1).
// The host sends it, the device mixes reflections with it, and the float reference mixes with the same byte.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace tripsitter::core {

// round(a * 255) of a clamped to [0, 1], ties away from zero (0.5 gives 128). A NaN gives an unspecified byte.
inline std::uint8_t albedo_byte(double a) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(a, 0.0, 1.0) * 255.0));
}

}  // namespace tripsitter::core

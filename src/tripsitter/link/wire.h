// What host and device agree on besides the bytes: which wire, and the number formats of scene memory.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include <tripsitter/core/fixed.h>

namespace tripsitter::link {

// v1: the board's sphere word; v2: framed worlds; v3: framed worlds with a header check and a session
// (docs/link_format.md). v3 is the default everywhere.
enum class WireVersion { kV1, kV2, kV3 };

inline std::optional<WireVersion> wire_by_name(std::string_view name) {
  if (name == "v1") return WireVersion::kV1;
  if (name == "v2") return WireVersion::kV2;
  if (name == "v3") return WireVersion::kV3;
  return std::nullopt;
}

inline constexpr std::string_view wire_name(WireVersion wire) {
  switch (wire) {
    case WireVersion::kV1: return "v1";
    case WireVersion::kV2: return "v2";
    case WireVersion::kV3: return "v3";
  }
  return "v3";
}

// The formats the device's scene memory holds; the host rounds and saturates to them before encoding.
struct SceneFormats {
  core::FixedFormat x, y, z, radius;
  std::uint32_t max_spheres = 1;
  // The indices of refraction of dielectrics the device takes, in the v2 wire's u4.12 (the path preset's are
  // narrower than the wire's).
  std::uint16_t ior_min = 1, ior_max = 65535;
  // The device walks a hierarchy of bounding spheres for rays that are not the camera's (the artix path preset):
  // the host sends one with each v3 world (host/hierarchy.h).
  bool hierarchy = false;
};

}  // namespace tripsitter::link

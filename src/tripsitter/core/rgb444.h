// The board's 12-bit colour: 4 bits per channel, packed 0xRGB.
#pragma once

#include <cstdint>

namespace tripsitter::core {

struct Rgb444 {
  std::uint16_t packed = 0;  // bits 11..8 red, 7..4 green, 3..0 blue

  constexpr Rgb444() = default;
  constexpr explicit Rgb444(std::uint16_t v) : packed(static_cast<std::uint16_t>(v & 0xFFF)) {}
  // REQUIRES each channel in 0..15.
  static constexpr Rgb444 from_channels(int r, int g, int b) {
    return Rgb444(static_cast<std::uint16_t>((r << 8) | (g << 4) | b));
  }
  constexpr int r() const { return (packed >> 8) & 0xF; }
  constexpr int g() const { return (packed >> 4) & 0xF; }
  constexpr int b() const { return packed & 0xF; }
  // 4-bit channel to 8 bits: 0x0..0xF becomes 0x00..0xFF (v * 17).
  static constexpr std::uint8_t expand(int channel) { return static_cast<std::uint8_t>(channel * 17); }
  constexpr bool operator==(const Rgb444&) const = default;
};

inline constexpr Rgb444 kBackground{0x036};  // pixels that hit nothing (SPEC.md section B)
inline constexpr Rgb444 kBlack{0x000};

}  // namespace tripsitter::core

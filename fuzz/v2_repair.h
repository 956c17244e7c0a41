// Helps the fuzzer past the v2 CRC: random changes to a frame almost never keep its CRC-32 right, so without
// help every mutated frame would stop at the CRC check and the code behind it would see only the seeds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include <tripsitter/core/crc32.h>
#include <tripsitter/link/wire_v2.h>

namespace tripsitter::fuzz {

// Rewrites the CRC-32 of every frame in `bytes` whose header is whole and consistent (magic, and a length of
// count * 24 that fits in the rest of the bytes); the rest is left as it is. Returns whether anything changed.
inline bool repair_v2_crcs(std::span<std::uint8_t> bytes) {
  const auto u32 = [&](std::size_t at) {
    return (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) |
           (std::uint32_t{bytes[at + 2]} << 8) | bytes[at + 3];
  };
  bool changed = false;
  std::size_t at = 0;
  while (at + link::kV2HeaderBytes <= bytes.size()) {
    const bool magic = bytes[at] == link::kV2Magic[0] && bytes[at + 1] == link::kV2Magic[1] &&
                       bytes[at + 2] == link::kV2Magic[2] && bytes[at + 3] == link::kV2Magic[3];
    const std::uint64_t count = magic ? u32(at + 12) : 0, length = magic ? u32(at + 16) : 0;
    const std::uint64_t crc_at = at + link::kV2HeaderBytes + length;
    if (!magic || length != count * link::kV2SphereBytes || crc_at + link::kV2TrailerBytes > bytes.size()) {
      ++at;
      continue;
    }
    const std::uint32_t crc = core::crc32(bytes.first(static_cast<std::size_t>(crc_at)).subspan(at));
    for (int k = 0; k < 4; ++k) {
      const auto b = static_cast<std::uint8_t>(crc >> (24 - 8 * k));
      changed = changed || bytes[crc_at + k] != b;
      bytes[crc_at + k] = b;
    }
    at = static_cast<std::size_t>(crc_at) + link::kV2TrailerBytes;
  }
  return changed;
}

}  // namespace tripsitter::fuzz

// Helps the fuzzer past the framed wires' CRCs: random changes to a frame almost never keep a CRC-32 right,
// so without help every mutated frame would stop at the first CRC check and the code behind it would see only
// the seeds.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

#include <tripsitter/core/crc32.h>
#include <tripsitter/link/frame.h>

namespace tripsitter::fuzz {

// Rewrites the CRCs of every frame of `wire` (v2 or v3) in `bytes`: on v3, the header CRC of every whole
// header after a magic; on both, the frame's CRC where the header is consistent (a length of count * 24, or on v3
// with content 1 of 24 more for each node, that fits in the rest of the bytes). The rest is left as it is. Returns
// whether anything changed.
inline bool repair_frame_crcs(link::WireVersion wire, std::span<std::uint8_t> bytes) {
  const bool v3 = wire == link::WireVersion::kV3;
  const auto& magic = v3 ? link::kV3Magic : link::kV2Magic;
  const std::size_t header_bytes = link::frame_header_bytes(wire);
  const std::size_t count_at = v3 ? 16 : 12, length_at = count_at + 4, header_crc_at = 24;
  const auto u32 = [&](std::size_t at) {
    return (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) |
           (std::uint32_t{bytes[at + 2]} << 8) | bytes[at + 3];
  };
  bool changed = false;
  const auto put_crc = [&](std::size_t from, std::size_t to) {  // the CRC-32 of bytes from..to-1, at `to`
    const std::uint32_t crc = core::crc32(bytes.subspan(from, to - from));
    for (std::size_t k = 0; k < 4; ++k) {
      const auto b = static_cast<std::uint8_t>(crc >> (24 - 8 * k));
      changed = changed || bytes[to + k] != b;
      bytes[to + k] = b;
    }
  };
  std::size_t at = 0;
  while (at + header_bytes <= bytes.size()) {
    if (!std::equal(magic.begin(), magic.end(), bytes.begin() + static_cast<std::ptrdiff_t>(at))) {
      ++at;
      continue;
    }
    if (v3) put_crc(at, at + header_crc_at);
    const std::uint64_t count = u32(at + count_at), length = u32(at + length_at);
    const std::uint64_t crc_at = at + header_bytes + length;
    const bool hierarchy = v3 && bytes[at + 6] == link::kContentHierarchy;
    const bool consistent = hierarchy ? length > count * link::kSphereBytes &&
                                            (length - count * link::kSphereBytes) % link::kNodeBytes == 0
                                      : length == count * link::kSphereBytes;
    if (!consistent || crc_at + link::kFrameTrailerBytes > bytes.size()) {
      ++at;
      continue;
    }
    put_crc(at, static_cast<std::size_t>(crc_at));
    at = static_cast<std::size_t>(crc_at) + link::kFrameTrailerBytes;
  }
  return changed;
}

}  // namespace tripsitter::fuzz

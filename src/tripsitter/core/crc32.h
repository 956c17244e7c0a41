// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320, init and final xor 0xFFFFFFFF), as used by zlib and PNG.
#pragma once

#include <cstdint>
#include <span>

namespace tripsitter::core {

// Continues a running CRC: crc32(b, crc32(a)) == crc32(a ++ b). Start with crc = 0.
std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

}  // namespace tripsitter::core

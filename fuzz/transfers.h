// The transfers and vertical blankings a receiver fuzzer's input asks for (receiver_fuzz.cpp and
// receiver_pins_fuzz.cpp describe the transfer bytes in their input layouts).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace tripsitter::fuzz {

struct Transfer {
  std::size_t bytes = 0;
  bool blanking = false;  // a vertical blanking after it
};

// The transfers the transfer bytes `ops` make of `size` link bytes: each op's bits 0..6 the transfer's length in
// units of `unit` bytes (0 an empty transfer), bit 7 a vertical blanking after it; the ops are used in turn,
// cyclically, until the link bytes run out (all of them at once when there are no ops).
inline std::vector<Transfer> transfers_of(std::span<const std::uint8_t> ops, std::size_t unit, std::size_t size) {
  std::vector<Transfer> transfers;
  std::size_t at = 0, op = 0, idle_ops = 0;
  while (at < size) {
    Transfer t{size - at, false};
    if (!ops.empty()) {
      const std::uint8_t o = ops[op++ % ops.size()];
      t.bytes = std::min(t.bytes, (o & 0x7F) * unit);
      t.blanking = (o & 0x80) != 0;
      // Only empty transfers: send the rest at once rather than loop for ever.
      idle_ops = t.bytes == 0 ? idle_ops + 1 : 0;
      if (idle_ops > ops.size()) t.bytes = size - at;
    }
    transfers.push_back(t);
    at += t.bytes;
  }
  return transfers;
}

}  // namespace tripsitter::fuzz

// Helpers the receiver's RTL tests share (receiver_rtl_test.cpp, receiver_blocks_rtl_test.cpp): a seeded random
// source and the byte surgery that edits a frame and keeps its CRCs good.
#pragma once

#include <cstddef>
#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include <tripsitter/core/crc32.h>
#include <tripsitter/link/wire.h>

namespace tripsitter::rtl {

using Bytes = std::vector<std::uint8_t>;

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : g_(seed) {}
  std::uint64_t below(std::uint64_t n) { return g_() % n; }
  std::int64_t between(std::int64_t lo, std::int64_t hi) {
    return lo + static_cast<std::int64_t>(below(static_cast<std::uint64_t>(hi - lo) + 1));
  }
  bool percent(int p) { return below(100) < static_cast<std::uint64_t>(p); }
  std::uint8_t byte() { return static_cast<std::uint8_t>(g_() >> 56); }
  std::uint64_t word() { return g_(); }

 private:
  std::mt19937_64 g_;
};

inline void put_be32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (std::size_t k = 0; k < 4; ++k) b[at + k] = static_cast<std::uint8_t>(v >> (24 - 8 * k));
}

// Fixes a frame's CRCs after its bytes were edited (the header CRC on v3, the trailer always).
inline void fix_crcs(link::WireVersion wire, Bytes& f) {
  if (wire == link::WireVersion::kV3) put_be32(f, 24, core::crc32(std::span<const std::uint8_t>(f).first(24)));
  put_be32(f, f.size() - 4, core::crc32(std::span<const std::uint8_t>(f).first(f.size() - 4)));
}

}  // namespace tripsitter::rtl

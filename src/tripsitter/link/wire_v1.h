// The v1 wire: the original board's 64-bit sphere word (SPEC.md section B, docs/link_format.md).
// One sphere per word, 8 bytes, most significant byte first. A v1 stream is a sequence of words with no
// framing; a device fed v1 words shows the latest one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <utility>
#include <vector>

#include <tripsitter/core/fixed.h>

namespace tripsitter::link {

inline constexpr std::size_t kV1WordBytes = 8;

// Field formats of the word: x is s16.3 (13.3), y and z are s15.3 (12.3).
inline constexpr core::FixedFormat kV1X{16, 3, true};
inline constexpr core::FixedFormat kV1Y{15, 3, true};
inline constexpr core::FixedFormat kV1Z{15, 3, true};
inline constexpr int kV1RadiusLog2Max = 63;  // 6-bit field; the radius is 2^r pixel units

struct V1Sphere {
  std::int32_t x_raw = 0;         // REQUIRES kV1X.contains(x_raw)
  std::int32_t y_raw = 0;         // REQUIRES kV1Y.contains(y_raw)
  std::int32_t z_raw = 0;         // REQUIRES kV1Z.contains(z_raw)
  std::uint8_t radius_log2 = 0;   // 0..63
  std::uint16_t colour = 0;       // RGB444, 0..0xFFF
  bool operator==(const V1Sphere&) const = default;
};

// Bit-exact packing: bits 63..48 x, 47..33 y, 32..18 z, 17..12 r, 11..0 colour.
std::uint64_t encode_v1_word(const V1Sphere& sphere);
// Every 64-bit value decodes (the word has no invalid patterns); fields are sign-extended.
V1Sphere decode_v1_word(std::uint64_t word);

// Appends the word's 8 bytes, most significant first.
void append_v1_bytes(std::uint64_t word, std::vector<std::uint8_t>& out);

// Reassembles words from a byte stream cut into transfers of any size: every 8 bytes, counted from the
// start of the stream, are one word.
class V1StreamDecoder {
 public:
  explicit V1StreamDecoder(std::function<void(const V1Sphere&)> on_word) : on_word_(std::move(on_word)) {}
  void push(std::span<const std::uint8_t> bytes);
  // Bytes of an incomplete word held so far (0..7).
  std::size_t pending_bytes() const { return filled_; }
  // Drops a partial word (the host's chip select went high mid-word).
  void reset() { filled_ = 0; word_ = 0; }

 private:
  std::function<void(const V1Sphere&)> on_word_;
  std::uint64_t word_ = 0;
  std::size_t filled_ = 0;
};

}  // namespace tripsitter::link

// The v3 wire (link/frame.h): decode_frame and the stream decoder, with the header's own CRC.
//
// Input: the bytes of one frame, or of a stream of frames and damage (the seeds are real encoded worlds).
// Everything below runs on the input as it is and, when that changes it, once more on the input with the
// header CRC after every magic and the frame CRC of every frame whose header is consistent rewritten
// (frame_repair.h), so that mutated headers and spheres get past the CRC checks.
//
// Checks:
//   - those of wire_v2 (frame_checks.h): decode_frame's round trip and failures; the stream decoder gives the
//     same frames and errors however the stream is cut into transfers (also where an intact header lies
//     inside the frame another announces: v3's cut rule looks at the frame's bytes only), every byte is in
//     one delivered frame or one report,
//     delivered frames re-encode to the bytes they came from, the buffer stays under one frame and one slice;
//   - a wrong header CRC is never passed: every delivered frame's header carries the CRC-32 of its first 24
//     bytes; decode_frame refuses an input whose first 8 bytes pass and whose header CRC is wrong as "bad
//     header CRC" at offset 24;
//   - a frame decode_frame accepts, with one bit of bytes 8..27 flipped (session, sequence, count, length or
//     the header CRC itself, chosen by a hash of the input) and its frame CRC made right again, is refused by
//     decode_frame as "bad header CRC" at offset 24, and the stream decoder begins with that report and 1
//     byte dropped: the damaged frame is never delivered.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <tripsitter/core/crc32.h>
#include <tripsitter/link/frame.h>

#include "check.h"
#include "frame_checks.h"
#include "frame_repair.h"

namespace {

namespace core = tripsitter::core;
namespace fuzz = tripsitter::fuzz;
namespace link = tripsitter::link;

constexpr auto kWire = link::WireVersion::kV3;
constexpr std::size_t kHeaderCrcAt = 24;  // the header CRC covers bytes 0..23
constexpr std::size_t kCoveredOnlyAt = 8;   // session, sequence, count and length: no check but the header CRC

std::uint32_t read_u32(std::span<const std::uint8_t> bytes, std::size_t at) {
  return (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) |
         (std::uint32_t{bytes[at + 2]} << 8) | bytes[at + 3];
}

void write_u32(std::span<std::uint8_t> bytes, std::size_t at, std::uint32_t value) {
  for (std::size_t k = 0; k < 4; ++k) bytes[at + k] = static_cast<std::uint8_t>(value >> (24 - 8 * k));
}

// REQUIRES a whole header in `frame`.
bool header_crc_right(std::span<const std::uint8_t> frame) {
  return read_u32(frame, kHeaderCrcAt) == core::crc32(frame.first(kHeaderCrcAt));
}

// The magic, the version, frac_bits and the reserved bytes: the checks before the header CRC's.
bool first_bytes_pass(std::span<const std::uint8_t> bytes) {
  return std::equal(link::kV3Magic.begin(), link::kV3Magic.end(), bytes.begin()) && bytes[4] == link::kV3Version &&
         bytes[5] <= link::kMaxFracBits && bytes[6] == 0 && bytes[7] == 0;
}

bool is_bad_header_crc(const link::FrameFailure& f) {
  return f.error == link::FrameError::kBadHeaderCrc && f.offset == kHeaderCrcAt;
}

void check_bytes(std::span<const std::uint8_t> bytes, std::uint32_t hash) {
  const std::vector<fuzz::FrameEvent> events = fuzz::check_frames(kWire, bytes);
  for (const fuzz::FrameEvent& e : events) {
    if (e.is_frame) FUZZ_CHECK(header_crc_right(bytes.subspan(e.at)), "a frame with a wrong header CRC was delivered");
  }
  const auto result = link::decode_frame(kWire, bytes, fuzz::kMaxSpheres);
  if (bytes.size() >= link::kV3HeaderBytes && first_bytes_pass(bytes) && !header_crc_right(bytes)) {
    FUZZ_CHECK(!result.ok() && is_bad_header_crc(result.error()),
               "a header with a wrong CRC was not refused as a bad header CRC at offset 24");
  }
  if (!result.ok()) return;

  // One bit of the intact frame's header damaged, its frame CRC made right again.
  std::vector<std::uint8_t> damaged(bytes.begin(), bytes.end());
  const std::size_t bit = hash % ((link::kV3HeaderBytes - kCoveredOnlyAt) * 8);
  damaged[kCoveredOnlyAt + bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
  const std::size_t crc_at = damaged.size() - link::kFrameTrailerBytes;
  write_u32(damaged, crc_at, core::crc32(std::span<const std::uint8_t>(damaged).first(crc_at)));
  const auto refused = link::decode_frame(kWire, damaged, fuzz::kMaxSpheres);
  FUZZ_CHECK(!refused.ok() && is_bad_header_crc(refused.error()),
             "a frame with one header bit flipped was not refused as a bad header CRC at offset 24");
  const std::vector<fuzz::FrameEvent> stream = fuzz::check_frames(kWire, damaged);
  FUZZ_CHECK(!stream.empty() && !stream[0].is_frame && stream[0].error == link::FrameError::kBadHeaderCrc &&
                 stream[0].offset == kHeaderCrcAt && stream[0].bytes == 1,
             "the stream decoder did not begin a frame with a flipped header bit with a bad header CRC report");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::uint32_t hash = 2166136261u;
  for (std::size_t i = 0; i < size; ++i) hash = (hash ^ data[i]) * 16777619u;
  check_bytes(std::span<const std::uint8_t>(data, size), hash);
  std::vector<std::uint8_t> repaired(data, data + size);
  if (fuzz::repair_frame_crcs(kWire, repaired)) check_bytes(repaired, hash);
  return 0;
}

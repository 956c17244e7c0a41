// The v2 wire (link/wire_v2.h): decode_v2_frame and the stream decoder.
//
// Input: the bytes of one frame, or of a stream of frames and damage (the seeds are real encoded worlds).
// Everything below runs on the input as it is and, when that changes it, once more on the input with the
// CRC of every frame whose header is consistent rewritten (v2_repair.h), so that mutated spheres get past
// the CRC check.
//
// Checks:
//   - decode_v2_frame: a frame that decodes is valid (frac_bits, count, spheres) and encodes back to exactly
//     the input; one sphere fewer of scene memory rejects it as too many spheres; a failure points inside
//     the input and says why;
//   - V2StreamDecoder: the stream fed at once and fed in transfers of 1..64 bytes (sizes drawn from a hash
//     of the input) gives the same frames and errors; every byte is in exactly one delivered frame or one
//     error report, in stream order; each delivered frame re-encodes to the very bytes it came from; the
//     buffer never holds more than one frame and one 4096-byte slice; nothing stays buffered at the end;
//   - a whole frame that decode_v2_frame accepts is one delivered frame and no error for the stream decoder.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <tripsitter/link/wire_v2.h>

#include "check.h"
#include "v2_repair.h"

namespace {

namespace link = tripsitter::link;

constexpr std::uint32_t kMaxSpheres = 4096;  // the wide preset's scene memory
constexpr std::size_t kSliceBytes = 4096;    // wire_v2.cpp takes input in slices of this size

// One callback of the stream decoder.
struct Event {
  bool is_frame = false;
  link::World world;               // is_frame
  link::V2Error error{};           // !is_frame
  std::size_t offset = 0;          // !is_frame
  std::size_t bytes = 0;           // the frame's size, or the bytes dropped with the error
  bool operator==(const Event&) const = default;
};

std::size_t frame_size(const link::World& w) {
  return link::kV2HeaderBytes + w.spheres.size() * link::kV2SphereBytes + link::kV2TrailerBytes;
}

bool valid_world(const link::World& w, std::uint32_t max_spheres) {
  if (w.frac_bits > link::kV2MaxFracBits || w.spheres.size() > max_spheres) return false;
  for (const link::WireSphere& s : w.spheres) {
    if (s.radius == 0 || s.material > link::kMaterialDielectric || s.ior == 0) return false;
  }
  return true;
}

// Feeds `bytes` to a stream decoder, all at once (seed 0) or in transfers of 1..64 bytes drawn from `seed`,
// then ends the stream.
std::vector<Event> decode_stream(std::span<const std::uint8_t> bytes, std::uint32_t seed) {
  std::vector<Event> events;
  link::V2StreamDecoder decoder(
      kMaxSpheres,
      {.on_frame = [&](link::World&& w) { events.push_back({true, std::move(w), {}, 0, 0}); },
       .on_error = [&](const link::V2Failure& f, std::size_t dropped) {
         FUZZ_CHECK(!f.detail.empty(), "a stream error without a detail");
         events.push_back({false, {}, f.error, f.offset, dropped});
       }});
  const std::size_t max_buffered =
      link::kV2HeaderBytes + std::size_t{kMaxSpheres} * link::kV2SphereBytes + link::kV2TrailerBytes + kSliceBytes;
  std::size_t at = 0;
  while (at < bytes.size()) {
    std::size_t n = bytes.size() - at;
    if (seed != 0) {
      seed = seed * 1103515245u + 12345u;
      n = std::min<std::size_t>(n, 1 + (seed >> 16) % 64);
    }
    decoder.push(bytes.subspan(at, n));
    at += n;
    FUZZ_CHECK(decoder.buffered_bytes() <= max_buffered, "the stream decoder buffers more than a frame and a slice");
  }
  decoder.end_of_stream();
  FUZZ_CHECK(decoder.buffered_bytes() == 0, "bytes still buffered after end_of_stream()");
  for (Event& e : events) {
    if (e.is_frame) e.bytes = frame_size(e.world);
  }
  return events;
}

void check_bytes(std::span<const std::uint8_t> bytes) {
  const std::uint8_t* data = bytes.data();
  const std::size_t size = bytes.size();

  // One frame.
  const auto result = link::decode_v2_frame(bytes, kMaxSpheres);
  if (result.ok()) {
    const link::World& world = result.value();
    FUZZ_CHECK(valid_world(world, kMaxSpheres), "decode_v2_frame accepted an invalid world");
    const std::vector<std::uint8_t> again = link::encode_v2_frame(world);
    FUZZ_CHECK(again.size() == size && std::equal(again.begin(), again.end(), data),
               "a decoded frame does not re-encode to the same bytes");
    if (!world.spheres.empty()) {
      const auto fewer = link::decode_v2_frame(bytes, static_cast<std::uint32_t>(world.spheres.size() - 1));
      FUZZ_CHECK(!fewer.ok() && fewer.error().error == link::V2Error::kTooManySpheres,
                 "a frame with one sphere more than the scene memory holds was not rejected as too many spheres");
    }
  } else {
    const link::V2Failure& f = result.error();
    FUZZ_CHECK(f.offset <= size, "a failure points beyond the input");
    FUZZ_CHECK(!f.detail.empty(), "a failure without a detail");
    FUZZ_CHECK(std::string(link::to_string(f.error)) != "unknown error", "a failure with an unknown error code");
  }

  // The stream decoder: at once, and in transfers.
  std::uint32_t hash = 2166136261u;
  for (std::size_t i = 0; i < size; ++i) hash = (hash ^ data[i]) * 16777619u;
  const std::vector<Event> whole = decode_stream(bytes, 0);
  const std::vector<Event> cut = decode_stream(bytes, hash | 1);
  FUZZ_CHECK(whole == cut, "frames or errors depend on how the stream is cut into transfers");

  std::size_t at = 0;
  for (const Event& e : whole) {
    FUZZ_CHECK(e.bytes > 0 && at + e.bytes <= size, "an event covers no bytes or bytes beyond the stream");
    if (e.is_frame) {
      FUZZ_CHECK(valid_world(e.world, kMaxSpheres), "the stream decoder delivered an invalid world");
      const std::vector<std::uint8_t> again = link::encode_v2_frame(e.world);
      FUZZ_CHECK(std::equal(again.begin(), again.end(), data + at),
                 "a delivered frame does not re-encode to the bytes it came from");
    } else if (e.error == link::V2Error::kBadMagic) {
      FUZZ_CHECK(e.offset == at, "a garbage report does not start where the previous event ended");
    } else {
      FUZZ_CHECK(e.offset >= at && e.offset <= size, "an error points before its frame or beyond the stream");
    }
    at += e.bytes;
  }
  FUZZ_CHECK(at == size, "delivered frames and dropped bytes do not add up to the stream");

  if (result.ok()) {
    FUZZ_CHECK(whole.size() == 1 && whole[0].is_frame && whole[0].world == result.value(),
               "a frame decode_v2_frame accepts is not exactly one frame for the stream decoder");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  check_bytes(std::span<const std::uint8_t>(data, size));
  std::vector<std::uint8_t> repaired(data, data + size);
  if (tripsitter::fuzz::repair_v2_crcs(repaired)) check_bytes(repaired);
  return 0;
}

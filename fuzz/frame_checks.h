// The checks the framed wires share (wire_v2_fuzz.cpp and wire_v3_fuzz.cpp list them): decode_frame and the
// stream decoder of link/frame.h on one input.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <tripsitter/core/crc32.h>
#include <tripsitter/link/frame.h>

#include "check.h"

namespace tripsitter::fuzz {

inline constexpr std::uint32_t kMaxSpheres = 4096;  // the wide preset's scene memory
inline constexpr std::size_t kSliceBytes = 4096;    // frame.cpp takes input in slices of this size

// One callback of the stream decoder.
struct FrameEvent {
  bool is_frame = false;
  link::World world;        // is_frame
  link::FrameError error{};  // !is_frame
  std::size_t offset = 0;   // !is_frame
  std::size_t bytes = 0;    // the frame's size, or the bytes dropped with the error
  std::size_t at = 0;       // where its bytes begin in the stream (not compared)
  bool operator==(const FrameEvent& o) const {
    return is_frame == o.is_frame && world == o.world && error == o.error && offset == o.offset && bytes == o.bytes;
  }
};

// A world keeps the frame's rules: its spheres', and a hierarchy's (v3 only, at most as many nodes as spheres the
// receiver holds).
inline bool valid_world(link::WireVersion wire, const link::World& w, std::uint32_t max_spheres) {
  if (w.frac_bits > link::kMaxFracBits || w.spheres.size() > max_spheres) return false;
  for (const link::WireSphere& s : w.spheres) {
    if (s.radius == 0 || s.material > link::kMaterialDielectric || s.ior == 0) return false;
  }
  if (!w.nodes.empty() && (wire != link::WireVersion::kV3 || w.nodes.size() > max_spheres)) return false;
  return !link::hierarchy_error(w).has_value();
}

// Feeds `bytes` to a stream decoder, all at once (seed 0) or in transfers of 1..64 bytes drawn from `seed`,
// then ends the stream. Checks the buffer bound on the way.
inline std::vector<FrameEvent> decode_stream(link::WireVersion wire, std::span<const std::uint8_t> bytes,
                                             std::uint32_t seed) {
  std::vector<FrameEvent> events;
  link::FrameStreamDecoder decoder(
      wire, kMaxSpheres,
      {.on_frame = [&](link::World&& w) { events.push_back({true, std::move(w), {}, 0, 0, 0}); },
       .on_error = [&](const link::FrameFailure& f, std::size_t dropped) {
         FUZZ_CHECK(!f.detail.empty(), "a stream error without a detail");
         events.push_back({false, {}, f.error, f.offset, dropped, 0});
       }});
  const std::size_t max_buffered = link::frame_bytes(wire, kMaxSpheres) + kSliceBytes;
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
  std::size_t start = 0;
  for (FrameEvent& e : events) {
    if (e.is_frame) e.bytes = link::frame_bytes(wire, e.world.spheres.size(), e.world.nodes.size());
    e.at = start;
    start += e.bytes;
  }
  return events;
}

// The checks both framed wires share; returns the stream decoder's events for the whole input at once.
//   - decode_frame: a frame that decodes is valid (frac_bits, count, spheres, hierarchy) and encodes back to exactly the
//     input; one sphere fewer of scene memory rejects it as too many spheres; a failure points inside the
//     input and says why;
//   - FrameStreamDecoder: the stream fed at once and fed in transfers of 1..64 bytes (sizes drawn from a hash
//     of the input) gives the same frames and errors; every
//     byte is in exactly one delivered frame or one error report, in stream order; each delivered frame
//     re-encodes to the very bytes it came from; the buffer never holds more than one frame and one 4096-byte
//     slice; nothing stays buffered at the end;
//   - a whole frame that decode_frame accepts is one delivered frame and no error for the stream decoder.
inline std::vector<FrameEvent> check_frames(link::WireVersion wire, std::span<const std::uint8_t> bytes) {
  const std::uint8_t* data = bytes.data();
  const std::size_t size = bytes.size();

  // One frame.
  const auto result = link::decode_frame(wire, bytes, kMaxSpheres);
  if (result.ok()) {
    const link::World& world = result.value();
    FUZZ_CHECK(valid_world(wire, world, kMaxSpheres), "decode_frame accepted an invalid world");
    const std::vector<std::uint8_t> again = link::encode_frame(wire, world);
    FUZZ_CHECK(again.size() == size && std::equal(again.begin(), again.end(), data),
               "a decoded frame does not re-encode to the same bytes");
    if (!world.spheres.empty()) {
      const auto fewer = link::decode_frame(wire, bytes, static_cast<std::uint32_t>(world.spheres.size() - 1));
      FUZZ_CHECK(!fewer.ok() && fewer.error().error == link::FrameError::kTooManySpheres,
                 "a frame with one sphere more than the scene memory holds was not rejected as too many spheres");
    }
  } else {
    const link::FrameFailure& f = result.error();
    FUZZ_CHECK(f.offset <= size, "a failure points beyond the input");
    FUZZ_CHECK(!f.detail.empty(), "a failure without a detail");
    FUZZ_CHECK(std::string(link::to_string(f.error)) != "unknown error", "a failure with an unknown error code");
  }

  // The stream decoder: at once, and in transfers.
  std::uint32_t hash = 2166136261u;
  for (std::size_t i = 0; i < size; ++i) hash = (hash ^ data[i]) * 16777619u;
  const std::vector<FrameEvent> whole = decode_stream(wire, bytes, 0);
  const std::vector<FrameEvent> cut = decode_stream(wire, bytes, hash | 1);
  FUZZ_CHECK(whole == cut, "frames or errors depend on how the stream is cut into transfers");

  for (const std::vector<FrameEvent>* events : {&whole, &cut}) {
    std::size_t at = 0;
    for (const FrameEvent& e : *events) {
      FUZZ_CHECK(e.bytes > 0 && at + e.bytes <= size, "an event covers no bytes or bytes beyond the stream");
      if (e.is_frame) {
        FUZZ_CHECK(valid_world(wire, e.world, kMaxSpheres), "the stream decoder delivered an invalid world");
        const std::vector<std::uint8_t> again = link::encode_frame(wire, e.world);
        FUZZ_CHECK(std::equal(again.begin(), again.end(), data + at),
                   "a delivered frame does not re-encode to the bytes it came from");
      } else if (e.error == link::FrameError::kBadMagic) {
        FUZZ_CHECK(e.offset == at, "a garbage report does not start where the previous event ended");
      } else {
        FUZZ_CHECK(e.offset >= at && e.offset <= size, "an error points before its frame or beyond the stream");
      }
      at += e.bytes;
    }
    FUZZ_CHECK(at == size, "delivered frames and dropped bytes do not add up to the stream");
  }

  if (result.ok()) {
    FUZZ_CHECK(whole.size() == 1 && whole[0].is_frame && whole[0].world == result.value(),
               "a frame decode_frame accepts is not exactly one frame for the stream decoder");
  }
  return whole;
}

}  // namespace tripsitter::fuzz

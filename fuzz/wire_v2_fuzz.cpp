// The v2 wire (link/frame.h): decode_frame and the stream decoder, on TripSitter's earlier framed wire.
//
// Input: the bytes of one frame, or of a stream of frames and damage (the seeds are real encoded worlds).
// Everything below runs on the input as it is and, when that changes it, once more on the input with the
// CRC of every frame whose header is consistent rewritten (frame_repair.h), so that mutated spheres get past
// the CRC check.
//
// Checks (frame_checks.h):
//   - decode_frame: a frame that decodes is valid (frac_bits, count, spheres) and encodes back to exactly
//     the input; one sphere fewer of scene memory rejects it as too many spheres; a failure points inside
//     the input and says why;
//   - FrameStreamDecoder: the stream fed at once and fed in transfers of 1..64 bytes (sizes drawn from a hash
//     of the input) gives the same frames and errors; every byte is in exactly one delivered frame or one
//     error report, in stream order; each delivered frame re-encodes to the very bytes it came from; the
//     buffer never holds more than one frame and one 4096-byte slice; nothing stays buffered at the end;
//   - a whole frame that decode_frame accepts is one delivered frame and no error for the stream decoder.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <tripsitter/link/frame.h>

#include "frame_checks.h"
#include "frame_repair.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fuzz = tripsitter::fuzz;
  constexpr auto kWire = tripsitter::link::WireVersion::kV2;
  fuzz::check_frames(kWire, std::span<const std::uint8_t>(data, size));
  std::vector<std::uint8_t> repaired(data, data + size);
  if (fuzz::repair_frame_crcs(kWire, repaired)) fuzz::check_frames(kWire, repaired);
  return 0;
}

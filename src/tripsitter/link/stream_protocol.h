// The link over a byte stream: what the bytes mean when host and device are two programs
// (docs/link_format.md, "Over a byte stream"). How they travel, over TCP, is transport/stream.h.
//
// Host to device: exactly the link bytes (v1 words or v2 frames), in transfers of at most the SPI driver's
// max_transfer_bytes. Device to host: the ready line as single bytes. The device sends a credit, 'R', when
// its ready line is high and nothing it granted this host is outstanding: on connect (if ready), after the
// host's last world was swapped into scene memory, and ('X' instead of 'R') after it was rejected. The host
// sends one world per credit; a newer world replaces one not yet sent. So the host never sends a world the
// device is not ready for, at most one world is in flight, and neither side ever waits on the other while
// holding what the other needs.
//
// The device serves one host at a time: a second host is refused with 'B' and its connection closed.
#pragma once

#include <cstdint>

#include <tripsitter/link/spi.h>

namespace tripsitter::link {

// The back channel, device to host: one byte each.
inline constexpr std::uint8_t kStreamReady = 'R';     // ready; the host's last world, if any, was taken
inline constexpr std::uint8_t kStreamRejected = 'X';  // ready; the host's last world was rejected
inline constexpr std::uint8_t kStreamBusy = 'B';      // another host is connected; this connection closes

// The device as its stream port needs it: the SPI endpoint (ready line, transfers) and what the receiver
// made of the bytes, as running totals. The credit rule compares these totals with those at the last credit.
class StreamEndpoint : public Endpoint {
 public:
  // The host went away: a partial frame is dropped and counted.
  virtual void end_of_stream() = 0;
  virtual std::uint64_t worlds_accepted() const = 0;  // complete worlds written to the back copy
  virtual std::uint64_t worlds_rejected() const = 0;  // frames (or v1 words) dropped as damaged or unacceptable
};

}  // namespace tripsitter::link

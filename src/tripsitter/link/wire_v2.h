// The v2 wire: TripSitter's framed protocol for many spheres with materials.
// The byte layout, with a worked example, is in docs/link_format.md; this header holds the constants
// that the host's encoder and the device's decoder share.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <tripsitter/core/result.h>

namespace tripsitter::link {

inline constexpr std::array<std::uint8_t, 4> kV2Magic{'T', 'S', 'W', '2'};
inline constexpr std::uint8_t kV2Version = 2;
inline constexpr std::size_t kV2HeaderBytes = 20;   // magic 4, version 1, frac_bits 1, reserved 2, sequence 4, count 4, length 4
inline constexpr std::size_t kV2SphereBytes = 24;
inline constexpr std::size_t kV2TrailerBytes = 4;   // CRC-32 of header and payload
inline constexpr int kV2MaxFracBits = 30;
inline constexpr double kV2IorScale = 4096.0;       // ior is carried as u4.12
inline constexpr double kV2FuzzScale = 65535.0;     // fuzz is carried as value * 65535

// Material codes on the wire.
inline constexpr std::uint8_t kMaterialLambertian = 0;
inline constexpr std::uint8_t kMaterialMetal = 1;
inline constexpr std::uint8_t kMaterialDielectric = 2;

struct WireSphere {
  std::int32_t x = 0, y = 0, z = 0;   // centre, view space, raw fixed point with the frame's frac_bits
  std::uint32_t radius = 0;           // raw fixed point with the frame's frac_bits; > 0
  std::uint8_t material = kMaterialLambertian;
  std::array<std::uint8_t, 3> albedo{};  // 0..255 stands for 0..1
  std::uint16_t fuzz = 0;             // fuzz * 65535
  std::uint16_t ior = 0;              // ior * 4096; > 0
  bool operator==(const WireSphere&) const = default;
};

struct World {
  std::uint32_t sequence = 0;
  std::uint8_t frac_bits = 0;         // 0..kV2MaxFracBits
  std::vector<WireSphere> spheres;
  bool operator==(const World&) const = default;
};

enum class V2Error {
  kBadMagic,        // the stream did not start with the magic where a frame was expected
  kBadVersion,      // version byte is not 2
  kBadHeader,       // frac_bits above kV2MaxFracBits or reserved bytes not zero
  kTooManySpheres,  // count above the receiver's limit (checked before anything is allocated)
  kBadLength,       // payload length is not count * 24
  kTruncated,       // the bytes end before the frame does
  kBadCrc,          // the CRC-32 does not match
  kBadSphere,       // a sphere with radius 0, unknown material or ior 0
  kTrailingBytes,   // decode_v2_frame: bytes after the end of the frame
};

const char* to_string(V2Error error);

struct V2Failure {
  V2Error error;
  std::size_t offset = 0;   // byte offset in the input at which the problem was found
  std::string detail;       // a sentence for people: what was expected and what was found
};

// Encodes one frame. REQUIRES world.frac_bits <= kV2MaxFracBits and every sphere valid (radius > 0,
// known material, ior > 0).
std::vector<std::uint8_t> encode_v2_frame(const World& world);

// Decodes exactly one frame that fills `bytes`.
core::Result<World, V2Failure> decode_v2_frame(std::span<const std::uint8_t> bytes, std::uint32_t max_spheres);

// Reassembles frames from a byte stream cut into transfers of any size. Damage never stops it: on any
// error it reports the error and the number of bytes it discarded, then hunts for the next magic.
// Never allocates more than max_spheres spheres for one frame.
class V2StreamDecoder {
 public:
  struct Callbacks {
    std::function<void(World&&)> on_frame;
    std::function<void(const V2Failure&, std::size_t bytes_dropped)> on_error;
  };
  V2StreamDecoder(std::uint32_t max_spheres, Callbacks callbacks);

  void push(std::span<const std::uint8_t> bytes);
  // The sender went away: a partial frame is dropped and reported as kTruncated, a run of garbage being
  // hunted through as kBadMagic (nothing is reported when nothing is buffered).
  void end_of_stream();
  std::size_t buffered_bytes() const { return buffer_.size(); }

 private:
  // Implementation state is free to change; see wire_v2.cpp.
  void make_room(std::size_t n);
  void process();
  bool try_frame();
  bool hunt();
  void start_hunt(std::string reason);
  void report_garbage();
  void report(const V2Failure& failure, std::size_t bytes_dropped);
  std::size_t stream_offset(std::size_t index) const { return buffer_offset_ + index; }

  std::uint32_t max_spheres_;
  Callbacks callbacks_;
  std::vector<std::uint8_t> buffer_;  // bytes not yet consumed; between calls the read position is 0
  std::size_t read_ = 0;              // read position in buffer_ while push() works
  std::size_t buffer_offset_ = 0;     // stream offset of buffer_[0]
  std::size_t frame_bytes_ = 0;       // size of the frame at read_ once its header has passed, else 0
  bool hunting_ = false;              // skipping bytes until the next magic
  std::size_t garbage_start_ = 0;     // stream offset of the first byte skipped in this hunt
  std::size_t garbage_bytes_ = 0;     // bytes skipped in this hunt and not yet reported
  std::string hunt_reason_;           // why the hunt started, for the kBadMagic report
};

}  // namespace tripsitter::link

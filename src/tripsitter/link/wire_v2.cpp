// The v2 frame codec and the receiver's stream decoder. The layout is in docs/link_format.md.
//
// The stream decoder keeps the bytes it has not consumed in one buffer and reads them through an offset;
// the consumed prefix is erased once per slice of input, so each byte is copied a bounded number of times
// and decoding stays linear in the input. The same header and body checks serve decode_v2_frame and the
// stream decoder, so both report the same errors at the same offsets.
#include <tripsitter/link/wire_v2.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <utility>

#include <tripsitter/core/crc32.h>

namespace tripsitter::link {
namespace {

// Offsets inside the header.
constexpr std::size_t kVersionAt = 4;
constexpr std::size_t kFracBitsAt = 5;
constexpr std::size_t kReservedAt = 6;
constexpr std::size_t kSequenceAt = 8;
constexpr std::size_t kCountAt = 12;
constexpr std::size_t kLengthAt = 16;
static_assert(kLengthAt + 4 == kV2HeaderBytes);

// Offsets inside one sphere record.
constexpr std::size_t kSphereXAt = 0;
constexpr std::size_t kSphereYAt = 4;
constexpr std::size_t kSphereZAt = 8;
constexpr std::size_t kSphereRadiusAt = 12;
constexpr std::size_t kSphereMaterialAt = 16;
constexpr std::size_t kSphereAlbedoAt = 17;
constexpr std::size_t kSphereFuzzAt = 20;
constexpr std::size_t kSphereIorAt = 22;
static_assert(kSphereIorAt + 2 == kV2SphereBytes);

// The stream decoder takes input in slices of this size, so its buffer never holds more than one frame
// and one slice.
constexpr std::size_t kSliceBytes = 4096;

std::uint32_t read_u32(std::span<const std::uint8_t> bytes, std::size_t at) {
  return (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) |
         (std::uint32_t{bytes[at + 2]} << 8) | std::uint32_t{bytes[at + 3]};
}

std::uint16_t read_u16(std::span<const std::uint8_t> bytes, std::size_t at) {
  return static_cast<std::uint16_t>((bytes[at] << 8) | bytes[at + 1]);
}

void put_u32(std::uint32_t value, std::vector<std::uint8_t>& out) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(value >> shift));
}

void put_u16(std::uint16_t value, std::vector<std::uint8_t>& out) {
  out.push_back(static_cast<std::uint8_t>(value >> 8));
  out.push_back(static_cast<std::uint8_t>(value));
}

std::string hex(std::uint32_t value, int digits) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%0*X", digits, static_cast<unsigned>(value));
  return text;
}

// "1 byte", "2 bytes"; "1 sphere", "0 spheres".
std::string count_text(std::size_t n, const char* noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}
std::string bytes_text(std::size_t n) { return count_text(n, "byte"); }

V2Failure failure(V2Error error, std::size_t offset, std::string detail) {
  return V2Failure{error, offset, std::move(detail)};
}

struct FrameHeader {
  std::uint32_t sequence = 0;
  std::uint8_t frac_bits = 0;
  std::uint32_t count = 0;
  std::uint32_t length = 0;
  std::size_t frame_bytes = 0;  // header + payload + CRC
};

// What the first bytes of a frame say: a failure as soon as any present byte is wrong, the header once all
// 20 bytes are present and right, and neither while more bytes are needed to tell. Fields are checked in
// the order of the format: magic, version, frac_bits and reserved, count, length.
struct HeaderCheck {
  std::optional<FrameHeader> header;
  std::optional<V2Failure> failure;
};

HeaderCheck inspect_header(std::span<const std::uint8_t> bytes, std::uint32_t max_spheres) {
  const std::size_t n = std::min(bytes.size(), kV2HeaderBytes);
  for (std::size_t i = 0; i < std::min(n, kV2Magic.size()); ++i) {
    if (bytes[i] != kV2Magic[i]) {
      return {std::nullopt, failure(V2Error::kBadMagic, i,
                                    "expected the magic \"TSW2\" but byte " + std::to_string(i) + " is " +
                                        hex(bytes[i], 2) + " instead of " + hex(kV2Magic[i], 2))};
    }
  }
  if (n <= kVersionAt) return {};
  if (bytes[kVersionAt] != kV2Version) {
    return {std::nullopt, failure(V2Error::kBadVersion, kVersionAt,
                                  "version byte is " + std::to_string(bytes[kVersionAt]) +
                                      " but this receiver only reads version " + std::to_string(kV2Version))};
  }
  if (n <= kFracBitsAt) return {};
  if (bytes[kFracBitsAt] > kV2MaxFracBits) {
    return {std::nullopt, failure(V2Error::kBadHeader, kFracBitsAt,
                                  "frac_bits is " + std::to_string(bytes[kFracBitsAt]) + " but at most " +
                                      std::to_string(kV2MaxFracBits) + " fractional bits are allowed")};
  }
  for (std::size_t at = kReservedAt; at < kSequenceAt; ++at) {
    if (n <= at) return {};
    if (bytes[at] != 0) {
      return {std::nullopt, failure(V2Error::kBadHeader, at,
                                    "reserved byte at offset " + std::to_string(at) + " is " + hex(bytes[at], 2) +
                                        " but reserved bytes must be zero")};
    }
  }
  if (n < kCountAt + 4) return {};
  const std::uint32_t count = read_u32(bytes, kCountAt);
  if (count > max_spheres) {
    return {std::nullopt, failure(V2Error::kTooManySpheres, kCountAt,
                                  "sphere count " + std::to_string(count) + " exceeds the scene memory of " +
                                      std::to_string(max_spheres) + " spheres")};
  }
  if (n < kLengthAt + 4) return {};
  const std::uint32_t length = read_u32(bytes, kLengthAt);
  const std::uint64_t expected = std::uint64_t{count} * kV2SphereBytes;
  if (length != expected) {
    return {std::nullopt, failure(V2Error::kBadLength, kLengthAt,
                                  "payload length is " + bytes_text(length) + " but a count of " +
                                      count_text(count, "sphere") + " calls for " + std::to_string(expected))};
  }
  FrameHeader header;
  header.sequence = read_u32(bytes, kSequenceAt);
  header.frac_bits = bytes[kFracBitsAt];
  header.count = count;
  header.length = length;
  header.frame_bytes = kV2HeaderBytes + std::size_t{length} + kV2TrailerBytes;
  return {header, std::nullopt};
}

// Checks the CRC and the spheres of a whole frame whose header has passed. Offsets are frame-relative.
core::Result<World, V2Failure> decode_body(std::span<const std::uint8_t> frame, const FrameHeader& header) {
  const std::size_t crc_at = kV2HeaderBytes + header.length;
  const std::uint32_t carried = read_u32(frame, crc_at);
  const std::uint32_t computed = core::crc32(frame.first(crc_at));
  if (carried != computed) {
    return failure(V2Error::kBadCrc, crc_at,
                   "the frame carries CRC-32 " + hex(carried, 8) + " but its " + bytes_text(crc_at) +
                       " of header and payload give " + hex(computed, 8));
  }
  World world;
  world.sequence = header.sequence;
  world.frac_bits = header.frac_bits;
  world.spheres.reserve(header.count);
  for (std::uint32_t i = 0; i < header.count; ++i) {
    const std::size_t at = kV2HeaderBytes + std::size_t{i} * kV2SphereBytes;
    WireSphere s;
    s.x = static_cast<std::int32_t>(read_u32(frame, at + kSphereXAt));
    s.y = static_cast<std::int32_t>(read_u32(frame, at + kSphereYAt));
    s.z = static_cast<std::int32_t>(read_u32(frame, at + kSphereZAt));
    s.radius = read_u32(frame, at + kSphereRadiusAt);
    s.material = frame[at + kSphereMaterialAt];
    for (std::size_t k = 0; k < 3; ++k) s.albedo[k] = frame[at + kSphereAlbedoAt + k];
    s.fuzz = read_u16(frame, at + kSphereFuzzAt);
    s.ior = read_u16(frame, at + kSphereIorAt);
    const std::string which = "sphere " + std::to_string(i) + " (bytes " + std::to_string(at) + ".." +
                              std::to_string(at + kV2SphereBytes - 1) + ")";
    if (s.radius == 0) {
      return failure(V2Error::kBadSphere, at + kSphereRadiusAt, which + " has radius 0; a radius must be above zero");
    }
    if (s.material > kMaterialDielectric) {
      return failure(V2Error::kBadSphere, at + kSphereMaterialAt,
                     which + " has material code " + std::to_string(s.material) +
                         "; known codes are 0 (lambertian), 1 (metal) and 2 (dielectric)");
    }
    if (s.ior == 0) {
      return failure(V2Error::kBadSphere, at + kSphereIorAt, which + " has ior 0; an ior must be above zero");
    }
    world.spheres.push_back(s);
  }
  return world;
}

}  // namespace

const char* to_string(V2Error error) {
  switch (error) {
    case V2Error::kBadMagic: return "bad magic";
    case V2Error::kBadVersion: return "bad version";
    case V2Error::kBadHeader: return "bad header";
    case V2Error::kTooManySpheres: return "too many spheres";
    case V2Error::kBadLength: return "bad length";
    case V2Error::kTruncated: return "truncated";
    case V2Error::kBadCrc: return "bad CRC";
    case V2Error::kBadSphere: return "bad sphere";
    case V2Error::kTrailingBytes: return "trailing bytes";
  }
  return "unknown error";
}

std::vector<std::uint8_t> encode_v2_frame(const World& world) {
  const auto count = static_cast<std::uint32_t>(world.spheres.size());
  const auto length = static_cast<std::uint32_t>(world.spheres.size() * kV2SphereBytes);
  std::vector<std::uint8_t> out;
  out.reserve(kV2HeaderBytes + std::size_t{length} + kV2TrailerBytes);
  out.insert(out.end(), kV2Magic.begin(), kV2Magic.end());
  out.push_back(kV2Version);
  out.push_back(world.frac_bits);
  out.push_back(0);
  out.push_back(0);
  put_u32(world.sequence, out);
  put_u32(count, out);
  put_u32(length, out);
  for (const WireSphere& s : world.spheres) {
    put_u32(static_cast<std::uint32_t>(s.x), out);
    put_u32(static_cast<std::uint32_t>(s.y), out);
    put_u32(static_cast<std::uint32_t>(s.z), out);
    put_u32(s.radius, out);
    out.push_back(s.material);
    out.insert(out.end(), s.albedo.begin(), s.albedo.end());
    put_u16(s.fuzz, out);
    put_u16(s.ior, out);
  }
  put_u32(core::crc32(out), out);
  return out;
}

core::Result<World, V2Failure> decode_v2_frame(std::span<const std::uint8_t> bytes, std::uint32_t max_spheres) {
  HeaderCheck check = inspect_header(bytes, max_spheres);
  if (check.failure) return std::move(*check.failure);
  if (!check.header) {
    return failure(V2Error::kTruncated, bytes.size(),
                   "the input ends after " + bytes_text(bytes.size()) + ", inside the " +
                       std::to_string(kV2HeaderBytes) + "-byte frame header");
  }
  const FrameHeader& header = *check.header;
  if (bytes.size() < header.frame_bytes) {
    return failure(V2Error::kTruncated, bytes.size(),
                   "the frame of " + count_text(header.count, "sphere") + " needs " +
                       bytes_text(header.frame_bytes) + " but the input ends after " + std::to_string(bytes.size()));
  }
  if (bytes.size() > header.frame_bytes) {
    const std::size_t extra = bytes.size() - header.frame_bytes;
    return failure(V2Error::kTrailingBytes, header.frame_bytes,
                   bytes_text(extra) + (extra == 1 ? " follows" : " follow") + " the end of the " +
                       std::to_string(header.frame_bytes) + "-byte frame");
  }
  return decode_body(bytes, header);
}

// ---- V2StreamDecoder ----
//
// At the read position the decoder is in one of two states. Expecting a frame, it checks the header as
// its bytes arrive, then waits for the whole frame. Hunting, it skips bytes until the magic appears.
// Every byte of the input ends up either in a delivered frame or in exactly one error report:
//   - garbage where a frame should start: a hunt begins at that byte; the whole run up to the next magic
//     (or the end of the stream) is one kBadMagic report;
//   - a header error or a bad CRC: the first byte of the frame is dropped and reported with the error,
//     and a hunt begins at the next byte, so a frame hidden inside the damaged one is still found;
//   - a bad sphere under a good CRC: the frame arrived as sent, so all of it is dropped with the report
//     and the next frame is expected right after it.
// The callbacks run in the middle of this work and must not call back into the decoder.

V2StreamDecoder::V2StreamDecoder(std::uint32_t max_spheres, Callbacks callbacks)
    : max_spheres_(max_spheres), callbacks_(std::move(callbacks)) {}

void V2StreamDecoder::push(std::span<const std::uint8_t> bytes) {
  while (!bytes.empty()) {
    const std::size_t n = std::min(bytes.size(), kSliceBytes);
    make_room(n);
    buffer_.insert(buffer_.end(), bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
    bytes = bytes.subspan(n);
    process();
    // Compact: drop the consumed prefix, so buffered_bytes() counts only bytes still pending.
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(read_));
    buffer_offset_ += read_;
    read_ = 0;
  }
}

// Grows the buffer by doubling, as bytes arrive (a header alone allocates nothing for the frame it
// announces), but never beyond the frame being received and one slice.
void V2StreamDecoder::make_room(std::size_t n) {
  const std::size_t needed = buffer_.size() + n;
  if (needed <= buffer_.capacity()) return;
  std::size_t target = std::max(needed, 2 * buffer_.capacity());
  if (frame_bytes_ > 0) target = std::min(target, std::max(needed, read_ + frame_bytes_ + kSliceBytes));
  buffer_.reserve(target);
}

void V2StreamDecoder::end_of_stream() {
  const std::size_t pending = buffer_.size() - read_;
  if (hunting_) {
    // A partial magic at the very end is counted with the garbage before it.
    garbage_bytes_ += pending;
    report_garbage();
  } else if (pending > 0) {
    std::string detail = "the stream ended " + bytes_text(pending) + " into a frame";
    detail += frame_bytes_ > 0 ? " of " + bytes_text(frame_bytes_)
                               : ", before its " + std::to_string(kV2HeaderBytes) + "-byte header was complete";
    report(failure(V2Error::kTruncated, stream_offset(buffer_.size()), std::move(detail)), pending);
  }
  buffer_offset_ += buffer_.size();
  buffer_.clear();
  read_ = 0;
  frame_bytes_ = 0;
  hunting_ = false;
  garbage_bytes_ = 0;
}

void V2StreamDecoder::process() {
  while (read_ < buffer_.size()) {
    if (!(hunting_ ? hunt() : try_frame())) return;
  }
}

bool V2StreamDecoder::try_frame() {
  const std::span<const std::uint8_t> rest = std::span<const std::uint8_t>(buffer_).subspan(read_);
  if (frame_bytes_ == 0) {
    HeaderCheck check = inspect_header(rest, max_spheres_);
    if (check.failure) {
      V2Failure& f = *check.failure;
      if (f.error == V2Error::kBadMagic) {
        start_hunt("where a frame should have started");
        return true;
      }
      f.offset += stream_offset(read_);
      const std::string reason = std::string("after the ") + to_string(f.error) + " in the frame at offset " +
                                 std::to_string(stream_offset(read_));
      report(f, 1);
      ++read_;
      start_hunt(reason);
      return true;
    }
    if (!check.header) return false;
    frame_bytes_ = check.header->frame_bytes;
  }
  if (rest.size() < frame_bytes_) return false;

  const std::span<const std::uint8_t> frame = rest.first(frame_bytes_);
  const std::size_t frame_bytes = std::exchange(frame_bytes_, 0);
  const HeaderCheck check = inspect_header(frame, max_spheres_);
  core::Result<World, V2Failure> result = decode_body(frame, *check.header);
  if (result.ok()) {
    read_ += frame_bytes;
    if (callbacks_.on_frame) callbacks_.on_frame(std::move(result).value());
    return true;
  }
  V2Failure f = result.error();
  const std::size_t frame_at = stream_offset(read_);
  f.offset += frame_at;
  if (f.error == V2Error::kBadSphere) {
    read_ += frame_bytes;
    report(f, frame_bytes);
    return true;
  }
  report(f, 1);
  ++read_;
  start_hunt(std::string("after the ") + to_string(f.error) + " in the frame at offset " + std::to_string(frame_at));
  return true;
}

bool V2StreamDecoder::hunt() {
  const std::size_t size = buffer_.size();
  std::size_t at = read_;
  // Stop at the first place where the magic, or the start of it cut off by the end of the buffer, begins.
  while (at < size) {
    const auto first = std::find(buffer_.begin() + static_cast<std::ptrdiff_t>(at), buffer_.end(), kV2Magic[0]);
    at = static_cast<std::size_t>(first - buffer_.begin());
    if (at == size) break;
    const std::size_t n = std::min(kV2Magic.size(), size - at);
    if (std::equal(kV2Magic.begin(), kV2Magic.begin() + static_cast<std::ptrdiff_t>(n), first)) break;
    ++at;
  }
  garbage_bytes_ += at - read_;
  read_ = at;
  if (size - at < kV2Magic.size()) return false;  // the end of the buffer, or a partial magic: wait
  report_garbage();
  hunting_ = false;
  return true;
}

void V2StreamDecoder::start_hunt(std::string reason) {
  hunting_ = true;
  garbage_start_ = stream_offset(read_);
  garbage_bytes_ = 0;
  hunt_reason_ = std::move(reason);
}

void V2StreamDecoder::report_garbage() {
  if (garbage_bytes_ == 0) return;
  const std::size_t dropped = std::exchange(garbage_bytes_, 0);
  report(failure(V2Error::kBadMagic, garbage_start_,
                 "skipped " + bytes_text(dropped) + " at offset " + std::to_string(garbage_start_) +
                     " looking for the magic \"TSW2\" " + hunt_reason_),
         dropped);
}

void V2StreamDecoder::report(const V2Failure& failure, std::size_t bytes_dropped) {
  if (callbacks_.on_error) callbacks_.on_error(failure, bytes_dropped);
}

}  // namespace tripsitter::link

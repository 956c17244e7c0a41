// The framed wires, v2 and v3: TripSitter's protocol for worlds of many spheres with materials. v3 adds a
// session number and a CRC over the header, so a damaged header is refused before any payload is awaited.
// The byte layouts, with worked examples, are in docs/link_format.md; this header holds the constants and
// codecs that the host's encoder and the device's decoder share.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <tripsitter/core/result.h>
#include <tripsitter/link/wire.h>

namespace tripsitter::link {

// The two framed wires share the sphere record and the trailer; they differ in the header.
inline constexpr std::array<std::uint8_t, 4> kV2Magic{'T', 'S', 'W', '2'};
inline constexpr std::uint8_t kV2Version = 2;
inline constexpr std::size_t kV2HeaderBytes = 20;   // magic 4, version 1, frac_bits 1, reserved 2, sequence 4, count 4, length 4
inline constexpr std::array<std::uint8_t, 4> kV3Magic{'T', 'S', 'W', '3'};
inline constexpr std::uint8_t kV3Version = 3;
// magic 4, version 1, frac_bits 1, reserved 2, session 4, sequence 4, count 4, length 4, header CRC 4
inline constexpr std::size_t kV3HeaderBytes = 28;
inline constexpr std::size_t kSphereBytes = 24;
// v3's content byte (header offset 6; reserved on v2): what the payload holds after the spheres.
inline constexpr std::uint8_t kContentSpheres = 0;    // nothing more
inline constexpr std::uint8_t kContentHierarchy = 1;  // the hierarchy's nodes, kNodeBytes each
inline constexpr std::size_t kNodeBytes = 24;
inline constexpr std::size_t kMaxNodes = 65535;       // first_child is 16 bits
inline constexpr int kMaxHierarchyDepth = 8;          // levels below the root
inline constexpr std::size_t kFrameTrailerBytes = 4;  // CRC-32 of header and payload
inline constexpr int kMaxFracBits = 30;
inline constexpr double kIorScale = 4096.0;         // ior is carried as u4.12
inline constexpr double kFuzzScale = 65535.0;       // fuzz is carried as value * 65535

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

// A node of the hierarchy of bounding spheres that a v3 world may carry (content 1; docs/link_format.md, "The
// hierarchy"): a bound, the nodes under it and the spheres in it. Node 0 is the root, which carries no bound (all
// four fields 0); every other node's bound encloses its spheres and its children's bounds. The nodes form a tree
// from the root and every sphere is in exactly one node.
struct WireNode {
  std::int32_t x = 0, y = 0, z = 0;   // the bound's centre, raw fixed point with the frame's frac_bits
  std::uint32_t radius = 0;           // the bound's radius; > 0 but on the root
  std::uint16_t first_child = 0;      // children are nodes first_child .. first_child + children - 1
  std::uint8_t children = 0;
  std::uint8_t sphere_count = 0;      // spheres first_sphere .. first_sphere + sphere_count - 1
  std::uint32_t first_sphere = 0;
  bool operator==(const WireNode&) const = default;
};

struct World {
  std::uint32_t session = 0;          // v3: the host's session (0 on v2, which has none)
  std::uint32_t sequence = 0;
  std::uint8_t frac_bits = 0;         // 0..kMaxFracBits
  std::vector<WireSphere> spheres;
  std::vector<WireNode> nodes;        // v3: the hierarchy, if the world carries one (else empty)
  bool operator==(const World&) const = default;
};

enum class FrameError {
  kBadMagic,        // the stream did not start with the magic where a frame was expected
  kBadVersion,      // version byte is not the wire's (2 or 3)
  kBadHeader,       // frac_bits above kMaxFracBits or reserved bytes not zero
  kBadHeaderCrc,    // v3: the header's CRC-32 does not match its first 24 bytes
  kTooManySpheres,  // count above the receiver's limit (checked before anything is allocated)
  kBadLength,       // payload length is not count * 24 (v3 content 1: not 24 * (count + nodes), 1 <= nodes <= limit)
  kTruncated,       // the bytes end before the frame does
  kBadCrc,          // the frame's CRC-32 does not match
  kBadSphere,       // a sphere with radius 0, unknown material or ior 0
  kBadHierarchy,    // v3 content 1: a node out of range, a cycle, a sphere in no node or two, a bound too small
  kTrailingBytes,   // decode_frame: bytes after the end of the frame
};

const char* to_string(FrameError error);

// Which world a frame carried, when the failure was found in a frame that arrived intact (both CRCs good:
// kBadSphere, kBadHierarchy), so the receiver can tell its sequence number was not lost on the link.
struct FrameId {
  std::uint32_t session = 0;
  std::uint32_t sequence = 0;
};

struct FrameFailure {
  FrameError error;
  std::size_t offset = 0;   // byte offset in the input at which the problem was found
  std::string detail;       // a sentence for people: what was expected and what was found
  std::optional<FrameId> intact;  // set for a frame that arrived as it was sent (kBadSphere, kBadHierarchy)
};

// The framed wires' sizes: header bytes, and a whole frame of `spheres` spheres and `nodes` nodes.
// REQUIRES wire != WireVersion::kV1 (here and below).
std::size_t frame_header_bytes(WireVersion wire);
std::size_t frame_bytes(WireVersion wire, std::size_t spheres, std::size_t nodes = 0);

// Encodes one frame. REQUIRES world.frac_bits <= kMaxFracBits and every sphere valid (radius > 0,
// known material, ior > 0), and nodes only on v3, a valid hierarchy (hierarchy_error); on v2, world.session
// is not carried.
std::vector<std::uint8_t> encode_frame(WireVersion wire, const World& world);

// Gives an encoded frame another session (v3 only) and sequence number, and fixes its CRCs: what the host's
// link does to each world as it starts to go out (sequence.h, Numbering). REQUIRES `frame` to be a whole frame that
// encode_frame(wire, ...) made.
void restamp_frame(WireVersion wire, std::span<std::uint8_t> frame, std::uint32_t session, std::uint32_t sequence);

// A ball in raw fixed point, for the hierarchy's rule that a bound encloses what lies in it.
struct Ball {
  std::int64_t x = 0, y = 0, z = 0, radius = 0;
};
// Whether `inner` lies inside `outer`, in exact integers: outer.radius >= inner.radius and the centres at most
// outer.radius - inner.radius apart. REQUIRES coordinates and radii of at most 33 bits.
bool encloses(const Ball& outer, const Ball& inner);

// Why a world's hierarchy breaks the rules of docs/link_format.md ("The hierarchy"), the first broken one in
// their order, or nothing when it keeps them (a world without nodes keeps them). Offsets are within the node
// records: node i's record begins at kNodeBytes * i.
struct HierarchyProblem {
  std::size_t offset = 0;
  std::string detail;
};
std::optional<HierarchyProblem> hierarchy_error(const World& world);

// Decodes exactly one frame that fills `bytes`. A receiver that walks no hierarchy (`hierarchy` false) refuses a
// frame that carries one at its header, as content it does not know (kBadHeader at the content byte).
core::Result<World, FrameFailure> decode_frame(WireVersion wire, std::span<const std::uint8_t> bytes,
                                               std::uint32_t max_spheres, bool hierarchy = true);

// Reassembles frames of one framed wire from a byte stream cut into transfers of any size; the frames and
// reports are the same however the stream is cut. Damage never stops it: on any error it reports the error
// and the number of bytes it discarded, then hunts for the next magic (docs/link_format.md, "How the
// receiver finds its way through damage"). Never allocates more than max_spheres spheres (and as many nodes) for
// one frame. Without `hierarchy`, a frame that carries one is refused at its header (decode_frame).
class FrameStreamDecoder {
 public:
  struct Callbacks {
    std::function<void(World&&)> on_frame;
    std::function<void(const FrameFailure&, std::size_t bytes_dropped)> on_error;
  };
  FrameStreamDecoder(WireVersion wire, std::uint32_t max_spheres, Callbacks callbacks, bool hierarchy = true);

  void push(std::span<const std::uint8_t> bytes);
  // The sender went away: a partial frame is dropped and reported as kTruncated, a run of garbage being
  // hunted through as kBadMagic (nothing is reported when nothing is buffered).
  void end_of_stream();
  std::size_t buffered_bytes() const { return buffer_.size(); }

 private:
  // Implementation state is free to change; see frame.cpp.
  void make_room(std::size_t n);
  void process();
  bool try_frame();
  bool hunt();
  std::optional<std::size_t> find_cut(std::span<const std::uint8_t> rest);
  void start_hunt(std::string reason);
  void report_garbage();
  void report(const FrameFailure& failure, std::size_t bytes_dropped);
  std::size_t stream_offset(std::size_t index) const { return buffer_offset_ + index; }

  WireVersion wire_;
  std::uint32_t max_spheres_;
  bool hierarchy_;
  Callbacks callbacks_;
  std::vector<std::uint8_t> buffer_;  // bytes not yet consumed; between calls the read position is 0
  std::size_t read_ = 0;              // read position in buffer_ while push() works
  std::size_t buffer_offset_ = 0;     // stream offset of buffer_[0]
  std::size_t frame_bytes_ = 0;       // size of the frame at read_ once its header has passed, else 0
  std::size_t cut_scan_ = 0;          // v3: where, from read_, to go on looking for a header that cuts the frame
  bool hunting_ = false;              // skipping bytes until the next magic
  std::size_t garbage_start_ = 0;     // stream offset of the first byte skipped in this hunt
  std::size_t garbage_bytes_ = 0;     // bytes skipped in this hunt and not yet reported
  std::string hunt_reason_;           // why the hunt started, for the kBadMagic report
};

}  // namespace tripsitter::link

// The framed wires' codec (v2 and v3) and the receiver's stream decoder. The layouts are in
// docs/link_format.md; the two wires differ only in their headers (Layout below).
//
// The stream decoder keeps the bytes it has not consumed in one buffer and reads them through an offset;
// the consumed prefix is erased once per slice of input, so each byte is copied a bounded number of times
// and decoding stays linear in the input. The same header and body checks serve decode_frame and the
// stream decoder, so both report the same errors at the same offsets.
#include <tripsitter/link/frame.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <utility>

#include <tripsitter/core/crc32.h>
#include <tripsitter/core/fixed.h>

namespace tripsitter::link {
namespace {

// Where a wire's header keeps its fields. Both headers begin with magic (0..3), version (4), frac_bits (5)
// and two bytes (6, 7): reserved on v2; on v3 the content (6) and a reserved byte (7).
struct Layout {
  std::array<std::uint8_t, 4> magic;
  std::uint8_t version;
  std::size_t header_bytes;
  std::optional<std::size_t> content_at;
  std::optional<std::size_t> session_at;
  std::size_t sequence_at, count_at, length_at;
  std::optional<std::size_t> header_crc_at;  // the CRC-32 of every header byte before it
};
constexpr std::size_t kVersionAt = 4;
constexpr std::size_t kFracBitsAt = 5;
constexpr std::size_t kContentAt = 6;
constexpr std::size_t kReservedEnd = 8;
const Layout kV2Layout{kV2Magic, kV2Version, kV2HeaderBytes, std::nullopt, std::nullopt, 8, 12, 16, std::nullopt};
const Layout kV3Layout{kV3Magic, kV3Version, kV3HeaderBytes, kContentAt, 8, 12, 16, 20, 24};

const Layout& layout_of(WireVersion wire) {
  if (wire == WireVersion::kV1) throw std::invalid_argument("the v1 wire has no frames");
  return wire == WireVersion::kV2 ? kV2Layout : kV3Layout;
}

// Offsets inside one sphere record.
constexpr std::size_t kSphereXAt = 0;
constexpr std::size_t kSphereYAt = 4;
constexpr std::size_t kSphereZAt = 8;
constexpr std::size_t kSphereRadiusAt = 12;
constexpr std::size_t kSphereMaterialAt = 16;
constexpr std::size_t kSphereAlbedoAt = 17;
constexpr std::size_t kSphereFuzzAt = 20;
constexpr std::size_t kSphereIorAt = 22;
static_assert(kSphereIorAt + 2 == kSphereBytes);

// Offsets inside one node record.
constexpr std::size_t kNodeXAt = 0;
constexpr std::size_t kNodeYAt = 4;
constexpr std::size_t kNodeZAt = 8;
constexpr std::size_t kNodeRadiusAt = 12;
constexpr std::size_t kNodeFirstChildAt = 16;
constexpr std::size_t kNodeChildrenAt = 18;
constexpr std::size_t kNodeSphereCountAt = 19;
constexpr std::size_t kNodeFirstSphereAt = 20;
static_assert(kNodeFirstSphereAt + 4 == kNodeBytes);

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

FrameFailure failure(FrameError error, std::size_t offset, std::string detail) {
  return FrameFailure{error, offset, std::move(detail), std::nullopt};
}

struct FrameHeader {
  std::uint32_t session = 0;
  std::uint32_t sequence = 0;
  std::uint8_t frac_bits = 0;
  std::uint32_t count = 0;
  std::uint32_t nodes = 0;      // v3 content 1: (length - 24 count) / 24; else 0
  std::uint32_t length = 0;
  std::size_t header_bytes = 0;
  std::size_t frame_bytes = 0;  // header + payload + CRC
};

// What the first bytes of a frame say: a failure as soon as any present byte is wrong, the header once all
// its bytes are present and right, and neither while more bytes are needed to tell. Fields are checked in
// the order of the format: magic, version, frac_bits and reserved, (v3) the header CRC, count, length. On
// v3 the count and length are read only under a good header CRC, so a damaged one is refused as such.
struct HeaderCheck {
  std::optional<FrameHeader> header;
  std::optional<FrameFailure> failure;
};

HeaderCheck inspect_header(const Layout& layout, std::span<const std::uint8_t> bytes, std::uint32_t max_spheres,
                           bool hierarchy) {
  const std::size_t n = std::min(bytes.size(), layout.header_bytes);
  const std::string magic_text(layout.magic.begin(), layout.magic.end());
  for (std::size_t i = 0; i < std::min(n, layout.magic.size()); ++i) {
    if (bytes[i] != layout.magic[i]) {
      return {std::nullopt, failure(FrameError::kBadMagic, i,
                                    "expected the magic \"" + magic_text + "\" but byte " + std::to_string(i) +
                                        " is " + hex(bytes[i], 2) + " instead of " + hex(layout.magic[i], 2))};
    }
  }
  if (n <= kVersionAt) return {};
  if (bytes[kVersionAt] != layout.version) {
    return {std::nullopt, failure(FrameError::kBadVersion, kVersionAt,
                                  "version byte is " + std::to_string(bytes[kVersionAt]) +
                                      " but this receiver reads version " + std::to_string(layout.version) +
                                      " after the magic \"" + magic_text + "\"")};
  }
  if (n <= kFracBitsAt) return {};
  if (bytes[kFracBitsAt] > kMaxFracBits) {
    return {std::nullopt, failure(FrameError::kBadHeader, kFracBitsAt,
                                  "frac_bits is " + std::to_string(bytes[kFracBitsAt]) + " but at most " +
                                      std::to_string(kMaxFracBits) + " fractional bits are allowed")};
  }
  if (layout.content_at && n > *layout.content_at && bytes[*layout.content_at] > kContentHierarchy) {
    return {std::nullopt, failure(FrameError::kBadHeader, *layout.content_at,
                                  "content byte is " + std::to_string(bytes[*layout.content_at]) +
                                      " but 0 (spheres) and 1 (spheres and a hierarchy) are the known contents")};
  }
  if (layout.content_at && n > *layout.content_at && bytes[*layout.content_at] == kContentHierarchy && !hierarchy) {
    return {std::nullopt, failure(FrameError::kBadHeader, *layout.content_at,
                                  "content byte is 1 (spheres and a hierarchy) but this receiver takes spheres only "
                                  "(content 0)")};
  }
  for (std::size_t at = layout.content_at ? *layout.content_at + 1 : kFracBitsAt + 1; at < kReservedEnd; ++at) {
    if (n <= at) return {};
    if (bytes[at] != 0) {
      return {std::nullopt, failure(FrameError::kBadHeader, at,
                                    "reserved byte at offset " + std::to_string(at) + " is " + hex(bytes[at], 2) +
                                        " but reserved bytes must be zero")};
    }
  }
  if (layout.header_crc_at) {
    if (n < layout.header_bytes) return {};
    const std::size_t at = *layout.header_crc_at;
    const std::uint32_t carried = read_u32(bytes, at);
    const std::uint32_t computed = core::crc32(bytes.first(at));
    if (carried != computed) {
      return {std::nullopt, failure(FrameError::kBadHeaderCrc, at,
                                    "the header carries CRC-32 " + hex(carried, 8) + " but its first " +
                                        bytes_text(at) + " give " + hex(computed, 8))};
    }
  }
  if (n < layout.count_at + 4) return {};
  const std::uint32_t count = read_u32(bytes, layout.count_at);
  if (count > max_spheres) {
    return {std::nullopt, failure(FrameError::kTooManySpheres, layout.count_at,
                                  "sphere count " + std::to_string(count) + " exceeds the scene memory of " +
                                      std::to_string(max_spheres) + " spheres")};
  }
  if (n < layout.length_at + 4) return {};
  const std::uint32_t length = read_u32(bytes, layout.length_at);
  const std::uint64_t expected = std::uint64_t{count} * kSphereBytes;
  std::uint32_t nodes = 0;
  if (layout.content_at && bytes[*layout.content_at] == kContentHierarchy) {
    // The nodes follow the spheres: at least the root, at most as many as the scene memory holds spheres.
    const std::uint64_t limit = std::min<std::uint64_t>(kMaxNodes, std::max<std::uint32_t>(max_spheres, 1));
    const std::uint64_t rest = length >= expected ? length - expected : 0;
    if (length < expected + kNodeBytes || rest % kNodeBytes != 0 || rest / kNodeBytes > limit) {
      return {std::nullopt, failure(FrameError::kBadLength, layout.length_at,
                                    "payload length is " + bytes_text(length) + " but a count of " +
                                        count_text(count, "sphere") + " and a hierarchy call for " +
                                        std::to_string(expected) + " plus 24 for each of 1 to " +
                                        std::to_string(limit) + " nodes")};
    }
    nodes = static_cast<std::uint32_t>(rest / kNodeBytes);
  } else if (length != expected) {
    return {std::nullopt, failure(FrameError::kBadLength, layout.length_at,
                                  "payload length is " + bytes_text(length) + " but a count of " +
                                      count_text(count, "sphere") + " calls for " + std::to_string(expected))};
  }
  if (n < layout.header_bytes) return {};
  FrameHeader header;
  if (layout.session_at) header.session = read_u32(bytes, *layout.session_at);
  header.sequence = read_u32(bytes, layout.sequence_at);
  header.frac_bits = bytes[kFracBitsAt];
  header.count = count;
  header.nodes = nodes;
  header.length = length;
  header.header_bytes = layout.header_bytes;
  header.frame_bytes = layout.header_bytes + std::size_t{length} + kFrameTrailerBytes;
  return {header, std::nullopt};
}

// Checks the CRC and the spheres of a whole frame whose header has passed. Offsets are frame-relative.
core::Result<World, FrameFailure> decode_body(std::span<const std::uint8_t> frame, const FrameHeader& header) {
  const std::size_t crc_at = header.header_bytes + header.length;
  const std::uint32_t carried = read_u32(frame, crc_at);
  const std::uint32_t computed = core::crc32(frame.first(crc_at));
  if (carried != computed) {
    return failure(FrameError::kBadCrc, crc_at,
                   "the frame carries CRC-32 " + hex(carried, 8) + " but its " + bytes_text(crc_at) +
                       " of header and payload give " + hex(computed, 8));
  }
  World world;
  world.session = header.session;
  world.sequence = header.sequence;
  world.frac_bits = header.frac_bits;
  world.spheres.reserve(header.count);
  const auto intact = [&header](FrameError error, std::size_t at, std::string detail) {
    FrameFailure f = failure(error, at, std::move(detail));
    f.intact = FrameId{header.session, header.sequence};
    return f;
  };
  const auto bad_sphere = [&](std::size_t at, std::string detail) {
    return intact(FrameError::kBadSphere, at, std::move(detail));
  };
  for (std::uint32_t i = 0; i < header.count; ++i) {
    const std::size_t at = header.header_bytes + std::size_t{i} * kSphereBytes;
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
                              std::to_string(at + kSphereBytes - 1) + ")";
    if (s.radius == 0) {
      return bad_sphere(at + kSphereRadiusAt, which + " has radius 0; a radius must be above zero");
    }
    if (s.material > kMaterialDielectric) {
      return bad_sphere(at + kSphereMaterialAt, which + " has material code " + std::to_string(s.material) +
                                                    "; known codes are 0 (lambertian), 1 (metal) and 2 (dielectric)");
    }
    if (s.ior == 0) {
      return bad_sphere(at + kSphereIorAt, which + " has ior 0; an ior must be above zero");
    }
    world.spheres.push_back(s);
  }
  const std::size_t nodes_at = header.header_bytes + std::size_t{header.count} * kSphereBytes;
  world.nodes.reserve(header.nodes);
  for (std::uint32_t i = 0; i < header.nodes; ++i) {
    const std::size_t at = nodes_at + std::size_t{i} * kNodeBytes;
    WireNode v;
    v.x = static_cast<std::int32_t>(read_u32(frame, at + kNodeXAt));
    v.y = static_cast<std::int32_t>(read_u32(frame, at + kNodeYAt));
    v.z = static_cast<std::int32_t>(read_u32(frame, at + kNodeZAt));
    v.radius = read_u32(frame, at + kNodeRadiusAt);
    v.first_child = read_u16(frame, at + kNodeFirstChildAt);
    v.children = frame[at + kNodeChildrenAt];
    v.sphere_count = frame[at + kNodeSphereCountAt];
    v.first_sphere = read_u32(frame, at + kNodeFirstSphereAt);
    world.nodes.push_back(v);
  }
  if (const std::optional<HierarchyProblem> problem = hierarchy_error(world))
    return intact(FrameError::kBadHierarchy, nodes_at + problem->offset, problem->detail);
  return world;
}

std::string range_text(std::uint64_t first, std::uint64_t n) {
  return n == 1 ? std::to_string(first) : std::to_string(first) + ".." + std::to_string(first + n - 1);
}

void set_u32(std::span<std::uint8_t> bytes, std::size_t at, std::uint32_t value) {
  for (std::size_t k = 0; k < 4; ++k) bytes[at + k] = static_cast<std::uint8_t>(value >> (24 - 8 * k));
}

// v3's cut rule. A v3 header is recognised by its magic and its CRC, so an intact header lying whole inside
// the bytes of a frame means the frame was cut off there (its sender restarted, or bytes of it were lost),
// and the frame ends where that header begins. The rule looks only at the frame's bytes, so a frame is cut
// or not whatever transfers it came in; payload holds such a header by chance once in 2^64 byte positions.
// `frame` is the frame's bytes so far (the stream decoder may not have them all); the search resumes at
// `scan` and leaves it where it must resume when more bytes come. v2 has no header check: never cut.
std::optional<std::size_t> find_embedded_header(const Layout& layout, std::span<const std::uint8_t> frame,
                                                std::size_t& scan) {
  if (!layout.header_crc_at) return std::nullopt;
  const std::size_t crc_at = *layout.header_crc_at;
  std::size_t at = std::max(scan, layout.header_bytes);  // the frame's own header passed its CRC
  while (at < frame.size()) {
    at = static_cast<std::size_t>(
        std::find(frame.begin() + static_cast<std::ptrdiff_t>(at), frame.end(), layout.magic[0]) - frame.begin());
    if (at == frame.size() || frame.size() - at < layout.header_bytes) break;  // look again when it is whole
    const std::span<const std::uint8_t> candidate = frame.subspan(at, layout.header_bytes);
    if (std::equal(layout.magic.begin(), layout.magic.end(), candidate.begin()) &&
        read_u32(candidate, crc_at) == core::crc32(candidate.first(crc_at))) {
      return at;
    }
    ++at;
  }
  scan = at;
  return std::nullopt;
}

std::string cut_text(std::size_t cut, std::size_t frame_size) {
  return "the intact header of another frame begins " + bytes_text(cut) + " into the " +
         std::to_string(frame_size) + "-byte frame";
}

}  // namespace

const char* to_string(FrameError error) {
  switch (error) {
    case FrameError::kBadMagic: return "bad magic";
    case FrameError::kBadVersion: return "bad version";
    case FrameError::kBadHeader: return "bad header";
    case FrameError::kBadHeaderCrc: return "bad header CRC";
    case FrameError::kTooManySpheres: return "too many spheres";
    case FrameError::kBadLength: return "bad length";
    case FrameError::kTruncated: return "truncated";
    case FrameError::kBadCrc: return "bad CRC";
    case FrameError::kBadSphere: return "bad sphere";
    case FrameError::kBadHierarchy: return "bad hierarchy";
    case FrameError::kTrailingBytes: return "trailing bytes";
  }
  return "unknown error";
}

std::size_t frame_header_bytes(WireVersion wire) { return layout_of(wire).header_bytes; }

std::size_t frame_bytes(WireVersion wire, std::size_t spheres, std::size_t nodes) {
  return frame_header_bytes(wire) + spheres * kSphereBytes + nodes * kNodeBytes + kFrameTrailerBytes;
}

bool encloses(const Ball& outer, const Ball& inner) {
  if (outer.radius < inner.radius) return false;
  const auto sq = [](std::int64_t v) { return static_cast<core::UInt128>(static_cast<core::Int128>(v) * v); };
  return sq(inner.x - outer.x) + sq(inner.y - outer.y) + sq(inner.z - outer.z) <= sq(outer.radius - inner.radius);
}

std::optional<HierarchyProblem> hierarchy_error(const World& world) {
  const std::vector<WireNode>& nodes = world.nodes;
  const std::size_t n = nodes.size();
  if (n == 0) return std::nullopt;
  const std::size_t count = world.spheres.size();
  const auto problem = [](std::size_t node, std::size_t field, std::string detail) {
    return HierarchyProblem{node * kNodeBytes + field, std::move(detail)};
  };
  const auto name = [](std::size_t i) { return "node " + std::to_string(i); };
  // Each record on its own: its bound, and ranges inside the world.
  for (std::size_t i = 0; i < n; ++i) {
    const WireNode& v = nodes[i];
    if (i == 0 && (v.x != 0 || v.y != 0 || v.z != 0 || v.radius != 0)) {
      const std::size_t field = v.x != 0 ? kNodeXAt : v.y != 0 ? kNodeYAt : v.z != 0 ? kNodeZAt : kNodeRadiusAt;
      return problem(0, field, "the root (node 0) carries no bound, but its x, y, z and radius are not all 0");
    }
    if (i > 0 && v.radius == 0) return problem(i, kNodeRadiusAt, name(i) + " has radius 0; a bound must be above zero");
    if (v.children == 0 && v.first_child != 0)
      return problem(i, kNodeFirstChildAt, name(i) + " has no children but first_child " + std::to_string(v.first_child));
    if (v.sphere_count == 0 && v.first_sphere != 0)
      return problem(i, kNodeFirstSphereAt, name(i) + " has no spheres but first_sphere " + std::to_string(v.first_sphere));
    if (i > 0 && v.children == 0 && v.sphere_count == 0)
      return problem(i, kNodeChildrenAt, name(i) + " holds neither nodes nor spheres");
    if (std::size_t{v.first_child} + v.children > n) {
      return problem(i, kNodeFirstChildAt, name(i) + " names nodes " + range_text(v.first_child, v.children) +
                                               " as its children but the world has " + count_text(n, "node"));
    }
    if (std::uint64_t{v.first_sphere} + v.sphere_count > count) {
      return problem(i, kNodeFirstSphereAt, name(i) + " names spheres " + range_text(v.first_sphere, v.sphere_count) +
                                                " but the world has " + count_text(count, "sphere"));
    }
  }
  // A tree from the root: each node reached once, at most kMaxHierarchyDepth levels down.
  std::vector<int> depth(n, -1);
  std::vector<std::size_t> order{0};
  depth[0] = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t i = order[k];
    for (std::size_t c = nodes[i].first_child; c < std::size_t{nodes[i].first_child} + nodes[i].children; ++c) {
      if (depth[c] >= 0) {
        return problem(i, kNodeFirstChildAt, name(i) + " names " + name(c) +
                                                 " as a child, which is reached from the root already: a cycle, or a "
                                                 "node with two parents");
      }
      depth[c] = depth[i] + 1;
      if (depth[c] > kMaxHierarchyDepth) {
        return problem(i, kNodeFirstChildAt, name(c) + " lies " + std::to_string(depth[c]) +
                                                 " levels below the root; at most " +
                                                 std::to_string(kMaxHierarchyDepth));
      }
      order.push_back(c);
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (depth[i] < 0) return problem(i, 0, name(i) + " is not reached from the root");
  // Every sphere in exactly one node.
  std::vector<std::int64_t> owner(count, -1);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t s = nodes[i].first_sphere; s < std::size_t{nodes[i].first_sphere} + nodes[i].sphere_count; ++s) {
      if (owner[s] >= 0) {
        return problem(i, kNodeFirstSphereAt, "sphere " + std::to_string(s) + " is in " +
                                                  name(static_cast<std::size_t>(owner[s])) + " and in " + name(i));
      }
      owner[s] = static_cast<std::int64_t>(i);
    }
  }
  for (std::size_t s = 0; s < count; ++s)
    if (owner[s] < 0) return problem(0, 0, "sphere " + std::to_string(s) + " is in no node");
  // Every bound encloses its spheres and its children's bounds (the root has none).
  for (std::size_t i = 1; i < n; ++i) {
    const WireNode& v = nodes[i];
    const Ball bound{v.x, v.y, v.z, v.radius};
    const auto inside = [&](std::int64_t x, std::int64_t y, std::int64_t z, std::int64_t r) {
      return encloses(bound, {x, y, z, r});
    };
    for (std::size_t s = v.first_sphere; s < std::size_t{v.first_sphere} + v.sphere_count; ++s) {
      const WireSphere& b = world.spheres[s];
      if (!inside(b.x, b.y, b.z, b.radius))
        return problem(i, kNodeRadiusAt, "the bound of " + name(i) + " does not enclose sphere " + std::to_string(s));
    }
    for (std::size_t c = v.first_child; c < std::size_t{v.first_child} + v.children; ++c) {
      const WireNode& b = nodes[c];
      if (!inside(b.x, b.y, b.z, b.radius))
        return problem(i, kNodeRadiusAt, "the bound of " + name(i) + " does not enclose the bound of " + name(c));
    }
  }
  return std::nullopt;
}

std::vector<std::uint8_t> encode_frame(WireVersion wire, const World& world) {
  const Layout& layout = layout_of(wire);
  if (!world.nodes.empty() && !layout.content_at)
    throw std::invalid_argument("encode_frame: only the v3 wire carries a hierarchy");
  const auto count = static_cast<std::uint32_t>(world.spheres.size());
  const auto length = static_cast<std::uint32_t>(world.spheres.size() * kSphereBytes + world.nodes.size() * kNodeBytes);
  std::vector<std::uint8_t> out;
  out.reserve(frame_bytes(wire, world.spheres.size(), world.nodes.size()));
  out.insert(out.end(), layout.magic.begin(), layout.magic.end());
  out.push_back(layout.version);
  out.push_back(world.frac_bits);
  out.push_back(world.nodes.empty() ? kContentSpheres : kContentHierarchy);
  out.push_back(0);
  if (layout.session_at) put_u32(world.session, out);
  put_u32(world.sequence, out);
  put_u32(count, out);
  put_u32(length, out);
  if (layout.header_crc_at) put_u32(core::crc32(out), out);
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
  for (const WireNode& v : world.nodes) {
    put_u32(static_cast<std::uint32_t>(v.x), out);
    put_u32(static_cast<std::uint32_t>(v.y), out);
    put_u32(static_cast<std::uint32_t>(v.z), out);
    put_u32(v.radius, out);
    put_u16(v.first_child, out);
    out.push_back(v.children);
    out.push_back(v.sphere_count);
    put_u32(v.first_sphere, out);
  }
  put_u32(core::crc32(out), out);
  return out;
}

void restamp_frame(WireVersion wire, std::span<std::uint8_t> frame, std::uint32_t session, std::uint32_t sequence) {
  const Layout& layout = layout_of(wire);
  if (frame.size() < layout.header_bytes + kFrameTrailerBytes)
    throw std::invalid_argument("restamp_frame: " + bytes_text(frame.size()) + " are no whole frame");
  if (layout.session_at) set_u32(frame, *layout.session_at, session);
  set_u32(frame, layout.sequence_at, sequence);
  if (layout.header_crc_at) set_u32(frame, *layout.header_crc_at, core::crc32(frame.first(*layout.header_crc_at)));
  const std::size_t crc_at = frame.size() - kFrameTrailerBytes;
  set_u32(frame, crc_at, core::crc32(frame.first(crc_at)));
}

core::Result<World, FrameFailure> decode_frame(WireVersion wire, std::span<const std::uint8_t> bytes,
                                               std::uint32_t max_spheres, bool hierarchy) {
  const Layout& layout = layout_of(wire);
  HeaderCheck check = inspect_header(layout, bytes, max_spheres, hierarchy);
  if (check.failure) return std::move(*check.failure);
  if (!check.header) {
    return failure(FrameError::kTruncated, bytes.size(),
                   "the input ends after " + bytes_text(bytes.size()) + ", inside the " +
                       std::to_string(layout.header_bytes) + "-byte frame header");
  }
  const FrameHeader& header = *check.header;
  if (bytes.size() < header.frame_bytes) {
    return failure(FrameError::kTruncated, bytes.size(),
                   "the frame of " + count_text(header.count, "sphere") + " needs " +
                       bytes_text(header.frame_bytes) + " but the input ends after " + std::to_string(bytes.size()));
  }
  if (bytes.size() > header.frame_bytes) {
    const std::size_t extra = bytes.size() - header.frame_bytes;
    return failure(FrameError::kTrailingBytes, header.frame_bytes,
                   bytes_text(extra) + (extra == 1 ? " follows" : " follow") + " the end of the " +
                       std::to_string(header.frame_bytes) + "-byte frame");
  }
  std::size_t scan = 0;
  if (const auto cut = find_embedded_header(layout, bytes, scan))
    return failure(FrameError::kTruncated, *cut, cut_text(*cut, header.frame_bytes));
  return decode_body(bytes, header);
}

// ---- FrameStreamDecoder ----
//
// At the read position the decoder is in one of two states. Expecting a frame, it checks the header as
// its bytes arrive, then waits for the whole frame. Hunting, it skips bytes until the magic appears.
// Every byte of the input ends up either in a delivered frame or in exactly one error report:
//   - garbage where a frame should start: a hunt begins at that byte; the whole run up to the next magic
//     (or the end of the stream) is one kBadMagic report;
//   - a header error or a bad CRC: the first byte of the frame is dropped and reported with the error,
//     and a hunt begins at the next byte, so a frame hidden inside the damaged one is still found;
//   - a bad sphere or hierarchy under a good CRC: the frame arrived as sent, so all of it is dropped with the report
//     and the next frame is expected right after it;
//   - v3: an intact header inside the frame's bytes (find_embedded_header): the frame up to it is dropped
//     as truncated and the frame that header begins is expected there.
// The callbacks run in the middle of this work and must not call back into the decoder.

FrameStreamDecoder::FrameStreamDecoder(WireVersion wire, std::uint32_t max_spheres, Callbacks callbacks,
                                       bool hierarchy)
    : wire_(wire), max_spheres_(max_spheres), hierarchy_(hierarchy), callbacks_(std::move(callbacks)) {
  layout_of(wire);  // throws on v1
}

void FrameStreamDecoder::push(std::span<const std::uint8_t> bytes) {
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
void FrameStreamDecoder::make_room(std::size_t n) {
  const std::size_t needed = buffer_.size() + n;
  if (needed <= buffer_.capacity()) return;
  std::size_t target = std::max(needed, 2 * buffer_.capacity());
  if (frame_bytes_ > 0) target = std::min(target, std::max(needed, read_ + frame_bytes_ + kSliceBytes));
  buffer_.reserve(target);
}

void FrameStreamDecoder::end_of_stream() {
  const std::size_t pending = buffer_.size() - read_;
  if (hunting_) {
    // A partial magic at the very end is counted with the garbage before it.
    garbage_bytes_ += pending;
    report_garbage();
  } else if (pending > 0) {
    std::string detail = "the stream ended " + bytes_text(pending) + " into a frame";
    detail += frame_bytes_ > 0 ? " of " + bytes_text(frame_bytes_)
                               : ", before its " + std::to_string(frame_header_bytes(wire_)) + "-byte header was complete";
    report(failure(FrameError::kTruncated, stream_offset(buffer_.size()), std::move(detail)), pending);
  }
  buffer_offset_ += buffer_.size();
  buffer_.clear();
  read_ = 0;
  frame_bytes_ = 0;
  cut_scan_ = 0;
  hunting_ = false;
  garbage_bytes_ = 0;
}

void FrameStreamDecoder::process() {
  while (read_ < buffer_.size()) {
    if (!(hunting_ ? hunt() : try_frame())) return;
  }
}

bool FrameStreamDecoder::try_frame() {
  const std::span<const std::uint8_t> rest = std::span<const std::uint8_t>(buffer_).subspan(read_);
  if (frame_bytes_ == 0) {
    HeaderCheck check = inspect_header(layout_of(wire_), rest, max_spheres_, hierarchy_);
    if (check.failure) {
      FrameFailure& f = *check.failure;
      if (f.error == FrameError::kBadMagic) {
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
  if (const std::optional<std::size_t> cut = find_cut(rest)) {
    const std::size_t frame_at = stream_offset(read_);
    report(failure(FrameError::kTruncated, stream_offset(read_ + *cut), cut_text(*cut, frame_bytes_) + " at offset " +
                                                                            std::to_string(frame_at)),
           *cut);
    read_ += *cut;
    frame_bytes_ = 0;
    cut_scan_ = 0;
    return true;
  }
  if (rest.size() < frame_bytes_) return false;
  cut_scan_ = 0;

  const std::span<const std::uint8_t> frame = rest.first(frame_bytes_);
  const std::size_t size = std::exchange(frame_bytes_, 0);
  const HeaderCheck check = inspect_header(layout_of(wire_), frame, max_spheres_, hierarchy_);
  core::Result<World, FrameFailure> result = decode_body(frame, *check.header);
  if (result.ok()) {
    read_ += size;
    if (callbacks_.on_frame) callbacks_.on_frame(std::move(result).value());
    return true;
  }
  FrameFailure f = result.error();
  const std::size_t frame_at = stream_offset(read_);
  f.offset += frame_at;
  if (f.intact) {
    read_ += size;
    report(f, size);
    return true;
  }
  report(f, 1);
  ++read_;
  start_hunt(std::string("after the ") + to_string(f.error) + " in the frame at offset " + std::to_string(frame_at));
  return true;
}

bool FrameStreamDecoder::hunt() {
  const auto& magic = layout_of(wire_).magic;
  const std::size_t size = buffer_.size();
  std::size_t at = read_;
  // Stop at the first place where the magic, or the start of it cut off by the end of the buffer, begins.
  while (at < size) {
    const auto first = std::find(buffer_.begin() + static_cast<std::ptrdiff_t>(at), buffer_.end(), magic[0]);
    at = static_cast<std::size_t>(first - buffer_.begin());
    if (at == size) break;
    const std::size_t n = std::min(magic.size(), size - at);
    if (std::equal(magic.begin(), magic.begin() + static_cast<std::ptrdiff_t>(n), first)) break;
    ++at;
  }
  garbage_bytes_ += at - read_;
  read_ = at;
  if (size - at < magic.size()) return false;  // the end of the buffer, or a partial magic: wait
  report_garbage();
  hunting_ = false;
  return true;
}

std::optional<std::size_t> FrameStreamDecoder::find_cut(std::span<const std::uint8_t> rest) {
  return find_embedded_header(layout_of(wire_), rest.first(std::min(rest.size(), frame_bytes_)), cut_scan_);
}

void FrameStreamDecoder::start_hunt(std::string reason) {
  hunting_ = true;
  garbage_start_ = stream_offset(read_);
  garbage_bytes_ = 0;
  hunt_reason_ = std::move(reason);
}

void FrameStreamDecoder::report_garbage() {
  if (garbage_bytes_ == 0) return;
  const auto& magic = layout_of(wire_).magic;
  const std::size_t dropped = std::exchange(garbage_bytes_, 0);
  report(failure(FrameError::kBadMagic, garbage_start_,
                 "skipped " + bytes_text(dropped) + " at offset " + std::to_string(garbage_start_) +
                     " looking for the magic \"" + std::string(magic.begin(), magic.end()) + "\" " + hunt_reason_),
         dropped);
}

void FrameStreamDecoder::report(const FrameFailure& failure, std::size_t bytes_dropped) {
  if (callbacks_.on_error) callbacks_.on_error(failure, bytes_dropped);
}

}  // namespace tripsitter::link

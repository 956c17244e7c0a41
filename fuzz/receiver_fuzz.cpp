// The device's receiver (device/receiver.h) fed arbitrary transfers, with vertical blankings in between.
//
// Input: a configuration byte, a count byte, that many transfer bytes, then the link bytes.
//   configuration: bit 0 the wire v1 (when clear: bit 5 chooses v3 over v2), bit 1 the preset (0 wide,
//                  1 board-2023; bit 7 set: artix-path, which takes a hierarchy on v3), bits 2..3 the transfer
//                  length unit (1, 4, 16 or 64 bytes), bit 4 keep the frames' CRCs as they are (when clear, the
//                  CRCs of every frame with a consistent header, and on v3 every header CRC, are rewritten first:
//                  frame_repair.h);
//   count:         0..15 transfer bytes (count % 16); none sends the link bytes as one transfer;
//   transfer byte: bits 0..6 the transfer's length in units (0 is an empty transfer), bit 7 a vertical
//                  blanking (swap_if_pending) after it. The transfer bytes are used in turn, cyclically,
//                  until the link bytes run out.
// At the end: end_of_stream() and one last vertical blanking.
//
// Checks, after every transfer and blanking:
//   - ready() is low exactly while a world accepted since the last swap waits; swap_if_pending() swaps
//     exactly when ready() was low, and raises it;
//   - a swapped-in scene memory is valid, holds at most the preset's spheres (one for v1), every centre and
//     radius inside the preset's formats (radius > 0; a power of two for v1), known materials, ior > 0, and a
//     hierarchy only for artix-path, which keeps the wire's rules (link::hierarchy_error) with every bound but the
//     root's inside the formats;
//   - it is the latest world accepted by a reference: link::FrameStreamDecoder fed the same transfers (or
//     aligned v1 words), with the receiver's documented acceptance rules and an independent model of its
//     sequence rules applied (docs/link_format.md, "Sessions and sequence numbers");
//   - a worker draws the last one without harm (no assertion, no overflow) at a few pixels: the corners,
//     the centre and where the first spheres' centres project, with up to core::kMaxBounces mirror bounces
//     (any world inside the formats must be drawable; docs/device.md bounds the intermediates), and with a
//     hierarchy the sphere units walk it for the same pixels' rays, each hit one the units confirm;
// and at the end: the counts of accepted, rejected, garbage, missing and replayed worlds and of sessions match
// the reference, and every link byte is in an accepted world or counted as dropped (replays included), and
// the bytes dropped are the reference's.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <vector>

#include <tripsitter/core/fixed.h>
#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/receiver.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/link/wire_v1.h>
#include <tripsitter/link/frame.h>

#include "check.h"
#include "trace_pixels.h"
#include "frame_repair.h"
#include "transfers.h"

namespace {

using tripsitter::fuzz::Transfer;
using tripsitter::fuzz::transfers_of;

namespace core = tripsitter::core;
namespace device = tripsitter::device;
namespace link = tripsitter::link;

// What the whole stream should do to the receiver.
struct Reference {
  std::vector<device::SceneMemory> accepted;  // scene memory after each accepted world, in order
  std::vector<std::size_t> accepted_bytes;
  std::uint64_t rejected = 0;
  std::uint64_t garbage_runs = 0;
  std::uint64_t missing = 0;         // sequence numbers skipped
  std::uint64_t replayed = 0;        // v3: intact worlds refused by the sequence rules
  std::uint64_t dropped_bytes = 0;   // in every report and every replay
  std::uint64_t sessions = 0;
};

// The receiver's sequence rules, written from docs/link_format.md apart from link::SequenceRules.
class SequenceModel {
 public:
  static constexpr std::size_t kEndedSessions = 16;  // remembered

  explicit SequenceModel(link::WireVersion wire) : v3_(wire == link::WireVersion::kV3) {}

  // Whether an intact world is shown; adds what it skipped to ref.missing and a session it begins.
  bool admit(std::uint32_t session, std::uint32_t sequence, Reference& ref) {
    if (!v3_) {  // v2: every world is shown; only a step forward skips numbers
      if (!last_) ++ref.sessions;
      if (last_ && sequence > *last_) ref.missing += sequence - *last_ - 1;
      last_ = sequence;
      return true;
    }
    if (session_ == session) {
      if (sequence <= *last_) return false;
      ref.missing += sequence - *last_ - 1;
      last_ = sequence;
      return true;
    }
    if (std::find(ended_.begin(), ended_.end(), session) != ended_.end()) return false;
    if (session_) {
      ended_.push_back(*session_);
      if (ended_.size() > kEndedSessions) ended_.pop_front();
    }
    ++ref.sessions;
    ref.missing += sequence == 0 ? 0 : sequence - 1;  // a host numbers from 1
    session_ = session;
    last_ = sequence;
    return true;
  }

 private:
  bool v3_;
  std::optional<std::uint32_t> session_;  // v3: the current session
  std::optional<std::uint32_t> last_;     // the last number seen (of the current session)
  std::deque<std::uint32_t> ended_;       // v3: the sessions that ended, oldest first
};

// The receiver's acceptance rules for a framed wire (receiver.h, docs/device.md): the sequence rules for every
// frame that arrived intact, then the preset's fractional bits, every centre and radius inside the preset's
// formats and, on a path preset, every dielectric's index of refraction in 0.25..8. The decoder gets the receiver's
// transfers: on v3 a frame in which another intact header begins is cut by it only while the decoder waits for its
// rest (wire_v3_fuzz.cpp).
Reference reference_frames(link::WireVersion wire, std::span<const std::uint8_t> bytes, const device::DevicePreset& p,
                           const std::vector<Transfer>& transfers) {
  Reference ref;
  SequenceModel sequence(wire);
  link::FrameStreamDecoder decoder(
      wire, p.max_spheres,
      {.on_frame =
           [&](link::World&& w) {
             const std::size_t size = link::frame_bytes(wire, w.spheres.size(), w.nodes.size());
             if (!sequence.admit(w.session, w.sequence, ref)) {
               ++ref.replayed;
               ref.dropped_bytes += size;
               return;
             }
             bool ok = w.frac_bits == p.frac_bits();
             for (const link::WireSphere& s : w.spheres) {
               ok = ok && p.holds_ball(s.x, s.y, s.z, s.radius);
               // A path preset takes a dielectric of index 0.25 to 8 only (docs/device.md).
               ok = ok && (!p.path || s.material != link::kMaterialDielectric ||
                           (s.ior >= device::kPathIorMin && s.ior <= device::kPathIorMax));
             }
             for (std::size_t i = 1; i < w.nodes.size(); ++i) {
               const link::WireNode& v = w.nodes[i];
               ok = ok && p.holds_ball(v.x, v.y, v.z, v.radius);
             }
             if (!ok) {
               ++ref.rejected;
               ref.dropped_bytes += size;
               return;
             }
             device::SceneMemory m;
             m.valid = true;
             m.sequence = w.sequence;
             for (const link::WireSphere& s : w.spheres) {
               m.geometry.push_back({{s.x, s.y, s.z}, s.radius});
               m.surfaces.push_back({s.material, s.albedo, s.fuzz, s.ior});
             }
             for (const link::WireNode& v : w.nodes) m.hierarchy.push_back(device::hierarchy_node(v));
             ref.accepted.push_back(std::move(m));
             ref.accepted_bytes.push_back(size);
           },
       .on_error =
           [&](const link::FrameFailure& f, std::size_t dropped) {
             ref.dropped_bytes += dropped;
             if (f.error == link::FrameError::kBadMagic) {
               ++ref.garbage_runs;
             } else if (f.intact && !sequence.admit(f.intact->session, f.intact->sequence, ref)) {
               ++ref.replayed;
             } else {
               ++ref.rejected;
             }
           }},
      p.walks_hierarchy());
  std::size_t at = 0;
  for (const Transfer& t : transfers) {
    decoder.push(bytes.subspan(at, t.bytes));
    at += t.bytes;
  }
  decoder.end_of_stream();
  return ref;
}

// The rule for v1: the word's s.3 fields rescaled to the preset's fractional bits, radius 2^r, all inside
// the preset's formats; the colour's nibbles as 8-bit albedo, lambertian, ior 1.5.
Reference reference_v1(std::span<const std::uint8_t> bytes, const device::DevicePreset& p) {
  Reference ref;
  const int f = p.frac_bits();
  for (std::size_t at = 0; at + link::kV1WordBytes <= bytes.size(); at += link::kV1WordBytes) {
    std::uint64_t word = 0;
    for (std::size_t i = 0; i < link::kV1WordBytes; ++i) word = (word << 8) | bytes[at + i];
    const link::V1Sphere s = link::decode_v1_word(word);
    const std::int64_t x = core::rescale_raw(s.x_raw, 3, f), y = core::rescale_raw(s.y_raw, 3, f),
                       z = core::rescale_raw(s.z_raw, 3, f);
    const int shift = s.radius_log2 + f;
    if (shift > 62 || !p.radius.contains(std::int64_t{1} << shift) || !p.x.contains(x) || !p.y.contains(y) ||
        !p.z.contains(z)) {
      ++ref.rejected;
      ref.dropped_bytes += link::kV1WordBytes;
      continue;
    }
    device::SceneMemory m;
    m.valid = true;
    m.sequence = static_cast<std::uint32_t>(ref.accepted.size() + 1);
    m.geometry.push_back({{x, y, z}, std::int64_t{1} << shift});
    const auto nibble = [&](int k) { return static_cast<std::uint8_t>(((s.colour >> k) & 0xF) * 17); };
    m.surfaces.push_back({link::kMaterialLambertian, {nibble(8), nibble(4), nibble(0)}, 0, 6144});
    ref.accepted.push_back(std::move(m));
    ref.accepted_bytes.push_back(link::kV1WordBytes);
  }
  if (bytes.size() % link::kV1WordBytes != 0) {  // the partial word at the end of the stream
    ++ref.rejected;
    ref.dropped_bytes += bytes.size() % link::kV1WordBytes;
  }
  return ref;
}

bool same_ball(const core::KernelSphere<std::int64_t>& s, const core::KernelSphere<std::int64_t>& t) {
  return s.center.x == t.center.x && s.center.y == t.center.y && s.center.z == t.center.z && s.radius == t.radius;
}

bool same_memory(const device::SceneMemory& a, const device::SceneMemory& b) {
  return a.valid == b.valid && a.sequence == b.sequence && a.geometry.size() == b.geometry.size() &&
         a.surfaces == b.surfaces && std::equal(a.geometry.begin(), a.geometry.end(), b.geometry.begin(), same_ball) &&
         a.hierarchy.size() == b.hierarchy.size() &&
         std::equal(a.hierarchy.begin(), a.hierarchy.end(), b.hierarchy.begin(), [](const auto& u, const auto& v) {
           return same_ball(u.bound, v.bound) && u.first_child == v.first_child && u.children == v.children &&
                  u.first_sphere == v.first_sphere && u.spheres == v.spheres;
         });
}

void check_front(const device::SceneMemory& m, const device::DevicePreset& p, link::WireVersion wire) {
  FUZZ_CHECK(m.valid, "a swapped-in scene memory is not valid");
  FUZZ_CHECK(m.geometry.size() == m.surfaces.size(), "geometry and surfaces differ in length");
  FUZZ_CHECK(m.geometry.size() <= p.max_spheres, "more spheres than the preset's scene memory");
  if (wire == link::WireVersion::kV1) FUZZ_CHECK(m.geometry.size() == 1, "a v1 world of other than one sphere");
  for (std::size_t i = 0; i < m.geometry.size(); ++i) {
    const auto& g = m.geometry[i];
    const device::SurfaceWord& s = m.surfaces[i];
    FUZZ_CHECK(p.x.contains(g.center.x) && p.y.contains(g.center.y) && p.z.contains(g.center.z),
               "a centre outside the preset's formats");
    FUZZ_CHECK(g.radius > 0 && p.radius.contains(g.radius), "a radius outside the preset's format or not above 0");
    if (wire == link::WireVersion::kV1) FUZZ_CHECK((g.radius & (g.radius - 1)) == 0, "a v1 radius not a power of two");
    FUZZ_CHECK(s.material <= link::kMaterialDielectric, "an unknown material in scene memory");
    FUZZ_CHECK(s.ior > 0, "ior 0 in scene memory");
  }
  if (m.hierarchy.empty()) return;
  FUZZ_CHECK(p.walks_hierarchy(), "a hierarchy in the scene memory of a preset that walks none");
  link::World w;
  for (const auto& g : m.geometry)
    w.spheres.push_back({static_cast<std::int32_t>(g.center.x), static_cast<std::int32_t>(g.center.y),
                         static_cast<std::int32_t>(g.center.z), static_cast<std::uint32_t>(g.radius), 0, {}, 0, 1});
  for (std::size_t i = 0; i < m.hierarchy.size(); ++i) {
    const device::HierarchyNode& v = m.hierarchy[i];
    if (i > 0) {
      FUZZ_CHECK(p.holds_ball(v.bound.center.x, v.bound.center.y, v.bound.center.z, v.bound.radius),
                 "a bound outside the preset's formats");
    }
    w.nodes.push_back(device::wire_node(v));
  }
  FUZZ_CHECK(!link::hierarchy_error(w).has_value(), "a hierarchy in scene memory that breaks the wire's rules");
}


}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::uint8_t config = data[0];
  const std::size_t op_count = std::min<std::size_t>(data[1] % 16, size - 2);
  const std::span<const std::uint8_t> ops(data + 2, op_count);
  const link::WireVersion wire = (config & 1)      ? link::WireVersion::kV1
                                 : (config & 0x20) ? link::WireVersion::kV3
                                                   : link::WireVersion::kV2;
  std::vector<std::uint8_t> link_bytes(data + 2 + op_count, data + size);
  if (wire != link::WireVersion::kV1 && !(config & 0x10)) tripsitter::fuzz::repair_frame_crcs(wire, link_bytes);
  const std::span<const std::uint8_t> bytes(link_bytes);

  const device::DevicePreset preset = (config & 0x80) ? device::artix_path_preset()
                                      : (config & 2)   ? device::board_2023_preset()
                                                       : device::wide_preset();
  const std::size_t unit = std::size_t{1} << (2 * ((config >> 2) & 3));
  const std::vector<Transfer> transfers = transfers_of(ops, unit, bytes.size());

  const Reference ref =
      wire == link::WireVersion::kV1 ? reference_v1(bytes, preset) : reference_frames(wire, bytes, preset, transfers);

  device::Receiver receiver(preset, wire);
  device::SceneMemory front;
  std::uint64_t accepted_at_swap = 0;  // worlds accepted when the last swap happened
  std::uint64_t swaps = 0;
  const auto check_ready = [&] {
    const std::uint64_t accepted = receiver.stats().worlds_accepted;
    FUZZ_CHECK(receiver.ready() == (accepted == accepted_at_swap),
               "ready() does not say whether an accepted world waits for the swap");
    FUZZ_CHECK(receiver.stats().worlds_replaced == accepted - swaps - (receiver.ready() ? 0 : 1),
               "worlds_replaced does not count the accepted worlds that were never swapped in");
    FUZZ_CHECK(accepted <= ref.accepted.size(), "more worlds accepted than the reference accepts");
  };
  const auto blanking = [&] {
    const bool was_ready = receiver.ready();
    const bool swapped = receiver.swap_if_pending(front);
    FUZZ_CHECK(swapped == !was_ready, "swap_if_pending() disagrees with the ready line");
    FUZZ_CHECK(receiver.ready(), "the ready line is low after a vertical blanking");
    if (!swapped) return;
    ++swaps;
    accepted_at_swap = receiver.stats().worlds_accepted;
    check_front(front, preset, wire);
    FUZZ_CHECK(accepted_at_swap >= 1 && same_memory(front, ref.accepted[accepted_at_swap - 1]),
               "the swapped-in world is not the latest accepted world of the reference");
  };

  std::size_t at = 0;
  for (const Transfer& t : transfers) {
    receiver.receive(bytes.subspan(at, t.bytes));
    at += t.bytes;
    check_ready();
    if (t.blanking) blanking();
  }
  receiver.end_of_stream();
  check_ready();
  blanking();

  const device::ReceiverStats& stats = receiver.stats();
  FUZZ_CHECK(stats.worlds_accepted == ref.accepted.size(), "accepted worlds differ from the reference");
  FUZZ_CHECK(stats.frames_rejected == ref.rejected, "rejected frames differ from the reference");
  FUZZ_CHECK(stats.garbage_runs == ref.garbage_runs, "garbage runs differ from the reference");
  FUZZ_CHECK(stats.worlds_missing == ref.missing, "missing worlds differ from the reference");
  FUZZ_CHECK(stats.worlds_replayed == ref.replayed, "replayed worlds differ from the reference");
  FUZZ_CHECK(stats.sessions == ref.sessions, "sessions differ from the reference");
  FUZZ_CHECK(stats.frames_rejected == 0 || !stats.last_error.empty(), "a rejection without a reason");
  std::uint64_t accepted_bytes = 0;
  for (const std::size_t b : ref.accepted_bytes) accepted_bytes += b;
  FUZZ_CHECK(stats.bytes_dropped == ref.dropped_bytes, "dropped bytes differ from the reference");
  FUZZ_CHECK(accepted_bytes + stats.bytes_dropped == bytes.size(),
             "link bytes lost: neither in an accepted world nor counted as dropped");
  if (ref.accepted.empty()) FUZZ_CHECK(!front.valid, "a scene memory shown without any accepted world");
  // Drawing costs far more than receiving: only the world shown last is drawn.
  if (front.valid) tripsitter::fuzz::trace_some_pixels(front, preset);
  return 0;
}

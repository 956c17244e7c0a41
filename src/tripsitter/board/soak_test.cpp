// Soak test of the link under damage: host -> SPI link -> damage -> device, the v3 and the v2 wire side by side
// through the very same damage.
//
// Fourteen kinds of fault, each in its own test and each on the wide and the board-2023 preset:
//   single-byte faults: one bit flipped, one byte dropped, one byte inserted, one byte duplicated;
//   bursts: 2 or 3 bits flipped in a frame, 2 to 16 bytes dropped from a frame;
//   transfers: a duplicated transfer, two transfers reordered;
//   a truncated frame (the next world follows), a host that stops mid-frame (the device's end_of_stream),
//   garbage between frames;
//   a replayed world (an old intact frame sent again), a host restart (a new session numbering from 1,
//   between frames or cutting one, with or without end_of_stream; and later frames of the ended session
//   replayed), and an intact world the device refuses for its content (a coordinate outside its format,
//   radius 0 under a good CRC, other fractional bits).
// A small v1 test at the end covers what the v1 wire can promise.
//
// Size. By default (CI) 100,800 worlds per wire in a Release build (3,600 per kind and preset) and a sixth of
// that under the address and thread sanitizers; TRIPSITTER_SOAK_WORLDS=N sends at least N worlds per wire,
// split evenly over the 28 runs (the large run: TRIPSITTER_SOAK_WORLDS=1000000).
//
// How a run goes. Worlds come from a host::Host (random_spheres, 1 to 64 of them, with random camera moves) or
// are synthesised directly as link::World (1 to 64 spheres anywhere in the preset's formats, extremes
// included). Each world is encoded on both wires and goes out through a real SpiLink that numbers it as it
// starts to go out (link::Numbering: on v3 the host's session and 1, 2, 3, ...; on v2 the same numbers without
// a session), in a random transfer size per world (1 byte to 4 KiB). Its transfers are then damaged or not on
// their way to one device::Receiver per wire, with swap_if_pending as vertical blanking after each world. Both
// wires draw the damage from the same seed per fault, so they get the same worlds, the same kind of damage, the
// same transfer sizes and noise, and the header hit on both or on neither in most cases. A device::Device per
// wire, fed the very same bytes, draws a real frame every 1000th world, which is compared with the world that
// should be on screen (its scene memory exactly, its frame statistics, and its pixels against a fresh Device
// given only that world).
//
// A run begins with one intact world, and goes on as a chain of episodes: 0 to 2 intact worlds, one fault,
// then intact worlds until both devices show the latest of them. The number of intact worlds a wire takes is
// the fault's *recovery* on that wire.
//
// What is measured, per fault and per wire (the table at the end, std::cout):
//   - worlds lost: worlds sent from the fault on that never reached the screen (the damaged one, and intact
//     worlds that a bogus header swallowed and that were delivered late and replaced before a blanking);
//   - recovery, as above;
//   - wrong worlds shown: a vertical blanking that put on screen a world other than the newest the host has
//     sent, or a replayed frame (found at each blanking from the screen alone, not from the model below). Apart
//     from those, "late": a world sent since the fault, older than the newest but newer than the one it
//     replaces. That happens in one way only (asserted): a damaged frame whose missing tail equals the next
//     world's first bytes (a dropped last byte 0x54, a frame cut just before a tail "TS") is completed by them,
//     intact and a blanking late, and the next world, robbed of its head, is lost. The bytes on the wire are
//     then exactly those of a fault that hit the next world's head, so that world counts as the one the fault
//     hit, and recovery is counted from it;
//   - worlds_missing against the worlds the link lost. "Lost by the link": sent, not delivered intact, and
//     followed later by a world of the same session that passed the sequence rules. A world lost at the very
//     end of a session (a host that restarts while sending it) is followed by no number of its session, so no
//     receiver can count it: such worlds are reported apart ("uncountable") and are not in the comparison.
// Each test prints its row of the table (a Markdown table, one row per kind of fault, v3 and v2 side by side)
// and the details of each variant of its fault; the binary run whole prints the whole table at the end.
//
// What is checked:
//   1. Nothing crashes, and every world swapped into scene memory equals exactly one sent world: sequence,
//      geometry and surfaces (at every vertical blanking, and on the real Device at each sample).
//   2. The receiver does exactly what the documented rule says, on both wires. A small model below runs the rule on
//      each episode's bytes: a frame is delivered where the decoder expects a frame and the bytes there form a frame
//      whose header passes (v3: magic, version, frac_bits and reserved, the header CRC, count, length; v2 the same
//      without the header CRC) and whose frame CRC is good; a header that fails, or a frame whose CRC fails, costs one
//      rejection and 1 byte, and the hunt for the magic resumes at the next byte; bytes skipped while hunting are one
//      garbage run; on v3, a whole header (magic and good header CRC) inside the bytes a frame announced cuts that
//      frame off there (one rejection, truncated, the bytes before that header) and is taken at once; at end_of_stream
//      an incomplete frame is one rejection (truncated) with all its bytes, a hunt in progress one garbage run. Every
//      delivered frame then goes through the sequence rules (link/sequence.h, re-implemented here): on v3 a world of
//      the current session with a higher number is shown and the numbers between count as missing, a lower or equal one
//      is a replay, a world of one of the last 16 ended sessions is a replay, any other session begins a new one
//      (missing += sequence - 1); on v2 every world is shown and only forward gaps count. A world that passed the rules
//      and that the device refuses for its content is a rejection with all its bytes, and not missing. The receiver's
//      worlds_accepted, worlds_replaced, frames_rejected, garbage_runs, bytes_dropped, worlds_replayed, worlds_missing
//      and sessions must move by exactly what the model says in every episode, the screen after every blanking must
//      show what it says, and every byte fed is in an accepted world or in bytes_dropped (a replayed world's bytes
//      included). Intact worlds are never lost (one that a bogus header swallowed is delivered once that header's CRC
//      has failed), except a world robbed of its head as above. A damaged world is delivered whole exactly when the damage left a copy of it intact (a stray byte
//      before or after it, a duplicated first or last transfer, a transfer duplicated whole, two equal transfers
//      swapped, or its tail borrowed from the next world as above); otherwise it is lost, with at least one report, and
//      a rejected frame whenever its magic arrived first.
//   3. Recovery: the model predicts each figure exactly (once the stream has passed the end of every frame
//      announced by a header in the fault and decided by its CRC, the next complete intact world is shown),
//      and it never takes more intact worlds than cover the largest frame the preset can announce.
//   4. v3, for every kind of fault: no wrong world is ever shown; worlds_missing equals the worlds lost by the
//      link in every episode; a fault loses at most the world it hit and the next intact world is shown
//      (recovery 1; the demand is for single-byte faults, and v3 meets it for all of these); a replayed
//      frame is counted in worlds_replayed and never shown; a restarted host begins a new session, accepted
//      from its first world on.
//   5. v2, what v2 guarantees: no wrong world is shown except replays, and worlds_missing equals the worlds
//      lost by the link except around replays and restarts (v2 shows a replayed world, and a step back or a
//      new host numbering from 1 is no gap it can see). Those are reported, not asserted; so are v2's
//      recoveries, which take many worlds when a damaged header still passes its checks.
//
// Timing is never asserted. Seeded std::mt19937_64 with the test's own arithmetic, so runs are reproducible on
// any standard library.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/board/board.h>
#include <tripsitter/core/crc32.h>
#include <tripsitter/core/sanitizers.h>
#include <tripsitter/device/device.h>
#include <tripsitter/device/receiver.h>
#include <tripsitter/device/test_util.h>
#include <tripsitter/host/host.h>
#include <tripsitter/link/frame.h>
#include <tripsitter/link/sequence.h>
#include <tripsitter/link/spi.h>
#include <tripsitter/link/wire_v1.h>
#include <tripsitter/scene/builtin.h>

namespace tripsitter::board {
namespace {

using Bytes = std::vector<std::uint8_t>;
using link::WireVersion;

using core::kSanitized;

constexpr int kKinds = 14;
constexpr int kPresets = 2;
constexpr std::uint64_t kRuns = kKinds * kPresets;
constexpr std::uint64_t kCiWorldsPerRun = kSanitized ? 600 : 3600;  // 28 runs: 100,800 worlds per wire
constexpr int kRenderEvery = 1000;       // a real frame through each wire's Device every this many worlds
constexpr int kMaxSpheresPerWorld = 64;  // the board-2023 scene memory
constexpr int kRecoveryGiveUp = 5000;    // intact worlds after which a run counts as never recovering
constexpr std::size_t kReplayPool = 48;  // recent intact worlds kept for replays

// Worlds per run: TRIPSITTER_SOAK_WORLDS (worlds per wire, over all runs) or the CI size.
struct Size {
  std::uint64_t per_run = kCiWorldsPerRun;
  std::string error;  // a value that is no positive number
};

const Size& soak_size() {
  static const Size s = [] {
    Size out;
    const char* v = std::getenv("TRIPSITTER_SOAK_WORLDS");
    if (v == nullptr || *v == '\0') return out;
    char* end = nullptr;
    const unsigned long long n = std::strtoull(v, &end, 10);
    if (*end != '\0' || n == 0 || v[0] == '-') {
      out.error = std::string("TRIPSITTER_SOAK_WORLDS=") + v + " is no positive number of worlds";
      return out;
    }
    out.per_run = (static_cast<std::uint64_t>(n) + kRuns - 1) / kRuns;
    return out;
  }();
  return s;
}

// ---- random numbers, the same on every standard library ----

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : g_(seed) {}
  std::uint64_t next() { return g_(); }
  std::uint64_t below(std::uint64_t n) { return g_() % n; }
  std::int64_t between(std::int64_t lo, std::int64_t hi) {
    return lo + static_cast<std::int64_t>(below(static_cast<std::uint64_t>(hi - lo) + 1));
  }
  bool percent(int p) { return below(100) < static_cast<std::uint64_t>(p); }
  std::uint8_t byte() { return static_cast<std::uint8_t>(g_() >> 56); }
  double unit() { return static_cast<double>(g_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }

 private:
  std::mt19937_64 g_;
};

std::uint32_t read_be32(std::span<const std::uint8_t> b, std::size_t at) {
  return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) | (std::uint32_t{b[at + 2]} << 8) |
         std::uint32_t{b[at + 3]};
}

void put_be32(Bytes& out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<std::uint8_t>(v >> s));
}

std::string grouped(std::uint64_t n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string fixed2(double v) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(2) << v;
  return s.str();
}

// ---- worlds ----

// What a world carries, before a wire encodes and numbers it (session and sequence 0).
class WorldSource {
 public:
  WorldSource(const device::DevicePreset& preset, int host_spheres, std::uint64_t seed)
      : preset_(preset),
        rng_(seed),
        host_(scene::random_spheres(host_spheres, static_cast<std::uint32_t>(seed)), formats_of(preset),
              WireVersion::kV3) {}

  link::World next() { return rng_.percent(50) ? from_host() : synthesised(); }

 private:
  link::World from_host() {
    host::Camera& c = host_.camera();
    switch (rng_.below(6)) {
      case 0: c.move(rng_.uniform(-2, 2)); break;
      case 1: c.strafe(rng_.uniform(-2, 2)); break;
      case 2: c.look(rng_.uniform(-10, 10), rng_.uniform(-5, 5)); break;
      case 3: c.orbit(rng_.uniform(-30, 30)); break;
      case 4: if (rng_.percent(10)) host_.reset(); break;
      default: break;  // the camera holds still: the same view again, under a new sequence number
    }
    auto decoded = link::decode_frame(WireVersion::kV3, host_.update().bytes, preset_.max_spheres);
    EXPECT_TRUE(decoded.ok()) << "the host made a frame its own device rejects";
    link::World w;
    if (decoded.ok()) w = std::move(decoded).value();
    EXPECT_EQ(w.sequence, 0u) << "the host numbers its worlds itself; the link should";
    return w;
  }

  std::int64_t coordinate(const core::FixedFormat& f, double plausible_lo, double plausible_hi) {
    switch (rng_.below(10)) {
      case 0: return f.min_raw();
      case 1: return f.max_raw();
      case 2: return rng_.between(f.min_raw(), f.max_raw());
      default: return f.quantize(rng_.uniform(plausible_lo, plausible_hi)).raw;
    }
  }

  link::World synthesised() {
    link::World w;
    w.frac_bits = static_cast<std::uint8_t>(preset_.frac_bits());
    const auto count = static_cast<std::size_t>(rng_.between(1, kMaxSpheresPerWorld));
    for (std::size_t i = 0; i < count; ++i) {
      link::WireSphere s;
      s.x = static_cast<std::int32_t>(coordinate(preset_.x, -500, 500));
      s.y = static_cast<std::int32_t>(coordinate(preset_.y, -400, 400));
      s.z = static_cast<std::int32_t>(coordinate(preset_.z, 20, 2000));
      s.radius = static_cast<std::uint32_t>(std::max<std::int64_t>(1, coordinate(preset_.radius, 0, 300)));
      s.material = static_cast<std::uint8_t>(rng_.below(3));
      for (auto& a : s.albedo) a = rng_.byte();
      s.fuzz = static_cast<std::uint16_t>(rng_.below(65536));
      s.ior = static_cast<std::uint16_t>(rng_.between(1, 65535));
      w.spheres.push_back(s);
    }
    return w;
  }

  device::DevicePreset preset_;
  Rng rng_;
  host::Host host_;
};

// One world as it went out on one wire.
struct SentWorld {
  Bytes frame;                     // numbered, as sent
  link::World world;               // what it carries (v2: session 0, which the wire does not carry)
  std::uint32_t host_session = 0;  // the harness's host session, on both wires
  std::uint64_t index = 0;         // the harness's count of worlds made: the same world on both wires
  bool refused = false;            // intact, but the device must refuse its content
};
using WorldPtr = std::shared_ptr<const SentWorld>;

// Whether scene memory holds exactly this world.
::testing::AssertionResult holds(const device::SceneMemory& m, const link::World& w) {
  if (!m.valid) return ::testing::AssertionFailure() << "scene memory holds no world";
  if (m.sequence != w.sequence)
    return ::testing::AssertionFailure() << "sequence " << m.sequence << ", sent " << w.sequence;
  if (m.geometry.size() != w.spheres.size() || m.surfaces.size() != w.spheres.size())
    return ::testing::AssertionFailure() << "world " << w.sequence << ": " << m.geometry.size() << " spheres, sent "
                                         << w.spheres.size();
  for (std::size_t i = 0; i < w.spheres.size(); ++i) {
    const link::WireSphere& s = w.spheres[i];
    const auto& g = m.geometry[i];
    const device::SurfaceWord& f = m.surfaces[i];
    if (g.center.x != s.x || g.center.y != s.y || g.center.z != s.z || g.radius != std::int64_t{s.radius})
      return ::testing::AssertionFailure() << "world " << w.sequence << ": geometry of sphere " << i << " differs";
    if (f != device::SurfaceWord{s.material, s.albedo, s.fuzz, s.ior})
      return ::testing::AssertionFailure() << "world " << w.sequence << ": surface of sphere " << i << " differs";
  }
  return ::testing::AssertionSuccess();
}

// ---- the rule, as a model of the documented decoder and sequence rules ----

// A framed wire's header layout (docs/link_format.md), written out here rather than taken from frame.cpp.
struct Shape {
  WireVersion wire;
  std::array<std::uint8_t, 4> magic;
  std::uint8_t version;
  std::size_t header_bytes;
  std::optional<std::size_t> session_at;
  std::size_t sequence_at, count_at, length_at;
  std::optional<std::size_t> header_crc_at;
};

Shape shape_of(WireVersion wire) {
  if (wire == WireVersion::kV3)
    return {wire, link::kV3Magic, link::kV3Version, 28, std::size_t{8}, 12, 16, 20, std::size_t{24}};
  return {wire, link::kV2Magic, link::kV2Version, 20, std::nullopt, 8, 12, 16, std::nullopt};
}

enum class Header { kNeedMore, kBadMagic, kFails, kPasses };

// The header checks in their order, on the bytes present at a frame start.
Header check_header(const Shape& s, std::span<const std::uint8_t> b, std::uint32_t max_spheres,
                    std::size_t& frame_bytes) {
  const std::size_t n = b.size();
  for (std::size_t i = 0; i < std::min<std::size_t>(n, 4); ++i)
    if (b[i] != s.magic[i]) return Header::kBadMagic;
  if (n < 5) return Header::kNeedMore;
  if (b[4] != s.version) return Header::kFails;
  if (n < 6) return Header::kNeedMore;
  if (b[5] > link::kMaxFracBits) return Header::kFails;
  for (std::size_t at = 6; at < 8; ++at) {
    if (n <= at) return Header::kNeedMore;
    if (b[at] != 0) return Header::kFails;
  }
  if (s.header_crc_at) {
    if (n < s.header_bytes) return Header::kNeedMore;
    if (core::crc32(b.first(*s.header_crc_at)) != read_be32(b, *s.header_crc_at)) return Header::kFails;
  }
  if (n < s.count_at + 4) return Header::kNeedMore;
  const std::uint32_t count = read_be32(b, s.count_at);
  if (count > max_spheres) return Header::kFails;
  if (n < s.length_at + 4) return Header::kNeedMore;
  const std::uint32_t length = read_be32(b, s.length_at);
  if (std::uint64_t{length} != std::uint64_t{count} * link::kSphereBytes) return Header::kFails;
  if (n < s.header_bytes) return Header::kNeedMore;
  frame_bytes = s.header_bytes + length + link::kFrameTrailerBytes;
  return Header::kPasses;
}

struct ModelFrame {
  std::size_t at = 0, bytes = 0;
  std::size_t ready_at = 0;  // stream position by which the decoder has delivered it
};

struct ModelOutcome {
  std::vector<ModelFrame> frames;  // frames with a good CRC, in the order delivered
  std::uint64_t rejected = 0, garbage_runs = 0, bytes_dropped = 0;
  bool pending = false;  // bytes still undecided at the end (never, when an episode ends in a shown world)
  // Every header that passed and whose frame was then decided (delivered, or its CRC failed): where it stood
  // and where its frame ended.
  std::vector<std::pair<std::size_t, std::size_t>> headers;
};

// Whether a whole v3 header (its magic and its header CRC; nothing else is looked at) starts at `at`.
bool intact_header_at(const Shape& s, std::span<const std::uint8_t> stream, std::size_t at) {
  return s.header_crc_at && at + s.header_bytes <= stream.size() &&
         std::equal(s.magic.begin(), s.magic.end(), stream.begin() + static_cast<std::ptrdiff_t>(at)) &&
         core::crc32(stream.subspan(at, *s.header_crc_at)) == read_be32(stream, at + *s.header_crc_at);
}

// The decoder on `stream`, everything fed in an episode; end_of_stream came at each position in `eos` (sorted).
ModelOutcome model_decoder(const Shape& shape, std::span<const std::uint8_t> stream, const std::vector<std::size_t>& eos,
                           std::uint32_t max_spheres) {
  ModelOutcome out;
  std::vector<std::size_t> ends = eos;
  if (ends.empty() || ends.back() != stream.size()) ends.push_back(stream.size());
  const auto magic_at = [&](std::size_t m) {
    return std::equal(shape.magic.begin(), shape.magic.end(), stream.begin() + static_cast<std::ptrdiff_t>(m));
  };
  std::size_t begin = 0;
  for (const std::size_t end : ends) {
    const bool at_eos = std::find(eos.begin(), eos.end(), end) != eos.end();
    std::size_t pos = begin;
    std::size_t hunt_from = 0;
    bool hunting = false;
    std::size_t blocker = begin;  // the decoder cannot move past a header that passed before its CRC is known
    while (true) {
      if (hunting) {
        std::size_t m = pos;
        while (m + 4 <= end && !magic_at(m)) ++m;
        if (m + 4 > end) {  // no magic before the end: garbage so far, reported only at end_of_stream
          if (at_eos) {
            ++out.garbage_runs;
            out.bytes_dropped += end - hunt_from;
          } else {
            out.pending = true;
          }
          break;
        }
        if (m > hunt_from) {
          ++out.garbage_runs;
          out.bytes_dropped += m - hunt_from;
        }
        pos = m;
        hunting = false;
        continue;
      }
      if (pos == end) break;
      std::size_t frame_bytes = 0;
      const Header h =
          check_header(shape, stream.subspan(pos, std::min(shape.header_bytes, end - pos)), max_spheres, frame_bytes);
      if (h == Header::kBadMagic) {
        hunting = true;
        hunt_from = pos;
        continue;
      }
      if (h == Header::kFails) {
        ++out.rejected;
        ++out.bytes_dropped;
        hunting = true;
        hunt_from = ++pos;
        continue;
      }
      if (h == Header::kNeedMore) {  // an incomplete header
        if (at_eos) {
          ++out.rejected;
          out.bytes_dropped += end - pos;
        } else {
          out.pending = true;
        }
        break;
      }
      // v3: a whole header with a good CRC inside the bytes a frame announced cuts the frame off there (one
      // rejection, truncated, with the bytes before that header), and that header is taken at once.
      if (shape.header_crc_at) {
        std::optional<std::size_t> inside;
        for (std::size_t a = pos + shape.header_bytes; a + shape.header_bytes <= std::min(pos + frame_bytes, end); ++a) {
          if (stream[a] == shape.magic[0] && intact_header_at(shape, stream.first(end), a)) {
            inside = a;
            break;
          }
        }
        if (inside) {
          ++out.rejected;
          out.bytes_dropped += *inside - pos;
          pos = *inside;
          continue;
        }
      }
      if (pos + frame_bytes > end) {  // an incomplete frame
        if (at_eos) {
          ++out.rejected;
          out.bytes_dropped += end - pos;
        } else {
          out.pending = true;
        }
        break;
      }
      const auto frame = stream.subspan(pos, frame_bytes);
      out.headers.emplace_back(pos, pos + frame_bytes);
      if (core::crc32(frame.first(frame_bytes - 4)) == read_be32(frame, frame_bytes - 4)) {
        out.frames.push_back({pos, frame_bytes, std::max(pos + frame_bytes, blocker)});
        pos += frame_bytes;
        continue;
      }
      ++out.rejected;
      ++out.bytes_dropped;
      blocker = std::max(blocker, pos + frame_bytes);
      hunting = true;
      hunt_from = ++pos;
    }
    begin = end;
  }
  return out;
}

// The receiver's sequence rules (docs/link_format.md, "Sessions and sequence numbers").
class RulesModel {
 public:
  explicit RulesModel(WireVersion wire) : v3_(wire == WireVersion::kV3) {}

  struct Verdict {
    bool show = true;
    std::uint64_t missing = 0;
    bool new_session = false;
  };

  Verdict check(std::uint32_t session, std::uint32_t sequence) {
    Verdict v;
    if (!v3_) {
      if (seen_ && sequence > last_) v.missing = sequence - last_ - 1;
      v.new_session = !seen_;
      seen_ = true;
      last_ = sequence;
      return v;
    }
    if (seen_ && session == session_) {
      if (sequence <= last_) {
        v.show = false;
        return v;
      }
      v.missing = sequence - last_ - 1;
      last_ = sequence;
      return v;
    }
    if (std::find(ended_.begin(), ended_.end(), session) != ended_.end()) {
      v.show = false;
      return v;
    }
    if (seen_) {
      ended_.push_back(session_);
      if (ended_.size() > link::SequenceRules::kRetiredSessions) ended_.pop_front();
    }
    v.new_session = true;
    v.missing = sequence == 0 ? 0 : sequence - 1;
    seen_ = true;
    session_ = session;
    last_ = sequence;
    return v;
  }

 private:
  bool v3_;
  bool seen_ = false;
  std::uint32_t session_ = 0, last_ = 0;
  std::deque<std::uint32_t> ended_;
};

// ---- faults ----

enum class Kind {
  kBitFlip,
  kByteDropped,
  kByteInserted,
  kByteDuplicated,
  kBitFlipBurst,
  kBytesDroppedBurst,
  kDuplicatedTransfer,
  kReorderedTransfers,
  kTruncatedFrame,
  kHostStops,
  kGarbage,
  kReplay,
  kHostRestart,
  kRefusedWorld,
};

const char* name_of(Kind k) {
  switch (k) {
    case Kind::kBitFlip: return "1 bit flipped";
    case Kind::kByteDropped: return "1 byte dropped";
    case Kind::kByteInserted: return "1 byte inserted";
    case Kind::kByteDuplicated: return "1 byte duplicated";
    case Kind::kBitFlipBurst: return "2 or 3 bits flipped in a frame";
    case Kind::kBytesDroppedBurst: return "2 to 16 bytes dropped from a frame";
    case Kind::kDuplicatedTransfer: return "duplicated transfer";
    case Kind::kReorderedTransfers: return "reordered transfers";
    case Kind::kTruncatedFrame: return "truncated frame";
    case Kind::kHostStops: return "host stops mid-frame";
    case Kind::kGarbage: return "garbage between frames";
    case Kind::kReplay: return "replayed world";
    case Kind::kHostRestart: return "host restart";
    case Kind::kRefusedWorld: return "intact world refused for its content";
  }
  return "?";
}

// Whether every byte from `at` to the end of `b` equals b[at].
bool same_to_the_end(const Bytes& b, std::size_t at) {
  return std::all_of(b.begin() + static_cast<std::ptrdiff_t>(at), b.end(), [&](std::uint8_t x) { return x == b[at]; });
}

bool single_byte(Kind k) {
  return k == Kind::kBitFlip || k == Kind::kByteDropped || k == Kind::kByteInserted || k == Kind::kByteDuplicated;
}

// The transfers a world goes out in: the real SpiLink, gated by the receiver's ready line.
class TransferRecorder : public link::Endpoint {
 public:
  explicit TransferRecorder(const device::Receiver& rx) : rx_(rx) {}
  bool ready() const override { return rx_.ready(); }
  void transfer(std::span<const std::uint8_t> bytes) override { transfers.emplace_back(bytes.begin(), bytes.end()); }
  std::vector<Bytes> transfers;

 private:
  const device::Receiver& rx_;
};

Bytes concat(const std::vector<Bytes>& transfers) {
  Bytes all;
  for (const Bytes& t : transfers) all.insert(all.end(), t.begin(), t.end());
  return all;
}

std::vector<Bytes> split(const Bytes& bytes, std::size_t transfer_bytes) {
  std::vector<Bytes> out;
  for (std::size_t at = 0; at < bytes.size(); at += transfer_bytes)
    out.emplace_back(bytes.begin() + static_cast<std::ptrdiff_t>(at),
                     bytes.begin() + static_cast<std::ptrdiff_t>(std::min(bytes.size(), at + transfer_bytes)));
  return out;
}

std::size_t random_transfer_bytes(Rng& rng) {
  switch (rng.below(10)) {
    case 0: return static_cast<std::size_t>(rng.between(1, 8));
    case 1: return static_cast<std::size_t>(rng.between(9, 64));
    case 2: case 3: return static_cast<std::size_t>(rng.between(65, 1023));
    case 4: return 4096;
    default: return 1024;  // the default SPI driver
  }
}

// What went into the stream in an episode, in order.
enum class PieceKind { kIntact, kDamaged, kReplay, kNoise };
struct Piece {
  std::size_t begin = 0, end = 0;
  PieceKind kind = PieceKind::kNoise;
  WorldPtr world;  // the world sent (intact, damaged) or sent again (replay)
};

enum class Refusal { kNone, kOutOfFormat, kRadiusZero, kFracBits };

// What one fault did on one wire.
struct LaneEvent {
  std::string variant;            // a finer name, e.g. "1 byte dropped / in the header"
  bool recovers_at_once = true;   // recovery must be 1 intact world
  bool damaged = false;           // a world went out damaged (the episode's piece of kind kDamaged)
  bool delivered_anyway = false;  // ...and a copy of it survived whole
  bool noise = false;             // bytes that are no world: the receiver must report them
  bool restart = false;           // a new host session began
};

// ---- figures ----

struct EventResult {
  int lost = 0, recovery = 0, wrong = 0, late = 0;
  std::uint64_t missing = 0, link_lost = 0, uncountable = 0, replayed = 0;
  bool damaged_delivered = false;
  bool borrowed = false;  // the damaged frame was completed by the next world's first bytes
};

struct Tally {
  std::uint64_t events = 0, lost = 0, wrong = 0, late = 0, missing = 0, link_lost = 0, uncountable = 0, replayed = 0;
  std::uint64_t delivered_anyway = 0, borrowed = 0;
  std::uint64_t inexact = 0;  // events where worlds_missing moved by other than the worlds the link lost
  int lost_max = 0;
  std::map<int, std::uint64_t> recovery;  // intact worlds needed -> events

  void add(const EventResult& r) {
    ++events;
    lost += static_cast<std::uint64_t>(r.lost);
    lost_max = std::max(lost_max, r.lost);
    wrong += static_cast<std::uint64_t>(r.wrong);
    late += static_cast<std::uint64_t>(r.late);
    borrowed += r.borrowed;
    missing += r.missing;
    link_lost += r.link_lost;
    uncountable += r.uncountable;
    replayed += r.replayed;
    delivered_anyway += r.damaged_delivered;
    inexact += r.missing != r.link_lost;
    ++recovery[r.recovery];
  }
  void merge(const Tally& o) {
    events += o.events;
    lost += o.lost;
    lost_max = std::max(lost_max, o.lost_max);
    wrong += o.wrong;
    late += o.late;
    borrowed += o.borrowed;
    missing += o.missing;
    link_lost += o.link_lost;
    uncountable += o.uncountable;
    replayed += o.replayed;
    delivered_anyway += o.delivered_anyway;
    inexact += o.inexact;
    for (const auto& [k, c] : o.recovery) recovery[k] += c;
  }
  int recovery_max() const { return recovery.empty() ? 0 : recovery.rbegin()->first; }
  double recovery_mean() const {
    std::uint64_t n = 0, sum = 0;
    for (const auto& [k, c] : recovery) n += c, sum += c * static_cast<std::uint64_t>(k);
    return n ? static_cast<double>(sum) / static_cast<double>(n) : 0;
  }
  double lost_mean() const { return events ? static_cast<double>(lost) / static_cast<double>(events) : 0; }
  std::string histogram() const {
    std::ostringstream s;
    std::uint64_t over = 0;
    int shown = 0;
    for (const auto& [k, c] : recovery) {
      if (shown++ < 5) s << (shown > 1 ? ", " : "") << k << ": " << c;
      else over += c;
    }
    if (over) s << ", more: " << over;
    return s.str();
  }
};

// ---- one wire: host side, link, receiver, the drawing device and the episode's records ----

class Lane {
 public:
  Lane(const device::DevicePreset& preset, WireVersion wire, std::uint32_t session)
      : preset_(preset),
        wire_(wire),
        shape_(shape_of(wire)),
        numbering_(wire, wire == WireVersion::kV3 ? session : 0),
        host_session_(session),
        rx_(preset_, wire),
        shadow_(preset_, wire),
        rules_(wire) {}
  Lane(const Lane&) = delete;
  Lane& operator=(const Lane&) = delete;

  WireVersion wire() const { return wire_; }
  const char* wire_name() const { return wire_ == WireVersion::kV3 ? "v3" : "v2"; }
  std::size_t header_bytes() const { return shape_.header_bytes; }
  const std::array<std::uint8_t, 4>& magic() const { return shape_.magic; }
  std::uint8_t version() const { return shape_.version; }
  const device::DevicePreset& preset() const { return preset_; }
  const std::deque<WorldPtr>& pool() const { return pool_; }
  const WorldPtr& latest() const { return latest_; }
  std::uint32_t host_session() const { return host_session_; }
  std::uint64_t worlds_sent() const { return worlds_sent_; }
  int failures() const { return failures_; }
  bool recovered() const { return recovered_; }
  const std::map<std::string, Tally>& tallies() const { return tallies_; }
  void set_context(std::string context) { context_ = std::move(context); }

  // -- the host --

  // A new host: another session, numbered from 1.
  void restart(std::uint32_t session) {
    numbering_ = link::Numbering(wire_, wire_ == WireVersion::kV3 ? session : 0);
    host_session_ = session;
  }

  // A world goes out through a real SpiLink that numbers it, in transfers of at most `tb` bytes.
  WorldPtr make(const link::World& content, std::size_t tb, std::uint64_t index, Refusal refusal,
                std::vector<Bytes>& transfers) {
    link::World c = content;
    if (refusal == Refusal::kOutOfFormat) c.spheres.at(0).x = static_cast<std::int32_t>(preset_.x.max_raw() + 1);
    if (refusal == Refusal::kFracBits)
      c.frac_bits = static_cast<std::uint8_t>(preset_.frac_bits() < link::kMaxFracBits ? preset_.frac_bits() + 1
                                                                                       : preset_.frac_bits() - 1);
    Bytes bytes = link::encode_frame(wire_, c);
    if (refusal == Refusal::kRadiusZero) {  // the link's numbering fixes the CRCs
      c.spheres.at(0).radius = 0;
      for (std::size_t k = 0; k < 4; ++k) bytes[shape_.header_bytes + 12 + k] = 0;
    }
    link::SpiLink spi({.max_transfer_bytes = tb}, numbering_);
    TransferRecorder rec(rx_);
    spi.submit(std::move(bytes));
    EXPECT_TRUE(spi.pump(rec)) << "the ready line was low after vertical blanking";
    numbering_ = *spi.numbering();
    auto w = std::make_shared<SentWorld>();
    w->frame = concat(rec.transfers);
    w->world = std::move(c);
    w->world.session = wire_ == WireVersion::kV3 ? numbering_.session() : 0;
    w->world.sequence = numbering_.last_sequence();
    w->host_session = host_session_;
    w->index = index;
    w->refused = refusal != Refusal::kNone;
    if (!w->refused) {
      auto decoded = link::decode_frame(wire_, w->frame, preset_.max_spheres);
      if (!decoded.ok() || decoded.value() != w->world) fail("the link sent a frame that is not the world numbered");
      pool_.push_back(w);
      if (pool_.size() > kReplayPool) pool_.pop_front();
    }
    latest_ = w;
    latest_shown_ = false;
    if (in_event_) since_event_.emplace_back(w, false);
    ++worlds_sent_;
    transfers = std::move(rec.transfers);
    return w;
  }

  void send_intact(const link::World& content, std::size_t tb, std::uint64_t index) {
    std::vector<Bytes> transfers;
    const WorldPtr w = make(content, tb, index, Refusal::kNone, transfers);
    feed(transfers, PieceKind::kIntact, w);
  }

  // -- the device --

  void feed(const std::vector<Bytes>& transfers, PieceKind kind, WorldPtr world) {
    Piece p{stream_.size(), 0, kind, std::move(world)};
    for (const Bytes& t : transfers) {
      rx_.receive(t);
      shadow_.transfer(t);
      stream_.insert(stream_.end(), t.begin(), t.end());
      bytes_fed_ += t.size();
    }
    p.end = stream_.size();
    pieces_.push_back(std::move(p));
  }

  void end_of_stream() {
    rx_.end_of_stream();
    shadow_.end_of_stream();
    eos_.push_back(stream_.size());
  }

  // Vertical blanking: the receiver's waiting world (if any) becomes scene memory. Right is the newest world the
  // host has sent. Late is an older one sent since the fault, still newer than the world it replaces (a damaged
  // frame that the next world's first bytes completed). Anything else, and anything a replay brought, is wrong.
  void vblank(bool replay_step) {
    if (rx_.swap_if_pending(front_)) {
      WorldPtr found;
      const auto consider = [&](const WorldPtr& w) {
        if (!found && w && holds(front_, w->world)) found = w;
      };
      if (!replay_step) consider(latest_);
      for (auto it = pieces_.rbegin(); it != pieces_.rend(); ++it) consider(it->world);
      consider(shown_);
      for (const WorldPtr& w : pool_) consider(w);
      if (!found) {
        fail("the device shows world " + std::to_string(front_.sequence) + ", which was never sent");
      } else {
        const auto sent_since_fault = std::find_if(since_event_.begin(), since_event_.end(),
                                                   [&](const auto& entry) { return entry.first == found; });
        if (replay_step) {
          ++wrong_;
        } else if (found != latest_) {
          const bool newer = !shown_ || found->index > shown_->index;
          ++(newer && sent_since_fault != since_event_.end() ? late_ : wrong_);
        }
        if (!replay_step && sent_since_fault != since_event_.end()) sent_since_fault->second = true;
        if (!replay_step && found == latest_) latest_shown_ = true;
        shown_ = found;
      }
    }
    steps_.push_back({stream_.size(), front_.valid ? std::optional(front_.sequence) : std::nullopt});
  }

  void expect_shown(const char* what) {
    if (!latest_shown_) fail(what);
  }

  // The real device, fed the same bytes, draws the world the receiver has on screen, and draws it exactly as a
  // device that was only ever given that world.
  void draw_and_compare() {
    ++renders_;
    device::FrameStats stats;
    const std::vector<core::Rgb444> pixels = device::testing::visible_pixels(shadow_, &stats);
    ASSERT_EQ(stats.has_world, front_.valid);
    if (!front_.valid) return;
    ASSERT_EQ(stats.sequence, front_.sequence);
    ASSERT_TRUE(shown_);
    ASSERT_TRUE(holds(shadow_.scene(), shown_->world)) << "the drawing device, " << wire_name();
    device::Device clean(preset_, wire_);
    clean.transfer(shown_->frame);
    device::FrameStats clean_stats;
    const std::vector<core::Rgb444> expected = device::testing::visible_pixels(clean, &clean_stats);
    ASSERT_EQ(clean_stats.sequence, shown_->world.sequence);
    EXPECT_EQ(stats.late_pixels, clean_stats.late_pixels);
    EXPECT_TRUE(pixels == expected) << "world " << shown_->world.sequence << " is drawn differently after the soak ("
                                    << wire_name() << ")";
  }

  // -- episodes --

  void begin_episode() {
    before_ = rx_.stats();
    front_before_ = front_.valid ? std::optional(front_.sequence) : std::nullopt;
    stream_.clear();
    steps_.clear();
    eos_.clear();
    pieces_.clear();
    since_event_.clear();
    in_event_ = false;
    event_ = {};
    wrong_ = 0;
    late_ = 0;
    recovery_ = 0;
    recovered_ = false;
    recovery_sizes_.clear();
    recovery_worlds_.clear();
  }

  void begin_event() { in_event_ = true; }
  void end_event(LaneEvent e) {
    event_ = std::move(e);
    region_end_ = stream_.size();
  }

  // After each intact world that follows the fault.
  void count_recovery() {
    recovery_sizes_.push_back(latest_->frame.size());
    recovery_worlds_.push_back(latest_);
    if (recovered_) return;
    ++recovery_;
    recovered_ = latest_shown_;
  }

  void give_up(Kind kind) {
    fail(std::string(name_of(kind)) + ": no recovery after " + std::to_string(recovery_) + " intact worlds");
  }

  void check_episode(Kind kind) {
    const ModelOutcome m = model_decoder(shape_, stream_, eos_, preset_.max_spheres);
    const device::ReceiverStats& now = rx_.stats();
    const bool v3 = wire_ == WireVersion::kV3;

    // Which world each delivered frame is, and what the sequence rules and the content checks make of it.
    struct Delivered {
      ModelFrame f;
      WorldPtr world;
      PieceKind from = PieceKind::kNoise;
      std::uint32_t sequence = 0;
      bool admitted = false, accepted = false;
    };
    std::vector<Delivered> frames;
    std::uint64_t forged = 0, accepted = 0, replayed = 0, missing = 0, sessions = 0;
    std::uint64_t rejected = m.rejected, dropped = m.bytes_dropped, accepted_bytes = 0;
    for (const ModelFrame& f : m.frames) {
      Delivered d{f, nullptr};
      const auto bytes = std::span<const std::uint8_t>(stream_).subspan(f.at, f.bytes);
      for (const Piece& p : pieces_) {
        if (p.begin <= f.at && f.at < p.end && p.world && std::ranges::equal(bytes, p.world->frame)) {
          d.world = p.world;
          d.from = p.kind;
          break;
        }
      }
      if (!d.world) ++forged;
      d.sequence = read_be32(bytes, shape_.sequence_at);
      const RulesModel::Verdict v =
          rules_.check(shape_.session_at ? read_be32(bytes, *shape_.session_at) : 0, d.sequence);
      if (!v.show) {
        ++replayed;
        dropped += f.bytes;
      } else {
        d.admitted = true;
        missing += v.missing;
        sessions += v.new_session;
        if (d.world && d.world->refused) {
          ++rejected;
          dropped += f.bytes;
        } else {
          d.accepted = true;
          ++accepted;
          accepted_bytes += f.bytes;
        }
      }
      frames.push_back(std::move(d));
    }
    const auto delivered_from = [&](const Piece& p) {
      return std::find_if(frames.begin(), frames.end(),
                          [&](const Delivered& d) { return d.world == p.world && d.from == p.kind; });
    };

    // A damaged frame whose missing tail equals the next world's first bytes is completed by them (delivered
    // intact, a blanking late), and that world, robbed of its head, is lost: the very stream of a fault that hit
    // the next world's first bytes. That world is then the one the fault hit.
    const Piece* damaged = nullptr;
    for (const Piece& p : pieces_)
      if (p.kind == PieceKind::kDamaged) damaged = &p;
    const bool borrowed = damaged && std::any_of(frames.begin(), frames.end(), [&](const Delivered& d) {
      return d.world == damaged->world && d.from == PieceKind::kDamaged && d.f.at + d.f.bytes > damaged->end;
    });
    const Piece* robbed = nullptr;
    for (const Piece& p : pieces_)
      if (borrowed && p.begin == damaged->end && p.kind == PieceKind::kIntact) robbed = &p;

    // The rule itself: no forged frame, nothing undecided, every byte accounted for, nothing intact lost.
    if (forged) fail("a frame with a good CRC that was never sent");
    if (m.pending) fail("the model has bytes left undecided after the shown world");
    if (accepted_bytes + dropped != stream_.size())
      fail("the model loses bytes: " + std::to_string(accepted_bytes) + " accepted + " + std::to_string(dropped) +
           " dropped of " + std::to_string(stream_.size()));
    for (const Piece& p : pieces_) {
      if (p.kind == PieceKind::kIntact && &p != robbed && delivered_from(p) == frames.end())
        fail("intact world " + std::to_string(p.world->world.sequence) + " was never delivered");
      // v3: a new world is taken from its first delivery on (a restarted host's first world included).
      if (v3 && (p.kind == PieceKind::kIntact || p.kind == PieceKind::kDamaged) && p.world) {
        const auto it = delivered_from(p);
        if (it != frames.end() && !it->admitted) fail("a new world was judged a replay");
      }
    }
    for (const Delivered& d : frames)
      if (v3 && d.from == PieceKind::kReplay && d.admitted) fail("a replayed world passed the sequence rules");

    // The receiver counts exactly what the rule says.
    const auto same = [&](const char* what, std::uint64_t got, std::uint64_t rule) {
      if (got != rule) fail(std::string(what) + " " + std::to_string(got) + ", the rule says " + std::to_string(rule));
    };
    same("worlds accepted", now.worlds_accepted - before_.worlds_accepted, accepted);
    same("frames rejected", now.frames_rejected - before_.frames_rejected, rejected);
    same("garbage runs", now.garbage_runs - before_.garbage_runs, m.garbage_runs);
    same("bytes dropped", now.bytes_dropped - before_.bytes_dropped, dropped);
    same("worlds replayed", now.worlds_replayed - before_.worlds_replayed, replayed);
    same("worlds missing", now.worlds_missing - before_.worlds_missing, missing);
    same("sessions", now.sessions - before_.sessions, sessions);

    // What was on screen after each step, and how many accepted worlds were replaced before a blanking.
    std::size_t next = 0;
    std::uint64_t replaced = 0;
    std::optional<std::uint32_t> expected = front_before_;
    for (const Step& s : steps_) {
      std::uint64_t this_step = 0;
      for (; next < frames.size() && frames[next].f.ready_at <= s.fed_end; ++next) {
        if (!frames[next].accepted) continue;
        expected = frames[next].sequence;
        ++this_step;
      }
      if (this_step > 1) replaced += this_step - 1;
      if (s.front != expected) {
        fail("after " + std::to_string(s.fed_end) + " bytes the screen shows " +
             (s.front ? std::to_string(*s.front) : "nothing") + ", the rule says " +
             (expected ? std::to_string(*expected) : "nothing"));
        break;
      }
    }
    same("worlds replaced", now.worlds_replaced - before_.worlds_replaced, replaced);

    // The damaged world: delivered whole exactly when a copy survived; otherwise lost, with at least one report,
    // and a rejected frame whenever its magic arrived first.
    EventResult r;
    const std::uint64_t reports =
        (now.frames_rejected - before_.frames_rejected) + (now.garbage_runs - before_.garbage_runs);
    for (const Piece& p : pieces_) {
      if (p.kind != PieceKind::kDamaged) continue;
      const bool arrived = delivered_from(p) != frames.end();
      r.damaged_delivered = arrived;
      if (arrived != event_.delivered_anyway && !(arrived && borrowed))
        fail(arrived ? "a damaged world was delivered" : "a world that survived its damage was lost");
      if (!arrived) {
        if (reports == 0 || now.bytes_dropped == before_.bytes_dropped) fail("a lost world was not counted");
        const bool magic_first =
            p.end - p.begin >= 4 &&
            std::equal(shape_.magic.begin(), shape_.magic.end(), stream_.begin() + static_cast<std::ptrdiff_t>(p.begin));
        if (magic_first && now.frames_rejected == before_.frames_rejected)
          fail("a damaged frame whose magic arrived was not rejected");
      }
    }
    if (event_.noise && reports == 0) fail("noise was not counted");

    // Worlds the link lost: sent, not delivered intact, and followed by a world of the same session that passed
    // the sequence rules (which is how a receiver can know). The rest were the last of their session.
    for (const Piece& p : pieces_) {
      if ((p.kind != PieceKind::kIntact && p.kind != PieceKind::kDamaged) || !p.world) continue;
      if (delivered_from(p) != frames.end()) continue;
      const bool followed = std::any_of(frames.begin(), frames.end(), [&](const Delivered& d) {
        return d.admitted && d.world && d.from != PieceKind::kReplay && d.world->host_session == p.world->host_session &&
               d.world->index > p.world->index;
      });
      ++(followed ? r.link_lost : r.uncountable);
    }
    r.missing = now.worlds_missing - before_.worlds_missing;
    r.replayed = now.worlds_replayed - before_.worlds_replayed;
    r.wrong = wrong_;
    r.late = late_;
    r.borrowed = borrowed;
    // Recovery counts from the world the fault hit.
    const bool first_robbed = robbed && !recovery_worlds_.empty() && robbed->world == recovery_worlds_.front();
    r.recovery = recovery_ - (first_robbed ? 1 : 0);
    for (const auto& [w, shown] : since_event_) r.lost += !shown;

    // Recovery: once the stream has passed the end of every frame announced by a header inside the fault, the
    // next complete intact world is shown; and never more intact worlds than cover the largest frame.
    std::size_t reach = 0;
    for (const auto& [at, end] : m.headers)
      if (at < region_end_) reach = std::max(reach, end);
    int predicted = 0;
    std::size_t fed = region_end_;
    for (std::size_t j = 0; j < recovery_sizes_.size(); ++j) {
      fed += recovery_sizes_[j];
      if (fed >= reach) {
        predicted = static_cast<int>(j) + 1;
        break;
      }
    }
    const auto undelivered = [&](int j) {  // the j-th intact world after the fault (from 1) was robbed
      const WorldPtr& w = recovery_worlds_[static_cast<std::size_t>(j - 1)];
      return std::none_of(frames.begin(), frames.end(), [&](const Delivered& d) { return d.world == w && d.from == PieceKind::kIntact; });
    };
    while (predicted > 0 && predicted <= static_cast<int>(recovery_worlds_.size()) && undelivered(predicted)) ++predicted;
    if (recovery_ != predicted)
      fail("recovery took " + std::to_string(recovery_) + " intact worlds, the rule says " + std::to_string(predicted));
    if (event_.recovers_at_once && r.recovery != 1)
      fail("recovery took " + std::to_string(r.recovery) + " intact worlds after the one the fault hit, not 1");
    std::size_t covered = 0;
    for (int j = 0; j + 1 < recovery_; ++j) covered += recovery_sizes_[static_cast<std::size_t>(j)];
    if (covered >= link::frame_bytes(wire_, preset_.max_spheres)) fail("recovery took longer than the largest frame");

    // What each wire promises.
    const bool replays_fed = std::any_of(pieces_.begin(), pieces_.end(),
                                         [](const Piece& p) { return p.kind == PieceKind::kReplay; });
    if ((v3 || !replays_fed) && r.wrong != 0) fail(std::to_string(r.wrong) + " wrong worlds shown");
    if (r.late != 0 && !borrowed) fail(std::to_string(r.late) + " worlds shown late, and none completed late");
    if ((v3 || (kind != Kind::kReplay && kind != Kind::kHostRestart)) && r.missing != r.link_lost)
      fail(std::to_string(r.missing) + " worlds counted missing, " + std::to_string(r.link_lost) +
           " lost by the link");
    if (v3 && (r.lost > 1 || r.recovery != 1))
      fail(std::string(single_byte(kind) ? "a single-byte fault" : "a fault") + " cost " + std::to_string(r.lost) +
           " worlds and a recovery of " + std::to_string(r.recovery) + " (v3: at most the world it hit, and 1)");
    if (v3 && event_.restart && now.sessions == before_.sessions) fail("the new host's session was not begun");
    if (v3 && replays_fed && r.replayed == 0) fail("a replay was not counted");

    tallies_[event_.variant].add(r);
  }

  Tally total() const {
    Tally t;
    for (const auto& [variant, v] : tallies_) t.merge(v);
    return t;
  }

  void report(std::ostream& os, const char* kind) const {
    const device::ReceiverStats& s = rx_.stats();
    const Tally t = total();
    os << "[soak] " << kind << ", " << wire_name() << ", preset " << preset_.name << ": " << worlds_sent_ << " worlds, "
       << renders_ << " frames drawn and compared, receiver " << s.worlds_accepted << " accepted, "
       << s.worlds_replaced << " replaced, " << s.frames_rejected << " rejected, " << s.garbage_runs
       << " garbage runs, " << s.worlds_replayed << " replayed, " << s.sessions << " sessions, " << s.bytes_dropped
       << " of " << bytes_fed_ << " bytes dropped; " << t.link_lost << " worlds lost by the link, " << s.worlds_missing
       << " counted missing\n";
    for (const auto& [variant, v] : tallies_) {
      os << "[soak]   " << std::left << std::setw(60) << variant << std::right << std::setw(6) << v.events
         << " events; lost max " << v.lost_max << ", mean " << fixed2(v.lost_mean()) << "; by the link "
         << v.link_lost << ", counted " << v.missing;
      if (v.uncountable) os << ", uncountable " << v.uncountable;
      if (v.replayed) os << "; " << v.replayed << " replayed";
      if (v.wrong) os << "; " << v.wrong << " WRONG worlds shown";
      if (v.delivered_anyway) os << "; " << v.delivered_anyway << " delivered anyway";
      if (v.borrowed) os << " (" << v.borrowed << " completed by the next world's first bytes, " << v.late
                         << " shown a blanking late)";
      os << "; recovery max " << v.recovery_max() << ", mean " << fixed2(v.recovery_mean()) << " (" << v.histogram()
         << ")\n";
    }
  }

 private:
  struct Step {
    std::size_t fed_end = 0;
    std::optional<std::uint32_t> front;
  };

  void fail(const std::string& what) {
    ADD_FAILURE() << context_ << ", " << wire_name() << ", preset " << preset_.name << ", "
                  << (event_.variant.empty() ? std::string("before the fault") : event_.variant) << ", world "
                  << worlds_sent_ << ": " << what;
    ++failures_;
  }

  device::DevicePreset preset_;
  WireVersion wire_;
  Shape shape_;
  link::Numbering numbering_;
  std::uint32_t host_session_;
  device::Receiver rx_;
  device::Device shadow_;
  device::SceneMemory front_;
  RulesModel rules_;
  WorldPtr latest_;  // the newest world the host has sent
  WorldPtr shown_;   // the world on screen
  bool latest_shown_ = false;
  std::deque<WorldPtr> pool_;
  std::string context_;

  // The episode.
  device::ReceiverStats before_;
  std::optional<std::uint32_t> front_before_;
  Bytes stream_;
  std::vector<Step> steps_;
  std::vector<std::size_t> eos_;
  std::vector<Piece> pieces_;
  bool in_event_ = false;
  std::size_t region_end_ = 0;
  std::vector<std::pair<WorldPtr, bool>> since_event_;  // worlds sent from the fault on, and whether shown
  LaneEvent event_;
  int wrong_ = 0;
  int late_ = 0;
  int recovery_ = 0;
  bool recovered_ = false;
  std::vector<std::size_t> recovery_sizes_;
  std::vector<WorldPtr> recovery_worlds_;

  std::map<std::string, Tally> tallies_;
  std::uint64_t worlds_sent_ = 0;
  std::uint64_t bytes_fed_ = 0;
  int renders_ = 0;
  int failures_ = 0;
};

// ---- one run: one kind of fault on one preset, both wires in lockstep ----

class Soak {
 public:
  Soak(device::DevicePreset preset, Kind kind, std::uint64_t seed)
      : preset_(std::move(preset)),
        kind_(kind),
        rng_(seed * 7919 + 17),
        source_(preset_, 1 + static_cast<int>((seed * 37) % kMaxSpheresPerWorld), seed) {
    session_ = new_session();
    for (const WireVersion wire : {WireVersion::kV3, WireVersion::kV2}) {
      lanes_.push_back(std::make_unique<Lane>(preset_, wire, session_));
      lanes_.back()->set_context(name_of(kind_));
    }
  }

  void run(std::uint64_t worlds) {
    if (lanes_[0]->worlds_sent() == 0) start();
    while (lanes_[0]->worlds_sent() < worlds && !::testing::Test::HasFatalFailure() && failures() < 20) episode();
  }

  int failures() const {
    int n = 0;
    for (const auto& lane : lanes_) n += lane->failures();
    return n;
  }
  std::uint64_t worlds() const { return lanes_[0]->worlds_sent(); }
  const Lane& lane(std::size_t i) const { return *lanes_[i]; }

  void report(std::ostream& os) const {
    for (const auto& lane : lanes_) lane->report(os, name_of(kind_));
  }

 private:
  std::uint32_t new_session() {
    std::uint32_t s = 0;
    while (s == 0 || s == session_ || std::find(ended_.begin(), ended_.end(), s) != ended_.end())
      s = static_cast<std::uint32_t>(rng_.next() >> 32);
    return s;
  }

  void maybe_draw() {
    if (lanes_[0]->worlds_sent() < next_render_) return;
    next_render_ += kRenderEvery;
    for (const auto& lane : lanes_) lane->draw_and_compare();
  }

  // The run's first world, intact; it belongs to the first episode, whose checks cover it.
  void start() {
    const link::World content = source_.next();
    const std::size_t tb = random_transfer_bytes(rng_);
    ++index_;
    first_episode_ = true;
    for (const auto& lane : lanes_) {
      lane->send_intact(content, tb, index_);
      lane->vblank(false);
      lane->expect_shown("the run's first world was not shown at once");
    }
  }

  void episode() {
    if (!first_episode_)
      for (const auto& lane : lanes_) lane->begin_episode();
    first_episode_ = false;

    // A clean start: intact worlds are shown at once.
    for (std::int64_t n = rng_.between(0, 2); n > 0; --n) {
      const link::World content = source_.next();
      const std::size_t tb = random_transfer_bytes(rng_);
      ++index_;
      for (const auto& lane : lanes_) {
        lane->send_intact(content, tb, index_);
        lane->vblank(false);
        lane->expect_shown("an intact world after a clean start was not shown at once");
      }
      maybe_draw();
    }

    // The fault, drawn from one seed for both wires.
    const link::World content = source_.next();
    const std::uint64_t seed = rng_.next();
    const std::uint32_t next_session = new_session();
    index_ += 2;  // the fault may send one world, and a host restart a second
    bool restarted = false;
    for (const auto& lane : lanes_) {
      Rng er(seed);
      lane->begin_event();
      LaneEvent e = fault(*lane, er, content, index_ - 1, next_session);
      // v3 never awaits bytes a damaged header announced (its CRC fails first), and a whole header that arrives
      // inside a frame still awaited cuts that frame off: every fault there is followed at once by the next
      // intact world. On v2 only where the flags say so.
      if (lane->wire() == WireVersion::kV3) e.recovers_at_once = true;
      restarted = e.restart;
      lane->end_event(std::move(e));
    }
    if (restarted) {
      ended_.push_back(session_);
      if (ended_.size() > link::SequenceRules::kRetiredSessions) ended_.pop_front();
      session_ = next_session;
    }
    maybe_draw();

    // Recovery: intact worlds until both wires show the latest.
    for (int n = 0;; ++n) {
      if (n == kRecoveryGiveUp) {
        for (const auto& lane : lanes_)
          if (!lane->recovered()) lane->give_up(kind_);
        return;
      }
      const link::World w = source_.next();
      const std::size_t tb = random_transfer_bytes(rng_);
      ++index_;
      bool all = true;
      for (const auto& lane : lanes_) {
        lane->send_intact(w, tb, index_);
        lane->vblank(false);
        lane->count_recovery();
        all = all && lane->recovered();
      }
      maybe_draw();
      if (all) break;
    }
    for (const auto& lane : lanes_) lane->check_episode(kind_);
  }

  // One fault on one wire. Runs once per wire with the same seed, so both wires draw the same numbers.
  LaneEvent fault(Lane& lane, Rng& er, const link::World& content, std::uint64_t index, std::uint32_t next_session) {
    LaneEvent e;
    const std::size_t hb = lane.header_bytes();
    const bool v3 = lane.wire() == WireVersion::kV3;
    const std::size_t tb = random_transfer_bytes(er);
    // A position below n, in the header more often than its share.
    const auto position = [&](std::size_t n) {
      const bool header = er.percent(30);
      const std::uint64_t r = er.next();
      return static_cast<std::size_t>(header ? r % std::min(hb, n) : r % n);
    };
    const auto where = [&](std::size_t pos) {
      return std::string(pos < 4 ? "in the magic" : pos < hb ? "in the header" : "in payload or CRC");
    };
    const auto named = [&](const std::string& detail) { return std::string(name_of(kind_)) + " / " + detail; };
    const auto send_damaged = [&](const Bytes& b, const WorldPtr& w) {
      lane.feed(split(b, tb), PieceKind::kDamaged, w);
      lane.vblank(false);
    };
    std::vector<Bytes> out;

    switch (kind_) {
      case Kind::kBitFlip: {
        const WorldPtr w = lane.make(content, tb, index, Refusal::kNone, out);
        Bytes b = w->frame;
        const std::size_t pos = position(b.size());
        b[pos] ^= static_cast<std::uint8_t>(0x80 >> er.below(8));
        e.variant = named(where(pos));
        e.damaged = true;
        e.recovers_at_once = v3 || pos >= hb;
        send_damaged(b, w);
        break;
      }
      case Kind::kByteDropped: {
        const WorldPtr w = lane.make(content, tb, index, Refusal::kNone, out);
        Bytes b = w->frame;
        const std::size_t pos = position(b.size());
        b.erase(b.begin() + static_cast<std::ptrdiff_t>(pos));
        e.variant = named(where(pos));
        e.damaged = true;
        e.recovers_at_once = v3 || pos >= hb;
        send_damaged(b, w);
        break;
      }
      case Kind::kByteInserted: {
        const WorldPtr w = lane.make(content, tb, index, Refusal::kNone, out);
        Bytes b = w->frame;
        const std::size_t n = b.size();
        const std::size_t pos = position(n + 1);  // before byte pos; n: after the frame
        const std::uint8_t v = er.byte();
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(pos), v);
        e.damaged = true;
        // A stray byte before or after an intact frame: at either end, or a copy of the first byte (a 'T' after
        // it) or of the last bytes next to them.
        e.delivered_anyway = pos == 0 || pos == n || (pos == 1 && v == w->frame[0]) ||
                             (v == w->frame[pos] && same_to_the_end(w->frame, pos));
        e.variant = named(pos == 0 ? "before the frame" : pos == n ? "after the frame" : where(pos));
        e.recovers_at_once = v3 || e.delivered_anyway || pos >= hb;
        send_damaged(b, w);
        break;
      }
      case Kind::kByteDuplicated: {
        const WorldPtr w = lane.make(content, tb, index, Refusal::kNone, out);
        Bytes b = w->frame;
        const std::size_t n = b.size();
        const std::size_t pos = position(n);
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(pos), b[pos]);
        e.damaged = true;
        // A copy of the first byte, or of one in a run that ends the frame, is a stray byte before or after an
        // intact frame.
        e.delivered_anyway = pos == 0 || same_to_the_end(w->frame, pos);
        e.variant = named(pos == 0 ? "the first byte (a stray byte before the frame)"
                                   : pos == n - 1 ? "the last byte (a stray byte after the frame)" : where(pos));
        e.recovers_at_once = v3 || pos == 0 || pos >= hb;
        send_damaged(b, w);
        break;
      }
      case Kind::kBitFlipBurst: {
        // CRC-32 has a Hamming distance of at least 4 for frames up to 91,607 bits, so no such flip can pass
        // unseen; the header checks may see it first.
        const WorldPtr w = lane.make(content, tb, index, Refusal::kNone, out);
        Bytes b = w->frame;
        const auto flips = static_cast<std::size_t>(er.between(2, 3));
        std::vector<std::size_t> bits;
        while (bits.size() < flips) {
          const std::size_t bit = position(b.size()) * 8 + er.below(8);
          if (std::find(bits.begin(), bits.end(), bit) == bits.end()) bits.push_back(bit);
        }
        bool in_header = false, in_magic = false;
        for (const std::size_t bit : bits) {
          b[bit / 8] ^= static_cast<std::uint8_t>(0x80 >> (bit % 8));
          in_header = in_header || bit / 8 < hb;
          in_magic = in_magic || bit / 8 < 4;
        }
        e.variant = named(in_magic ? "in the magic" : in_header ? "in the header" : "in payload or CRC");
        e.damaged = true;
        e.recovers_at_once = v3 || !in_header;
        send_damaged(b, w);
        break;
      }
      case Kind::kBytesDroppedBurst: {
        const WorldPtr w = lane.make(content, tb, index, Refusal::kNone, out);
        Bytes b = w->frame;
        bool in_header = false;
        for (auto n = er.between(2, 16); n > 0; --n) {
          const std::size_t at = position(b.size());
          in_header = in_header || at < hb;
          b.erase(b.begin() + static_cast<std::ptrdiff_t>(at));
        }
        e.variant = named(in_header ? "in the header" : "in payload or CRC");
        e.damaged = true;
        e.recovers_at_once = v3 || !in_header;
        send_damaged(b, w);
        break;
      }
      case Kind::kDuplicatedTransfer: {
        const WorldPtr w = lane.make(content, tb, index, Refusal::kNone, out);
        const std::size_t n = out.size();
        const bool first = er.percent(30), last = er.percent(30);
        const std::size_t i = first ? 0 : last ? n - 1 : static_cast<std::size_t>(er.below(n));
        Bytes copy = out[i];
        out.insert(out.begin() + static_cast<std::ptrdiff_t>(i) + 1, std::move(copy));
        // The frame survives, behind or ahead of the copy, when the copy is of its first or last transfer.
        e.damaged = true;
        e.delivered_anyway = i == 0 || i == n - 1;
        e.recovers_at_once = v3 || i > 0 || out[0].size() >= hb;
        e.variant = named(n == 1 ? "the whole frame (v2: a valid repeat; v3: a replay)"
                                 : i == 0 ? "the first" : i == n - 1 ? "the last" : "one in the middle");
        lane.feed(out, PieceKind::kDamaged, w);
        lane.vblank(false);
        break;
      }
      case Kind::kReorderedTransfers: {
        // Transfers small enough for at least two per frame; two of them change places.
        const auto largest = static_cast<std::int64_t>(link::frame_bytes(lane.wire(), content.spheres.size())) - 1;
        const bool small = er.percent(50);
        const auto r = er.next();
        const auto limit = static_cast<std::uint64_t>(small ? std::min<std::int64_t>(64, largest) : largest);
        const WorldPtr w = lane.make(content, static_cast<std::size_t>(1 + r % limit), index, Refusal::kNone, out);
        const std::size_t n = out.size();
        const auto i = static_cast<std::size_t>(er.below(n - 1));
        const std::size_t j = er.percent(50) ? i + 1 : i + 1 + static_cast<std::size_t>(er.below(n - 1 - i));
        std::swap(out[i], out[j]);
        e.damaged = true;
        e.delivered_anyway = concat(out) == w->frame;  // two transfers with the same bytes
        std::size_t header_bytes_in_place = 0;          // how much of the header still comes first
        for (std::size_t k = 0; k < n && header_bytes_in_place < hb; ++k) {
          if (k == i || k == j) break;
          header_bytes_in_place += out[k].size();
        }
        const bool in_place = e.delivered_anyway || header_bytes_in_place >= hb;
        e.recovers_at_once = in_place;
        e.variant = named(std::string(j == i + 1 ? "adjacent" : "apart") +
                          (in_place ? ", header in place" : ", header moved"));
        lane.feed(out, PieceKind::kDamaged, w);
        lane.vblank(false);
        break;
      }
      case Kind::kTruncatedFrame: {
        // The host stops sending the world and sends the next one: a cut header fails on the next frame's bytes,
        // a whole header announces more bytes than came.
        const WorldPtr w = lane.make(content, tb, index, Refusal::kNone, out);
        const bool in_header = er.percent(25);
        const std::uint64_t r = er.next();
        const std::size_t keep = 1 + static_cast<std::size_t>(in_header ? r % (hb - 1) : r % (w->frame.size() - 1));
        e.variant = named(keep < hb ? "inside the header" : "after the header");
        e.damaged = true;
        e.recovers_at_once = keep < hb;
        send_damaged(Bytes(w->frame.begin(), w->frame.begin() + static_cast<std::ptrdiff_t>(keep)), w);
        break;
      }
      case Kind::kHostStops: {
        const WorldPtr w = lane.make(content, tb, index, Refusal::kNone, out);
        e.damaged = true;
        Bytes sent;
        if (er.percent(85)) {
          const std::uint64_t r = er.next();
          sent.assign(w->frame.begin(), w->frame.begin() + 1 + static_cast<std::ptrdiff_t>(r % (w->frame.size() - 1)));
          e.variant = named(sent.size() < hb ? "inside the header" : "after the header");
        } else {
          // It sent noise and maybe the start of a frame, and went away.
          noise(lane, er, sent);
          if (er.percent(50)) sent.insert(sent.end(), w->frame.begin(), w->frame.begin() + er.between(1, 30));
          e.variant = named("after noise");
        }
        send_damaged(sent, w);
        lane.end_of_stream();
        lane.vblank(false);
        break;
      }
      case Kind::kGarbage: {
        const WorldPtr w = lane.make(content, tb, index, Refusal::kNone, out);
        lane.feed(out, PieceKind::kIntact, w);
        lane.vblank(false);
        Bytes g;
        e = noise(lane, er, g);
        e.noise = true;
        lane.feed(split(g, random_transfer_bytes(er)), PieceKind::kNoise, nullptr);
        lane.vblank(false);
        break;
      }
      case Kind::kReplay: {
        // An old intact frame sent again: the world on screen, or an older one of this session.
        const WorldPtr latest = lane.latest();
        std::vector<WorldPtr> older;
        for (const WorldPtr& p : lane.pool())
          if (p->host_session == lane.host_session() && p != latest) older.push_back(p);
        const bool old = er.percent(60);
        const std::uint64_t r = er.next();
        const WorldPtr w = old && !older.empty() ? older[r % older.size()] : latest;
        e.variant = named(w == latest ? "the world on screen" : "an older world of this session");
        lane.feed(split(w->frame, tb), PieceKind::kReplay, w);
        lane.vblank(true);
        break;
      }
      case Kind::kHostRestart: {
        const std::uint64_t v = er.below(100);
        std::vector<WorldPtr> ended;
        for (const WorldPtr& p : lane.pool())
          if (std::find(ended_.begin(), ended_.end(), p->host_session) != ended_.end()) ended.push_back(p);
        const std::uint64_t r = er.next();
        if (v >= 85 && !ended.empty()) {
          // A frame of a session that ended (one of the last 16), sent again.
          const WorldPtr w = ended[r % ended.size()];
          e.variant = named("a world of an ended session replayed");
          lane.feed(split(w->frame, tb), PieceKind::kReplay, w);
          lane.vblank(true);
          break;
        }
        e.restart = true;
        if (v < 25 || v >= 85) {
          e.variant = named("between frames");
        } else if (v < 70) {
          // The old host is cut off in the middle of a world; the device may or may not be told.
          const bool told = v < 50;
          const WorldPtr w = lane.make(content, tb, index, Refusal::kNone, out);
          const std::size_t keep = 1 + static_cast<std::size_t>(r % (w->frame.size() - 1));
          e.damaged = true;
          e.recovers_at_once = told || keep < hb;
          e.variant = named(std::string("cutting a frame ") + (keep < hb ? "in its header" : "after its header") +
                            (told ? ", end_of_stream" : ", device not told"));
          send_damaged(Bytes(w->frame.begin(), w->frame.begin() + static_cast<std::ptrdiff_t>(keep)), w);
          if (told) {
            lane.end_of_stream();
            lane.vblank(false);
          }
        }
        lane.restart(next_session);
        if (v >= 70 && v < 85) {
          // The new host's first world is damaged (a flipped payload bit): it is missing once world 2 arrives.
          const WorldPtr w = lane.make(content, tb, index + 1, Refusal::kNone, out);
          Bytes b = w->frame;
          const std::size_t bit = (hb + static_cast<std::size_t>(r % (b.size() - hb))) * 8 + er.below(8);
          b[bit / 8] ^= static_cast<std::uint8_t>(0x80 >> (bit % 8));
          e.damaged = true;
          e.variant = named("the new host's first world damaged");
          send_damaged(b, w);
        }
        break;
      }
      case Kind::kRefusedWorld: {
        const auto refusal = static_cast<Refusal>(1 + er.below(3));
        const WorldPtr w = lane.make(content, tb, index, refusal, out);
        e.variant = named(refusal == Refusal::kOutOfFormat ? "a coordinate outside the device's format"
                          : refusal == Refusal::kRadiusZero ? "radius 0 (a bad sphere)"
                                                            : "other fractional bits");
        lane.feed(out, PieceKind::kIntact, w);
        lane.vblank(false);
        break;
      }
    }
    return e;
  }

  // Noise between frames: random bytes, an idle line, a partial magic, or something that looks like a frame.
  LaneEvent noise(const Lane& lane, Rng& er, Bytes& g) {
    LaneEvent e;
    const bool v3 = lane.wire() == WireVersion::kV3;
    const auto random_bytes = [&](std::size_t n) {
      for (std::size_t i = 0; i < n; ++i) g.push_back(er.byte());
    };
    // A header with these fields. The same numbers are drawn on both wires; v3 gets the header CRC right only
    // when asked (noise has none).
    const auto header = [&](std::uint32_t count, std::uint32_t length, int bad_version, bool reserved, bool crc_right) {
      const auto session = static_cast<std::uint32_t>(er.next());
      const auto sequence = static_cast<std::uint32_t>(er.below(1u << 31));
      const auto crc_noise = static_cast<std::uint32_t>(er.next());
      Bytes h(lane.magic().begin(), lane.magic().end());
      h.push_back(bad_version ? static_cast<std::uint8_t>(bad_version) : lane.version());
      h.push_back(static_cast<std::uint8_t>(lane.preset().frac_bits()));
      h.push_back(0);
      h.push_back(reserved ? 1 : 0);
      if (v3) put_be32(h, session);
      put_be32(h, sequence);
      put_be32(h, count);
      put_be32(h, length);
      if (v3) put_be32(h, crc_right ? core::crc32(h) : crc_noise);
      g.insert(g.end(), h.begin(), h.end());
    };
    const auto named = [&](const std::string& detail) { return std::string("garbage / ") + detail; };
    switch (er.below(6)) {
      case 0:
        random_bytes(static_cast<std::size_t>(er.between(1, 300)));
        e.variant = named("random bytes");
        break;
      case 1:
        g.assign(static_cast<std::size_t>(er.between(1, 300)), er.percent(50) ? 0x00 : 0xFF);
        e.variant = named("idle line (00 or FF)");
        break;
      case 2:
        random_bytes(static_cast<std::size_t>(er.between(0, 100)));
        g.insert(g.end(), lane.magic().begin(), lane.magic().begin() + static_cast<std::ptrdiff_t>(er.between(1, 3)));
        e.variant = named("ending in part of a magic");
        break;
      case 3: {
        // Noise that holds a plausible header, then too few or wrong bytes. v2 takes what follows as its payload
        // until it can check the CRC; v3 checks the header's CRC first.
        random_bytes(static_cast<std::size_t>(er.between(0, 50)));
        const bool big = lane.preset().max_spheres > 64 && er.percent(30);
        const std::uint32_t max = lane.preset().max_spheres;
        const auto count =
            static_cast<std::uint32_t>(big ? er.between(65, max) : er.between(0, std::min<std::uint32_t>(64, max)));
        header(count, count * 24, 0, false, false);
        random_bytes(static_cast<std::size_t>(er.between(0, 200)));
        e.recovers_at_once = v3;
        e.variant = named(big ? "plausible header, 65 to max_spheres spheres" : "plausible header, up to 64 spheres");
        break;
      }
      case 4: {
        // A header that fails a check (on v3 under a right header CRC, so that the check itself is reached).
        random_bytes(static_cast<std::size_t>(er.between(0, 50)));
        const auto count = static_cast<std::uint32_t>(er.between(0, 64));
        switch (er.below(4)) {
          case 0: header(count, count * 24 + 1, 0, false, true); break;  // bad length
          case 1:  // too many spheres
            header(lane.preset().max_spheres + 1 + static_cast<std::uint32_t>(er.below(1000)), 0, 0, false, true);
            break;
          case 2: header(count, count * 24, 9, false, true); break;      // bad version
          default: header(count, count * 24, 0, true, true); break;      // reserved byte
        }
        random_bytes(static_cast<std::size_t>(er.between(0, 100)));
        e.variant = named("header that fails its checks");
        break;
      }
      default:
        random_bytes(static_cast<std::size_t>(er.between(0, 50)));
        g.insert(g.end(), lane.magic().begin(), lane.magic().end());
        random_bytes(static_cast<std::size_t>(er.between(0, 40)));
        e.variant = named("magic then random bytes");
        break;
    }
    return e;
  }

  device::DevicePreset preset_;
  Kind kind_;
  Rng rng_;
  WorldSource source_;
  std::uint32_t session_ = 0;          // the current host's session
  std::deque<std::uint32_t> ended_;    // the last 16 sessions that ended
  std::vector<std::unique_ptr<Lane>> lanes_;  // v3, v2
  std::uint64_t index_ = 0;
  std::uint64_t next_render_ = kRenderEvery;
  bool first_episode_ = false;
};

// ---- the table ----

struct Row {
  std::uint64_t worlds = 0;  // per wire
  std::array<Tally, 2> wire; // v3, v2
};

std::map<Kind, Row>& table() {
  static std::map<Kind, Row> rows;
  return rows;
}

std::string lost_cell(const Tally& t) { return std::to_string(t.lost_max) + ", " + fixed2(t.lost_mean()); }
std::string recovery_cell(const Tally& t) { return std::to_string(t.recovery_max()) + ", " + fixed2(t.recovery_mean()); }
std::string wrong_cell(const Tally& t) {
  return grouped(t.wrong) + (t.late ? " (" + grouped(t.late) + " late)" : "");
}
std::string missing_cell(const Tally& t) {
  std::string s = t.inexact == 0 ? "yes, " + grouped(t.missing)
                                 : "no, in " + grouped(t.inexact) + " events: " + grouped(t.missing) + " counted, " +
                                       grouped(t.link_lost) + " lost";
  if (t.uncountable) s += " (+" + grouped(t.uncountable) + " uncountable)";
  return s;
}

void print_table(std::ostream& os, const std::map<Kind, Row>& rows) {
  std::uint64_t worlds = 0;
  for (const auto& [kind, row] : rows) worlds += row.worlds;
  os << "[soak] " << grouped(worlds) << " worlds per wire. lost: worlds sent from the fault on that never reached the "
        "screen (max, mean per fault); recovery: intact worlds after the one the fault hit until the latest is shown "
        "(max, mean); wrong: worlds shown that were not the newest sent, or were a replay (late: intact, in order, a "
        "blanking late); missing = lost: whether worlds_missing equalled the worlds the link lost in every event, and "
        "the totals (uncountable: lost as the last world of a session)\n";
  os << "| fault | events | v3 lost | v3 recovery | v3 wrong | v3 missing = lost | v2 lost | v2 recovery | v2 wrong | "
        "v2 missing = lost |\n";
  os << "| --- | ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | --- |\n";
  for (const auto& [kind, row] : rows) {
    const Tally& a = row.wire[0];
    const Tally& b = row.wire[1];
    os << "| " << name_of(kind) << " | " << grouped(a.events) << " | " << lost_cell(a) << " | " << recovery_cell(a)
       << " | " << wrong_cell(a) << " | " << missing_cell(a) << " | " << lost_cell(b) << " | " << recovery_cell(b)
       << " | " << wrong_cell(b) << " | " << missing_cell(b) << " |\n";
  }
}

// The whole table once, when the binary ran more than one kind (ctest runs each test on its own).
class TableEnvironment : public ::testing::Environment {
 public:
  void TearDown() override {
    if (table().size() > 1) print_table(std::cout, table());
  }
};
[[maybe_unused]] ::testing::Environment* const kTableEnvironment =
    ::testing::AddGlobalTestEnvironment(new TableEnvironment);

void soak(Kind kind) {
  ASSERT_TRUE(soak_size().error.empty()) << soak_size().error;
  const std::uint64_t per_run = soak_size().per_run;
  std::uint64_t seed = 1 + static_cast<std::uint64_t>(kind) * 2;
  Row row;
  for (const device::DevicePreset& preset : {device::wide_preset(), device::board_2023_preset()}) {
    Soak s(preset, kind, seed++);
    s.run(per_run);
    s.report(std::cout);
    EXPECT_GE(s.worlds(), per_run);
    EXPECT_EQ(s.lane(0).worlds_sent(), s.lane(1).worlds_sent()) << "the wires went out of step";
    row.worlds += s.worlds();
    for (std::size_t i = 0; i < 2; ++i) row.wire[i].merge(s.lane(i).total());
  }
  // v3's promises, over the whole kind (each event is checked as it ends, too).
  const Tally& v3 = row.wire[0];
  EXPECT_EQ(v3.wrong, 0u) << "v3 showed a wrong world";
  EXPECT_EQ(v3.missing, v3.link_lost) << "v3: every world the link lost is counted as missing";
  if (single_byte(kind)) {
    EXPECT_LE(v3.lost_max, 1) << "v3: a single-byte fault costs at most the world it hit";
    EXPECT_EQ(v3.recovery_max(), 1) << "v3: after a single-byte fault the next intact world is shown";
  }
  if (kind == Kind::kReplay) {
    EXPECT_EQ(v3.replayed, v3.events) << "v3: every replay is counted";
  }
  // v2: the same, except what replays and restarts do to it.
  const Tally& v2 = row.wire[1];
  if (kind != Kind::kReplay && kind != Kind::kHostRestart) {
    EXPECT_EQ(v2.wrong, 0u) << "v2 showed a wrong world without a replay";
    EXPECT_EQ(v2.missing, v2.link_lost) << "v2: every world the link lost is counted as missing";
  }
  std::map<Kind, Row> one{{kind, row}};
  print_table(std::cout, one);
  table()[kind] = row;
}

TEST(Soak, BitFlip) { soak(Kind::kBitFlip); }
TEST(Soak, ByteDropped) { soak(Kind::kByteDropped); }
TEST(Soak, ByteInserted) { soak(Kind::kByteInserted); }
TEST(Soak, ByteDuplicated) { soak(Kind::kByteDuplicated); }
TEST(Soak, BitFlipBursts) { soak(Kind::kBitFlipBurst); }
TEST(Soak, DroppedByteBursts) { soak(Kind::kBytesDroppedBurst); }
TEST(Soak, DuplicatedTransfers) { soak(Kind::kDuplicatedTransfer); }
TEST(Soak, ReorderedTransfers) { soak(Kind::kReorderedTransfers); }
TEST(Soak, TruncatedFrames) { soak(Kind::kTruncatedFrame); }
TEST(Soak, HostStopsMidFrame) { soak(Kind::kHostStops); }
TEST(Soak, GarbageBetweenFrames) { soak(Kind::kGarbage); }
TEST(Soak, ReplayedWorlds) { soak(Kind::kReplay); }
TEST(Soak, HostRestarts) { soak(Kind::kHostRestart); }
TEST(Soak, RefusedWorlds) { soak(Kind::kRefusedWorld); }

// v1 has no framing and no check: every 8 bytes are a sphere, so a flipped bit is a different sphere and a
// lost byte shifts every later word until the stream ends. What it can promise is what end_of_stream gives:
// a host that stops mid-word costs that partial word (one rejection, its bytes), and the next word is shown.
TEST(Soak, V1HostStopsMidWord) {
  const device::DevicePreset preset = device::board_2023_preset();
  host::Host h(scene::random_spheres(1, 5), formats_of(preset), WireVersion::kV1);
  device::Receiver rx(preset, WireVersion::kV1);
  device::SceneMemory front;
  Rng rng(99);
  std::uint64_t stops = 0, bytes_lost = 0;
  for (int i = 0; i < 2000; ++i) {
    h.camera().orbit(rng.uniform(-20, 20));
    const Bytes word = h.update().bytes;
    ASSERT_EQ(word.size(), link::kV1WordBytes);
    if (rng.percent(30)) {
      const auto cut = static_cast<std::size_t>(rng.between(1, 7));
      rx.receive(std::span(word).first(cut));
      rx.end_of_stream();
      ++stops;
      bytes_lost += cut;
      ASSERT_EQ(rx.stats().frames_rejected, stops);
      ASSERT_EQ(rx.stats().bytes_dropped, bytes_lost);
      ASSERT_FALSE(rx.swap_if_pending(front)) << "a partial word was shown";
      continue;
    }
    rx.receive(word);
    ASSERT_TRUE(rx.swap_if_pending(front));
    ASSERT_EQ(front.geometry.size(), 1u);
    const link::V1Sphere s = link::decode_v1_word(read_be32(word, 0) * (std::uint64_t{1} << 32) + read_be32(word, 4));
    const int f = preset.frac_bits();
    EXPECT_EQ(front.geometry[0].center.x, core::rescale_raw(s.x_raw, 3, f));
    EXPECT_EQ(front.geometry[0].center.z, core::rescale_raw(s.z_raw, 3, f));
  }
  std::cout << "[soak] v1, host stops mid-word: " << stops << " stops, " << bytes_lost
            << " bytes dropped, recovery 1 word each\n";
}

}  // namespace
}  // namespace tripsitter::board

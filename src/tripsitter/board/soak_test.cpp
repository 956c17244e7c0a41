// Soak test of the link under damage: host -> SPI link -> damage -> device, over more than 100,000 worlds.
//
// Seven kinds of damage, each in its own test and each on the wide and the board-2023 preset (v2 wire):
// random bit flips, dropped bytes, a duplicated transfer, reordered transfers, a truncated frame, garbage
// between frames, and a host that stops in the middle of a frame (the device's end_of_stream). A small
// v1 test at the end covers what the v1 wire can promise.
//
// How a run goes. Worlds come from a host::Host (random_spheres, 1 to 64 of them, with random camera
// moves) or are synthesised directly as link::World (1 to 64 spheres anywhere in the preset's formats,
// extremes included), numbered 1, 2, 3, ... in the order they are sent, as a host numbers its worlds; every
// sent world is kept, keyed by its sequence. Each world goes through a real SpiLink (a random transfer size per world, 1 byte to 4 KiB),
// whose transfers are then damaged or not on their way to the device. The bulk of the worlds goes to a
// device::Receiver, with swap_if_pending as vertical blanking after each world; a device::Device fed the
// very same bytes draws a real frame every 1000th world, which is compared with the world that should be
// on screen (its scene memory exactly, its frame statistics, and its pixels against a fresh Device that
// was given only that world).
//
// A run begins with one intact world, and goes on as a chain of episodes: 0 to 2 intact worlds, one damage
// event, then intact worlds until the device shows the latest of them. The number of intact worlds this
// takes is the event's *recovery*.
//
// What is checked:
//   1. Nothing crashes, and every world swapped into scene memory equals exactly one sent world: sequence,
//      geometry and surfaces (checked at every vertical blanking, and on the real Device at each sample).
//   2. Every damaged world is counted, exactly. The rule (docs/link_format.md, "How the receiver finds its
//      way through damage") is executed by a small model below on the episode's bytes: a frame is
//      delivered where the decoder expects a frame and the bytes there form a frame with a good CRC; a
//      header that fails checks 2 to 5, or a frame whose CRC fails, costs one rejection and 1 byte, and the
//      hunt resumes at the next byte; bytes skipped while hunting for the magic are one garbage run,
//      reported when the next magic is found; at end_of_stream an incomplete frame is one rejection
//      (truncated) with all its bytes, a hunt in progress one garbage run. The receiver's frames_rejected,
//      garbage_runs, bytes_dropped, worlds_accepted and worlds_replaced must move by exactly what the model
//      says, and every byte fed is either in an accepted world or in bytes_dropped.
//      Which damage leaves a frame valid: a duplicated transfer that holds a whole frame is a valid repeat
//      (the world is accepted twice); a duplicated *first* or *last* transfer of a longer frame leaves the
//      frame intact behind or ahead of a copy, so the world is still delivered and only the copy is dropped;
//      a reorder of two transfers with the same bytes changes nothing. Any other damaged world is lost: its
//      bytes are all dropped and the receiver makes at least one report for it, a rejected frame whenever
//      its magic arrived first (a frame whose magic is damaged or cut is noise to the receiver, counted as
//      a garbage run). Intact worlds are never lost: one that a bogus header swallowed as payload is
//      delivered once that header's CRC has failed (if several arrive before a blanking, the newest is
//      shown and the others count as replaced).
//      And the worlds: the receiver's worlds_missing (sequence numbers skipped between accepted worlds,
//      docs/link_format.md "What the receiver counts") moves by exactly the number of damaged worlds lost,
//      in every episode: 1 for a damaged world that did not arrive, 0 for one delivered anyway and for noise.
//      This is exact here because the harness sends every world it numbers, one at a time, and every
//      episode ends with an accepted world, whose sequence number reveals the gap; the world that starts the
//      run gives the receiver its first sequence number. (A device can count a lost world only once a later
//      world arrives: the last world before a host goes for good is in frames_rejected alone.)
//   3. The device recovers, and the test says how fast (std::cout): after each event, how many intact
//      worlds until the latest one is on screen; the model predicts each figure exactly and the test
//      asserts that it does. Recovery is 1 (the very next intact world is shown) whenever the world's own
//      header reaches the device unchanged and in place, and after end_of_stream. A header that passes its
//      checks but announces more bytes than the damaged world brought (a truncated frame; bytes dropped or a
//      transfer moved inside the header; noise that happens to hold a plausible header) makes the decoder
//      take the following worlds' bytes as that frame's payload until it can check the CRC, so recovery then
//      takes as many intact worlds as cover the announced frame, and never more than cover the largest
//      frame the preset can announce (24 + 24 x max_spheres bytes). Both bounds are asserted.
//
// Timing is never asserted. Seeded std::mt19937_64 with the test's own arithmetic, so runs are reproducible
// on any standard library.
#include <algorithm>
#include <cstdint>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/board/board.h>
#include <tripsitter/core/crc32.h>
#include <tripsitter/device/device.h>
#include <tripsitter/device/receiver.h>
#include <tripsitter/device/test_util.h>
#include <tripsitter/host/host.h>
#include <tripsitter/link/spi.h>
#include <tripsitter/link/wire_v1.h>
#include <tripsitter/link/wire_v2.h>
#include <tripsitter/scene/builtin.h>

namespace tripsitter::board {
namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr int kWorldsPerRun = 7200;          // 7 damage kinds x 2 presets x 7200 = 100,800 worlds
constexpr int kRenderEvery = 1000;           // a real frame through the Device every this many worlds
constexpr int kMaxSpheresPerWorld = 64;      // the board-2023 scene memory
constexpr int kRecoveryGiveUp = 5000;        // intact worlds after which a run counts as never recovering

// ---- random numbers, the same on every standard library ----

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : g_(seed) {}
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

// ---- worlds ----

struct SentWorld {
  Bytes frame;
  link::World world;
};

std::uint32_t read_be32(std::span<const std::uint8_t> b, std::size_t at) {
  return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) | (std::uint32_t{b[at + 2]} << 8) |
         std::uint32_t{b[at + 3]};
}

std::size_t frame_bytes_for(std::size_t spheres) {
  return link::kV2HeaderBytes + spheres * link::kV2SphereBytes + link::kV2TrailerBytes;
}

// Worlds as a host sends them, numbered 1, 2, 3, ... whichever way they were made (the host's own frames
// are renumbered: its numbers count its updates, and half of the worlds do not come from it).
class WorldSource {
 public:
  WorldSource(const device::DevicePreset& preset, int host_spheres, std::uint64_t seed)
      : preset_(preset),
        rng_(seed),
        host_(scene::random_spheres(host_spheres, static_cast<std::uint32_t>(seed)), formats_of(preset),
              link::WireVersion::kV2) {}

  SentWorld next() { return rng_.percent(50) ? from_host() : synthesised(); }

 private:
  SentWorld from_host() {
    host::Camera& c = host_.camera();
    switch (rng_.below(6)) {
      case 0: c.move(rng_.uniform(-2, 2)); break;
      case 1: c.strafe(rng_.uniform(-2, 2)); break;
      case 2: c.look(rng_.uniform(-10, 10), rng_.uniform(-5, 5)); break;
      case 3: c.orbit(rng_.uniform(-30, 30)); break;
      case 4: if (rng_.percent(10)) host_.reset(); break;
      default: break;  // the camera holds still: the same view again, under a new sequence number
    }
    SentWorld w;
    auto decoded = link::decode_v2_frame(host_.update().bytes, preset_.max_spheres);
    EXPECT_TRUE(decoded.ok()) << "the host made a frame its own device rejects";
    if (decoded.ok()) w.world = std::move(decoded).value();
    w.world.sequence = next_sequence_++;
    w.frame = link::encode_v2_frame(w.world);
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

  SentWorld synthesised() {
    link::World w;
    w.sequence = next_sequence_++;
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
    SentWorld sent;
    sent.frame = link::encode_v2_frame(w);
    sent.world = std::move(w);
    return sent;
  }

  device::DevicePreset preset_;
  Rng rng_;
  host::Host host_;
  std::uint32_t next_sequence_ = 1;
};

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

// ---- the rule, as a model of the documented decoder ----

// Checks 1 to 5 of docs/link_format.md ("Checks and errors") on the bytes present at a frame start.
enum class Header { kNeedMore, kBadMagic, kFails, kPasses };

Header check_header(std::span<const std::uint8_t> b, std::uint32_t max_spheres, std::size_t& frame_bytes) {
  const std::size_t n = b.size();
  for (std::size_t i = 0; i < std::min<std::size_t>(n, 4); ++i)
    if (b[i] != link::kV2Magic[i]) return Header::kBadMagic;
  if (n < 5) return Header::kNeedMore;
  if (b[4] != link::kV2Version) return Header::kFails;
  if (n < 6) return Header::kNeedMore;
  if (b[5] > link::kV2MaxFracBits) return Header::kFails;
  for (std::size_t at = 6; at < 8; ++at) {
    if (n <= at) return Header::kNeedMore;
    if (b[at] != 0) return Header::kFails;
  }
  if (n < 16) return Header::kNeedMore;
  const std::uint32_t count = read_be32(b, 12);
  if (count > max_spheres) return Header::kFails;
  if (n < 20) return Header::kNeedMore;
  const std::uint32_t length = read_be32(b, 16);
  if (std::uint64_t{length} != std::uint64_t{count} * link::kV2SphereBytes) return Header::kFails;
  frame_bytes = link::kV2HeaderBytes + length + link::kV2TrailerBytes;
  return Header::kPasses;
}

struct ModelFrame {
  std::size_t at = 0, bytes = 0;
  std::size_t ready_at = 0;  // stream position by which the decoder has delivered it
  std::uint32_t sequence = 0;
};

struct ModelOutcome {
  std::vector<ModelFrame> frames;
  std::uint64_t rejected = 0, garbage_runs = 0, bytes_dropped = 0;
  std::size_t forged = 0;  // frames with a good CRC that no one sent (would be a CRC failure, not a decoder one)
  bool pending = false;    // bytes still undecided at the end (never, when an episode ends in a shown world)
  // Every header that passed checks 1 to 5 and whose frame was then decided (delivered, or its CRC failed):
  // where it stood and where its frame ended.
  std::vector<std::pair<std::size_t, std::size_t>> headers;
};

// `stream` is everything fed in an episode; end_of_stream came at each position in `eos` (sorted).
ModelOutcome model_decoder(std::span<const std::uint8_t> stream, const std::vector<std::size_t>& eos,
                           std::uint32_t max_spheres,
                           const std::unordered_map<std::uint32_t, SentWorld>& sent) {
  ModelOutcome out;
  std::vector<std::size_t> ends = eos;
  if (ends.empty() || ends.back() != stream.size()) ends.push_back(stream.size());
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
        while (m + 4 <= end && !std::equal(link::kV2Magic.begin(), link::kV2Magic.end(), stream.begin() + static_cast<std::ptrdiff_t>(m)))
          ++m;
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
      const Header h = check_header(stream.subspan(pos, std::min<std::size_t>(20, end - pos)), max_spheres, frame_bytes);
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
      if (h == Header::kNeedMore || pos + frame_bytes > end) {  // an incomplete frame
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
        const std::uint32_t sequence = read_be32(frame, 8);
        const auto it = sent.find(sequence);
        if (it == sent.end() || !std::equal(frame.begin(), frame.end(), it->second.frame.begin(), it->second.frame.end()))
          ++out.forged;
        out.frames.push_back({pos, frame_bytes, std::max(pos + frame_bytes, blocker), sequence});
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

// ---- damage ----

enum class Damage { kBitFlips, kDroppedBytes, kDuplicatedTransfer, kReorderedTransfers, kTruncatedFrame, kGarbage, kHostStops };

const char* name_of(Damage d) {
  switch (d) {
    case Damage::kBitFlips: return "bit flips";
    case Damage::kDroppedBytes: return "dropped bytes";
    case Damage::kDuplicatedTransfer: return "duplicated transfer";
    case Damage::kReorderedTransfers: return "reordered transfers";
    case Damage::kTruncatedFrame: return "truncated frame";
    case Damage::kGarbage: return "garbage between frames";
    case Damage::kHostStops: return "host stops mid-frame";
  }
  return "?";
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

// What one damage event did, for the tallies and the bounds.
struct Event {
  std::string variant;  // a finer name, e.g. "truncated frame / inside the header"
  // Recovery must take exactly 1 intact world: the damaged world's first 20 bytes reached the device
  // unchanged and first (so its header announces its true size), or no header that could pass came at all.
  bool recovers_at_once = true;
};

// ---- figures ----

struct Tally {
  std::uint64_t events = 0, lost = 0, delivered_anyway = 0;
  std::uint64_t missing = 0;  // what the receiver's worlds_missing counted
  std::map<int, std::uint64_t> recovery;  // intact worlds needed -> events
  void add(int k) { ++recovery[k]; }
  int max() const { return recovery.empty() ? 0 : recovery.rbegin()->first; }
  double mean() const {
    std::uint64_t n = 0, sum = 0;
    for (const auto& [k, c] : recovery) n += c, sum += c * static_cast<std::uint64_t>(k);
    return n ? static_cast<double>(sum) / static_cast<double>(n) : 0;
  }
  std::string histogram() const {
    std::ostringstream s;
    std::uint64_t over = 0;
    int shown = 0;
    for (const auto& [k, c] : recovery) {
      if (shown++ < 6) s << (shown > 1 ? ", " : "") << k << ": " << c;
      else over += c;
    }
    if (over) s << ", more: " << over;
    return s.str();
  }
};

// ---- one run ----

class Soak {
 public:
  Soak(device::DevicePreset preset, Damage damage, std::uint64_t seed)
      : preset_(std::move(preset)),
        damage_(damage),
        rng_(seed * 7919 + 17),
        source_(preset_, 1 + static_cast<int>((seed * 37) % kMaxSpheresPerWorld), seed),
        rx_(preset_, link::WireVersion::kV2),
        shadow_(preset_, link::WireVersion::kV2) {}

  void run(int worlds) {
    if (worlds_ == 0) start();
    while (worlds_ < worlds && !::testing::Test::HasFatalFailure() && failures_ < 20) episode();
  }

  void report(std::ostream& os) const {
    os << "[soak] " << name_of(damage_) << ", preset " << preset_.name << ": " << worlds_ << " worlds, "
       << renders_ << " frames drawn and compared, receiver " << rx_.stats().worlds_accepted << " accepted, "
       << rx_.stats().frames_rejected << " rejected, " << rx_.stats().garbage_runs << " garbage runs, "
       << rx_.stats().bytes_dropped << " of " << bytes_fed_ << " bytes dropped; " << lost() << " worlds lost, "
       << rx_.stats().worlds_missing << " counted missing\n";
    for (const auto& [variant, t] : tallies_) {
      os << "[soak]   " << std::left << std::setw(52) << variant << std::right << std::setw(6) << t.events
         << " events, " << std::setw(5) << t.lost << " worlds lost (" << std::setw(5) << t.missing << " counted), "
         << std::setw(5) << t.delivered_anyway
         << " delivered anyway; recovery max " << t.max() << ", mean " << std::fixed << std::setprecision(2)
         << t.mean() << std::defaultfloat << " (" << t.histogram() << ")\n";
    }
  }

  int worlds() const { return worlds_; }
  std::uint64_t lost() const {
    std::uint64_t n = 0;
    for (const auto& [variant, t] : tallies_) n += t.lost;
    return n;
  }
  std::uint64_t missing() const { return rx_.stats().worlds_missing; }

 private:
  // -- the wire --

  SentWorld next_world() {
    SentWorld w = source_.next();
    ++worlds_;
    const std::uint32_t seq = w.world.sequence;
    EXPECT_EQ(sent_.count(seq), 0u) << "sequence " << seq << " sent twice";
    sent_[seq] = w;
    return w;
  }

  std::size_t random_transfer_bytes() {
    switch (rng_.below(10)) {
      case 0: return static_cast<std::size_t>(rng_.between(1, 8));
      case 1: return static_cast<std::size_t>(rng_.between(9, 64));
      case 2: case 3: return static_cast<std::size_t>(rng_.between(65, 1023));
      case 4: return 4096;
      default: return 1024;  // the default SPI driver
    }
  }

  std::vector<Bytes> transfers_of(const SentWorld& w, std::size_t transfer_bytes) {
    link::SpiLink spi({.max_transfer_bytes = transfer_bytes});
    TransferRecorder rec(rx_);
    spi.submit(w.frame);
    EXPECT_TRUE(spi.pump(rec)) << "the ready line was low after vertical blanking";
    EXPECT_EQ(concat(rec.transfers), w.frame);
    return std::move(rec.transfers);
  }

  void feed(const std::vector<Bytes>& transfers) {
    for (const Bytes& t : transfers) {
      rx_.receive(t);
      shadow_.transfer(t);
      episode_bytes_.insert(episode_bytes_.end(), t.begin(), t.end());
      bytes_fed_ += t.size();
    }
  }

  // Vertical blanking: the receiver's waiting world (if any) becomes scene memory; a sample of them is drawn.
  void vblank() {
    if (rx_.swap_if_pending(front_)) {
      const auto it = sent_.find(front_.sequence);
      if (it == sent_.end()) {
        ADD_FAILURE() << "the device shows world " << front_.sequence << ", which was never sent";
        ++failures_;
      } else if (const auto r = holds(front_, it->second.world); !r) {
        ADD_FAILURE() << "the device shows a world that differs from the one sent: " << r.message();
        ++failures_;
      }
    }
    steps_.push_back({episode_bytes_.size(), front_.valid ? std::optional(front_.sequence) : std::nullopt});
    if (worlds_ >= next_render_) {
      next_render_ += kRenderEvery;
      draw_and_compare();
    }
  }

  void end_of_stream() {
    rx_.end_of_stream();
    shadow_.end_of_stream();
    eos_.push_back(episode_bytes_.size());
  }

  // The real device, fed the same bytes, draws the world the receiver above has on screen, and draws it
  // exactly as a device that was only ever given that world.
  void draw_and_compare() {
    ++renders_;
    device::FrameStats stats;
    const std::vector<core::Rgb444> pixels = device::testing::visible_pixels(shadow_, &stats);
    ASSERT_EQ(stats.has_world, front_.valid);
    if (!front_.valid) return;
    ASSERT_EQ(stats.sequence, front_.sequence);
    const SentWorld& w = sent_.at(front_.sequence);
    ASSERT_TRUE(holds(shadow_.scene(), w.world)) << "the drawing device";
    device::Device clean(preset_, link::WireVersion::kV2);
    clean.transfer(w.frame);
    device::FrameStats clean_stats;
    const std::vector<core::Rgb444> expected = device::testing::visible_pixels(clean, &clean_stats);
    ASSERT_EQ(clean_stats.sequence, w.world.sequence);
    EXPECT_EQ(stats.late_pixels, clean_stats.late_pixels);
    EXPECT_TRUE(pixels == expected) << "world " << w.world.sequence << " is drawn differently after the soak";
  }

  void send_intact(const SentWorld& w) { feed(transfers_of(w, random_transfer_bytes())); }

  // -- damage --

  Event damage_world(const SentWorld& w, std::vector<Bytes>& out, bool& delivered_anyway) {
    Event e;
    delivered_anyway = false;
    const Bytes& f = w.frame;
    // A position in the frame, the header (first 20 bytes) chosen more often than its share.
    const auto position = [&](std::size_t size) {
      return rng_.percent(30) ? static_cast<std::size_t>(rng_.below(std::min<std::size_t>(20, size)))
                              : static_cast<std::size_t>(rng_.below(size));
    };
    switch (damage_) {
      case Damage::kBitFlips: {
        // 1 to 3 bits: CRC-32 has a Hamming distance of at least 4 for frames up to 91,607 bits, so no
        // such flip can pass unseen; the header checks may see it first.
        Bytes b = f;
        const auto flips = static_cast<std::size_t>(rng_.between(1, 3));
        std::vector<std::size_t> bits;
        while (bits.size() < flips) {
          const std::size_t bit = position(b.size()) * 8 + rng_.below(8);
          if (std::find(bits.begin(), bits.end(), bit) == bits.end()) bits.push_back(bit);
        }
        for (const std::size_t bit : bits) {
          b[bit / 8] ^= static_cast<std::uint8_t>(0x80 >> (bit % 8));
          if (bit / 8 < 20) e.recovers_at_once = false;
        }
        const bool magic = std::any_of(bits.begin(), bits.end(), [](std::size_t bit) { return bit / 8 < 4; });
        e.variant = std::string("bit flips / ") + (magic ? "in the magic" : !e.recovers_at_once ? "in the header" : "in payload or CRC");
        out = split(b, random_transfer_bytes());
        break;
      }
      case Damage::kDroppedBytes: {
        Bytes b = f;
        const auto n = static_cast<std::size_t>(rng_.between(1, 16));
        for (std::size_t i = 0; i < n; ++i) {
          const std::size_t at = position(b.size());
          if (at < 20) e.recovers_at_once = false;
          b.erase(b.begin() + static_cast<std::ptrdiff_t>(at));
        }
        e.variant = std::string("dropped bytes / ") + (e.recovers_at_once ? "in payload or CRC" : "in the header");
        out = split(b, random_transfer_bytes());
        break;
      }
      case Damage::kDuplicatedTransfer: {
        out = transfers_of(w, random_transfer_bytes());
        const std::size_t n = out.size();
        const std::size_t i = rng_.percent(30) ? 0 : rng_.percent(30) ? n - 1 : static_cast<std::size_t>(rng_.below(n));
        Bytes copy = out[i];
        out.insert(out.begin() + static_cast<std::ptrdiff_t>(i) + 1, std::move(copy));
        // The frame survives, behind or ahead of the copy, when the copy is of its first or last transfer.
        delivered_anyway = i == 0 || i == n - 1;
        e.recovers_at_once = i > 0 || out[0].size() >= 20;
        e.variant = n == 1 ? "duplicated transfer / the whole frame (a valid repeat)"
                           : i == 0 ? "duplicated transfer / the first" : i == n - 1 ? "duplicated transfer / the last"
                                                                         : "duplicated transfer / one in the middle";
        break;
      }
      case Damage::kReorderedTransfers: {
        // Transfers small enough for at least two per frame; two of them change places.
        const std::size_t size = f.size();
        const auto largest = static_cast<std::int64_t>(size) - 1;
        const auto tb = static_cast<std::size_t>(rng_.between(1, rng_.percent(50) ? std::min<std::int64_t>(64, largest) : largest));
        out = transfers_of(w, tb);
        const std::size_t n = out.size();
        const std::size_t i = static_cast<std::size_t>(rng_.below(n - 1));
        const std::size_t j = rng_.percent(50) ? i + 1 : i + 1 + static_cast<std::size_t>(rng_.below(n - 1 - i));
        std::swap(out[i], out[j]);
        delivered_anyway = concat(out) == f;  // two transfers with the same bytes
        std::size_t header_bytes_in_place = 0;  // how much of the frame's first 20 bytes still comes first
        for (std::size_t k = 0; k < n && header_bytes_in_place < 20; ++k) {
          if (k == i || k == j) break;
          header_bytes_in_place += out[k].size();
        }
        e.recovers_at_once = delivered_anyway || header_bytes_in_place >= 20;
        e.variant = std::string("reordered transfers / ") + (j == i + 1 ? "adjacent" : "apart") +
                    (e.recovers_at_once ? ", header in place" : ", header moved");
        break;
      }
      case Damage::kTruncatedFrame: {
        const std::size_t keep = rng_.percent(25) ? static_cast<std::size_t>(rng_.between(1, 19))
                                                  : static_cast<std::size_t>(rng_.between(1, static_cast<std::int64_t>(f.size()) - 1));
        out = split(Bytes(f.begin(), f.begin() + static_cast<std::ptrdiff_t>(keep)), random_transfer_bytes());
        // A cut header fails on the next frame's bytes (its count or length field then holds part of a magic);
        // a whole header announces more bytes than came.
        e.recovers_at_once = keep < 20;
        e.variant = keep < 20 ? "truncated frame / inside the header" : "truncated frame / after the header";
        break;
      }
      case Damage::kGarbage:
      case Damage::kHostStops:
        break;
    }
    return e;
  }

  // Noise between frames: random bytes, an idle line, a partial magic, or something that looks like a frame.
  Event garbage(Bytes& g) {
    Event e;
    const auto random_bytes = [&](std::size_t n) {
      for (std::size_t i = 0; i < n; ++i) g.push_back(rng_.byte());
    };
    const auto header = [&](std::uint32_t count, std::uint32_t length) {
      g.insert(g.end(), link::kV2Magic.begin(), link::kV2Magic.end());
      g.push_back(link::kV2Version);
      g.push_back(static_cast<std::uint8_t>(preset_.frac_bits()));
      g.push_back(0);
      g.push_back(0);
      for (std::uint32_t v : {static_cast<std::uint32_t>(rng_.below(1u << 31)), count, length})
        for (int s = 24; s >= 0; s -= 8) g.push_back(static_cast<std::uint8_t>(v >> s));
    };
    switch (rng_.below(6)) {
      case 0:
        random_bytes(static_cast<std::size_t>(rng_.between(1, 300)));
        e.variant = "garbage / random bytes";
        break;
      case 1:
        g.assign(static_cast<std::size_t>(rng_.between(1, 300)), rng_.percent(50) ? 0x00 : 0xFF);
        e.variant = "garbage / idle line (00 or FF)";
        break;
      case 2:
        random_bytes(static_cast<std::size_t>(rng_.between(0, 100)));
        g.insert(g.end(), link::kV2Magic.begin(), link::kV2Magic.begin() + static_cast<std::ptrdiff_t>(rng_.between(1, 3)));
        e.variant = "garbage / ending in part of a magic";
        break;
      case 3: {
        // A header that passes every check, then too few or wrong bytes: the decoder takes what follows as
        // its payload until it can check the CRC.
        random_bytes(static_cast<std::size_t>(rng_.between(0, 50)));
        const bool big = preset_.max_spheres > 64 && rng_.percent(30);
        const auto count = static_cast<std::uint32_t>(big ? rng_.between(65, preset_.max_spheres)
                                                          : rng_.between(0, std::min<std::uint32_t>(64, preset_.max_spheres)));
        header(count, count * 24);
        random_bytes(static_cast<std::size_t>(rng_.between(0, 200)));
        e.recovers_at_once = false;
        e.variant = big ? "garbage / plausible header, 65 to max_spheres spheres" : "garbage / plausible header, up to 64 spheres";
        break;
      }
      case 4: {
        random_bytes(static_cast<std::size_t>(rng_.between(0, 50)));
        const auto count = static_cast<std::uint32_t>(rng_.between(0, 64));
        switch (rng_.below(4)) {
          case 0: header(count, count * 24 + 1); break;  // bad length
          case 1: header(preset_.max_spheres + 1 + static_cast<std::uint32_t>(rng_.below(1000)), 0); break;  // too many
          case 2: header(count, count * 24); g[g.size() - 16] = 3; break;  // bad version
          default: header(count, count * 24); g[g.size() - 14] = 1; break;  // reserved byte
        }
        random_bytes(static_cast<std::size_t>(rng_.between(0, 100)));
        e.variant = "garbage / header that fails its checks";
        break;
      }
      default:
        random_bytes(static_cast<std::size_t>(rng_.between(0, 50)));
        g.insert(g.end(), link::kV2Magic.begin(), link::kV2Magic.end());
        random_bytes(static_cast<std::size_t>(rng_.between(0, 40)));
        e.variant = "garbage / magic then random bytes";
        break;
    }
    return e;
  }

  // -- episodes --

  // The run's first world, intact: the receiver counts missing worlds from its first sequence number on.
  void start() {
    const SentWorld w = next_world();
    send_intact(w);
    vblank();
    if (!front_.valid || front_.sequence != w.world.sequence) {
      ADD_FAILURE() << "the run's first world was not shown at once";
      ++failures_;
    }
  }

  struct Step {
    std::size_t fed_end = 0;
    std::optional<std::uint32_t> front;
  };

  // What an episode sent, for its checks.
  struct EpisodeLog {
    std::optional<std::uint32_t> front_before;
    std::vector<std::uint32_t> intact;        // every world that went out undamaged
    std::optional<std::uint32_t> damaged;     // the damaged world, if the event has one
    bool delivered_anyway = false;            // the rule says the damaged world still arrives whole
    bool magic_first = false;                 // the damaged world's bytes began with a whole magic
    std::size_t region_end = 0;               // stream position where the damage event ends
    std::vector<std::size_t> recovery_sizes;  // frame sizes of the intact worlds after the event
    int recovery = 0;
  };

  void episode() {
    const device::ReceiverStats before = rx_.stats();
    EpisodeLog log;
    log.front_before = front_.valid ? std::optional(front_.sequence) : std::nullopt;
    episode_bytes_.clear();
    steps_.clear();
    eos_.clear();

    // A clean start: intact worlds are shown at once.
    for (std::int64_t n = rng_.between(0, 2); n > 0; --n) {
      const SentWorld w = next_world();
      log.intact.push_back(w.world.sequence);
      send_intact(w);
      vblank();
      if (!front_.valid || front_.sequence != w.world.sequence) {
        ADD_FAILURE() << "an intact world after a clean start was not shown at once";
        ++failures_;
      }
    }

    // The event.
    Event e;
    const std::size_t event_begin = episode_bytes_.size();
    if (damage_ == Damage::kGarbage) {
      const SentWorld w = next_world();
      log.intact.push_back(w.world.sequence);
      send_intact(w);
      vblank();
      Bytes g;
      e = garbage(g);
      feed(split(g, random_transfer_bytes()));
      vblank();
    } else if (damage_ == Damage::kHostStops) {
      const SentWorld w = next_world();
      log.damaged = w.world.sequence;
      Bytes sent_part;
      if (rng_.percent(85)) {
        sent_part.assign(w.frame.begin(), w.frame.begin() + rng_.between(1, static_cast<std::int64_t>(w.frame.size()) - 1));
        e.variant = sent_part.size() < 20 ? "host stops / inside the header" : "host stops / after the header";
      } else {
        // It sent noise and maybe the start of a frame, and went away.
        garbage(sent_part);
        if (rng_.percent(50)) sent_part.insert(sent_part.end(), w.frame.begin(), w.frame.begin() + rng_.between(1, 30));
        e.variant = "host stops / after noise";
      }
      feed(split(sent_part, random_transfer_bytes()));
      vblank();
      end_of_stream();
      vblank();
    } else {
      const SentWorld w = next_world();
      log.damaged = w.world.sequence;
      std::vector<Bytes> out;
      e = damage_world(w, out, log.delivered_anyway);
      feed(out);
      vblank();
    }
    log.region_end = episode_bytes_.size();
    log.magic_first = log.region_end - event_begin >= 4 &&
                      std::equal(link::kV2Magic.begin(), link::kV2Magic.end(),
                                 episode_bytes_.begin() + static_cast<std::ptrdiff_t>(event_begin));

    // Recovery: intact worlds until the latest is on screen.
    while (true) {
      const SentWorld w = next_world();
      log.intact.push_back(w.world.sequence);
      log.recovery_sizes.push_back(w.frame.size());
      send_intact(w);
      vblank();
      ++log.recovery;
      if (front_.valid && front_.sequence == w.world.sequence) break;
      if (log.recovery == kRecoveryGiveUp) {
        ADD_FAILURE() << name_of(damage_) << " (" << e.variant << "): no recovery after " << log.recovery
                      << " intact worlds";
        ++failures_;
        return;
      }
    }
    check_episode(before, e, log);
  }

  void check_episode(const device::ReceiverStats& before, const Event& e, const EpisodeLog& log) {
    const ModelOutcome m = model_decoder(episode_bytes_, eos_, preset_.max_spheres, sent_);
    const device::ReceiverStats& now = rx_.stats();
    const auto fail = [&](const std::string& what) {
      ADD_FAILURE() << name_of(damage_) << " (" << e.variant << "), preset " << preset_.name << ", world " << worlds_
                    << ": " << what;
      ++failures_;
    };
    const auto delivered = [&](std::uint32_t sequence) {
      return std::any_of(m.frames.begin(), m.frames.end(), [&](const ModelFrame& f) { return f.sequence == sequence; });
    };

    // The rule itself: no forged frame, nothing undecided, every byte in a frame or dropped, and nothing
    // intact is ever lost (a world swallowed by a bogus header is delivered once its CRC has failed).
    if (m.forged) fail("a frame with a good CRC that was never sent");
    if (m.pending) fail("the model has bytes left undecided after the shown world");
    std::uint64_t accepted_bytes = 0;
    for (const ModelFrame& f : m.frames) accepted_bytes += f.bytes;
    if (accepted_bytes + m.bytes_dropped != episode_bytes_.size()) fail("the model loses bytes");
    for (const std::uint32_t seq : log.intact)
      if (!delivered(seq)) fail("intact world " + std::to_string(seq) + " was never delivered");

    // The receiver counts exactly what the rule says.
    const auto same = [&](const char* what, std::uint64_t got, std::uint64_t rule) {
      if (got != rule) fail(std::string(what) + " " + std::to_string(got) + ", the rule says " + std::to_string(rule));
    };
    same("worlds accepted", now.worlds_accepted - before.worlds_accepted, m.frames.size());
    same("frames rejected", now.frames_rejected - before.frames_rejected, m.rejected);
    same("garbage runs", now.garbage_runs - before.garbage_runs, m.garbage_runs);
    same("bytes dropped", now.bytes_dropped - before.bytes_dropped, m.bytes_dropped);

    // What was on screen after each step, and how many accepted worlds were replaced before a blanking.
    std::size_t next_frame = 0;
    std::uint64_t replaced = 0;
    std::optional<std::uint32_t> expected = log.front_before;
    for (const Step& s : steps_) {
      std::size_t this_step = 0;
      while (next_frame < m.frames.size() && m.frames[next_frame].ready_at <= s.fed_end) {
        expected = m.frames[next_frame++].sequence;
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
    same("worlds replaced", now.worlds_replaced - before.worlds_replaced, replaced);

    // The damaged world: delivered whole exactly when the rule says so; otherwise lost, with at least one
    // report, and a rejected frame whenever its magic arrived first.
    Tally& t = tallies_[e.variant];
    ++t.events;
    const std::uint64_t counted_missing = now.worlds_missing - before.worlds_missing;
    t.missing += counted_missing;
    const std::uint64_t reports = (now.frames_rejected - before.frames_rejected) + (now.garbage_runs - before.garbage_runs);
    if (log.damaged) {
      const bool arrived = delivered(*log.damaged);
      if (arrived != log.delivered_anyway) fail(arrived ? "a damaged world was delivered" : "a world that survived its damage was lost");
      if (arrived) {
        ++t.delivered_anyway;
      } else {
        ++t.lost;
        if (reports == 0 || now.bytes_dropped == before.bytes_dropped) fail("a lost world was not counted");
        if (log.magic_first && now.frames_rejected == before.frames_rejected) fail("a damaged frame whose magic arrived was not rejected");
      }
    } else if (reports == 0) {
      fail("noise was not counted");
    }
    const std::uint64_t damaged_lost = log.damaged && !delivered(*log.damaged) ? 1 : 0;
    if (counted_missing != damaged_lost)
      fail(std::to_string(counted_missing) + " worlds counted missing, " + std::to_string(damaged_lost) +
           " damaged worlds lost");

    // Recovery: once the stream has passed the end of every frame announced by a header inside the damage,
    // the next complete intact world is shown. So 1 when no such header announces more than came, and never
    // more intact worlds than cover the largest frame the preset can announce.
    t.add(log.recovery);
    std::size_t reach = 0;
    for (const auto& [at, end] : m.headers)
      if (at < log.region_end) reach = std::max(reach, end);
    int predicted = 0;
    std::size_t fed = log.region_end;
    for (std::size_t j = 0; j < log.recovery_sizes.size() && predicted == 0; ++j) {
      fed += log.recovery_sizes[j];
      if (fed >= reach) predicted = static_cast<int>(j) + 1;
    }
    if (log.recovery != predicted)
      fail("recovery took " + std::to_string(log.recovery) + " intact worlds, the rule says " + std::to_string(predicted));
    if ((e.recovers_at_once || damage_ == Damage::kHostStops) && log.recovery != 1)
      fail("recovery took " + std::to_string(log.recovery) + " intact worlds, not 1");
    std::size_t covered = 0;
    for (int j = 0; j + 1 < log.recovery; ++j) covered += log.recovery_sizes[static_cast<std::size_t>(j)];
    if (covered >= frame_bytes_for(preset_.max_spheres)) fail("recovery took longer than the largest frame");
  }

  device::DevicePreset preset_;
  Damage damage_;
  Rng rng_;
  WorldSource source_;
  device::Receiver rx_;
  device::Device shadow_;
  device::SceneMemory front_;
  std::unordered_map<std::uint32_t, SentWorld> sent_;
  Bytes episode_bytes_;
  std::vector<Step> steps_;
  std::vector<std::size_t> eos_;
  std::map<std::string, Tally> tallies_;
  int worlds_ = 0;
  int next_render_ = kRenderEvery;
  int renders_ = 0;
  int failures_ = 0;
  std::uint64_t bytes_fed_ = 0;
};

void soak(Damage damage) {
  std::uint64_t seed = 1 + static_cast<std::uint64_t>(damage) * 2;
  for (const device::DevicePreset& preset : {device::wide_preset(), device::board_2023_preset()}) {
    Soak s(preset, damage, seed++);
    s.run(kWorldsPerRun);
    s.report(std::cout);
    EXPECT_GE(s.worlds(), kWorldsPerRun);
    EXPECT_EQ(s.missing(), s.lost()) << "every damaged world that was lost is counted as missing";
  }
}

TEST(Soak, RandomBitFlips) { soak(Damage::kBitFlips); }
TEST(Soak, DroppedBytes) { soak(Damage::kDroppedBytes); }
TEST(Soak, DuplicatedTransfers) { soak(Damage::kDuplicatedTransfer); }
TEST(Soak, ReorderedTransfers) { soak(Damage::kReorderedTransfers); }
TEST(Soak, TruncatedFrames) { soak(Damage::kTruncatedFrame); }
TEST(Soak, GarbageBetweenFrames) { soak(Damage::kGarbage); }
TEST(Soak, HostStopsMidFrame) { soak(Damage::kHostStops); }

// v1 has no framing and no check: every 8 bytes are a sphere, so a flipped bit is a different sphere and a
// lost byte shifts every later word until the stream ends. What it can promise is what end_of_stream gives:
// a host that stops mid-word costs that partial word (one rejection, its bytes), and the next word is shown.
TEST(Soak, V1HostStopsMidWord) {
  const device::DevicePreset preset = device::board_2023_preset();
  host::Host h(scene::random_spheres(1, 5), formats_of(preset), link::WireVersion::kV1);
  device::Receiver rx(preset, link::WireVersion::kV1);
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

// Co-simulation of the receiver RTL (rtl/receiver/: ts_spi_rx -> ts_receiver -> ts_scene_memory, in
// ts_receiver_top) against the C++ device model, device::Receiver (src/tripsitter/device/receiver.h).
//
// The RTL is driven from its pins: the test bit-bangs SCLK, MOSI and CS_n (SPI mode 0, most significant bit
// first) at 10 MHz against the 100 MHz device clock (5 clocks per SCLK half period; one test at the fastest
// allowed, clk/8), and gives the very same bytes, transfer by transfer, to a device::Receiver. After every
// transfer (and end of stream) it waits until the RTL has taken every byte and is idle, then compares every
// ReceiverStats counter and the ready line; at each vertical blanking it calls swap_if_pending on the model and
// pulses vblank_swap on the RTL, then compares the whole front scene memory (valid, sequence, sphere count,
// and every sphere's geometry, metal flag and albedo, read through both read ports). The first mismatch is
// reported with both values and the step that produced it, and the run stops there.
//
// Streams (fixed seeds): good worlds of random spheres on v1, v2 and v3 and both presets (wide, board-2023),
// then damaged streams with the soak test's kinds of damage (board/soak_test.cpp): bit flips, dropped,
// inserted and duplicated bytes, bursts, duplicated and reordered transfers, truncated frames, a host stopping
// mid-frame (end_of_stream), garbage, replayed worlds, host restarts (cutting a frame or not, and replays of
// ended sessions), worlds refused for their content, and headers that lie (too many spheres, bad length, a
// frame announcing the whole scene memory), plus frames with a header inside their payload (v3's cut rule)
// and transfers that end inside a byte (chip select rising mid-byte: the RTL drops the partial byte; the
// model never sees it). About 44,000 compared steps in all; 10 s in a Release build.
#include <array>
#include <cstdint>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <verilated.h>

#include "Vts_rx_crc32.h"
#include "Vts_rx_v1_board.h"
#include "Vts_rx_v1_wide.h"
#include "Vts_rx_v2_board.h"
#include "Vts_rx_v2_wide.h"
#include "Vts_rx_v3_artix_path.h"
#include "Vts_rx_v3_board.h"
#include "Vts_rx_v3_wide.h"
#include "hierarchy_worlds.h"
#include "test_util.h"

#include <tripsitter/core/crc32.h>
#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/receiver.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/link/frame.h>
#include <tripsitter/link/sequence.h>
#include <tripsitter/link/wire_v1.h>

namespace tripsitter::rtl {
namespace {

using link::WireVersion;

// ---- The configurations: one Verilated model per wire and preset (rtl/receiver/CMakeLists.txt) ----

struct WideCfg {
  static device::DevicePreset preset() { return device::wide_preset(); }
  static constexpr int kAw = 12;  // log2 of max_spheres
  static constexpr int kXw = 24, kYw = 24, kZw = 24, kRw = 24;
};
struct BoardCfg {
  static device::DevicePreset preset() { return device::board_2023_preset(); }
  static constexpr int kAw = 6;
  static constexpr int kXw = 16, kYw = 15, kZw = 15, kRw = 16;
};
struct ArtixPathCfg {  // v3 worlds with a hierarchy (DevicePreset::walks_hierarchy)
  static device::DevicePreset preset() { return device::artix_path_preset(); }
  static constexpr int kAw = 8;
  static constexpr int kXw = 22, kYw = 22, kZw = 22, kRw = 21;
};
template <class M, WireVersion W, class P>
struct Cfg : P {
  using Model = M;
  static constexpr WireVersion kWire = W;
};
using V1Wide = Cfg<Vts_rx_v1_wide, WireVersion::kV1, WideCfg>;
using V2Wide = Cfg<Vts_rx_v2_wide, WireVersion::kV2, WideCfg>;
using V3Wide = Cfg<Vts_rx_v3_wide, WireVersion::kV3, WideCfg>;
using V1Board = Cfg<Vts_rx_v1_board, WireVersion::kV1, BoardCfg>;
using V2Board = Cfg<Vts_rx_v2_board, WireVersion::kV2, BoardCfg>;
using V3Board = Cfg<Vts_rx_v3_board, WireVersion::kV3, BoardCfg>;
using V3ArtixPath = Cfg<Vts_rx_v3_artix_path, WireVersion::kV3, ArtixPathCfg>;

// ---- What is compared ----

struct Counters {
  std::uint64_t worlds_accepted = 0, worlds_replaced = 0, frames_rejected = 0, garbage_runs = 0, bytes_dropped = 0,
                worlds_missing = 0, worlds_replayed = 0, sessions = 0;
  bool ready = true;
};

Counters counters_of(const device::Receiver& rx) {
  const device::ReceiverStats& s = rx.stats();
  return Counters{s.worlds_accepted, s.worlds_replaced, s.frames_rejected, s.garbage_runs, s.bytes_dropped,
                  s.worlds_missing,  s.worlds_replayed, s.sessions,        rx.ready()};
}

// The first counter that differs, as "name: model A, RTL B"; empty when all agree.
std::string first_difference(const Counters& model, const Counters& rtl) {
  const std::array<std::pair<const char*, std::pair<std::uint64_t, std::uint64_t>>, 9> fields{{
      {"worlds_accepted", {model.worlds_accepted, rtl.worlds_accepted}},
      {"worlds_replaced", {model.worlds_replaced, rtl.worlds_replaced}},
      {"frames_rejected", {model.frames_rejected, rtl.frames_rejected}},
      {"garbage_runs", {model.garbage_runs, rtl.garbage_runs}},
      {"bytes_dropped", {model.bytes_dropped, rtl.bytes_dropped}},
      {"worlds_missing", {model.worlds_missing, rtl.worlds_missing}},
      {"worlds_replayed", {model.worlds_replayed, rtl.worlds_replayed}},
      {"sessions", {model.sessions, rtl.sessions}},
      {"ready", {model.ready ? 1u : 0u, rtl.ready ? 1u : 0u}},
  }};
  for (const auto& [name, values] : fields) {
    if (values.first != values.second) {
      std::ostringstream out;
      out << name << ": model " << values.first << ", RTL " << values.second;
      return out.str();
    }
  }
  return {};
}

struct FrontSphere {
  std::int64_t x = 0, y = 0, z = 0, r = 0;
  bool metal = false;
  std::array<std::uint8_t, 3> albedo{};
  bool operator==(const FrontSphere&) const = default;
};

struct Front {
  bool valid = false;
  std::uint32_t sequence = 0;
  std::vector<FrontSphere> spheres;
};

Front front_of(const device::SceneMemory& scene) {
  Front f;
  f.valid = scene.valid;
  f.sequence = scene.sequence;
  for (std::size_t i = 0; i < scene.geometry.size(); ++i) {
    const auto& g = scene.geometry[i];
    const device::SurfaceWord& s = scene.surfaces.at(i);
    f.spheres.push_back(FrontSphere{g.center.x, g.center.y, g.center.z, g.radius, s.material == link::kMaterialMetal,
                                    s.albedo});
  }
  return f;
}

std::string first_difference(const Front& model, const Front& rtl) {
  std::ostringstream out;
  if (model.valid != rtl.valid) {
    out << "front valid: model " << model.valid << ", RTL " << rtl.valid;
  } else if (model.sequence != rtl.sequence) {
    out << "front sequence: model " << model.sequence << ", RTL " << rtl.sequence;
  } else if (model.spheres.size() != rtl.spheres.size()) {
    out << "front sphere count: model " << model.spheres.size() << ", RTL " << rtl.spheres.size();
  } else {
    for (std::size_t i = 0; i < model.spheres.size(); ++i) {
      const FrontSphere& a = model.spheres[i];
      const FrontSphere& b = rtl.spheres[i];
      const std::array<std::pair<const char*, std::pair<std::int64_t, std::int64_t>>, 7> fields{{
          {"x", {a.x, b.x}},
          {"y", {a.y, b.y}},
          {"z", {a.z, b.z}},
          {"radius", {a.r, b.r}},
          {"metal", {a.metal, b.metal}},
          {"albedo r", {a.albedo[0], b.albedo[0]}},
          {"albedo g", {a.albedo[1], b.albedo[1]}},
      }};
      for (const auto& [name, values] : fields) {
        if (values.first != values.second) {
          out << "front sphere " << i << " " << name << ": model " << values.first << ", RTL " << values.second;
          return out.str();
        }
      }
      if (a.albedo[2] != b.albedo[2]) {
        out << "front sphere " << i << " albedo b: model " << int{a.albedo[2]} << ", RTL " << int{b.albedo[2]};
        return out.str();
      }
    }
  }
  return out.str();
}

std::int64_t sign_extend(std::uint64_t v, int bits) {
  const std::uint64_t sign = std::uint64_t{1} << (bits - 1);
  v &= (sign << 1) - 1;
  return static_cast<std::int64_t>(v ^ sign) - static_cast<std::int64_t>(sign);
}

// ---- The RTL, driven from its pins ----

template <class C>
class Rig {
 public:
  explicit Rig(int half_period) : half_(half_period), ctx_(std::make_unique<VerilatedContext>()) {
    ctx_->randReset(2);  // random initial state: the reset must make it irrelevant
    top_ = std::make_unique<typename C::Model>(ctx_.get());
    top_->clk = 0;
    top_->rst = 1;
    top_->cs_n = 1;
    top_->sclk = 0;
    top_->mosi = 0;
    top_->end_of_stream = 0;
    top_->vblank_swap = 0;
    top_->rd_addr = 0;
    ticks(4);
    top_->rst = 0;
    ticks(2);
  }
  Rig(const Rig&) = delete;
  Rig& operator=(const Rig&) = delete;
  ~Rig() { top_->final(); }

  // One transfer: chip select low, the bytes, then `extra_bits` bits of a byte that is never finished, chip
  // select high. Returns false (with `error`) if the RTL did not take the bytes and settle.
  bool transfer(std::span<const std::uint8_t> bytes, int extra_bits, std::string& error) {
    top_->cs_n = 0;
    ticks(half_);
    for (const std::uint8_t byte : bytes) {
      for (int bit = 7; bit >= 0; --bit) clock_bit((byte >> bit) & 1);
    }
    for (int bit = 0; bit < extra_bits; ++bit) clock_bit(bit & 1);
    ticks(half_);
    top_->cs_n = 1;
    ticks(half_);
    sent_ += bytes.size();
    return settle(error);
  }

  bool end_of_stream(std::string& error) {
    top_->end_of_stream = 1;
    tick();
    top_->end_of_stream = 0;
    return settle(error);
  }

  bool vblank(std::string& error) {
    top_->vblank_swap = 1;
    tick();
    top_->vblank_swap = 0;
    tick();
    return settle(error);
  }

  Counters counters() const {
    return Counters{top_->worlds_accepted, top_->worlds_replaced, top_->frames_rejected, top_->garbage_runs,
                    top_->bytes_dropped,   top_->worlds_missing,  top_->worlds_replayed, top_->sessions,
                    top_->ready != 0};
  }

  // The whole front copy, read through both ports: port 0 reads sphere i while port 1 reads sphere count-1-i;
  // the two readings of each sphere must agree.
  Front front(std::string& error) {
    Front f;
    f.valid = top_->front_valid != 0;
    f.sequence = top_->front_sequence;
    const std::size_t count = top_->front_count;
    f.spheres.resize(count);
    std::vector<FrontSphere> other(count);
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t j = count - 1 - i;
      top_->rd_addr = static_cast<std::uint32_t>(i | (j << C::kAw));
      tick();
      f.spheres[i] = read_port(0);
      other[j] = read_port(1);
    }
    for (std::size_t i = 0; i < count; ++i) {
      if (!(f.spheres[i] == other[i])) {
        error = "read ports 0 and 1 disagree on front sphere " + std::to_string(i);
        break;
      }
    }
    return f;
  }

  std::uint64_t cut_bytes() const { return cut_bytes_; }

  // Sphere 0 read through port 0 with the address presented in the very clock of a swap, and in the clock
  // after: the first reading comes from the copy that was the front when its address was presented.
  std::pair<FrontSphere, FrontSphere> read_across_swap() {
    top_->rd_addr = 0;
    top_->vblank_swap = 1;
    tick();
    const FrontSphere before = read_port(0);
    top_->vblank_swap = 0;
    tick();
    return {before, read_port(0)};
  }

 private:
  void tick() {
    top_->clk = 0;
    top_->eval();
    top_->clk = 1;
    top_->eval();
    if (top_->spi_byte_cut) ++cut_bytes_;
  }
  void ticks(int n) {
    for (int i = 0; i < n; ++i) tick();
  }
  // Mode 0: MOSI changes while SCLK is low; the slave samples on the rising edge.
  void clock_bit(int bit) {
    top_->mosi = static_cast<std::uint8_t>(bit);
    top_->sclk = 0;
    ticks(half_);
    top_->sclk = 1;
    ticks(half_);
  }
  // Waits until every byte sent is in and the engine is idle (bounded: a hung RTL fails, never blocks).
  bool settle(std::string& error) {
    for (int i = 0; i < 4'000'000; ++i) {
      if (top_->bytes_received == sent_ && top_->idle) return true;
      tick();
    }
    error = "the RTL did not settle: " + std::to_string(top_->bytes_received) + " of " + std::to_string(sent_) +
            " bytes taken, idle " + std::to_string(int{top_->idle});
    return false;
  }
  FrontSphere read_port(int p) const {
    const auto field = [&](std::uint64_t packed, int bits) {
      return (packed >> (p * bits)) & ((std::uint64_t{1} << bits) - 1);
    };
    FrontSphere s;
    s.x = sign_extend(field(top_->rd_x, C::kXw), C::kXw);
    s.y = sign_extend(field(top_->rd_y, C::kYw), C::kYw);
    s.z = sign_extend(field(top_->rd_z, C::kZw), C::kZw);
    s.r = static_cast<std::int64_t>(field(top_->rd_r, C::kRw));
    s.metal = ((top_->rd_metal >> p) & 1) != 0;
    const std::uint64_t albedo = field(top_->rd_albedo, 24);
    s.albedo = {static_cast<std::uint8_t>(albedo >> 16), static_cast<std::uint8_t>(albedo >> 8),
                static_cast<std::uint8_t>(albedo)};
    return s;
  }

  int half_;
  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<typename C::Model> top_;
  std::uint64_t sent_ = 0;
  std::uint64_t cut_bytes_ = 0;
};

// ---- Model and RTL side by side ----

template <class C>
class CoSim {
 public:
  explicit CoSim(int half_period = 5) : rig_(half_period), model_(C::preset(), C::kWire) {}

  // Each returns false after the first mismatch (reported with ADD_FAILURE); later calls do nothing.
  bool transfer(std::span<const std::uint8_t> bytes, int extra_bits = 0) {
    if (failed_) return false;
    ++steps_;
    model_.receive(bytes);
    std::string error;
    if (!rig_.transfer(bytes, extra_bits, error)) return fail(error);
    return compare("a transfer of " + std::to_string(bytes.size()) + " bytes");
  }
  bool end_of_stream() {
    if (failed_) return false;
    ++steps_;
    model_.end_of_stream();
    std::string error;
    if (!rig_.end_of_stream(error)) return fail(error);
    return compare("end of stream");
  }
  bool vblank() {
    if (failed_) return false;
    ++steps_;
    model_.swap_if_pending(front_);
    std::string error;
    if (!rig_.vblank(error)) return fail(error);
    if (!compare("a vertical blanking")) return false;
    const Front rtl = rig_.front(error);
    if (!error.empty()) return fail(error);
    const std::string diff = first_difference(front_of(front_), rtl);
    if (!diff.empty()) return fail(diff + " (after a vertical blanking)");
    ++swaps_checked_;
    return true;
  }
  // A vertical blanking during which port 0 reads sphere 0 in the clock of the swap and the clock after.
  bool vblank_reading_across() {
    if (failed_) return false;
    ++steps_;
    const Front old_front = front_of(front_);
    model_.swap_if_pending(front_);
    const Front new_front = front_of(front_);
    const auto [before, after] = rig_.read_across_swap();
    if (!old_front.spheres.empty() && !(before == old_front.spheres[0])) return fail("read in the swap's clock: not the old front");
    if (!new_front.spheres.empty() && !(after == new_front.spheres[0])) return fail("read after the swap: not the new front");
    std::string error;
    if (!rig_.vblank(error)) return fail(error);  // a second blanking: nothing is pending
    return compare("a vertical blanking read across");
  }
  // A stream cut into transfers of 1 to max_transfer bytes; a few of them end inside a byte.
  bool send(const Bytes& bytes, Rng& rng, std::size_t max_transfer, int cut_percent = 3) {
    std::size_t at = 0;
    while (at < bytes.size()) {
      const std::size_t n = std::min<std::size_t>(bytes.size() - at, 1 + rng.below(max_transfer));
      const int extra = rng.percent(cut_percent) ? static_cast<int>(rng.between(1, 7)) : 0;
      if (!transfer(std::span<const std::uint8_t>(bytes).subspan(at, n), extra)) return false;
      at += n;
    }
    return true;
  }

  ~CoSim() {
    const device::ReceiverStats& s = model_.stats();
    std::cout << "  " << steps_ << " steps, " << swaps_checked_ << " front copies compared; model: accepted "
              << s.worlds_accepted << ", replaced " << s.worlds_replaced << ", rejected " << s.frames_rejected
              << ", garbage runs " << s.garbage_runs << ", bytes dropped " << s.bytes_dropped << ", missing "
              << s.worlds_missing << ", replayed " << s.worlds_replayed << ", sessions " << s.sessions
              << "; partial bytes cut " << rig_.cut_bytes() << "\n";
  }
  CoSim(const CoSim&) = delete;
  CoSim& operator=(const CoSim&) = delete;

  const device::Receiver& model() const { return model_; }
  const device::SceneMemory& front() const { return front_; }
  bool failed() const { return failed_; }
  int steps() const { return steps_; }
  int swaps_checked() const { return swaps_checked_; }
  std::uint64_t cut_bytes() const { return rig_.cut_bytes(); }
  void set_context(std::string context) { context_ = std::move(context); }

 private:
  bool compare(const std::string& what) {
    const std::string diff = first_difference(counters_of(model_), rig_.counters());
    if (!diff.empty()) return fail(diff + " (after " + what + ")");
    return true;
  }
  bool fail(const std::string& what) {
    failed_ = true;
    ADD_FAILURE() << "step " << steps_ << ", " << context_ << ": " << what
                  << "\nmodel's last error: " << model_.stats().last_error;
    return false;
  }

  Rig<C> rig_;
  device::Receiver model_;
  device::SceneMemory front_;
  bool failed_ = false;
  int steps_ = 0;
  int swaps_checked_ = 0;
  std::string context_ = "start";
};

// ---- Worlds ----

// A raw value in a format: mostly moderate, sometimes at the extremes.
std::int64_t raw_in(Rng& rng, const core::FixedFormat& f) {
  if (rng.percent(10)) return rng.percent(50) ? f.max_raw() : std::max<std::int64_t>(f.min_raw(), f.is_signed ? f.min_raw() : 1);
  const std::int64_t span = std::min<std::int64_t>(f.max_raw(), std::int64_t{1} << (f.frac_bits + 11));
  return rng.between(f.is_signed ? -span : 1, span);
}

link::WireSphere random_sphere(Rng& rng, const device::DevicePreset& p) {
  link::WireSphere s;
  s.x = static_cast<std::int32_t>(raw_in(rng, p.x));
  s.y = static_cast<std::int32_t>(raw_in(rng, p.y));
  s.z = static_cast<std::int32_t>(raw_in(rng, p.z));
  s.radius = static_cast<std::uint32_t>(std::max<std::int64_t>(1, raw_in(rng, p.radius)));
  s.material = static_cast<std::uint8_t>(rng.below(3));
  s.albedo = {rng.byte(), rng.byte(), rng.byte()};
  s.fuzz = static_cast<std::uint16_t>(rng.below(65536));
  s.ior = static_cast<std::uint16_t>(rng.between(1, 65535));
  // A path preset takes dielectrics of 0.25..8 only: mostly those, now and then one outside.
  if (p.path && rng.percent(97))
    s.ior = static_cast<std::uint16_t>(rng.between(device::kPathIorMin, device::kPathIorMax));
  return s;
}

// A world of 0 (now and then) to max_spheres random spheres in the preset's formats.
link::World random_world(Rng& rng, const device::DevicePreset& p, int max_spheres) {
  link::World w;
  w.frac_bits = static_cast<std::uint8_t>(p.frac_bits());
  const int n = static_cast<int>(rng.between(rng.percent(5) ? 0 : 1, max_spheres));
  for (int i = 0; i < n; ++i) w.spheres.push_back(random_sphere(rng, p));
  return w;
}

// The host's side of a framed wire: numbered frames (link::Numbering), and what it sent, for replays.
class Host {
 public:
  Host(WireVersion wire, device::DevicePreset preset, std::uint32_t session)
      : wire_(wire), preset_(std::move(preset)), numbering_(wire, session) {}

  Bytes frame(Rng& rng, int max_spheres) { return stamp(random_world(rng, preset_, max_spheres)); }
  Bytes stamp(const link::World& w) {
    Bytes bytes = link::encode_frame(wire_, w);
    numbering_.stamp(bytes);
    sent_.push_back(bytes);
    if (sent_.size() > 64) sent_.erase(sent_.begin());
    return bytes;
  }
  // The host restarts: a new session (v3), numbering from 1 again.
  void restart(std::uint32_t session) { numbering_ = link::Numbering(wire_, session); }
  const Bytes& sent_before(std::size_t back) const { return sent_.at(sent_.size() - 1 - std::min(back, sent_.size() - 1)); }
  const device::DevicePreset& preset() const { return preset_; }
  WireVersion wire() const { return wire_; }

 private:
  WireVersion wire_;
  device::DevicePreset preset_;
  link::Numbering numbering_;
  std::vector<Bytes> sent_;
};


// ---- Good worlds ----

template <class C>
void good_worlds(std::uint64_t seed, int worlds, int max_spheres, int half_period = 5) {
  CoSim<C> sim(half_period);
  Rng rng(seed);
  const device::DevicePreset p = C::preset();
  if (C::kWire == WireVersion::kV1) {
    for (int i = 0; i < worlds && !sim.failed(); ++i) {
      // Mostly radii the preset holds; a few it refuses (the board's r <= 12, wide's r <= 19; r up to 63).
      link::V1Sphere s;
      s.x_raw = static_cast<std::int32_t>(rng.between(link::kV1X.min_raw(), link::kV1X.max_raw()));
      s.y_raw = static_cast<std::int32_t>(rng.between(link::kV1Y.min_raw(), link::kV1Y.max_raw()));
      s.z_raw = static_cast<std::int32_t>(rng.between(link::kV1Z.min_raw(), link::kV1Z.max_raw()));
      s.radius_log2 = static_cast<std::uint8_t>(rng.percent(85) ? rng.between(0, 12) : rng.between(13, 63));
      s.colour = static_cast<std::uint16_t>(rng.below(4096));
      Bytes bytes;
      link::append_v1_bytes(link::encode_v1_word(s), bytes);
      sim.set_context("v1 word " + std::to_string(i));
      sim.send(bytes, rng, 8, 0);
      if (rng.percent(60)) sim.vblank();
    }
  } else {
    Host host(C::kWire, p, 0x5EED0001u);
    for (int i = 0; i < worlds && !sim.failed(); ++i) {
      sim.set_context("world " + std::to_string(i));
      sim.send(host.frame(rng, max_spheres), rng, 1024, 0);
      if (rng.percent(70)) sim.vblank();  // otherwise the next world replaces it
    }
  }
  sim.vblank();
  EXPECT_FALSE(sim.failed());
  EXPECT_GT(sim.model().stats().worlds_accepted, static_cast<std::uint64_t>(worlds / 2));
  EXPECT_GT(sim.swaps_checked(), worlds / 3);
}

// ---- Damaged streams (the soak test's kinds of fault) ----

enum class Fault {
  kBitFlip, kByteDrop, kByteInsert, kByteDup, kBurstFlip, kBurstDrop, kDupTransfer, kReorder, kTruncate,
  kStopMidFrame, kGarbage, kReplay, kRestart, kContent, kLyingHeader, kEmbeddedHeader,
};
constexpr int kFaults = 16;

const char* name_of(Fault f) {
  switch (f) {
    case Fault::kBitFlip: return "bit flip";
    case Fault::kByteDrop: return "byte dropped";
    case Fault::kByteInsert: return "byte inserted";
    case Fault::kByteDup: return "byte duplicated";
    case Fault::kBurstFlip: return "2-3 bits flipped";
    case Fault::kBurstDrop: return "2-16 bytes dropped";
    case Fault::kDupTransfer: return "duplicated transfer";
    case Fault::kReorder: return "transfers reordered";
    case Fault::kTruncate: return "truncated frame";
    case Fault::kStopMidFrame: return "host stops mid-frame";
    case Fault::kGarbage: return "garbage";
    case Fault::kReplay: return "replayed world";
    case Fault::kRestart: return "host restart";
    case Fault::kContent: return "world refused for its content";
    case Fault::kLyingHeader: return "lying header";
    case Fault::kEmbeddedHeader: return "header inside a payload";
  }
  return "?";
}

template <class C>
void damage_one(CoSim<C>& sim, Host& host, Rng& rng, Fault fault, int max_spheres, std::uint32_t& next_session) {
  const WireVersion wire = host.wire();
  const device::DevicePreset& p = host.preset();
  const std::size_t kT = 1 + rng.below(rng.percent(50) ? 16 : 512);  // transfer size for this fault
  Bytes f = host.frame(rng, max_spheres);
  switch (fault) {
    case Fault::kBitFlip: f[rng.below(f.size())] ^= static_cast<std::uint8_t>(1u << rng.below(8)); break;
    case Fault::kByteDrop: f.erase(f.begin() + static_cast<std::ptrdiff_t>(rng.below(f.size()))); break;
    case Fault::kByteInsert:
      f.insert(f.begin() + static_cast<std::ptrdiff_t>(rng.below(f.size() + 1)), rng.percent(20) ? 0x54 : rng.byte());
      break;
    case Fault::kByteDup: {
      const std::size_t at = rng.below(f.size());
      f.insert(f.begin() + static_cast<std::ptrdiff_t>(at), f[at]);
      break;
    }
    case Fault::kBurstFlip: {
      const std::size_t at = rng.below(f.size());
      const int bits = static_cast<int>(rng.between(2, 3));
      for (int k = 0; k < bits; ++k) {
        const std::size_t i = std::min(f.size() - 1, at + rng.below(4));
        f[i] ^= static_cast<std::uint8_t>(1u << rng.below(8));
      }
      break;
    }
    case Fault::kBurstDrop: {
      const std::size_t n = std::min<std::size_t>(f.size(), static_cast<std::size_t>(rng.between(2, 16)));
      const std::size_t at = rng.below(f.size() - n + 1);
      f.erase(f.begin() + static_cast<std::ptrdiff_t>(at), f.begin() + static_cast<std::ptrdiff_t>(at + n));
      break;
    }
    case Fault::kDupTransfer:
    case Fault::kReorder: {
      // Transfer-level faults: cut the frame into transfers and duplicate one, or swap two neighbours.
      std::vector<Bytes> parts;
      for (std::size_t at = 0; at < f.size(); at += kT)
        parts.emplace_back(f.begin() + static_cast<std::ptrdiff_t>(at),
                           f.begin() + static_cast<std::ptrdiff_t>(std::min(f.size(), at + kT)));
      const std::size_t i = rng.below(parts.size());
      if (fault == Fault::kDupTransfer) {
        parts.insert(parts.begin() + static_cast<std::ptrdiff_t>(i), parts[i]);
      } else if (parts.size() > 1) {
        const std::size_t j = std::min(i, parts.size() - 2);
        std::swap(parts[j], parts[j + 1]);
      }
      for (const Bytes& part : parts) sim.transfer(part);
      return;
    }
    case Fault::kTruncate: f.resize(rng.below(f.size())); break;
    case Fault::kStopMidFrame:
      f.resize(rng.below(f.size()));
      sim.send(f, rng, kT);
      sim.end_of_stream();
      if (wire == WireVersion::kV3 && rng.percent(70)) host.restart(next_session++);  // it reconnects
      return;
    case Fault::kGarbage: {
      // Noise between frames, sometimes holding pieces of the magic or a whole header that fails.
      Bytes g;
      const int n = static_cast<int>(rng.between(1, 64));
      for (int k = 0; k < n; ++k) g.push_back(rng.byte());
      const Bytes head(f.begin(), f.begin() + static_cast<std::ptrdiff_t>(std::min<std::size_t>(f.size(), 28)));
      const std::size_t piece = rng.below(head.size() + 1);
      g.insert(g.begin() + static_cast<std::ptrdiff_t>(rng.below(g.size() + 1)), head.begin(),
               head.begin() + static_cast<std::ptrdiff_t>(piece));
      if (rng.percent(50)) sim.send(g, rng, kT);
      sim.send(f, rng, kT);
      if (rng.percent(50)) sim.send(g, rng, kT);
      return;
    }
    case Fault::kReplay:
      sim.send(f, rng, kT);
      f = host.sent_before(1 + rng.below(6));
      break;
    case Fault::kRestart: {
      // A new session numbering from 1 (v2: numbering from 1 again), between frames or cutting this one.
      if (rng.percent(50)) f.resize(rng.below(f.size()));
      sim.send(f, rng, kT);
      if (rng.percent(30)) sim.end_of_stream();
      const Bytes old = host.sent_before(rng.below(4));
      host.restart(next_session++);
      f = host.frame(rng, max_spheres);
      if (rng.percent(60)) {
        sim.send(f, rng, kT);
        f = old;  // a frame of the ended session, sent again
      }
      break;
    }
    case Fault::kContent: {
      link::World w = random_world(rng, p, max_spheres);
      if (w.spheres.empty()) w.spheres.push_back(random_sphere(rng, p));
      link::WireSphere& s = w.spheres[rng.below(w.spheres.size())];
      switch (rng.below(8)) {
        case 0: s.x = static_cast<std::int32_t>(p.x.max_raw() + 1); break;
        case 1: s.y = static_cast<std::int32_t>(p.y.min_raw() - 1); break;
        case 2: s.z = static_cast<std::int32_t>(p.z.max_raw() + rng.between(1, 1000)); break;
        case 3: s.radius = static_cast<std::uint32_t>(p.radius.max_raw() + 1); break;
        case 4: s.radius = 0; break;
        case 5: s.material = static_cast<std::uint8_t>(rng.between(3, 255)); break;
        case 6: s.ior = 0; break;
        default: w.frac_bits = static_cast<std::uint8_t>(p.frac_bits() + (rng.percent(50) ? 1 : -1)); break;
      }
      f = host.stamp(w);
      break;
    }
    case Fault::kLyingHeader: {
      // A header whose CRC (v3) matches and that still must be refused, or that announces the whole scene
      // memory and so swallows what follows (v2 waits for all of it; v3 cuts it at the next intact header).
      const std::size_t count_at = wire == WireVersion::kV3 ? 16 : 12;
      const std::size_t length_at = count_at + 4;
      const std::uint32_t max = p.max_spheres;
      switch (rng.below(6)) {
        case 0: put_be32(f, count_at, max + 1 + static_cast<std::uint32_t>(rng.below(1000))); break;
        case 1: put_be32(f, length_at, static_cast<std::uint32_t>(f.size() + 1)); break;  // not count * 24
        case 2: f[5] = static_cast<std::uint8_t>(rng.between(31, 255)); break;
        case 3: f[6 + rng.below(2)] = static_cast<std::uint8_t>(rng.between(1, 255)); break;
        case 4: f[4] = static_cast<std::uint8_t>(rng.percent(50) ? 1 : 4); break;
        default: {
          // v2 waits for every byte such a header announces: at most 100 spheres there, to bound the run.
          const std::uint32_t most = wire == WireVersion::kV3 ? max : std::min<std::uint32_t>(max, 100);
          const std::uint32_t n = rng.percent(50) ? most : static_cast<std::uint32_t>(rng.between(1, 8));
          put_be32(f, count_at, n);
          put_be32(f, length_at, n * 24);
          break;
        }
      }
      fix_crcs(wire, f);
      break;
    }
    case Fault::kEmbeddedHeader: {
      // A header (intact, or with a broken CRC) placed inside the payload of a frame whose own CRC is good.
      Bytes inner = host.frame(rng, 2);
      if (f.size() < 100) f = host.frame(rng, 8);
      if (f.size() >= 90) {
        const std::size_t hb = wire == WireVersion::kV3 ? 28 : 20;
        const std::size_t at = static_cast<std::size_t>(rng.between(static_cast<std::int64_t>(hb),
                                                                    static_cast<std::int64_t>(f.size() - 4 - 28)));
        if (rng.percent(30)) inner[24 + rng.below(4)] ^= 0x01;
        std::copy(inner.begin(), inner.begin() + 28, f.begin() + static_cast<std::ptrdiff_t>(at));
        fix_crcs(wire, f);
      }
      break;
    }
  }
  sim.send(f, rng, kT);
}

template <class C>
void damaged_streams(std::uint64_t seed, int episodes_per_fault, int max_spheres) {
  CoSim<C> sim;
  Rng rng(seed);
  Host host(C::kWire, C::preset(), 0xABCD0001u);
  std::uint32_t next_session = 0xABCD0002u;
  for (int e = 0; e < episodes_per_fault * kFaults && !sim.failed(); ++e) {
    const auto fault = static_cast<Fault>(e % kFaults);
    sim.set_context(std::string("episode ") + std::to_string(e) + " (" + name_of(fault) + ")");
    for (std::int64_t k = rng.between(0, 2); k > 0; --k) {
      sim.send(host.frame(rng, max_spheres), rng, 1024);
      if (rng.percent(50)) sim.vblank();
    }
    damage_one(sim, host, rng, fault, max_spheres, next_session);
    if (rng.percent(50)) sim.vblank();
    for (std::int64_t k = rng.between(1, 2); k > 0; --k) sim.send(host.frame(rng, max_spheres), rng, 1024);
    sim.vblank();
  }
  EXPECT_FALSE(sim.failed());
  const device::ReceiverStats& s = sim.model().stats();
  // The streams must have exercised what they are for.
  EXPECT_GT(s.frames_rejected, 0u);
  EXPECT_GT(s.garbage_runs, 0u);
  EXPECT_GT(s.worlds_accepted, 0u);
  if (C::kWire == WireVersion::kV3) {
    EXPECT_GT(s.worlds_replayed, 0u);
  }
  EXPECT_GT(s.worlds_missing, 0u);
  EXPECT_GT(sim.cut_bytes(), 0u);
}

// v1 under damage: dropped bytes shift every later word, garbage is read as words, a word outside the preset
// is refused, a host that stops mid-word loses it.
template <class C>
void v1_damage(std::uint64_t seed, int episodes) {
  CoSim<C> sim;
  Rng rng(seed);
  for (int e = 0; e < episodes && !sim.failed(); ++e) {
    sim.set_context("v1 episode " + std::to_string(e));
    Bytes bytes;
    for (std::int64_t k = rng.between(1, 6); k > 0; --k) {
      link::V1Sphere s{static_cast<std::int32_t>(rng.between(-4096, 4095)),
                       static_cast<std::int32_t>(rng.between(-2048, 2047)),
                       static_cast<std::int32_t>(rng.between(-2048, 2047)),
                       static_cast<std::uint8_t>(rng.between(0, rng.percent(80) ? 12 : 63)),
                       static_cast<std::uint16_t>(rng.below(4096))};
      link::append_v1_bytes(link::encode_v1_word(s), bytes);
    }
    switch (rng.below(4)) {
      case 0: bytes.erase(bytes.begin() + static_cast<std::ptrdiff_t>(rng.below(bytes.size()))); break;
      case 1: bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(rng.below(bytes.size())), rng.byte()); break;
      case 2: bytes[rng.below(bytes.size())] ^= static_cast<std::uint8_t>(1u << rng.below(8)); break;
      default: break;
    }
    sim.send(bytes, rng, 12);
    if (rng.percent(25)) sim.end_of_stream();
    if (rng.percent(60)) sim.vblank();
  }
  sim.end_of_stream();
  sim.vblank();
  EXPECT_FALSE(sim.failed());
  EXPECT_GT(sim.model().stats().frames_rejected, 0u);
  EXPECT_GT(sim.model().stats().worlds_replaced, 0u);
  EXPECT_GT(sim.cut_bytes(), 0u);
}

// Hostile streams, in the spirit of fuzz/receiver_fuzz.cpp: frames nested in frames, headers that pass (with
// matching header CRCs on v3) and announce frames that swallow what follows, runs of magics and partial magics,
// noise; cut into transfers of any size, with ends of stream and blankings anywhere.
template <class C>
void hostile_streams(std::uint64_t seed, int pieces, std::uint32_t most_announced) {
  CoSim<C> sim;
  Rng rng(seed);
  const WireVersion wire = C::kWire;
  const device::DevicePreset p = C::preset();
  Host host(wire, p, 0x0BAD0001u);
  std::uint32_t next_session = 0x0BAD0002u;
  const std::size_t hb = wire == WireVersion::kV3 ? 28 : 20;
  const std::size_t count_at = wire == WireVersion::kV3 ? 16 : 12;
  const Bytes magic = wire == WireVersion::kV3 ? Bytes{'T', 'S', 'W', '3'} : Bytes{'T', 'S', 'W', '2'};
  for (int i = 0; i < pieces && !sim.failed(); ++i) {
    Bytes piece;
    const std::uint64_t kind = rng.below(7);
    sim.set_context("hostile piece " + std::to_string(i) + " (kind " + std::to_string(kind) + ")");
    switch (kind) {
      case 0: piece = host.frame(rng, 6); break;
      case 1: {
        // A header alone that passes, announcing up to `most_announced` spheres.
        piece = host.frame(rng, 1);
        const auto n = static_cast<std::uint32_t>(rng.between(0, most_announced));
        put_be32(piece, count_at, n);
        put_be32(piece, count_at + 4, n * 24);
        fix_crcs(wire, piece);
        piece.resize(hb + rng.below(8));
        break;
      }
      case 2: {
        // Frames nested in a frame's payload, the outer CRC good or not.
        piece = host.frame(rng, 12);
        while (piece.size() < hb + 4 + 150) piece = host.frame(rng, 12);
        for (std::int64_t k = rng.between(1, 2); k > 0; --k) {
          const Bytes inner = host.frame(rng, 2);
          const std::size_t room = piece.size() - 4 - hb;
          if (inner.size() > room) continue;
          const std::size_t at = hb + rng.below(room - inner.size() + 1);
          std::copy(inner.begin(), inner.end(), piece.begin() + static_cast<std::ptrdiff_t>(at));
        }
        if (rng.percent(60)) fix_crcs(wire, piece);
        break;
      }
      case 3:
        // Magics and partial magics back to back.
        for (std::int64_t k = rng.between(1, 6); k > 0; --k)
          piece.insert(piece.end(), magic.begin(), magic.begin() + static_cast<std::ptrdiff_t>(rng.between(1, 4)));
        break;
      case 4:
        for (std::int64_t k = rng.between(1, 40); k > 0; --k) piece.push_back(rng.byte());
        break;
      case 5: {
        // A good frame with one byte changed to a magic letter.
        piece = host.frame(rng, 4);
        piece[rng.below(piece.size())] = magic[rng.below(4)];
        break;
      }
      default:
        host.restart(next_session++);
        piece = host.frame(rng, 3);
        break;
    }
    sim.send(piece, rng, rng.percent(50) ? 8 : 300);
    if (rng.percent(4)) sim.end_of_stream();
    if (rng.percent(25)) sim.vblank();
  }
  sim.end_of_stream();
  sim.vblank();
  EXPECT_FALSE(sim.failed());
  EXPECT_GT(sim.model().stats().worlds_accepted, 0u);
  EXPECT_GT(sim.model().stats().frames_rejected, 0u);
}

// ---- Tests ----

TEST(RtlCrc32, MatchesTheLinksCrc) {
  auto ctx = std::make_unique<VerilatedContext>();
  ctx->randReset(2);
  auto top = std::make_unique<Vts_rx_crc32>(ctx.get());
  const auto tick = [&] {
    top->clk = 0;
    top->eval();
    top->clk = 1;
    top->eval();
  };
  top->rst = 1;
  top->en = 0;
  top->clear = 0;
  tick();
  top->rst = 0;
  Rng rng(20);
  for (int c = 0; c < 300; ++c) {
    Bytes bytes(static_cast<std::size_t>(rng.between(0, 120)));
    for (auto& b : bytes) b = rng.byte();
    if (c == 0) bytes = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};  // the check value 0xCBF43926
    // Clear alone, or with the first byte (as the receiver does at a frame's first byte).
    const bool clear_with_first = c % 2 == 1 && !bytes.empty();
    top->clear = 1;
    top->en = 0;
    for (std::size_t i = 0; i < bytes.size(); ++i) {
      if (i > 0 || clear_with_first) {
        top->en = 1;
        top->data = bytes[i];
        top->clear = i == 0 ? 1 : 0;
      } else {
        tick();  // clear alone
        top->clear = 0;
        top->en = 1;
        top->data = bytes[i];
      }
      tick();
    }
    if (bytes.empty()) tick();
    top->en = 0;
    top->clear = 0;
    const std::uint32_t expected = core::crc32(bytes);
    ASSERT_EQ(top->crc, expected) << "case " << c << ", " << bytes.size() << " bytes";
  }
  top->final();
}

TEST(RtlReceiver, V1WideGoodWords) { good_worlds<V1Wide>(101, 60, 1); }
TEST(RtlReceiver, V1BoardGoodWords) { good_worlds<V1Board>(102, 60, 1); }
TEST(RtlReceiver, V2WideGoodWorlds) { good_worlds<V2Wide>(201, 40, 24); }
TEST(RtlReceiver, V2BoardGoodWorlds) { good_worlds<V2Board>(202, 40, 64); }
TEST(RtlReceiver, V3WideGoodWorlds) { good_worlds<V3Wide>(301, 40, 24); }
TEST(RtlReceiver, V3BoardGoodWorlds) { good_worlds<V3Board>(302, 40, 64); }
// SCLK at clk/8, the fastest the SPI slave takes.
TEST(RtlReceiver, V3BoardGoodWorldsAtClkOver8) { good_worlds<V3Board>(303, 10, 16, 4); }

TEST(RtlReceiver, V1WideDamaged) { v1_damage<V1Wide>(111, 80); }
TEST(RtlReceiver, V1BoardDamaged) { v1_damage<V1Board>(112, 80); }
TEST(RtlReceiver, V2WideDamaged) { damaged_streams<V2Wide>(211, 12, 12); }
TEST(RtlReceiver, V2BoardDamaged) { damaged_streams<V2Board>(212, 12, 12); }
TEST(RtlReceiver, V3WideDamaged) { damaged_streams<V3Wide>(311, 12, 12); }
TEST(RtlReceiver, V3BoardDamaged) { damaged_streams<V3Board>(312, 12, 12); }

TEST(RtlReceiver, V2WideHostile) { hostile_streams<V2Wide>(221, 300, 60); }
TEST(RtlReceiver, V2BoardHostile) { hostile_streams<V2Board>(222, 300, 64); }
TEST(RtlReceiver, V3WideHostile) { hostile_streams<V3Wide>(321, 300, 4096); }
TEST(RtlReceiver, V3BoardHostile) { hostile_streams<V3Board>(322, 300, 64); }

// The artix path preset's receiver, which takes worlds with a hierarchy: worlds without one as every v3 receiver
// takes them (good, damaged and hostile streams), and the host's hierarchies of random path worlds, each sent as
// built and broken in one of the ways the wire's rules name (hierarchy_worlds.h), with good worlds between, a chain
// too deep, and headers that lie about the hierarchy: every world the model accepts is accepted and shown, every
// one it refuses is refused and counted, the last good world staying on screen.
TEST(RtlReceiver, V3ArtixPathGoodWorlds) { good_worlds<V3ArtixPath>(341, 20, 24); }
TEST(RtlReceiver, V3ArtixPathDamaged) { damaged_streams<V3ArtixPath>(342, 4, 12); }
TEST(RtlReceiver, V3ArtixPathHostile) { hostile_streams<V3ArtixPath>(345, 100, 256); }
TEST(RtlReceiver, V3ArtixPathHierarchies) {
  CoSim<V3ArtixPath> sim;
  Rng rng(343);
  std::mt19937_64 worlds(344);
  Host host(WireVersion::kV3, hierarchy::preset(), 0x41A70001u);
  int sent = 0, refused = 0;
  for (int trial = 0; trial < 12 && !sim.failed(); ++trial) {
    const link::World w = hierarchy::random_world(worlds, trial % 6 == 0);
    sim.set_context("world " + std::to_string(trial) + " as built, " + std::to_string(w.nodes.size()) + " nodes");
    sim.send(host.stamp(w), rng, 1024, 0);
    sim.vblank();
    if (w.nodes.size() < 2) continue;
    for (const hierarchy::Damage& d : hierarchy::damages()) {
      link::World broken = w;
      if (!d.apply(broken, worlds) || rng.percent(50)) continue;
      sim.set_context("world " + std::to_string(trial) + ", " + d.name);
      ++sent;
      refused += !hierarchy::accepted(broken);
      sim.send(host.stamp(broken), rng, 1024, 0);
      if (rng.percent(50)) sim.vblank();
    }
  }
  sim.set_context("a chain 9 deep");
  sim.send(host.stamp(hierarchy::chain(9)), rng, 1024, 0);
  sim.vblank();
  // Headers that lie about the hierarchy: content 1 with no node's bytes, with part of one (12 bytes; 32, a multiple
  // of 8 but not of 24), with more nodes than scene memory holds spheres; a content byte of 2. Each refused at its
  // header; a good world after each.
  const link::World good = hierarchy::random_world(worlds, false);
  for (int lie = 0; lie < 5; ++lie) {
    Bytes f = host.stamp(good);
    const std::uint32_t spheres_bytes = static_cast<std::uint32_t>(good.spheres.size() * 24);
    const std::uint32_t lengths[] = {spheres_bytes, spheres_bytes + 12, spheres_bytes + 32, spheres_bytes + 24 * 257};
    if (lie < 4) {
      f[6] = link::kContentHierarchy;
      put_be32(f, 20, lengths[lie]);
    } else {
      f[6] = 2;
    }
    fix_crcs(WireVersion::kV3, f);
    sim.set_context("a lying header " + std::to_string(lie));
    sim.send(f, rng, 1024, 0);
    sim.send(host.stamp(good), rng, 1024, 0);
    sim.vblank();
  }
  EXPECT_FALSE(sim.failed());
  EXPECT_GT(sent, 50);
  EXPECT_GT(refused, 40);
  EXPECT_GT(sim.model().stats().frames_rejected, static_cast<std::uint64_t>(refused / 2));
  EXPECT_GT(sim.swaps_checked(), 12);
}

// A big world on the wide preset: the commit copies hundreds of spheres, and a damaged copy of it must not
// touch the world waiting for the swap.
TEST(RtlReceiver, V3WideBigWorldAndADamagedOneWhilePending) {
  CoSim<V3Wide> sim;
  Rng rng(321);
  Host host(WireVersion::kV3, device::wide_preset(), 77);
  sim.set_context("a world of 300 spheres");
  link::World w = random_world(rng, device::wide_preset(), 1);
  while (w.spheres.size() < 300) w.spheres.push_back(random_sphere(rng, device::wide_preset()));
  const Bytes big = host.stamp(w);
  sim.send(big, rng, 1024, 0);
  sim.set_context("a damaged world while one is pending");
  Bytes bad = host.frame(rng, 20);
  bad[bad.size() / 2] ^= 0x40;
  sim.send(bad, rng, 1024, 0);
  sim.vblank();
  EXPECT_EQ(sim.front().geometry.size(), 300u);
  EXPECT_FALSE(sim.failed());
}

// v2's weakness (docs/link_format.md, "Why one damaged byte costs one world"): a byte lost in the sequence
// field shifts a zero into count and length, which still agree, and the decoder waits for 256 times the frame
// (74 KB here), reading the following worlds as its payload. The RTL must hold all of it in its byte buffer,
// fail its CRC, and go back over it to find the worlds inside, as the model does.
TEST(RtlReceiver, V2WideWorldsSwallowedByALyingHeader) {
  CoSim<V2Wide> sim;
  Rng rng(231);
  const device::DevicePreset p = device::wide_preset();
  Host host(WireVersion::kV2, p, 0);
  sim.set_context("the damaged frame");
  link::World w = random_world(rng, p, 1);
  w.spheres.clear();
  for (int i = 0; i < 12; ++i) w.spheres.push_back(random_sphere(rng, p));
  w.spheres[0].x = 5;  // the first payload byte is 0
  Bytes f = host.stamp(w);
  f.erase(f.begin() + 8);  // count and length become 12 * 256 spheres and 12 * 256 * 24 bytes
  sim.send(f, rng, 1024, 0);
  std::size_t sent = 0;
  for (int i = 0; sent < 80'000 && !sim.failed(); ++i) {
    sim.set_context("swallowed world " + std::to_string(i));
    const Bytes g = host.frame(rng, 12);
    sent += g.size();
    sim.send(g, rng, 1024, 0);
    if (i % 50 == 0) sim.vblank();
    if (sent < 70'000) {
      EXPECT_EQ(sim.model().stats().worlds_accepted, 0u);  // swallowed, so far
    }
  }
  sim.vblank();
  EXPECT_FALSE(sim.failed());
  // Then the lying frame's CRC failed, and the hunt through its bytes delivered the worlds inside at once.
  EXPECT_EQ(sim.model().stats().frames_rejected, 1u);
  EXPECT_GT(sim.model().stats().worlds_accepted, 200u);
  const Bytes& newest = host.sent_before(0);
  const std::uint32_t newest_sequence = (std::uint32_t{newest.at(8)} << 24) | (std::uint32_t{newest.at(9)} << 16) |
                                        (std::uint32_t{newest.at(10)} << 8) | newest.at(11);
  EXPECT_EQ(sim.front().sequence, newest_sequence);  // the newest world is shown
}

// The read ports' timing contract across a swap (data the clock after the address, from the copy that was the
// front then).
TEST(RtlReceiver, V3BoardReadsAcrossASwap) {
  CoSim<V3Board> sim;
  Rng rng(351);
  Host host(WireVersion::kV3, device::board_2023_preset(), 9);
  for (int i = 0; i < 6 && !sim.failed(); ++i) {
    sim.set_context("world " + std::to_string(i));
    sim.send(host.frame(rng, 4), rng, 64, 0);
    sim.vblank_reading_across();
  }
  EXPECT_FALSE(sim.failed());
}

// v3 remembers 16 ended sessions: frames of those are replays; a frame of the 17th oldest is shown again.
TEST(RtlReceiver, V3BoardEndedSessions) {
  CoSim<V3Board> sim;
  Rng rng(331);
  std::vector<Bytes> first_of_session;
  Host host(WireVersion::kV3, device::board_2023_preset(), 1000);
  for (std::uint32_t s = 0; s < 20 && !sim.failed(); ++s) {
    host.restart(1000 + s);
    sim.set_context("session " + std::to_string(s));
    first_of_session.push_back(host.frame(rng, 3));
    sim.send(first_of_session.back(), rng, 64, 0);
    sim.send(host.frame(rng, 3), rng, 64, 0);
    sim.vblank();
  }
  // Newest first: session 19 is current (its first world is old), 18..3 have ended, 2..0 are forgotten and
  // so begin sessions again.
  for (std::size_t s = first_of_session.size(); s-- > 0 && !sim.failed();) {
    sim.set_context("a replay of session " + std::to_string(s));
    sim.send(first_of_session[s], rng, 64, 0);
    sim.vblank();
  }
  EXPECT_FALSE(sim.failed());
  EXPECT_EQ(sim.model().stats().worlds_replayed, 17u);
  EXPECT_EQ(sim.model().stats().sessions, 23u);
}

// Chip select rising inside a byte: the partial byte is dropped and the stream goes on from the next transfer.
TEST(RtlReceiver, V3BoardChipSelectRisingMidByte) {
  CoSim<V3Board> sim;
  Rng rng(341);
  Host host(WireVersion::kV3, device::board_2023_preset(), 5);
  for (int i = 0; i < 12 && !sim.failed(); ++i) {
    sim.set_context("world " + std::to_string(i));
    sim.send(host.frame(rng, 4), rng, 9, 40);
    sim.vblank();
  }
  EXPECT_FALSE(sim.failed());
  EXPECT_GT(sim.cut_bytes(), 5u);
  EXPECT_EQ(sim.model().stats().frames_rejected, 0u);
}

}  // namespace
}  // namespace tripsitter::rtl

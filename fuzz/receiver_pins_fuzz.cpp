// The receiver RTL from its pins (rtl/receiver/ts_receiver_top.sv, Verilated: SPI slave -> receiver -> scene
// memory) against the C++ receiver (device/receiver.h), with SCLK, MOSI and CS_n driven at legal and illegal
// timings.
//
// Input: a configuration byte, a count byte and that many transfer bytes, as receiver_fuzz.cpp; then a timing
// count byte and that many timing records of 2 bytes; then the link bytes (at most kMaxLinkBytes are used).
//   configuration: as receiver_fuzz.cpp: bit 0 the wire v1 (when clear: bit 5 chooses v3 over v2), bit 1 the preset
//                  (0 wide, 1 board-2023), bits 2..3 the transfer length unit (1, 4, 16 or 64 bytes), bit 4 keep
//                  the frames' CRCs as they are (when clear they are rewritten first: frame_repair.h); and bit 6
//                  allow illegal timings (when clear, every timing is mapped into ts_spi_rx's contract);
//   count:         0..15 transfer bytes (count % 16); none sends the link bytes as one transfer;
//   transfer byte: bits 0..6 the transfer's length in units (0 is an empty transfer), bit 7 a vertical blanking
//                  (swap_if_pending; vblank_swap on the RTL) after it; used in turn, cyclically;
//   timing count:  0..15 timing records (count % 16), used in turn, one per transfer, cyclically; none: SCLK at
//                  clk/6 (half periods of 3 clocks, the least ts_spi_rx takes), MOSI changed at SCLK's falling
//                  edge, no cut, 3-clock gaps;
//   timing record: byte 0: bits 0..2 SCLK's low half period, bits 3..5 its high half period, as codes 0..7 for
//                  3, 3, 4, 4, 5, 5, 8, 12 device clocks (with bit 6 of the configuration, codes 0 and 1 are the
//                  illegal 1 and 2 clocks); bits 6..7 when MOSI changes: 0 at SCLK's fall, 1 one clock before
//                  its rise, 2 the bit's value only in the clock of the rise (illegal: no setup; else mid-low), 3
//                  the next bit's value already in the clock of the rise (illegal: no hold, a mode 1 host; else
//                  two clocks before the rise);
//                  byte 1: bits 0..2 a cut: chip select rises after that many bits (1..7) of the transfer's last
//                  byte, which is lost; bits 3..4 chip select (illegal ones only with bit 6 of the configuration):
//                  0 legal (falls with SCLK's first low half period, rises a clock after its last fall), 1 falls
//                  late, from one clock after the first rising edge to two before it, 2 rises early, 0 to 2
//                  clocks after the last rising edge, 3 stays high only 1 or 2 clocks before the next transfer;
//                  bits 5..6 the gap after the transfer: 3, 6 or 20 clocks, or 24 clocks with three SCLK pulses
//                  (and MOSI changes) while chip select is high; bit 7 an end of stream (the host went away:
//                  end_of_stream on both) in clock n * k / 8 of the transfer's n clocks, k = (byte 0 ^ byte 1) & 7,
//                  so anywhere from before chip select falls to the middle of a byte or the gap: the C++ receiver
//                  gets the bytes delivered up to that clock (a byte the RTL takes in the clock of end_of_stream
//                  comes first, ts_rx_frame.sv), then end_of_stream(). ts_rx_frame keeps one pending end of stream,
//                  so before raising another the pins are held until the RTL is idle (the first one handled).
// At the end: end of stream and one last vertical blanking.
//
// A transfer is legal when its half periods, MOSI moments, chip select and the gap before it all keep ts_spi_rx's
// contract (its comment: half periods of 3 clocks or more, MOSI changing only while SCLK is low, a mode 0 host).
// Checks:
//   - ts_spi_rx (its byte_valid and byte_data, read from the model: receiver_pins.vlt): the bytes it delivers in a
//     legal transfer are exactly the transfer's link bytes, less the last one when the transfer is cut, and
//     spi_byte_cut pulses once for a cut transfer and never otherwise; in an illegal transfer anything may come
//     out, and whatever does is what the C++ receiver is given;
//   - the C++ receiver gets the bytes ts_spi_rx delivered, in the same order, with the same ends of stream and
//     vertical blankings between them;
//   - where the RTL is idle (its timing contract): at the end of a transfer's gap when it happens to be idle with
//     every delivered byte taken, and, waiting for it, before and after every vertical blanking and after the last
//     end of stream: every ReceiverStats counter the top has (worlds_accepted, worlds_replaced, frames_rejected,
//     garbage_runs, bytes_dropped, worlds_missing, worlds_replayed, sessions) and the ready line equal the C++
//     receiver's, and bytes_received is the number of bytes delivered; at the end overflow_bytes is 0 (the link
//     bytes are fewer than the smallest buffer); the RTL becomes idle within kSettleClocks whenever it is waited for;
//   - after every vertical blanking: the front copy (valid, sequence, sphere count, and every sphere's x, y, z,
//     radius, metal flag and albedo, read through both read ports, which must agree) equals the C++ front
//     SceneMemory.
// RECEIVER_PINS_TRACE=1 in the environment prints every step (to read a reproducer).
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <verilated.h>

// The models' root classes (the SPI slave's public signals) are Verilator's code, with anonymous structs.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpedantic"
#if defined(__clang__)
#pragma clang diagnostic ignored "-Wgnu-anonymous-struct"
#pragma clang diagnostic ignored "-Wnested-anon-types"
#endif
#include "Vts_pins_v1_board.h"
#include "Vts_pins_v1_board___024root.h"
#include "Vts_pins_v1_wide.h"
#include "Vts_pins_v1_wide___024root.h"
#include "Vts_pins_v2_board.h"
#include "Vts_pins_v2_board___024root.h"
#include "Vts_pins_v2_wide.h"
#include "Vts_pins_v2_wide___024root.h"
#include "Vts_pins_v3_board.h"
#include "Vts_pins_v3_board___024root.h"
#include "Vts_pins_v3_wide.h"
#include "Vts_pins_v3_wide___024root.h"
#pragma GCC diagnostic pop

#include <tripsitter/device/preset.h>
#include <tripsitter/device/receiver.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/link/frame.h>

#include "check.h"
#include "frame_repair.h"
#include "transfers.h"

namespace {

using tripsitter::fuzz::Transfer;

namespace device = tripsitter::device;
namespace link = tripsitter::link;

// Fewer than board-2023's 4 KiB byte buffer (ts_rx_frame), so the RTL never overflows; and few enough that an
// execution stays fast (a byte is 16 to 192 clocks on the pins, 48 at the default timing).
constexpr std::size_t kMaxLinkBytes = 512;
// The most clocks the RTL may take to become idle once the pins are quiet.
constexpr int kSettleClocks = 2'000'000;

bool tracing() {
  static const bool on = std::getenv("RECEIVER_PINS_TRACE") != nullptr;
  return on;
}

// ---- The configurations: one Verilated model per wire and preset (fuzz/CMakeLists.txt) ----

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
template <class M, link::WireVersion W, class P>
struct Cfg : P {
  using Model = M;
  static constexpr link::WireVersion kWire = W;
};

// ---- The input ----

// The transfers of receiver_fuzz.cpp's rule; no link bytes still make one empty transfer, which moves the pins.
std::vector<Transfer> pin_transfers_of(std::span<const std::uint8_t> ops, std::size_t unit, std::size_t size) {
  std::vector<Transfer> transfers = tripsitter::fuzz::transfers_of(ops, unit, size);
  if (transfers.empty()) transfers.push_back({});
  return transfers;
}

enum class Mosi { kAtFall, kSetup1, kMidLow, kSetup2, kSetup0, kHold0 };
enum class Cs { kLegal, kLateFall, kEarlyRise, kShortGap };

// One transfer's timing (a timing record, decoded).
struct Timing {
  int low = 3, high = 3;  // SCLK half periods, device clocks
  Mosi mosi = Mosi::kAtFall;
  int cut_bits = 0;        // 1..7: chip select rises after that many bits of the last byte
  Cs cs = Cs::kLegal;
  int cs_shift = 0;        // kLateFall: -1..2 clocks before the first rise; kEarlyRise: 0..2 after the last; kShortGap: 1..2
  int gap = 3;             // clocks of chip select high after the transfer
  bool sclk_while_deselected = false;
  bool end_of_stream = false;
  int end_of_stream_eighth = 0;  // where in the transfer: eighths of its clocks
  bool legal() const { return low >= 3 && high >= 3 && mosi != Mosi::kSetup0 && mosi != Mosi::kHold0 && cs == Cs::kLegal; }
};

Timing timing_of(std::uint8_t b0, std::uint8_t b1, bool allow_illegal) {
  static constexpr std::array<int, 8> kHalf{3, 3, 4, 4, 5, 5, 8, 12};
  const auto half = [&](int code) { return allow_illegal && code < 2 ? code + 1 : kHalf[static_cast<std::size_t>(code)]; };
  Timing t;
  t.low = half(b0 & 7);
  t.high = half((b0 >> 3) & 7);
  switch (b0 >> 6) {
    case 0: t.mosi = Mosi::kAtFall; break;
    case 1: t.mosi = Mosi::kSetup1; break;
    case 2: t.mosi = allow_illegal ? Mosi::kSetup0 : Mosi::kMidLow; break;
    default: t.mosi = allow_illegal ? Mosi::kHold0 : Mosi::kSetup2; break;
  }
  t.cut_bits = b1 & 7;
  if (allow_illegal) t.cs = static_cast<Cs>((b1 >> 3) & 3);
  const int mix = (b0 ^ b1 ^ (b1 >> 5)) & 3;
  switch (t.cs) {
    case Cs::kLateFall: t.cs_shift = mix - 1; break;
    case Cs::kEarlyRise: t.cs_shift = mix % 3; break;
    case Cs::kShortGap: t.cs_shift = 1 + (mix & 1); break;
    case Cs::kLegal: break;
  }
  static constexpr std::array<int, 4> kGap{3, 6, 20, 24};
  t.gap = kGap[static_cast<std::size_t>((b1 >> 5) & 3)];
  t.sclk_while_deselected = ((b1 >> 5) & 3) == 3;
  if (t.cs == Cs::kShortGap) t.gap = t.cs_shift;
  t.end_of_stream = (b1 & 0x80) != 0;
  t.end_of_stream_eighth = (b0 ^ b1) & 7;
  return t;
}

// ---- The pins: one transfer as a waveform, clock by clock ----

struct Pins {
  std::uint8_t cs_n = 1, sclk = 0, mosi = 0;
};

// The clocks of one transfer: `whole` bytes and then `cut_bits` bits of `cut_byte`, chip select and the gap after.
std::vector<Pins> waveform(std::span<const std::uint8_t> whole, std::uint8_t cut_byte, const Timing& t,
                           std::uint8_t mosi_before) {
  std::vector<std::uint8_t> bits;
  for (const std::uint8_t b : whole) {
    for (int k = 7; k >= 0; --k) bits.push_back(static_cast<std::uint8_t>((b >> k) & 1));
  }
  for (int k = 0; k < t.cut_bits; ++k) bits.push_back(static_cast<std::uint8_t>((cut_byte >> (7 - k)) & 1));

  std::vector<Pins> w;
  w.reserve(bits.size() * static_cast<std::size_t>(t.low + t.high) + 32 + static_cast<std::size_t>(t.gap));
  // MOSI changes: (clock, value), applied in order and held.
  std::vector<std::pair<std::size_t, std::uint8_t>> mosi_changes;
  std::size_t first_rise = 0, last_rise = 0;
  for (std::size_t i = 0; i < bits.size(); ++i) {
    const std::size_t start = w.size();
    const std::size_t rise = start + static_cast<std::size_t>(t.low);
    if (i == 0) first_rise = rise;
    last_rise = rise;
    for (int c = 0; c < t.low; ++c) w.push_back({0, 0, 0});
    for (int c = 0; c < t.high; ++c) w.push_back({0, 1, 0});
    const auto low = static_cast<std::size_t>(t.low);
    switch (t.mosi) {
      case Mosi::kAtFall: mosi_changes.push_back({start, bits[i]}); break;
      case Mosi::kSetup1: mosi_changes.push_back({rise - 1, bits[i]}); break;
      case Mosi::kMidLow: mosi_changes.push_back({start + low / 2, bits[i]}); break;
      case Mosi::kSetup2: mosi_changes.push_back({rise - std::min<std::size_t>(2, low), bits[i]}); break;
      case Mosi::kSetup0: mosi_changes.push_back({rise, bits[i]}); break;
      case Mosi::kHold0:
        if (i == 0) mosi_changes.push_back({start, bits[0]});
        if (i + 1 < bits.size()) mosi_changes.push_back({rise, bits[i + 1]});
        break;
    }
  }
  if (bits.empty()) {
    for (int c = 0; c < 3; ++c) w.push_back({0, 0, 0});  // an empty transfer: chip select low alone
  } else {
    w.push_back({0, 0, 0});  // SCLK's last fall; chip select rises in the clock after
  }
  const std::size_t selected_end = w.size();  // chip select is high from here
  // The gap, chip select high: SCLK low, or pulsing (another device's traffic) with 3 quiet clocks each side.
  if (t.sclk_while_deselected) {
    for (int c = 0; c < 3; ++c) w.push_back({1, 0, 0});
    for (int p = 0; p < 3; ++p) {
      mosi_changes.push_back({w.size(), static_cast<std::uint8_t>(p & 1)});
      for (int c = 0; c < 3; ++c) w.push_back({1, 0, 0});
      for (int c = 0; c < 3; ++c) w.push_back({1, 1, 0});
    }
    for (int c = 0; c < 3; ++c) w.push_back({1, 0, 0});
  } else {
    for (int c = 0; c < t.gap; ++c) w.push_back({1, 0, 0});
  }
  // Chip select: low over the transfer, except as the timing moves its edges.
  std::size_t fall = 0, rise = selected_end;
  if (!bits.empty() && t.cs == Cs::kLateFall) {
    fall = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, static_cast<std::ptrdiff_t>(first_rise) - t.cs_shift));
  }
  if (!bits.empty() && t.cs == Cs::kEarlyRise) rise = last_rise + static_cast<std::size_t>(t.cs_shift);
  for (std::size_t c = 0; c < w.size(); ++c) w[c].cs_n = c >= fall && c < rise ? 0 : 1;
  // MOSI.
  std::uint8_t mosi = mosi_before;
  std::size_t next = 0;
  for (std::size_t c = 0; c < w.size(); ++c) {
    while (next < mosi_changes.size() && mosi_changes[next].first <= c) mosi = mosi_changes[next++].second;
    w[c].mosi = mosi;
  }
  return w;
}

// ---- What is compared ----

struct FrontSphere {
  std::int64_t x = 0, y = 0, z = 0, r = 0;
  bool metal = false;
  std::array<std::uint8_t, 3> albedo{};
  bool operator==(const FrontSphere&) const = default;
};

std::int64_t sign_extend(std::uint64_t v, int bits) {
  const std::uint64_t sign = std::uint64_t{1} << (bits - 1);
  v &= (sign << 1) - 1;
  return static_cast<std::int64_t>(v ^ sign) - static_cast<std::int64_t>(sign);
}

[[noreturn]] void disagree(const std::string& what, const std::string& where) {
  std::fprintf(stderr, "receiver_pins: %s (%s)\n", what.c_str(), where.c_str());
  FUZZ_CHECK(false, "the RTL and the C++ receiver disagree, or ts_spi_rx broke its contract (line above)");
  std::abort();
}

std::string bytes_text(std::span<const std::uint8_t> bytes) {
  std::string s;
  char hex[4];
  for (const std::uint8_t b : bytes) {
    std::snprintf(hex, sizeof hex, "%02x", b);
    s += hex;
  }
  return s;
}

// ---- The RTL and the model side by side ----

template <class C>
class Bench {
 public:
  explicit Bench(std::uint32_t seed) : ctx_(std::make_unique<VerilatedContext>()), model_(C::preset(), C::kWire) {
    ctx_->randReset(2);  // random initial state (from a seed of the input): the reset must make it irrelevant
    ctx_->randSeed(static_cast<int>(seed & 0x7FFFFFFF) | 1);
    Verilated::threadContextp(ctx_.get());
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
    ticks(3);
  }
  Bench(const Bench&) = delete;
  Bench& operator=(const Bench&) = delete;
  ~Bench() { top_->final(); }

  // One transfer on the pins, `whole` bytes and the cut (t.cut_bits of `cut_byte`), then its gap. `clean`: a legal
  // transfer, which must deliver exactly `whole`.
  void transfer(std::span<const std::uint8_t> whole, std::uint8_t cut_byte, const Timing& t, bool clean) {
    const std::size_t delivered_before = delivered_.size();
    const std::uint64_t cuts_before = cuts_;
    ++step_;
    const std::vector<Pins> wave = waveform(whole, cut_byte, t, top_->mosi);
    const std::size_t eos_at =
        t.end_of_stream ? wave.size() * static_cast<std::size_t>(t.end_of_stream_eighth) / 8 : wave.size();
    for (std::size_t c = 0; c < wave.size(); ++c) {
      if (c == eos_at) raise_end_of_stream();
      top_->cs_n = wave[c].cs_n;
      top_->sclk = wave[c].sclk;
      top_->mosi = wave[c].mosi;
      tick();
    }
    const std::span<const std::uint8_t> got = std::span(delivered_).subspan(delivered_before);
    if (tracing()) {
      const bool as_sent = std::equal(got.begin(), got.end(), whole.begin(), whole.end());
      std::fprintf(stderr,
                   "step %d: transfer of %zu bytes%s (SCLK %d/%d, MOSI %d, CS %d/%d, gap %d%s%s), %s: %zu delivered%s, "
                   "%llu cut\n",
                   step_, whole.size(), t.cut_bits ? " and a cut byte" : "", t.low, t.high, static_cast<int>(t.mosi),
                   static_cast<int>(t.cs), t.cs_shift, t.gap, t.sclk_while_deselected ? ", SCLK pulses" : "",
                   t.end_of_stream ? ", end of stream" : "", clean ? "legal" : "illegal", got.size(),
                   as_sent ? " (as sent)" : " (not as sent)", static_cast<unsigned long long>(cuts_ - cuts_before));
    }
    if (clean) {
      if (!std::equal(got.begin(), got.end(), whole.begin(), whole.end())) {
        disagree("ts_spi_rx delivered " + bytes_text(got) + " for the legal transfer " + bytes_text(whole),
                 where("a transfer"));
      }
      const std::uint64_t expected_cuts = t.cut_bits > 0 ? 1 : 0;
      if (cuts_ - cuts_before != expected_cuts) {
        disagree("spi_byte_cut pulsed " + std::to_string(cuts_ - cuts_before) + " times for a legal transfer " +
                     (t.cut_bits ? "cut after " + std::to_string(t.cut_bits) + " bits" : "not cut"),
                 where("a transfer"));
      }
    }
    // Compare where the RTL happens to be idle with every byte taken (its timing contract).
    if (top_->idle && top_->bytes_received == delivered_.size()) {
      end_of_stream_unhandled_ = false;
      compare("the end of a transfer");
    }
  }

  // The last end of stream, with the pins quiet.
  void end_of_stream() {
    settle();
    raise_end_of_stream();
    settle();
    compare("end of stream");
  }

  void vblank() {
    settle();
    compare("before a vertical blanking");
    ++step_;
    model_.swap_if_pending(front_);
    top_->vblank_swap = 1;
    tick();
    top_->vblank_swap = 0;
    tick();
    settle();
    compare("a vertical blanking");
    compare_front();
  }

  void finish() {
    settle();
    compare("the end of the input");
    if (top_->overflow_bytes != 0) disagree("overflow_bytes " + std::to_string(top_->overflow_bytes), where("the end"));
  }

 private:
  void tick() {
    top_->clk = 0;
    top_->eval();
    top_->clk = 1;
    top_->eval();
    const auto* root = top_->rootp;
    if (root->ts_receiver_top__DOT__u_spi__DOT__byte_valid) {
      delivered_.push_back(root->ts_receiver_top__DOT__u_spi__DOT__byte_data);
    }
    if (top_->spi_byte_cut) ++cuts_;
  }
  void ticks(int n) {
    for (int i = 0; i < n; ++i) tick();
  }
  // end_of_stream for one clock, wherever the pins are; the C++ receiver's end_of_stream() after every byte
  // delivered so far: ts_spi_rx's byte_valid seen after the last clock is taken in this one, before the end.
  void raise_end_of_stream() {
    if (end_of_stream_unhandled_) {
      // The pins held as they are (a longer half period or gap) until the RTL has handled the last one.
      for (int i = 0; !top_->idle; ++i) {
        if (i > kSettleClocks) disagree("the RTL is not idle after " + std::to_string(kSettleClocks) + " clocks", where("holding the pins"));
        tick();
      }
    }
    ++step_;
    feed();
    model_.end_of_stream();
    top_->end_of_stream = 1;
    tick();
    top_->end_of_stream = 0;
    end_of_stream_unhandled_ = true;
    if (tracing()) std::fprintf(stderr, "step %d: end of stream after %zu bytes\n", step_, delivered_.size());
  }
  // Until every delivered byte is taken (bytes_received counts each, overflow_bytes each one dropped as full).
  void wait_taken() {
    for (int i = 0; top_->bytes_received + top_->overflow_bytes != delivered_.size(); ++i) {
      if (i > 16) disagree("bytes_received " + std::to_string(top_->bytes_received) + " of " +
                               std::to_string(delivered_.size()) + " delivered",
                           where("taking the delivered bytes"));
      tick();
    }
  }
  void settle() {
    wait_taken();
    for (int i = 0; !top_->idle; ++i) {
      if (i > kSettleClocks) disagree("the RTL is not idle after " + std::to_string(kSettleClocks) + " clocks", where("settling"));
      tick();
    }
    end_of_stream_unhandled_ = false;
  }
  // The C++ receiver gets the bytes delivered since it was last fed, as one transfer.
  void feed() {
    if (fed_ < delivered_.size()) model_.receive(std::span(delivered_).subspan(fed_));
    fed_ = delivered_.size();
  }
  std::string where(const std::string& what) const {
    return "step " + std::to_string(step_) + ", " + what + ", " + std::to_string(delivered_.size()) +
           " bytes delivered; the C++ receiver's last error: " + model_.stats().last_error;
  }
  void compare(const std::string& what) {
    feed();
    const device::ReceiverStats& s = model_.stats();
    const std::array<std::pair<const char*, std::pair<std::uint64_t, std::uint64_t>>, 10> fields{{
        {"worlds_accepted", {s.worlds_accepted, top_->worlds_accepted}},
        {"worlds_replaced", {s.worlds_replaced, top_->worlds_replaced}},
        {"frames_rejected", {s.frames_rejected, top_->frames_rejected}},
        {"garbage_runs", {s.garbage_runs, top_->garbage_runs}},
        {"bytes_dropped", {s.bytes_dropped, top_->bytes_dropped}},
        {"worlds_missing", {s.worlds_missing, top_->worlds_missing}},
        {"worlds_replayed", {s.worlds_replayed, top_->worlds_replayed}},
        {"sessions", {s.sessions, top_->sessions}},
        {"ready", {model_.ready() ? 1u : 0u, top_->ready}},
        {"bytes_received", {delivered_.size(), top_->bytes_received}},
    }};
    for (const auto& [name, values] : fields) {
      if (values.first != values.second) {
        disagree(std::string(name) + ": C++ " + std::to_string(values.first) + ", RTL " + std::to_string(values.second),
                 where(what));
      }
    }
    ++compared_;
    if (tracing()) {
      std::fprintf(stderr, "  compared at %s: accepted %llu, rejected %llu, garbage %llu, dropped %llu, ready %d\n",
                   what.c_str(), static_cast<unsigned long long>(s.worlds_accepted),
                   static_cast<unsigned long long>(s.frames_rejected), static_cast<unsigned long long>(s.garbage_runs),
                   static_cast<unsigned long long>(s.bytes_dropped), model_.ready() ? 1 : 0);
    }
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
  // The whole front copy against the C++ front: port 0 reads sphere i while port 1 reads sphere count-1-i.
  void compare_front() {
    const std::string at = where("the front copy after a vertical blanking");
    if ((top_->front_valid != 0) != front_.valid) {
      disagree("front valid: C++ " + std::to_string(front_.valid) + ", RTL " + std::to_string(top_->front_valid), at);
    }
    if (!front_.valid) return;
    if (top_->front_sequence != front_.sequence) {
      disagree("front sequence: C++ " + std::to_string(front_.sequence) + ", RTL " + std::to_string(top_->front_sequence), at);
    }
    const std::size_t count = top_->front_count;
    if (count != front_.geometry.size()) {
      disagree("front sphere count: C++ " + std::to_string(front_.geometry.size()) + ", RTL " + std::to_string(count), at);
    }
    std::vector<FrontSphere> port0(count), port1(count);
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t j = count - 1 - i;
      top_->rd_addr = static_cast<std::uint32_t>(i | (j << C::kAw));
      tick();
      port0[i] = read_port(0);
      port1[j] = read_port(1);
    }
    for (std::size_t i = 0; i < count; ++i) {
      const auto& g = front_.geometry[i];
      const device::SurfaceWord& s = front_.surfaces.at(i);
      const FrontSphere expected{g.center.x, g.center.y, g.center.z, g.radius, s.material == link::kMaterialMetal,
                                 s.albedo};
      if (!(port0[i] == port1[i])) disagree("read ports 0 and 1 disagree on front sphere " + std::to_string(i), at);
      if (!(port0[i] == expected)) {
        const FrontSphere& r = port0[i];
        char text[320];
        std::snprintf(text, sizeof text,
                      "front sphere %zu: C++ (%lld %lld %lld r %lld metal %d albedo %d %d %d), RTL (%lld %lld %lld r "
                      "%lld metal %d albedo %d %d %d)",
                      i, static_cast<long long>(expected.x), static_cast<long long>(expected.y),
                      static_cast<long long>(expected.z), static_cast<long long>(expected.r), expected.metal,
                      expected.albedo[0], expected.albedo[1], expected.albedo[2], static_cast<long long>(r.x),
                      static_cast<long long>(r.y), static_cast<long long>(r.z), static_cast<long long>(r.r), r.metal,
                      r.albedo[0], r.albedo[1], r.albedo[2]);
        disagree(text, at);
      }
    }
  }

  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<typename C::Model> top_;
  device::Receiver model_;
  device::SceneMemory front_;
  std::vector<std::uint8_t> delivered_;  // every byte ts_spi_rx delivered, in order
  std::size_t fed_ = 0;                  // how many of them the C++ receiver has
  std::uint64_t cuts_ = 0;               // spi_byte_cut pulses
  bool end_of_stream_unhandled_ = false; // raised, and the RTL not idle since
  int step_ = 0;
  int compared_ = 0;
};

struct Input {
  std::vector<std::uint8_t> link_bytes;
  std::vector<Transfer> transfers;
  std::span<const std::uint8_t> records;  // 2 bytes each
  bool allow_illegal = false;
  std::uint32_t seed = 0;
};

template <class C>
void run(const Input& in) {
  Bench<C> bench(in.seed);
  const std::span<const std::uint8_t> bytes(in.link_bytes);
  const std::size_t records = in.records.size() / 2;
  bool previous_gap_legal = true;
  std::size_t at = 0;
  for (std::size_t k = 0; k < in.transfers.size(); ++k) {
    const Transfer& tr = in.transfers[k];
    Timing t;
    if (records > 0) {
      const std::size_t r = k % records;
      t = timing_of(in.records[2 * r], in.records[2 * r + 1], in.allow_illegal);
    }
    std::span<const std::uint8_t> whole = bytes.subspan(at, tr.bytes);
    at += tr.bytes;
    std::uint8_t cut_byte = 0;
    if (whole.empty()) t.cut_bits = 0;  // nothing to cut
    if (t.cut_bits > 0) {
      cut_byte = whole.back();
      whole = whole.first(whole.size() - 1);
    }
    // Legal: its own timing, and chip select high long enough before it. A short gap after it spoils this
    // transfer too: its last byte or cut may show up only after the next transfer has begun.
    const bool clean = t.legal() && previous_gap_legal;
    const bool short_gap_after = t.cs == Cs::kShortGap;
    bench.transfer(whole, cut_byte, t, clean && !short_gap_after);
    previous_gap_legal = !short_gap_after;
    if (tr.blanking) bench.vblank();
  }
  bench.end_of_stream();
  bench.vblank();
  bench.finish();
}

using V1Wide = Cfg<Vts_pins_v1_wide, link::WireVersion::kV1, WideCfg>;
using V2Wide = Cfg<Vts_pins_v2_wide, link::WireVersion::kV2, WideCfg>;
using V3Wide = Cfg<Vts_pins_v3_wide, link::WireVersion::kV3, WideCfg>;
using V1Board = Cfg<Vts_pins_v1_board, link::WireVersion::kV1, BoardCfg>;
using V2Board = Cfg<Vts_pins_v2_board, link::WireVersion::kV2, BoardCfg>;
using V3Board = Cfg<Vts_pins_v3_board, link::WireVersion::kV3, BoardCfg>;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::uint8_t config = data[0];
  std::size_t at = 2;
  const std::size_t op_count = std::min<std::size_t>(data[1] % 16, size - at);
  const std::span<const std::uint8_t> ops(data + at, op_count);
  at += op_count;
  std::size_t record_count = 0;
  if (at < size) {
    const std::size_t wanted = data[at] % 16;
    ++at;
    record_count = std::min(wanted, (size - at) / 2);
  }
  Input in;
  in.records = std::span<const std::uint8_t>(data + at, 2 * record_count);
  at += 2 * record_count;
  in.allow_illegal = (config & 0x40) != 0;

  const link::WireVersion wire = (config & 1)      ? link::WireVersion::kV1
                                 : (config & 0x20) ? link::WireVersion::kV3
                                                   : link::WireVersion::kV2;
  in.link_bytes.assign(data + at, data + std::min(size, at + kMaxLinkBytes));
  if (wire != link::WireVersion::kV1 && !(config & 0x10)) tripsitter::fuzz::repair_frame_crcs(wire, in.link_bytes);
  const std::size_t unit = std::size_t{1} << (2 * ((config >> 2) & 3));
  in.transfers = pin_transfers_of(ops, unit, in.link_bytes.size());
  // The seed of the RTL's random initial state: from the input, so that a reproducer runs the same again.
  std::uint32_t seed = 2166136261u;
  for (std::size_t i = 0; i < size; ++i) seed = (seed ^ data[i]) * 16777619u;
  in.seed = seed;

  const bool board = (config & 2) != 0;
  switch (wire) {
    case link::WireVersion::kV1: board ? run<V1Board>(in) : run<V1Wide>(in); break;
    case link::WireVersion::kV2: board ? run<V2Board>(in) : run<V2Wide>(in); break;
    case link::WireVersion::kV3: board ? run<V3Board>(in) : run<V3Wide>(in); break;
  }
  return 0;
}

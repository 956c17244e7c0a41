// The board without its microcontroller (ts_arty_top, STANDALONE = 1: the ROM host plays the worlds of a camera path
// into the artix device), Verilated with one sphere unit, against the C++ device model: its VGA pins, sampled once a
// pixel clock, must carry the model's frame of the ROM's first world, and after a (bouncing) press of BTN0 the frame
// of the next one, and after BTN1 the first world's again (wire v2 shows an old world sent again). The LEDs must count
// the worlds accepted. Only the board's pins are used: the frames are found from the vertical sync.
//
// The ROM image is the host's (host::make_rom_image, as `tripsitter rom` writes it): written to the file the model was
// Verilated with (TS_BOARD_TEST_ROM) before the model is made, whose $readmemh reads it then.
#include <algorithm>
#include <bitset>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <memory>
#include <regex>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "Vts_arty_top_standalone_1.h"
#include "Vts_arty_top_standalone_1_planted.h"
#include "Vts_arty_top_spi_1.h"
#include "rtl_ports.h"
#include "vga_frames.h"

#include <tripsitter/board/board.h>
#include <tripsitter/device/device.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/vga.h>
#include <tripsitter/host/host.h>
#include <tripsitter/host/rom_image.h>
#include <tripsitter/scene/builtin.h>

namespace tripsitter::rtl {
namespace {

using device::VgaSample;
using Frame = std::vector<VgaSample>;

constexpr int kFrameSamples = device::kVga640x480.h_total() * device::kVga640x480.v_total();
// The first sample with vsync low is line 490's first: 10 lines after a frame's first sample (line 480, column 0,
// where the device and its model start a frame and swap in a waiting world).
constexpr int kSyncAfterFrameStart = device::kVga640x480.v_front_porch * device::kVga640x480.h_total();
constexpr int kCyclesPerPixelClock = 4;
constexpr int kDebounceCycles = 64;  // the model's DEBOUNCE_CYCLES (CMakeLists.txt)

// The artix device of the board's Verilated top: one sphere unit, wire v2.
device::DevicePreset one_unit() {
  device::DevicePreset p = device::artix_preset();
  p.workers = 1;
  return p;
}

// The ROM image of the test: two worlds of the cluster scene, 40 degrees apart.
host::RomImage test_rom() {
  host::Host h(*scene::builtin("cluster"), board::formats_of(one_unit()), link::WireVersion::kV2);
  return host::make_rom_image(h, {host::CameraPath::Kind::kOrbit, 80}, 2, link::Numbering(link::WireVersion::kV2, 0));
}

// The board's top (either build), a clock at a time; its VGA pins sampled once every 4 clocks (a sample holds for a
// pixel clock's 4 clocks, so any fixed clock of the 4 sees each one once), and frames cut out of the samples at the
// vertical sync.
template <class Top>
class Board {
 public:
  Board() : ctx_(std::make_unique<VerilatedContext>()) {
    ctx_->randReset(2);  // random power-up state, but for the flip-flops given one (the reset's)
    top_ = std::make_unique<Top>(ctx_.get());
    top_->rst_btn_n = 1;
    top_->btn = 0;
    top_->pmod_sclk = 0;
    top_->pmod_mosi = 0;
    top_->pmod_cs_n = 1;
  }
  ~Board() { top_->final(); }

  Top& top() { return *top_; }

  void tick() {
    rising_edge(*top_);
    if (cycle_++ % kCyclesPerPixelClock != 0) return;
    const VgaSample s{top_->vga_hs_n != 0, top_->vga_vs_n != 0,
                      core::Rgb444::from_channels(top_->vga_r, top_->vga_g, top_->vga_b)};
    if (frame_start_ < 0) {
      // Before the first frame is found: the samples of the last 10 lines, to look back from the vertical sync.
      history_.push_back(s);
      const std::size_t n = history_.size();
      if (n >= 2 && history_[n - 2].vsync_n && !s.vsync_n && n > kSyncAfterFrameStart) {
        frame_start_ = 0;
        pending_.assign(history_.end() - kSyncAfterFrameStart - 1, history_.end());
        history_.clear();
      }
      return;
    }
    pending_.push_back(s);
  }
  void ticks(int n) {
    for (int i = 0; i < n; ++i) tick();
  }

  // The next whole frame, from its line 480; the frames follow one another without a gap.
  Frame next_frame() {
    while (static_cast<int>(pending_.size()) < kFrameSamples) tick();
    Frame f(pending_.begin(), pending_.begin() + kFrameSamples);
    pending_.erase(pending_.begin(), pending_.begin() + kFrameSamples);
    return f;
  }

  // A press of a button (bit `b` of btn) that bounces on the way down and up: two short contacts (each shorter than
  // the debounce), then held, then released with one more contact: four contacts in all, so that a board that took
  // each as a press would step four worlds, back to where it was with the test's two.
  void press(int b) {
    const auto level = [&](bool down, int cycles) {
      top_->btn = static_cast<CData>(down ? top_->btn | (1u << b) : top_->btn & ~(1u << b));
      ticks(cycles);
    };
    for (const int c : {kDebounceCycles / 3, kDebounceCycles / 2}) {
      level(true, c);
      level(false, c / 2);
    }
    level(true, 3 * kDebounceCycles);
    level(false, kDebounceCycles / 2);
    level(true, kDebounceCycles / 3);
    level(false, 3 * kDebounceCycles);
  }

  unsigned leds() const { return top_->led; }

  // A microcontroller on Pmod JD: chip select low, the bytes in SPI mode 0 (MOSI set while SCLK is low, SCLK high for
  // `half` clocks, low for `half`), chip select high. Returns the clocks from the last SCLK rising edge to READY
  // falling, within `watch` clocks after chip select rises (-1: it did not fall).
  int spi_transfer(std::span<const std::uint8_t> bytes, int half, int watch) {
    top_->pmod_cs_n = 0;
    ticks(half);
    for (const std::uint8_t byte : bytes) {
      for (int bit = 7; bit >= 0; --bit) {
        top_->pmod_mosi = (byte >> bit) & 1;
        ticks(half);
        top_->pmod_sclk = 1;
        ticks(half);
        top_->pmod_sclk = 0;
      }
    }
    ticks(half);
    top_->pmod_cs_n = 1;
    for (int i = 0; i < watch; ++i) {
      if (!top_->pmod_ready) return 2 * half + i;
      tick();
    }
    return -1;
  }

  // After a reset of the device in the middle of a frame: its frames start anew, found again from the sync.
  void find_frames_again() {
    frame_start_ = -1;
    pending_.clear();
  }

 private:
  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<Top> top_;
  std::uint64_t cycle_ = 0;
  long frame_start_ = -1;
  std::vector<VgaSample> history_, pending_;
};

// Where two frames first differ, the second one the board's.
std::string first_difference(const Frame& model, const Frame& board) { return rtl::first_difference(model, board, "board"); }

Frame model_frame(device::Device& model) {
  device::FrameStats stats;
  return rtl::frame_samples(model, stats);
}

// Frames of the board until one is not `before`: it must be `after`, within `frames`, and the frame after it too
// (the board stays on the world it stepped to), with the LEDs at `leds`. Empty if so; else what was seen.
template <class Top>
std::string shows_next(Board<Top>& board, const Frame& before, const Frame& after, unsigned leds,
                       const std::string& what) {
  constexpr int kFrames = 3;
  for (int i = 0; i < kFrames; ++i) {
    const Frame f = board.next_frame();
    if (f == before) continue;
    std::string diff = first_difference(after, f);
    if (!diff.empty()) return what + ", frame " + std::to_string(i) + ": " + diff;
    diff = first_difference(after, board.next_frame());
    if (!diff.empty()) return what + ": the frame after it: " + diff;
    if (board.leds() != leds)
      return what + ": LD7..LD4 " + std::bitset<4>(board.leds()).to_string() + ", not " +
             std::bitset<4>(leds).to_string();
    return "";
  }
  return what + ": still the frame before after " + std::to_string(kFrames) + " frames (LD7..LD4 " +
         std::bitset<4>(board.leds()).to_string() + ": refused, rejected, accepted)";
}

TEST(BoardRtl, TheRomBytesAreTheHostsConstant) {
  std::ifstream in(TS_ARTY_TOP);
  std::stringstream text;
  text << in.rdbuf();
  std::smatch m;
  const std::string s = text.str();
  ASSERT_TRUE(std::regex_search(s, m, std::regex(R"(parameter int ROM_BYTES = (\d+))"))) << TS_ARTY_TOP;
  EXPECT_EQ(std::stoul(m[1]), host::kBoardRomBytes) << "ts_arty_top's ROM_BYTES, host/rom_image.h's kBoardRomBytes";
}

// The test's ROM, written where the models read it; the model's frames without a world and of the two worlds.
struct Expected {
  Frame empty;
  Frame world[2];
};

Expected write_rom_and_model_frames() {
  const host::RomImage rom = test_rom();
  EXPECT_LE(rom.bytes.size(), host::kBoardRomBytes);
  const auto worlds = host::rom_worlds(rom.bytes);
  if (!worlds.ok()) throw std::logic_error("the test's ROM image: " + worlds.error());
  {
    // Written beside and renamed, so that a test running at the same time never reads half a file.
    const std::string tmp = std::string(TS_BOARD_TEST_ROM) + ".tmp-" + std::to_string(::getpid());
    std::ofstream(tmp) << host::to_readmemh(rom.bytes, {"board_rtl_test"});
    std::filesystem::rename(tmp, TS_BOARD_TEST_ROM);
  }

  // The model, given the ROM's worlds as the ROM host sends them.
  device::Device model(one_unit(), link::WireVersion::kV2, 1, device::DeviceModel::kPlain);
  Expected e;
  e.empty = model_frame(model);
  for (int k : {0, 1}) {
    model.transfer(worlds.value()[k]);
    e.world[k] = model_frame(model);
    EXPECT_NE(e.world[k], e.empty) << "world " << k << " draws nothing";
  }
  EXPECT_NE(e.world[0], e.world[1]) << "the two worlds look alike: a step would not show";
  return e;
}

// The board from its configuration: world 0; BTN0, pressed with bounces: world 1; BTN1: world 0 again (its sequence
// number 1 after 2); RESET: world 0 from a device without a world. LD5..LD4 count the worlds accepted, 1, 2, 3 and
// after the reset 1; LD7..LD6 stay dark (nothing refused). Empty if all that was seen; else the first thing that was
// not.
template <class Top>
std::string step_through(const Expected& e) {
  Board<Top> board;
  // Reset comes from the configuration; world 0 goes out during the first frame and is shown from the next.
  std::string wrong = shows_next(board, e.empty, e.world[0], 0b0001, "world 0 after configuration");
  if (!wrong.empty()) return wrong;
  board.press(0);
  wrong = shows_next(board, e.world[0], e.world[1], 0b0010, "world 1 after BTN0");
  if (!wrong.empty()) return wrong;
  board.press(1);
  wrong = shows_next(board, e.world[1], e.world[0], 0b0011, "world 0 after BTN1");
  if (!wrong.empty()) return wrong;
  board.top().rst_btn_n = 0;
  board.ticks(100);
  board.top().rst_btn_n = 1;
  board.find_frames_again();  // the device restarts its frames with the reset
  return shows_next(board, e.empty, e.world[0], 0b0001, "world 0 after RESET");
}

TEST(BoardRtl, StandaloneShowsTheRomsWorldsAndTheButtonsStepThem) {
  const std::string wrong = step_through<Vts_arty_top_standalone_1>(write_rom_and_model_frames());
  EXPECT_TRUE(wrong.empty()) << wrong;
}

// The same board with its debouncers' planted bug (TS_PLANT_NO_DEBOUNCE: every contact a press): the bouncing press
// of BTN0 steps four worlds, so world 0 comes back after world 1, and the walk above must say so.
TEST(BoardRtl, PlantedNoDebounceIsCaught) {
  const std::string wrong = step_through<Vts_arty_top_standalone_1_planted>(write_rom_and_model_frames());
  RecordProperty("caught", wrong);
  EXPECT_NE(wrong.find("after BTN0"), std::string::npos) << (wrong.empty() ? "not caught" : wrong);
}

// The board with the microcontroller (STANDALONE = 0): a world on wire v3 through Pmod JD at 10 MHz, as an EFM32
// would send it, is shown as the model shows it, with LD4 counting it; READY is high before and falls after it. Then
// the next world with a byte of its payload flipped: refused (LD6 toggles, LD7 lights), the first world stays.
TEST(BoardRtl, WithTheMicrocontrollerShowsItsWorldsAndRefusesADamagedOne) {
  constexpr int kHalf = 5;  // 10 MHz
  host::Host h(*scene::builtin("cluster"), board::formats_of(one_unit()), link::WireVersion::kV3);
  link::Numbering numbering(link::WireVersion::kV3, 7);
  std::vector<std::uint8_t> first = h.update().bytes;
  numbering.stamp(first);
  host::step_camera(h.camera(), {host::CameraPath::Kind::kOrbit, 40}, 1);
  std::vector<std::uint8_t> damaged = h.update().bytes;
  numbering.stamp(damaged);
  damaged[damaged.size() / 2] ^= 0x10;

  device::Device model(one_unit(), link::WireVersion::kV3, 1, device::DeviceModel::kPlain);
  const Frame empty = model_frame(model);
  model.transfer(first);
  const Frame shown = model_frame(model);
  ASSERT_NE(shown, empty);

  Board<Vts_arty_top_spi_1> board;
  EXPECT_EQ(board.next_frame(), empty);
  ASSERT_TRUE(board.top().pmod_ready) << "READY is high while the device waits for a world";
  const int ready_fell = board.spi_transfer(first, kHalf, 10'000);
  ASSERT_GE(ready_fell, 0) << "READY did not fall after a world";
  RecordProperty("ready_fell_clocks_after_last_sclk_rise", ready_fell);
  std::string wrong = shows_next(board, empty, shown, 0b0001, "the microcontroller's world");
  EXPECT_TRUE(wrong.empty()) << wrong;
  EXPECT_TRUE(board.top().pmod_ready) << "READY is high again once the world is shown";

  EXPECT_EQ(board.spi_transfer(damaged, kHalf, 10'000), -1) << "a damaged world takes no ready away";
  EXPECT_EQ(board.leds(), 0b1101u) << "refused, one rejected, one accepted";
  for (int i = 0; i < 2; ++i) EXPECT_EQ(first_difference(shown, board.next_frame()), "") << "frame " << i;
}

}  // namespace
}  // namespace tripsitter::rtl

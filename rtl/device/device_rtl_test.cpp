// The whole device as RTL (ts_device: receiver, scene memory, N workers, controller, line buffers, VGA timing) against
// the C++ device model (device::Device), pin for pin: the same link bytes go to both, the RTL's through its SPI
// pins (mode 0, most significant bit first, SCLK a tenth of the clock, as the link's default 10 MHz), and every
// sample of a whole frame (hsync_n, vsync_n and the 12-bit colour of all 800 x 525 pixel clocks) is compared, with
// the frame's late pixels. The first differing sample is printed with both values.
//
// Timing: the model takes a transfer at once and shows its world from the next vertical blanking, which run_frame
// starts with; the RTL shifts the bits in, checks the frame and writes scene memory, and shows the world from the
// first vertical blanking after that. The frame compared is the first one of the world on each side.
#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <verilated.h>

#include "Vts_device_board.h"
#include "Vts_device_board_1.h"
#include "Vts_device_wide.h"
#include "Vts_device_wide_7.h"

#include <tripsitter/device/device.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/test_util.h>
#include <tripsitter/link/frame.h>

namespace tripsitter::device {
namespace {

constexpr int kHalfBit = 5;  // device clocks per SCLK half period: 10 MHz against 100 MHz
constexpr int kFrameSamples = kVga640x480.h_total() * kVga640x480.v_total();

// A frame as the connector carries it, one sample per pixel clock from the start of vertical blanking.
struct Capture {
  std::vector<VgaSample> samples;
  int late_pixels = 0;
};

template <class Model>
class Rig {
 public:
  Rig() : ctx_(std::make_unique<VerilatedContext>()) {
    ctx_->randReset(2);  // random power-up state: the reset must make it irrelevant
    top_ = std::make_unique<Model>(ctx_.get());
    top_->clk = 0;
    top_->rst = 1;
    top_->spi_cs_n = 1;
    top_->spi_sclk = 0;
    top_->spi_mosi = 0;
    for (int i = 0; i < 4; ++i) tick();
    top_->rst = 0;
  }
  Rig(const Rig&) = delete;
  Rig& operator=(const Rig&) = delete;
  ~Rig() { top_->final(); }

  // One SPI transfer from the pins, then clocks until the receiver has taken every byte and is idle.
  void transfer(const std::vector<std::uint8_t>& bytes) {
    top_->spi_cs_n = 0;
    ticks(kHalfBit);
    for (const std::uint8_t byte : bytes) {
      for (int bit = 7; bit >= 0; --bit) {
        top_->spi_mosi = (byte >> bit) & 1;  // changes while SCLK is low, sampled on its rising edge
        ticks(kHalfBit);
        top_->spi_sclk = 1;
        ticks(kHalfBit);
        top_->spi_sclk = 0;
      }
    }
    ticks(kHalfBit);
    top_->spi_cs_n = 1;
    for (int i = 0; i < 4'000'000 && !top_->receiver_idle; ++i) tick();
  }
  std::uint64_t accepted() const { return top_->worlds_accepted; }

  // Runs to the next start of vertical blanking (where a waiting world is swapped in), then captures the frame
  // that starts there: one sample per vga_strobe, the first being line 480's column 0.
  Capture frame() {
    while (!(top_->beam_line == 480 && top_->beam_column == 0)) tick();
    Capture c;
    c.samples.reserve(kFrameSamples);
    while (static_cast<int>(c.samples.size()) < kFrameSamples) {
      tick();
      if (top_->late_valid) c.late_pixels += top_->late_pixels;
      if (top_->vga_strobe) {
        VgaSample s;
        s.hsync_n = top_->vga_hsync_n != 0;
        s.vsync_n = top_->vga_vsync_n != 0;
        s.colour = core::Rgb444::from_channels(top_->vga_r, top_->vga_g, top_->vga_b);
        c.samples.push_back(s);
      }
    }
    // Leave the beam past the frame's start, so that the next frame() waits for the next one.
    while (top_->beam_line == 480 && top_->beam_column == 0) tick();
    return c;
  }

 private:
  void tick() {
    top_->clk = 1;
    top_->eval();
    top_->clk = 0;
    top_->eval();
  }
  void ticks(int n) {
    for (int i = 0; i < n; ++i) tick();
  }

  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<Model> top_;
};

std::string describe(const VgaSample& s) {
  std::ostringstream o;
  o << "hsync_n " << s.hsync_n << " vsync_n " << s.vsync_n << " colour 0x" << std::hex << s.colour.packed;
  return o.str();
}

// Empty if the frames are the same; else the first differing sample, with both values.
std::string first_difference(const std::vector<VgaSample>& model, const std::vector<VgaSample>& rtl) {
  if (model.size() != rtl.size()) return "sample counts differ";
  for (std::size_t i = 0; i < model.size(); ++i) {
    if (model[i] == rtl[i]) continue;
    const int line = (static_cast<int>(i) / kVga640x480.h_total() + kVga640x480.v_visible) % kVga640x480.v_total();
    const int col = static_cast<int>(i) % kVga640x480.h_total();
    return "line " + std::to_string(line) + " column " + std::to_string(col) + ": model " + describe(model[i]) +
           ", RTL " + describe(rtl[i]);
  }
  return "";
}

// A world of random spheres (random_world: in view, behind the camera, around it, huge, tiny, at the formats'
// limits), each with a surface (metals with random albedos), as a frame on `wire`.
std::vector<std::uint8_t> random_frame(const DevicePreset& p, link::WireVersion wire, std::uint32_t sequence,
                                       std::mt19937_64& rng) {
  SceneMemory scene = testing::random_world(p, rng);
  scene.surfaces.resize(scene.geometry.size());
  for (SurfaceWord& s : scene.surfaces) {
    s.material = rng() % 3 == 0 ? link::kMaterialMetal : link::kMaterialLambertian;
    s.albedo = {static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng())};
    s.ior = 6144;  // 1.5: every sphere on the wire carries an index of refraction, used or not
  }
  if (p.max_bounces > 0) {
    // Three metal spheres in view that see each other, so that pixels reflect up to the cut-off.
    const std::int64_t unit = std::int64_t{1} << p.frac_bits();
    for (const auto& [x, y, z, r] : {std::array<std::int64_t, 4>{0, 40, 700, 220}, {-330, -60, 520, 140},
                                     {300, 90, 480, 120}}) {
      scene.geometry.push_back({{x * unit, y * unit, z * unit}, r * unit});
      scene.surfaces.push_back({});
      scene.surfaces.back().material = link::kMaterialMetal;
      scene.surfaces.back().ior = 6144;
      scene.surfaces.back().albedo = {static_cast<std::uint8_t>(150 + rng() % 106), static_cast<std::uint8_t>(rng()),
                                      static_cast<std::uint8_t>(200 + rng() % 56)};
    }
  }
  return testing::frame_of_scene(p, sequence, scene, wire, 7);
}

// Worlds one after another to the model and the RTL; each world's first frame compared sample by sample.
// Returns the reflections the model's frames traced (the mirror model's worlds should have some).
template <class Model>
std::uint64_t compare_worlds(const DevicePreset& preset, link::WireVersion wire, int worlds, std::uint64_t seed) {
  std::uint64_t reflections = 0;
  std::mt19937_64 rng(seed);
  Device model(preset, wire, 1, DeviceModel::kPlain);
  Rig<Model> rtl;
  for (int w = 1; w <= worlds; ++w) {
    const std::vector<std::uint8_t> bytes = random_frame(preset, wire, static_cast<std::uint32_t>(w), rng);
    model.transfer(bytes);
    rtl.transfer(bytes);
    EXPECT_EQ(rtl.accepted(), model.receiver_stats().worlds_accepted) << "world " << w;
    if (rtl.accepted() != model.receiver_stats().worlds_accepted) return reflections;
    std::vector<VgaSample> expected;
    expected.reserve(kFrameSamples);
    const FrameStats stats = model.run_frame([&](const VgaSample& s) { expected.push_back(s); });
    // Both must show this world: a world refused by both would compare a background against a background.
    EXPECT_TRUE(stats.has_world && stats.sequence == static_cast<std::uint32_t>(w)) << "world " << w << " not shown";
    EXPECT_EQ(model.receiver_stats().frames_rejected, 0u) << model.receiver_stats().last_error;
    const Capture got = rtl.frame();
    const std::string diff = first_difference(expected, got.samples);
    EXPECT_TRUE(diff.empty()) << preset.name << ", " << preset.workers << " workers, world " << w << " ("
                              << model.scene().geometry.size() << " spheres): " << diff;
    EXPECT_EQ(got.late_pixels, stats.late_pixels) << "world " << w;
    if (!diff.empty()) return reflections;
    reflections += stats.reflections;
  }
  return reflections;
}

// A simulated frame of the board-2023 top with ten workers takes about 4 s here, of the wide top with ten pipelined
// workers about 30 s (each world costs two: the one it arrives in and the one compared): few worlds per test.
TEST(DeviceRtl, Board2023TenWorkersV2) {
  compare_worlds<Vts_device_board>(board_2023_preset(), link::WireVersion::kV2, 3, 1);
}

TEST(DeviceRtl, Board2023OneWorker) {
  DevicePreset p = board_2023_preset();
  p.workers = 1;
  compare_worlds<Vts_device_board_1>(p, link::WireVersion::kV2, 2, 2);
}

TEST(DeviceRtl, WideTenWorkersV3) {
  EXPECT_GT(compare_worlds<Vts_device_wide>(wide_preset(), link::WireVersion::kV3, 1, 3), 0u);
}

TEST(DeviceRtl, WideSevenWorkers) {
  DevicePreset p = wide_preset();
  p.workers = 7;
  EXPECT_GT(compare_worlds<Vts_device_wide_7>(p, link::WireVersion::kV3, 1, 4), 0u);
}

}  // namespace
}  // namespace tripsitter::device

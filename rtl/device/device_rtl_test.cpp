// The whole device as RTL (ts_device: receiver, scene memory, N workers, controller, line buffers, VGA timing) against
// the C++ device model (device::Device), pin for pin, through the back-end that `--device rtl` selects
// (rtl_device.h): the same link bytes go to both, the RTL's through its SPI pins (mode 0, most significant bit
// first, SCLK a tenth of the clock, as the link's default 10 MHz), and every
// sample of a whole frame (hsync_n, vsync_n and the 12-bit colour of all 800 x 525 pixel clocks) is compared, with
// the frame's late pixels. The first differing sample is printed with both values.
//
// Timing: the model takes a transfer at once and shows its world from the next vertical blanking, which run_frame
// starts with; the RTL shifts the bits in, checks the frame and writes scene memory, and shows the world from the
// first vertical blanking after that. The frame compared is the first one of the world on each side.
#include <array>
#include <fstream>
#include <iostream>
#include <iterator>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "Vts_device_board_1_planted.h"
#include "rtl_device.h"
#include "verilated_device.h"
#include "vga_frames.h"

#include <tripsitter/device/device.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/test_util.h>
#include <tripsitter/link/frame.h>
#include <tripsitter/link/wire_v1.h>

namespace tripsitter::device {
namespace {

// The RTL back-end for `preset` on `wire`, failing the test if this program has no such build.
std::unique_ptr<Backend> rtl_device(const DevicePreset& preset, link::WireVersion wire) {
  auto made = rtl::make_rtl_device(preset, wire);
  if (!made) ADD_FAILURE() << made.error();
  return made ? std::move(made).value() : nullptr;
}

using rtl::first_difference;
using rtl::frame_samples;

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
  // A tie: a sphere twice, with another surface, so that the closest-hit rule decides which one every pixel shows.
  if (!scene.geometry.empty() && scene.geometry.size() < p.max_spheres) {
    scene.geometry.push_back(scene.geometry.front());
    scene.surfaces.push_back(scene.surfaces.front());
    scene.surfaces.back().albedo = {9, 200, 77};
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

// A v1 word, the original board's: one sphere, and a world of its own (the device shows the latest word). Kinds in
// turn: in view; anywhere in the word's formats (behind the camera, around it, off to a side); at the formats' ends
// with the largest radius board-2023 holds (2^12), reaching into view. Every word is one board-2023 accepts.
std::vector<std::uint8_t> random_v1_word(int kind, std::mt19937_64& rng) {
  const auto between = [&](std::int64_t lo, std::int64_t hi) {
    return static_cast<std::int32_t>(lo + static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(hi - lo + 1)));
  };
  constexpr std::int32_t kUnit = 1 << link::kV1X.frac_bits;
  link::V1Sphere s;
  switch (kind % 3) {
    case 0: {
      const std::int32_t z = between(200, 1500);
      s = {between(-z / 2, z / 2) * kUnit, between(-z / 3, z / 3) * kUnit, z * kUnit,
           static_cast<std::uint8_t>(between(3, 8)), 0};
      break;
    }
    case 1:
      s = {between(link::kV1X.min_raw(), link::kV1X.max_raw()), between(link::kV1Y.min_raw(), link::kV1Y.max_raw()),
           between(link::kV1Z.min_raw(), link::kV1Z.max_raw()), static_cast<std::uint8_t>(between(0, 12)), 0};
      break;
    default: {
      const auto either = [&](std::int64_t a, std::int64_t b) { return static_cast<std::int32_t>(rng() % 2 ? a : b); };
      s = {either(link::kV1X.max_raw(), link::kV1X.min_raw()), either(link::kV1Y.max_raw(), link::kV1Y.min_raw()),
           static_cast<std::int32_t>(link::kV1Z.max_raw()), 12, 0};
      break;
    }
  }
  s.colour = static_cast<std::uint16_t>(rng() % 4096);
  std::vector<std::uint8_t> bytes;
  link::append_v1_bytes(link::encode_v1_word(s), bytes);
  return bytes;
}

// What compare_worlds saw in the model's frames.
struct Compared {
  std::uint64_t reflections = 0;     // the mirror model's worlds should have some
  std::uint64_t sphere_samples = 0;  // samples neither background nor black (blanking, a late pixel): a sphere drawn
};

// Worlds one after another to the model and the RTL (frames on v2 and v3, words on v1); each world's first frame
// compared sample by sample, with the frame's statistics and the receiver's counters.
Compared compare_worlds(const DevicePreset& preset, link::WireVersion wire, int worlds, std::uint64_t seed) {
  Compared compared;
  std::mt19937_64 rng(seed);
  Device model(preset, wire, 1, DeviceModel::kPlain);
  const std::unique_ptr<Backend> rtl = rtl_device(preset, wire);
  if (!rtl) return compared;
  for (int w = 1; w <= worlds; ++w) {
    const std::vector<std::uint8_t> bytes = wire == link::WireVersion::kV1
                                                ? random_v1_word(w - 1, rng)
                                                : random_frame(preset, wire, static_cast<std::uint32_t>(w), rng);
    model.transfer(bytes);
    rtl->transfer(bytes);
    EXPECT_EQ(rtl->receiver_stats().worlds_accepted, model.receiver_stats().worlds_accepted) << "world " << w;
    if (rtl->receiver_stats().worlds_accepted != model.receiver_stats().worlds_accepted) return compared;
    EXPECT_EQ(rtl->ready(), model.ready()) << "world " << w;
    FrameStats stats;
    const std::vector<VgaSample> expected = frame_samples(model, stats);
    // Both must show this world: a world refused by both would compare a background against a background.
    EXPECT_TRUE(stats.has_world && stats.sequence == static_cast<std::uint32_t>(w)) << "world " << w << " not shown";
    EXPECT_EQ(model.receiver_stats().frames_rejected, 0u) << model.receiver_stats().last_error;
    FrameStats got;
    const std::vector<VgaSample> samples = frame_samples(*rtl, got);
    const std::string diff = first_difference(expected, samples);
    EXPECT_TRUE(diff.empty()) << preset.name << ", " << preset.workers << " workers, world " << w << " ("
                              << model.scene().geometry.size() << " spheres): " << diff;
    EXPECT_EQ(got.late_pixels, stats.late_pixels) << "world " << w;
    EXPECT_EQ(got.late_lines, stats.late_lines) << "world " << w;
    EXPECT_EQ(got.has_world, stats.has_world) << "world " << w;
    EXPECT_EQ(got.sequence, stats.sequence) << "world " << w;
    EXPECT_EQ(rtl->has_world(), model.has_world());
    if (!diff.empty()) return compared;
    compared.reflections += stats.reflections;
    for (const VgaSample& v : expected) {
      compared.sphere_samples += v.colour != core::kBackground && v.colour != core::kBlack;
    }
  }
  return compared;
}

// A simulated frame of a random world with the board-2023 top's ten workers takes about 3 s here, with one worker
// about 0.35 s, with the wide top's ten pipelined workers about 18 s (each world costs two frames: the one it arrives
// in and the one compared): many worlds with one worker, few with more.
TEST(DeviceRtl, Board2023TenWorkersV2) {
  compare_worlds(board_2023_preset(), link::WireVersion::kV2, 3, 1);
}

// The board as the report shipped it: board-2023's hardware, its 10 workers, the v1 wire's sphere words.
TEST(DeviceRtl, Board2023TenWorkersV1) {
  EXPECT_GT(compare_worlds(board_2023_preset(), link::WireVersion::kV1, 3, 8).sphere_samples, 0u)
      << "no word drew a sphere";
}

TEST(DeviceRtl, Board2023OneWorker) {
  DevicePreset p = board_2023_preset();
  p.workers = 1;
  compare_worlds(p, link::WireVersion::kV2, 12, 2);
}

TEST(DeviceRtl, WideTenWorkersV3) {
  EXPECT_GT(compare_worlds(wide_preset(), link::WireVersion::kV3, 1, 3).reflections, 0u);
}

TEST(DeviceRtl, WideSevenWorkers) {
  DevicePreset p = wide_preset();
  p.workers = 7;
  EXPECT_GT(compare_worlds(p, link::WireVersion::kV3, 1, 4).reflections, 0u);
}

TEST(DeviceRtl, WideOneWorker) {
  DevicePreset p = wide_preset();
  p.workers = 1;
  EXPECT_GT(compare_worlds(p, link::WireVersion::kV3, 3, 5).reflections, 0u);
}

// The artix device (ts_artix_device): its sphere units, the world's constants and cull, the tile lists and the
// queues, with the preset's 9 units, 5 (a prime) and 1. A frame of 9 units takes about 20 s here.
TEST(DeviceRtl, ArtixNineUnits) {
  EXPECT_GT(compare_worlds(artix_preset(), link::WireVersion::kV3, 1, 12).reflections, 0u);
}

TEST(DeviceRtl, ArtixFiveUnits) {
  DevicePreset p = artix_preset();
  p.workers = 5;
  EXPECT_GT(compare_worlds(p, link::WireVersion::kV3, 1, 13).reflections, 0u);
}

TEST(DeviceRtl, ArtixOneUnit) {
  DevicePreset p = artix_preset();
  p.workers = 1;
  EXPECT_GT(compare_worlds(p, link::WireVersion::kV3, 3, 14).reflections, 0u);
}

TEST(DeviceRtl, Board2023SevenWorkers) {
  DevicePreset p = board_2023_preset();
  p.workers = 7;
  compare_worlds(p, link::WireVersion::kV2, 2, 6);
}

}  // namespace
}  // namespace tripsitter::device

namespace tripsitter::device {
namespace {

// A link that damages: after each piece the RTL's receiver counters (ReceiverStats but its last_error text) and ready
// line equal the model's, and the world both finally show is the same one.
void expect_same_receiver(const Backend& rtl, const Device& model, const std::string& after) {
  const ReceiverStats& r = rtl.receiver_stats();
  const ReceiverStats& m = model.receiver_stats();
  EXPECT_EQ(r.worlds_accepted, m.worlds_accepted) << after;
  EXPECT_EQ(r.worlds_replaced, m.worlds_replaced) << after;
  EXPECT_EQ(r.frames_rejected, m.frames_rejected) << after;
  EXPECT_EQ(r.garbage_runs, m.garbage_runs) << after;
  EXPECT_EQ(r.bytes_dropped, m.bytes_dropped) << after;
  EXPECT_EQ(r.worlds_missing, m.worlds_missing) << after;
  EXPECT_EQ(r.worlds_replayed, m.worlds_replayed) << after;
  EXPECT_EQ(r.sessions, m.sessions) << after;
  EXPECT_EQ(rtl.ready(), model.ready()) << after;
}

// On board-2023's receiver and on the artix device's, whose world is prepared after the receiver writes it.
TEST(DeviceRtl, DamagedLinkAtThePins) {
  DevicePreset board = board_2023_preset();
  board.workers = 1;
  DevicePreset artix = artix_preset();
  artix.workers = 1;
  for (const auto& [p, wire] : {std::pair{board, link::WireVersion::kV2}, std::pair{artix, link::WireVersion::kV3}}) {
    SCOPED_TRACE(p.name);
    Device model(p, wire, 1, DeviceModel::kPlain);
    const std::unique_ptr<Backend> rtl = rtl_device(p, wire);
    ASSERT_TRUE(rtl);
    std::mt19937_64 rng(11);
    const auto world = [&](std::uint32_t sequence) { return random_frame(p, wire, sequence, rng); };
    std::vector<std::uint8_t> flipped = world(1);
    flipped[flipped.size() / 2] ^= 0x10;               // the CRC fails
    std::vector<std::uint8_t> cut = world(2);
    cut.resize(cut.size() * 2 / 3);                    // cut short, then a whole frame: the cut one is rejected
    const std::vector<std::uint8_t> garbage = {0x00, 0x13, 0x37, 0xff, 0x42};
    std::vector<std::vector<std::uint8_t>> pieces = {flipped, cut, world(3), garbage, world(5), world(5)};
    int n = 0;
    for (const std::vector<std::uint8_t>& piece : pieces) {
      model.transfer(piece);
      rtl->transfer(piece);
      expect_same_receiver(*rtl, model, "piece " + std::to_string(n++));
    }
    model.end_of_stream();
    rtl->end_of_stream();
    expect_same_receiver(*rtl, model, "the end of the stream");
    EXPECT_GT(model.receiver_stats().frames_rejected, 0u);
    EXPECT_GT(model.receiver_stats().worlds_missing, 0u);
    FrameStats m;
    FrameStats r;
    const std::string diff = first_difference(frame_samples(model, m), frame_samples(*rtl, r));
    EXPECT_TRUE(diff.empty()) << diff;
    EXPECT_EQ(r.sequence, m.sequence);
    EXPECT_TRUE(m.has_world);
  }
}

// v1 words damaged at the pins of the board as it shipped: a word board-2023 refuses (a radius of 2^13), a word cut
// short by the host going away, a byte lost (the words after it are read shifted until the stream ends), then good
// words: the counters and ready line as the model's after every piece. (No frame: Board2023TenWorkersV1 compares
// the frames of the words this build accepts, receiver_rtl_test the receiver's v1 damage at length.)
TEST(DeviceRtl, DamagedV1WordsAtThePins) {
  const DevicePreset p = board_2023_preset();
  Device model(p, link::WireVersion::kV1, 1, DeviceModel::kPlain);
  const std::unique_ptr<Backend> rtl = rtl_device(p, link::WireVersion::kV1);
  ASSERT_TRUE(rtl);
  std::mt19937_64 rng(12);
  std::vector<std::uint8_t> refused;
  link::append_v1_bytes(link::encode_v1_word({0, 0, 400 * 8, 13, 0xF00}), refused);
  std::vector<std::uint8_t> cut = random_v1_word(0, rng);
  cut.resize(5);
  std::vector<std::uint8_t> lost = random_v1_word(1, rng);
  const std::vector<std::uint8_t> after_lost = random_v1_word(0, rng);
  lost.insert(lost.end(), after_lost.begin(), after_lost.end());
  lost.erase(lost.begin() + 3);
  const std::vector<std::vector<std::uint8_t>> pieces = {random_v1_word(0, rng), refused, cut, {}, lost, {},
                                                         random_v1_word(2, rng), random_v1_word(0, rng)};
  int n = 0;
  for (const std::vector<std::uint8_t>& piece : pieces) {
    if (piece.empty()) {  // the host went away
      model.end_of_stream();
      rtl->end_of_stream();
    } else {
      model.transfer(piece);
      rtl->transfer(piece);
    }
    expect_same_receiver(*rtl, model, "piece " + std::to_string(n++));
  }
  EXPECT_GT(model.receiver_stats().frames_rejected, 1u);  // the refused word and the cut one
  EXPECT_GT(model.receiver_stats().worlds_replaced, 0u);
  EXPECT_GT(model.receiver_stats().worlds_accepted, 3u);
}

// The equivalence catches a planted bug: the square-root unit's comparison flipped (the test-only copy of the unit that
// rtl/worker/CMakeLists.txt writes) in an otherwise equal build of the one-worker board.
TEST(DeviceRtl, PlantedSqrtBugDiffers) {
  DevicePreset p = board_2023_preset();
  p.workers = 1;
  Device model(p, link::WireVersion::kV2, 1, DeviceModel::kPlain);
  rtl::RtlDevice<Vts_device_board_1_planted> planted(5, {}, "");
  std::mt19937_64 rng(2);
  const std::vector<std::uint8_t> bytes = random_frame(p, link::WireVersion::kV2, 1, rng);
  model.transfer(bytes);
  planted.transfer(bytes);
  FrameStats m;
  FrameStats r;
  const std::vector<VgaSample> expected = frame_samples(model, m);
  ASSERT_TRUE(m.has_world);
  const std::string diff = first_difference(expected, frame_samples(planted, r));
  EXPECT_FALSE(diff.empty()) << "the planted bug went unseen";
  std::cout << "the planted bug: " << diff << "\n";
}

// Only the builds there are: another worker count, wire or preset, or an SCLK the device cannot sample, is refused
// with a reason.
TEST(DeviceRtl, RefusesWhatIsNotBuilt) {
  DevicePreset p = wide_preset();
  p.workers = 3;
  const auto three = rtl::make_rtl_device(p, link::WireVersion::kV3);
  ASSERT_FALSE(three);
  EXPECT_NE(three.error().find("not for wide with 3 workers on wire v3"), std::string::npos) << three.error();
  EXPECT_NE(three.error().find(rtl::rtl_builds()), std::string::npos) << three.error();
  EXPECT_FALSE(rtl::make_rtl_device(board_2023_preset(), link::WireVersion::kV3));
  // On v1 only the board as it shipped, 10 workers.
  DevicePreset seven = board_2023_preset();
  seven.workers = 7;
  const auto v1_seven = rtl::make_rtl_device(seven, link::WireVersion::kV1);
  ASSERT_FALSE(v1_seven);
  EXPECT_NE(v1_seven.error().find("board-2023 with 10 workers on wire v1"), std::string::npos) << v1_seven.error();
  EXPECT_FALSE(rtl::make_rtl_device(wide_preset(), link::WireVersion::kV1));
  EXPECT_FALSE(rtl::make_rtl_device(path_preset(), link::WireVersion::kV2));
  rtl::RtlOptions fast;
  fast.spi_hz = rtl::kMaxSpiHz + 1;
  EXPECT_FALSE(rtl::make_rtl_device(board_2023_preset(), link::WireVersion::kV2, fast));
  rtl::RtlOptions no_worker;
  no_worker.vcd = ::testing::TempDir() + "rtl_refused.vcd";
  no_worker.vcd_worker = 10;
  EXPECT_FALSE(rtl::make_rtl_device(board_2023_preset(), link::WireVersion::kV2, no_worker));
  EXPECT_TRUE(rtl::make_rtl_device(board_2023_preset(), link::WireVersion::kV2));
  EXPECT_TRUE(rtl::make_rtl_device(board_2023_preset(), link::WireVersion::kV1));
}

// The VCD: the top's pins always, one worker's inner signals only when asked, for the lines asked.
TEST(DeviceRtl, VcdOfPinsAndOneWorker) {
  DevicePreset p = board_2023_preset();
  for (const int worker : {-1, 4}) {
    rtl::RtlOptions o;
    o.vcd = ::testing::TempDir() + "rtl_device_" + std::to_string(worker + 1) + ".vcd";
    o.vcd_worker = worker;
    o.vcd_lines = 2;
    auto made = rtl::make_rtl_device(p, link::WireVersion::kV2, o);
    ASSERT_TRUE(made) << made.error();
    FrameStats stats;
    frame_samples(*made.value(), stats);
    std::ifstream in(o.vcd);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find(" spi_sclk "), std::string::npos);
    EXPECT_NE(text.find(" vga_hsync_n "), std::string::npos);
    // The scopes of the trace: the top, and with a worker that worker's (Verilator names the generate block).
    const bool has_worker = text.find("$scope module g_worker[4] $end") != std::string::npos;
    EXPECT_EQ(has_worker, worker == 4) << text.substr(0, 2000);
    EXPECT_EQ(text.find("$scope module g_worker[3] $end"), std::string::npos);
    // Every clock from reset to two lines into the frame: at least the clocks to the frame's start.
    const std::size_t last_time = text.rfind("\n#");
    ASSERT_NE(last_time, std::string::npos);
    const std::uint64_t ns = std::stoull(text.substr(last_time + 2));
    EXPECT_GE(ns, 2u * 800u * 4u * 10u);
    EXPECT_LT(ns, 50u * 800u * 4u * 10u);
  }
}

}  // namespace
}  // namespace tripsitter::device

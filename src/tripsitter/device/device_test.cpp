#include <tripsitter/device/device.h>

#include <random>

#include <array>

#include <gtest/gtest.h>

#include <tripsitter/link/frame.h>

#include "test_util.h"

namespace tripsitter::device {
namespace {

using testing::frame_of;
using testing::visible_pixels;

TEST(Device, BeforeAnyWorldTheScreenIsBackground) {
  Device d(wide_preset(), link::WireVersion::kV2);
  FrameStats stats;
  const auto pixels = visible_pixels(d, &stats);
  ASSERT_EQ(pixels.size(), 640u * 480u);
  EXPECT_FALSE(stats.has_world);
  for (const auto& p : pixels) ASSERT_EQ(p, core::kBackground);
}

TEST(Device, FrameFromTheSignalEqualsTheWorkersFunction) {
  const DevicePreset p = wide_preset();
  Device d(p, link::WireVersion::kV2);
  d.transfer(frame_of(p, 3, {{0, 0, 400, 64}, {-150, 60, 350, 40}, {120, -80, 500, 100}}));
  FrameStats stats;
  const auto pixels = visible_pixels(d, &stats);
  EXPECT_TRUE(stats.has_world);
  EXPECT_EQ(stats.sequence, 3u);
  EXPECT_EQ(stats.late_pixels, 0);
  const Worker w(p.sqrt_iterations);
  for (int row = 0; row < 480; ++row)
    for (int col = 0; col < 640; ++col)
      ASSERT_EQ(pixels[static_cast<std::size_t>(row * 640 + col)], w.shade(col, row, d.scene())) << col << "," << row;
}

TEST(Device, BoardPresetShowsTheBlackStripAndCountsIt) {
  const DevicePreset p = board_2023_preset();
  Device d(p, link::WireVersion::kV2);
  d.transfer(frame_of(p, 1, {{0, 0, 400, 64}}));
  FrameStats stats;
  const auto pixels = visible_pixels(d, &stats);
  EXPECT_EQ(stats.late_pixels, 60 * 480);
  EXPECT_EQ(stats.late_lines, 480);
  for (int row = 0; row < 480; row += 37)
    for (int col = 580; col < 640; ++col) ASSERT_EQ(pixels[static_cast<std::size_t>(row * 640 + col)], core::kBlack);
  EXPECT_EQ(pixels[240 * 640 + 320], core::Rgb444(0x770));
  EXPECT_EQ(d.total_late_lines(), 480u);
}

TEST(Device, AWorldArrivingMidFrameWaitsForVerticalBlanking) {
  const DevicePreset p = wide_preset();
  Device d(p, link::WireVersion::kV2);
  d.transfer(frame_of(p, 1, {{0, 0, 400, 64}}));
  // Run into the next frame's drawing, then send another world half-way down the screen.
  std::vector<core::Rgb444> pixels;
  int clock = 0;
  for (; clock < 420000; ++clock) {
    const int line = (480 + clock / 800) % 525;
    const int col = clock % 800;
    if (line == 240 && col == 0) {
      EXPECT_TRUE(d.ready());
      d.transfer(frame_of(p, 2, {{200, 0, 400, 64}}));
      EXPECT_FALSE(d.ready());
    }
    const VgaSample s = d.tick();
    if (line < 480 && col < 640) pixels.push_back(s.colour);
  }
  // Every line of this frame shows world 1, the lines below 240 included.
  const Worker w(p.sqrt_iterations);
  SceneMemory world1;
  world1.geometry.push_back({{0, 0, p.z.quantize(400).raw}, p.radius.quantize(64).raw});
  for (int row = 0; row < 480; ++row)
    for (int col = 0; col < 640; col += 7)
      ASSERT_EQ(pixels[static_cast<std::size_t>(row * 640 + col)], w.shade(col, row, world1)) << col << "," << row;
  FrameStats stats;
  visible_pixels(d, &stats);
  EXPECT_EQ(stats.sequence, 2u);
  EXPECT_TRUE(d.ready());
}

TEST(Device, RunFrameRequiresTheStartOfBlanking) {
  Device d(wide_preset(), link::WireVersion::kV2);
  d.tick();
  EXPECT_THROW(d.run_frame([](const VgaSample&) {}), std::logic_error);
}

TEST(Device, RejectsAnInvalidPreset) {
  DevicePreset p = wide_preset();
  p.workers = 0;
  EXPECT_THROW(Device(p, link::WireVersion::kV2), std::invalid_argument);
}

// A v2 frame of metal spheres (pixel units) with the given albedos.
std::vector<std::uint8_t> metal_frame(const DevicePreset& p, std::uint32_t sequence,
                                      const std::vector<std::array<double, 4>>& xyzr,
                                      const std::vector<std::array<std::uint8_t, 3>>& albedos) {
  link::World w;
  w.sequence = sequence;
  w.frac_bits = static_cast<std::uint8_t>(p.frac_bits());
  for (std::size_t i = 0; i < xyzr.size(); ++i) {
    link::WireSphere ws;
    ws.x = static_cast<std::int32_t>(p.x.quantize(xyzr[i][0]).raw);
    ws.y = static_cast<std::int32_t>(p.y.quantize(xyzr[i][1]).raw);
    ws.z = static_cast<std::int32_t>(p.z.quantize(xyzr[i][2]).raw);
    ws.radius = static_cast<std::uint32_t>(p.radius.quantize(xyzr[i][3]).raw);
    ws.material = link::kMaterialMetal;
    ws.albedo = albedos[i];
    ws.ior = 6144;
    w.spheres.push_back(ws);
  }
  return link::encode_frame(link::WireVersion::kV2, w);
}

TEST(Device, AMetalSphereFromTheWireReflectsTheBackground) {
  const DevicePreset p = wide_preset();
  Device d(p, link::WireVersion::kV2);
  d.transfer(metal_frame(p, 1, {{0, 0, 400, 64}}, {{255, 170, 128}}));
  FrameStats stats;
  const auto pixels = visible_pixels(d, &stats);
  EXPECT_EQ(stats.late_pixels, 0);
  EXPECT_EQ(pixels[240 * 640 + 320], core::Rgb444::from_channels(0, 2, 3));  // (0, 3, 6) tinted
  EXPECT_EQ(pixels[0], core::kBackground);
  const Worker w(p);
  for (int row = 0; row < 480; row += 5)
    for (int col = 0; col < 640; ++col)
      ASSERT_EQ(pixels[static_cast<std::size_t>(row * 640 + col)], w.shade(col, row, d.scene())) << col << "," << row;
}

// Two nearly flat mirrors around the camera: every pixel bounces 3 times, so each worker finishes 24 of its
// 64 pixels (controller_test.cpp, Mirror.LatePixelsGrowWithTheBounceCutOff, has the arithmetic).
TEST(Device, BouncingPixelsAreLateOnEveryLine) {
  const DevicePreset p = wide_preset();
  Device d(p, link::WireVersion::kV2);
  d.transfer(metal_frame(p, 1, {{0, 0, 100000, 99000}, {0, 0, -100000, 99000}}, {{255, 255, 255}, {200, 200, 200}}));
  FrameStats stats;
  const auto pixels = visible_pixels(d, &stats);
  EXPECT_EQ(stats.late_pixels, 400 * 480);
  EXPECT_EQ(stats.late_lines, 480);
  for (int row = 0; row < 480; row += 31)
    for (int col = 240; col < 640; ++col) ASSERT_EQ(pixels[static_cast<std::size_t>(row * 640 + col)], core::kBlack);
  EXPECT_NE(pixels[100 * 640 + 5], core::kBlack);
}

// The fast model on two threads (lines computed ahead from vertical blanking on) shows exactly what the
// plain model shows, frame after frame, late pixels included.
TEST(Device, ParallelFramesEqualThePlainModel) {
  std::mt19937 rng(12);
  for (const DevicePreset& p : {wide_preset(), board_2023_preset()}) {
    Device plain(p, link::WireVersion::kV2, 1, DeviceModel::kPlain), parallel(p, link::WireVersion::kV2, 2);
    for (int world = 0; world < 4; ++world) {
      std::vector<std::array<double, 4>> spheres;
      std::uniform_real_distribution<double> xy(-300, 300), z(150, 1500), r(5, 120);
      const int count = world == 3 ? 60 : 1 + world * 7;  // 60 spheres: late pixels on the wide preset too
      for (int i = 0; i < count && i < static_cast<int>(p.max_spheres); ++i) spheres.push_back({xy(rng), xy(rng) / 2, z(rng) / 2, r(rng) / 2});
      const auto bytes = frame_of(p, static_cast<std::uint32_t>(world + 1), spheres);
      plain.transfer(bytes);
      parallel.transfer(bytes);
      FrameStats a, b;
      ASSERT_EQ(visible_pixels(plain, &a), visible_pixels(parallel, &b)) << p.name << " world " << world;
      EXPECT_EQ(a.late_pixels, b.late_pixels);
      EXPECT_EQ(a.late_lines, b.late_lines);
      EXPECT_EQ(a.sequence, b.sequence);
    }
  }
}

// run_frame produces a frame line by line; tick() one clock at a time: the same samples, and the same
// position afterwards.
TEST(Device, RunFrameGivesTheSamplesOfTick) {
  const DevicePreset p = board_2023_preset();
  Device by_frame(p, link::WireVersion::kV2, 1, DeviceModel::kPlain), by_tick(p, link::WireVersion::kV2, 1, DeviceModel::kPlain);
  for (int frame = 0; frame < 2; ++frame) {
    const auto bytes = frame_of(p, static_cast<std::uint32_t>(frame + 1), {{0, 0, 400, 64}, {-100, 50, 300, 30}});
    by_frame.transfer(bytes);
    by_tick.transfer(bytes);
    std::vector<VgaSample> a, b;
    const FrameStats stats = by_frame.run_frame([&](const VgaSample& s) { a.push_back(s); });
    for (int i = 0; i < 800 * 525; ++i) b.push_back(by_tick.tick());
    ASSERT_EQ(a, b) << "frame " << frame;
    EXPECT_EQ(stats.late_pixels, by_tick.current_frame().late_pixels);
  }
  EXPECT_NO_THROW(by_tick.run_frame([](const VgaSample&) {}));  // back at the start of vertical blanking
}

// The fast model against the plain one, whole frames through the wire and the VGA signal, with mirrors:
// the same pixels and the same late pixels and lines, frame after frame; with one helper thread, with none,
// and with three driven a clock at a time.
TEST(Device, FastFramesWithMirrorsEqualThePlainModel) {
  std::mt19937 rng(21);
  for (const DevicePreset& p : {wide_preset(), board_2023_preset()}) {
    Device plain(p, link::WireVersion::kV2, 1, DeviceModel::kPlain), fast(p, link::WireVersion::kV2, 2),
        ticked(p, link::WireVersion::kV2, 4), alone(p, link::WireVersion::kV2, 1);
    for (int world = 0; world < 3; ++world) {
      std::vector<std::array<double, 4>> spheres;
      std::vector<std::array<std::uint8_t, 3>> albedos;
      std::uniform_real_distribution<double> xy(-300, 300), z(150, 1500), r(5, 120);
      const int count = world == 2 ? 64 : 5 + world * 10;  // 64: late pixels on the wide preset too
      for (int i = 0; i < count && i < static_cast<int>(p.max_spheres); ++i) {
        spheres.push_back({xy(rng), xy(rng) / 2, z(rng) / 2, r(rng) / 2});
        albedos.push_back({static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng()), 255});
      }
      const auto bytes = metal_frame(p, static_cast<std::uint32_t>(world + 1), spheres, albedos);
      plain.transfer(bytes);
      fast.transfer(bytes);
      ticked.transfer(bytes);
      alone.transfer(bytes);
      FrameStats a, b, c;
      const auto expected = visible_pixels(plain, &a);
      ASSERT_EQ(expected, visible_pixels(fast, &b)) << p.name << " world " << world;
      ASSERT_EQ(expected, visible_pixels(alone, &c)) << p.name << " world " << world;
      EXPECT_EQ(c.late_lines, a.late_lines);
      std::vector<core::Rgb444> by_tick;
      for (int clock = 0; clock < 800 * 525; ++clock) {
        const VgaSample s = ticked.tick();
        if ((480 + clock / 800) % 525 < 480 && clock % 800 < 640) by_tick.push_back(s.colour);
      }
      ASSERT_EQ(expected, by_tick) << p.name << " world " << world;
      EXPECT_EQ(ticked.current_frame().late_pixels, a.late_pixels);
      EXPECT_EQ(a.late_pixels, b.late_pixels);
      EXPECT_EQ(a.late_lines, b.late_lines);
      EXPECT_EQ(a.sequence, b.sequence);
      EXPECT_EQ(a.worst_line_cycles, b.worst_line_cycles);
      EXPECT_EQ(a.reflections, b.reflections);
      EXPECT_EQ(a.worst_line_cycles, c.worst_line_cycles);
      EXPECT_EQ(a.reflections, c.reflections);
      EXPECT_EQ(ticked.current_frame().worst_line_cycles, a.worst_line_cycles);
      if (world == 2) {
        EXPECT_GT(a.late_lines, 0) << p.name;
      }
    }
    EXPECT_EQ(plain.total_late_pixels(), fast.total_late_pixels());
    EXPECT_EQ(plain.total_late_lines(), fast.total_late_lines());
    EXPECT_EQ(plain.total_late_lines(), ticked.total_late_lines());
  }
}

// trace_late_pixels, a measurement option of the model: whole frames through the wire and the VGA signal, in both
// models, show the same pixels and count the same late pixels, lines and reflections with it as without, on the
// presets with mirrors (the board's few workers make every line late). The demand is the same in both models;
// traced it is exact, at least the untraced lower bound, and the same on a frame with no late line.
TEST(Device, TracingLatePixelsChangesNothingShown) {
  std::mt19937 rng(33);
  DevicePreset board_few = board_2023_preset();
  board_few.name = "board-2023, 4 workers, 2 bounces";
  board_few.workers = 4;
  board_few.max_bounces = 2;
  DevicePreset board_one = board_2023_preset();
  board_one.name = "board-2023, 640 workers, 1 bounce";  // nothing late
  board_one.workers = 640;
  board_one.max_bounces = 1;
  for (const DevicePreset& off : {wide_preset(), board_2023_preset(), board_few, board_one}) {
    DevicePreset on = off;
    on.trace_late_pixels = true;
    std::vector<std::array<double, 4>> spheres;
    std::vector<std::array<std::uint8_t, 3>> albedos;
    std::uniform_real_distribution<double> xy(-300, 300), z(150, 1500), r(5, 120);
    // A large metal sphere on the left, where the workers with few pixels on time draw, then random ones.
    spheres.push_back({-300, 0, 400, 150});
    albedos.push_back({255, 200, 100});
    const int count = off.name == "wide" ? 44 : 5;
    for (int i = 0; i < count; ++i) {
      spheres.push_back({xy(rng), xy(rng) / 2, z(rng) / 2, r(rng) / 2});
      albedos.push_back({static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng()), 255});
    }
    const auto bytes = metal_frame(off, 1, spheres, albedos);
    std::vector<FrameStats> stats;  // plain off, plain on, fast off, fast on
    std::vector<std::vector<core::Rgb444>> frames;
    for (const DeviceModel model : {DeviceModel::kPlain, DeviceModel::kFast}) {
      for (const DevicePreset* p : std::array<const DevicePreset*, 2>{&off, &on}) {
        Device d(*p, link::WireVersion::kV2, 2, model);
        d.transfer(bytes);
        FrameStats s;
        frames.push_back(visible_pixels(d, &s));
        stats.push_back(s);
      }
    }
    for (std::size_t i = 1; i < frames.size(); ++i) {
      ASSERT_EQ(frames[0], frames[i]) << off.name << ", run " << i;
      EXPECT_EQ(stats[0].late_pixels, stats[i].late_pixels) << off.name << ", run " << i;
      EXPECT_EQ(stats[0].late_lines, stats[i].late_lines) << off.name << ", run " << i;
      EXPECT_EQ(stats[0].reflections, stats[i].reflections) << off.name << ", run " << i;
    }
    EXPECT_EQ(stats[0].worst_line_cycles, stats[2].worst_line_cycles) << off.name;
    EXPECT_EQ(stats[1].worst_line_cycles, stats[3].worst_line_cycles) << off.name;
    EXPECT_LE(stats[0].worst_line_cycles, stats[1].worst_line_cycles) << off.name;
    if (off.max_bounces > 0) {
      EXPECT_GT(stats[0].reflections, 1000u) << off.name;
    }
    if (off.workers == 640) {
      EXPECT_EQ(stats[0].late_lines, 0) << off.name;
      EXPECT_EQ(stats[0].worst_line_cycles, stats[1].worst_line_cycles) << off.name;
      EXPECT_LE(stats[0].worst_line_cycles, off.lead_cycles) << off.name;
    } else {
      EXPECT_GT(stats[0].late_lines, 0) << off.name;
      EXPECT_GT(stats[0].worst_line_cycles, off.lead_cycles) << off.name;
    }
  }
}

// The frame's demand is the largest of its lines': the board's demo sphere, 58 of 64 pixels a worker on time,
// needs 64 * 51 cycles on every line; reflections are the mirror model's on-time pixels' only.
TEST(Device, TheWorstLineOfTheBoardsDemoNeeds64PixelsOf51Cycles) {
  const DevicePreset p = board_2023_preset();
  for (const DeviceModel model : {DeviceModel::kPlain, DeviceModel::kFast}) {
    Device d(p, link::WireVersion::kV2, 2, model);
    d.transfer(frame_of(p, 1, {{0, 0, 400, 64}}));
    FrameStats stats;
    visible_pixels(d, &stats);
    EXPECT_EQ(stats.worst_line_cycles, 64 * 51);
    EXPECT_EQ(stats.reflections, 0u);
  }
}

}  // namespace
}  // namespace tripsitter::device

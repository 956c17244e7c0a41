#include <tripsitter/device/fast_tracer.h>

#include <algorithm>
#include <array>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/core/sanitizers.h>
#include <tripsitter/link/frame.h>

#include "test_util.h"

namespace tripsitter::device {
namespace {

using testing::random_world;
using testing::wide_32_preset;

// Fewer worlds under the sanitizers, which run the whole suite many times slower.
constexpr int kWorldsPerPreset = core::kSanitized ? 60 : 250;
constexpr int kRowsPerWorld = 8;

// The presets the fast model is checked in: the shipped mirror-model ones, the board's with mirrors, schedules
// with other worker counts and leads, 32-bit formats, and the artix preset's sphere units, also with a prime count
// of them (late lines).
std::vector<DevicePreset> presets_under_test() {
  DevicePreset board_mirrors = board_2023_preset();
  board_mirrors.name = "board-2023 with 2 bounces";
  board_mirrors.max_bounces = 2;
  DevicePreset wide_7 = wide_preset();
  wide_7.name = "wide, 7 workers, lead 2000";
  wide_7.workers = 7;
  wide_7.lead_cycles = 2000;
  DevicePreset board_64 = board_2023_preset();
  board_64.name = "board-2023, 64 workers, 12 sqrt iterations";
  board_64.workers = 64;
  board_64.sqrt_iterations = 12;
  DevicePreset artix_5 = artix_preset();
  artix_5.name = "artix, 5 units";
  artix_5.workers = 5;
  return {wide_preset(), board_2023_preset(), board_mirrors, wide_7, board_64, wide_32_preset(), artix_preset(),
          artix_5};
}

// Many random worlds: every checked row of the fast model equals the plain model's, pixel for pixel, with
// the same late pixels and reflections.
TEST(FastTracer, RowsEqualThePlainModelOnRandomWorlds) {
  std::mt19937_64 rng(2026);
  for (const DevicePreset& p : presets_under_test()) {
    const Controller plain(p);
    FastTracer fast(p);
    int late = 0, reflections = 0, fallback_worlds = 0;
    for (int world = 0; world < kWorldsPerPreset; ++world) {
      const SceneMemory scene = random_world(p, rng);
      fast.load(scene);
      fallback_worlds += fast.narrow() ? 0 : 1;
      for (int k = 0; k < kRowsPerWorld; ++k) {
        const int row = k == 0 ? 240 : static_cast<int>(rng() % 480);
        std::array<core::Rgb444, kLineWidth> expected, got;
        expected.fill(core::Rgb444(0xABC));
        got.fill(core::Rgb444(0xDEF));
        const LineResult a = plain.render_line(row, scene, expected);
        const LineResult b = fast.render_line(row, got);
        ASSERT_EQ(a.late_pixels, b.late_pixels) << p.name << " world " << world << " row " << row;
        ASSERT_EQ(a.reflections, b.reflections) << p.name << " world " << world << " row " << row;
        ASSERT_EQ(a.demand_cycles, b.demand_cycles) << p.name << " world " << world << " row " << row;
        for (int col = 0; col < kLineWidth; ++col)
          ASSERT_EQ(expected[static_cast<std::size_t>(col)], got[static_cast<std::size_t>(col)])
              << p.name << " world " << world << " row " << row << " col " << col;
        late += a.late_pixels;
        reflections += a.reflections;
      }
    }
    // The worlds exercise what they are meant to.
    EXPECT_GT(reflections, p.max_bounces > 0 ? 100 : -1) << p.name;
    if (p.name == "board-2023") {
      EXPECT_GT(late, 60 * kRowsPerWorld * kWorldsPerPreset / 2) << p.name;
    }
    if (p.name == "artix, 5 units") {
      EXPECT_GT(late, 0) << p.name;
    }
    if (p.x.total_bits > 29) {
      EXPECT_GT(fallback_worlds, 0) << p.name;
      EXPECT_LT(fallback_worlds, kWorldsPerPreset) << p.name;
    } else {
      EXPECT_EQ(fallback_worlds, 0) << p.name;
    }
  }
}

// With trace_late_pixels (every column traced, no columns_ shortcut) the fast model still gives the plain model's
// rows, and both show what they show without it: the same colours, late pixels and reflections. The demand is
// the same in both models either way; tracing the late pixels can only raise it, and only on late lines.
TEST(FastTracer, TracingLatePixelsChangesNothingShownAndGivesTheExactDemand) {
  std::mt19937_64 rng(2028);
  for (const DevicePreset& off : presets_under_test()) {
    DevicePreset on = off;
    on.trace_late_pixels = true;
    const Controller plain_off(off), plain_on(on);
    FastTracer fast_off(off), fast_on(on);
    int late_lines = 0, raised = 0;
    for (int world = 0; world < kWorldsPerPreset / 4; ++world) {
      const SceneMemory scene = random_world(off, rng);
      fast_off.load(scene);
      fast_on.load(scene);
      for (int k = 0; k < kRowsPerWorld; ++k) {
        const int row = k == 0 ? 240 : static_cast<int>(rng() % 480);
        std::array<std::array<core::Rgb444, kLineWidth>, 4> lines;
        for (std::size_t i = 0; i < lines.size(); ++i) lines[i].fill(core::Rgb444(static_cast<std::uint16_t>(0x123 * (i + 1))));
        const std::array<LineResult, 4> r{plain_off.render_line(row, scene, lines[0]), fast_off.render_line(row, lines[1]),
                                          plain_on.render_line(row, scene, lines[2]), fast_on.render_line(row, lines[3])};
        const std::string where = off.name + " world " + std::to_string(world) + " row " + std::to_string(row);
        for (std::size_t i = 1; i < r.size(); ++i) {
          ASSERT_EQ(lines[0], lines[i]) << where << ", line " << i;
          ASSERT_EQ(r[0].late_pixels, r[i].late_pixels) << where << ", line " << i;
          ASSERT_EQ(r[0].reflections, r[i].reflections) << where << ", line " << i;
        }
        ASSERT_EQ(r[0].demand_cycles, r[1].demand_cycles) << where;
        ASSERT_EQ(r[2].demand_cycles, r[3].demand_cycles) << where;
        if (r[0].late_pixels == 0) {
          ASSERT_EQ(r[0].demand_cycles, r[2].demand_cycles) << where;
          ASSERT_LE(r[0].demand_cycles, off.lead_cycles) << where;
        } else {
          ASSERT_GT(r[0].demand_cycles, off.lead_cycles) << where;
          ASSERT_LE(r[0].demand_cycles, r[2].demand_cycles) << where;
          ++late_lines;
          raised += r[0].demand_cycles < r[2].demand_cycles;
        }
      }
    }
    // The board's worlds are late on most lines, and some late pixels reflect where the preset has mirrors.
    if (off.name.starts_with("board-2023")) {
      EXPECT_GT(late_lines, kWorldsPerPreset / 8) << off.name;
    }
    if (off.max_bounces > 0 && late_lines > 0 && !off.demand_exact()) {  // exact already: nothing to raise
      EXPECT_GT(raised, 0) << off.name;
    }
  }
}

// Worlds the random ones rarely hit exactly: spheres tangent to the camera's plane and to column and row
// planes, a sphere through the camera, equal spheres (ties go to the one sent first), an empty world.
// The fast model's 64-bit arithmetic runs the kernel's quadratic (core::hit_num) to the same num as the
// device's 128-bit one. Coefficients within the wide preset's documented widths (docs/device.md), so that no
// check fires in builds with TRIPSITTER_CHECK_FIXED.
TEST(NarrowArith, GivesTheKernelsNumOfFixedArith) {
  for (const DevicePreset& p : {wide_preset(), board_2023_preset(), wide_32_preset()}) {
    const FixedArith fixed{SqrtUnit(p.sqrt_iterations), FixedArith::extra_bits_of(p)};
    const NarrowArith narrow{fixed};
    std::mt19937_64 rng(21);
    int hits = 0;
    for (int i = 0; i < 200000; ++i) {
      // a < 2^40, |b| < 2^47 and |c'| <= 2^50: b^2, 4ac' < 2^95.
      const int a_bits = 1 + static_cast<int>(rng() % 39), b_bits = 1 + static_cast<int>(rng() % 47);
      const std::int64_t a = static_cast<std::int64_t>(rng() >> (64 - a_bits)) + 1;
      const std::int64_t b = static_cast<std::int64_t>(rng() >> (64 - b_bits)) * (rng() % 4 == 0 ? -1 : 1);
      // c' near b^2 / 4a, so that both hits and misses are common.
      const auto near = static_cast<std::int64_t>(static_cast<double>(b) * static_cast<double>(b) / (4.0 * a));
      const std::int64_t c_prime = std::clamp<std::int64_t>(
          near + static_cast<std::int64_t>(rng() % 2001) - 1000 - static_cast<std::int64_t>(rng() % (near / 8 + 1)),
          -(std::int64_t{1} << 50), std::int64_t{1} << 50);
      const std::int64_t got = core::hit_num(narrow, a, b, c_prime);
      const core::Int128 want = core::hit_num(fixed, core::Int128{a}, core::Int128{b}, core::Int128{c_prime});
      ASSERT_TRUE(core::Int128{got} == want) << p.name << " a=" << a << " b=" << b << " c'=" << c_prime;
      if (got > 0) ++hits;
    }
    EXPECT_GT(hits, 20000) << p.name;
  }
}

TEST(FastTracer, RowsEqualThePlainModelOnEdgeWorlds) {
  const DevicePreset p = wide_preset();
  const std::int64_t s = 16;  // raw units per pixel unit
  std::vector<SceneMemory> worlds;
  constexpr std::uint8_t kLambertian = link::kMaterialLambertian, kMetal = link::kMaterialMetal;
  const auto world = [&](std::vector<core::KernelSphere<std::int64_t>> g, std::vector<std::uint8_t> materials) {
    SceneMemory m;
    m.valid = true;
    m.geometry = std::move(g);
    for (std::size_t i = 0; i < m.geometry.size(); ++i)
      m.surfaces.push_back({materials[i % materials.size()], {200, 100, 50}, 0, 6144});
    worlds.push_back(std::move(m));
  };
  world({}, {kLambertian});
  world({{{0, 0, -100 * s}, 100 * s}, {{0, 0, 400 * s}, 64 * s}}, {kLambertian});  // touches z = 0
  world({{{0, 0, 0}, 100 * s}}, {kLambertian});                                     // camera at its centre
  world({{{100 * s, 0, 0}, 100 * s}}, {kMetal});                                    // camera on its surface
  // Equal spheres of different materials: the one sent first wins every tie.
  world({{{0, 0, 400 * s}, 64 * s}, {{0, 0, 400 * s}, 64 * s}, {{0, 0, 400 * s}, 64 * s}}, {kLambertian, kMetal});
  world({{{0, 0, 400 * s}, 64 * s}, {{0, 0, 400 * s}, 64 * s}}, {kMetal, kLambertian});
  // The same for reflected rays: a mirror shows pairs of equal spheres behind the camera, sent far apart
  // among enough others that the search for reflected rays groups them differently.
  {
    std::vector<core::KernelSphere<std::int64_t>> g(16, core::KernelSphere<std::int64_t>{{0, 0, 3000 * s}, 10 * s});
    for (std::size_t i = 0; i < g.size(); ++i) g[i].center.x = (static_cast<std::int64_t>(i) * 60 - 500) * s;
    g[0] = {{0, 0, 500 * s}, 150 * s};
    g[1] = g[6] = {{0, 0, -300 * s}, 60 * s};
    g[7] = g[2] = {{150 * s, 60 * s, -300 * s}, 60 * s};
    g[3] = g[12] = {{-150 * s, -60 * s, -250 * s}, 60 * s};
    g[13] = g[4] = {{-150 * s, 90 * s, -280 * s}, 60 * s};
    g[5] = g[10] = {{150 * s, -90 * s, -260 * s}, 60 * s};
    world(g, {kMetal, kLambertian, kMetal, kLambertian, kMetal, kLambertian, kMetal, kLambertian, kMetal, kLambertian,
              kMetal, kMetal, kMetal, kLambertian, kLambertian, kLambertian});
  }
  // Centre on the ray of column 100 and row 40 (on the planes of both), the smallest radii.
  world({{{-220 * s, -200 * s, 320 * s}, 2}, {{-220 * s, -200 * s, 320 * s}, 1}}, {kLambertian});
  world({{{-220 * s, -200 * s, 320 * s}, 1}}, {kMetal});
  world({{{-320 * s, -240 * s, 320 * s}, 3}, {{319 * s, 239 * s, 320 * s}, 2}}, {kLambertian});
  for (std::size_t w = 0; w < worlds.size(); ++w) {
    const Controller plain(p);
    FastTracer fast(p);
    fast.load(worlds[w]);
    for (int row = 0; row < 480; ++row) {
      std::array<core::Rgb444, kLineWidth> expected, got;
      const LineResult a = plain.render_line(row, worlds[w], expected);
      const LineResult b = fast.render_line(row, got);
      ASSERT_EQ(a.late_pixels, b.late_pixels) << "world " << w << " row " << row;
      ASSERT_EQ(a.reflections, b.reflections) << "world " << w << " row " << row;
      ASSERT_EQ(a.demand_cycles, b.demand_cycles) << "world " << w << " row " << row;
      ASSERT_EQ(expected, got) << "world " << w << " row " << row;
    }
  }
}

}  // namespace
}  // namespace tripsitter::device

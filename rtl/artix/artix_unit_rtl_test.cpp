// One artix unit's RTL (ts_artix_unit.sv: issue port, sphere unit, shading and reflection, queues) held to the
// model's line: every colour of the unit's columns equal to artix::trace_pixel_with's and written to the line
// buffer in the cycle before artix::unit_finish_cycles says it is there, late pixels not written at all. Scene
// memory and the tile lists are modelled here as registered reads of the world (artix::prepare_world's spheres
// and artix::row_tiles), the directions written as ts_artix_camera would.
#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sphere_unit_draw.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_artix_unit_12.h>
#include <Vts_artix_unit_5.h>

#include <tripsitter/device/artix_units.h>
#include <tripsitter/device/preset.h>

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;

constexpr int kCoordW = 22, kDirW = 18, kLineCycles = 3200;

using sphere_unit::pack3;

struct Write {
  int slot;
  int colour;
};

// Runs one line window of unit U of N on row `row` of `world`: the writes to its line buffer bank, by cycle.
template <class Top>
std::map<std::int64_t, Write> run_line(Top& top, int unit, int units, const artix::UnitWorld& world, int row,
                                       bool& overflow) {
  const artix::RowTiles tiles = artix::row_tiles(world, row, device::DeviceUnits{}.tile_columns);
  // The row's directions, written (as the camera generator does while the line before is shown) into the bank
  // the next start makes current.
  top.unit_id = static_cast<unsigned>(unit);
  top.start = 0;
  top.flush = 0;
  top.spheres = static_cast<unsigned>(world.spheres.size());
  for (int k = 0, col = unit; col < 640; ++k, col += units) {
    top.dir_we = 1;
    top.dir_slot = static_cast<unsigned>(k);
    put(top.dir_d, pack3(artix::camera_direction(col, row), kDirW));
    rising_edge(top);
  }
  top.dir_we = 0;

  std::map<std::int64_t, Write> writes;
  unsigned tile_count = 0, tile_sphere = 0;
  int sphere_addr = 0;
  for (std::int64_t cycle = 0; cycle < kLineCycles + 100; ++cycle) {
    top.start = cycle == 0;
    top.flush = cycle == kLineCycles - 1;
    // Registered reads: what the ports asked for in the cycle before.
    top.tile_count = tile_count;
    top.tile_sphere = tile_sphere;
    const artix::UnitSphere& s = world.spheres.empty() ? artix::UnitSphere{} : world.spheres[static_cast<std::size_t>(
                                                                                  std::min<int>(sphere_addr, static_cast<int>(world.spheres.size()) - 1))];
    put(top.sphere_c, pack3(s.c, kCoordW));
    top.sphere_r = static_cast<unsigned>(s.r);
    top.sphere_e = static_cast<unsigned>(s.e) & 0x3f;
    top.sphere_r2s = static_cast<std::uint64_t>(s.r2s);
    top.sphere_rinv = static_cast<unsigned>(s.rinv);
    top.sphere_metal = s.metal;
    top.sphere_albedo = static_cast<unsigned>(s.albedo[0]) << 16 | static_cast<unsigned>(s.albedo[1]) << 8 | s.albedo[2];
    top.eval();
    if (top.px_we) writes[cycle] = {static_cast<int>(top.px_slot), static_cast<int>(top.px_colour)};
    const auto list = tiles.list(static_cast<int>(top.tile));
    tile_count = static_cast<unsigned>(list.size());
    tile_sphere = top.tile_pos < list.size() ? static_cast<unsigned>(list[top.tile_pos]) : 0u;
    sphere_addr = static_cast<int>(top.sphere_addr);
    rising_edge(top);
  }
  overflow = top.overflow != 0;
  return writes;
}

// A random world as the preset's tests draw them: spheres in view and around, a third metal.
artix::UnitWorld random_world(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> u(-1, 1);
  artix::UnitWorld w;
  for (int i = 0; i < count; ++i) {
    const double z = std::ldexp(1.0 + u(rng), 9 + static_cast<int>(rng() % 6));
    core::KernelSphere<std::int64_t> k;
    k.center = {static_cast<std::int64_t>(u(rng) * z), static_cast<std::int64_t>(u(rng) * z * 0.75),
                static_cast<std::int64_t>(rng() % 8 == 0 ? u(rng) * z : z)};
    k.radius = std::max<std::int64_t>(1, static_cast<std::int64_t>(z * (0.02 + 0.3 * (u(rng) + 1) / 2)));
    core::KernelSurface surface;
    surface.metal = rng() % 3 == 0;
    for (auto& a : surface.albedo) a = static_cast<std::uint8_t>(rng() % 256);
    w.spheres.push_back(artix::prepare_sphere(k, surface));
    w.bounds.push_back(artix::cull_bounds(w.spheres.back()));
  }
  return w;
}

template <class Top>
void expect_line_equals_model(int unit, int units, const artix::UnitWorld& world, int row, const std::string& what,
                              int& late_seen, int& reflected_seen) {
  // One model per build, reset once: windows follow each other as on the device. Its context outlives it.
  static const auto context = std::make_unique<VerilatedContext>();
  static std::unique_ptr<Top> top;
  if (!top) {
    top = std::make_unique<Top>(context.get());
    top->rst = 1;
    for (int i = 0; i < 4; ++i) rising_edge(*top);
    top->rst = 0;
  }
  bool overflow = false;
  const auto writes = run_line(*top, unit, units, world, row, overflow);
  EXPECT_FALSE(overflow) << what;

  device::DevicePreset preset = device::artix_preset();
  preset.workers = units;
  const artix::RowTiles tiles = artix::row_tiles(world, row, preset.units->tile_columns);
  std::vector<core::PixelTrace> pixels(640);
  std::vector<int> tests(640);
  const std::span<const artix::UnitSphere> spheres(world.spheres);
  for (int col = 0; col < 640; ++col) {
    const auto list = tiles.list(col / preset.units->tile_columns);
    tests[static_cast<std::size_t>(col)] = static_cast<int>(list.size());
    pixels[static_cast<std::size_t>(col)] = artix::trace_pixel(col, row, spheres, preset.max_bounces);
  }
  const auto finish = artix::unit_finish_cycles(preset, static_cast<std::int64_t>(spheres.size()), pixels, tests);
  std::size_t expected_writes = 0;
  for (int k = 0, col = unit; col < 640; ++k, col += units) {
    const auto c = static_cast<std::size_t>(col);
    reflected_seen += pixels[c].bounces > 0;
    if (finish[c] > kLineCycles) {
      ++late_seen;
      continue;
    }
    ++expected_writes;
    const auto it = writes.find(finish[c] - 1);
    ASSERT_NE(it, writes.end()) << what << ": column " << col << " due in cycle " << finish[c] - 1;
    EXPECT_EQ(it->second.slot, k) << what << ": column " << col;
    EXPECT_EQ(it->second.colour, static_cast<int>(pixels[c].colour.packed)) << what << ": column " << col;
  }
  EXPECT_EQ(writes.size(), expected_writes) << what;
}

template <class Top>
void random_lines(int unit, int units, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  int late = 0, reflected = 0;
  for (int world = 0; world < 12; ++world) {
    const int count = world == 0 ? 0 : world < 9 ? static_cast<int>(rng() % 24) : 150 + static_cast<int>(rng() % 100);
    const artix::UnitWorld w = random_world(rng, count);
    for (int i = 0; i < 3; ++i) {
      const int row = i == 0 ? 240 : static_cast<int>(rng() % 480);
      expect_line_equals_model<Top>(unit, units, w, row,
                                    "world " + std::to_string(world) + " (" + std::to_string(count) + " spheres), row " +
                                        std::to_string(row),
                                    late, reflected);
    }
  }
  // The draw reaches what it should: reflections, and late pixels on the big worlds.
  EXPECT_GT(reflected, 20);
  EXPECT_GT(late, 0);
}

TEST(ArtixUnitRtl, LinesEqualTheModelUnit0Of12) { random_lines<Vts_artix_unit_12>(0, 12, 31); }
TEST(ArtixUnitRtl, LinesEqualTheModelUnit11Of12) { random_lines<Vts_artix_unit_12>(11, 12, 33); }
TEST(ArtixUnitRtl, LinesEqualTheModelUnit3Of5) { random_lines<Vts_artix_unit_5>(3, 5, 32); }

}  // namespace
}  // namespace tripsitter::rtl

#include <tripsitter/device/artix_kernel.h>
#include <tripsitter/device/artix_units.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/core/sanitizers.h>

#include "test_util.h"

namespace tripsitter::device {
namespace {

using artix::UnitRay;
using artix::UnitSphere;
using artix::Vec3i;

UnitSphere sphere_at(double x, double y, double z, double r, bool metal = false) {
  const DevicePreset p = artix_preset();
  core::KernelSphere<std::int64_t> s{{p.x.quantize(x).raw, p.y.quantize(y).raw, p.z.quantize(z).raw},
                                     std::max<std::int64_t>(1, p.radius.quantize(r).raw)};
  return artix::prepare_sphere(s, core::KernelSurface{metal, {255, 255, 255}});
}

TEST(Artix, CameraDirectionsAreUnitAndFollowTheBoardsRays) {
  double worst_length = 0, worst_component = 0;
  for (int row = 0; row < core::kScreenHeight; ++row) {
    for (int col = 0; col < core::kScreenWidth; ++col) {
      const Vec3i d = artix::camera_direction(col, row);
      const auto v = core::device_ray<double>(col, row);
      const double len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
      const double exact[3] = {v.x / len * 131072, v.y / len * 131072, v.z / len * 131072};
      double sq = 0;
      for (std::size_t k = 0; k < 3; ++k) {
        ASSERT_LE(std::abs(d[k]), artix::kDirectionMax);
        worst_component = std::max(worst_component, std::abs(static_cast<double>(d[k]) - exact[k]));
        sq += static_cast<double>(d[k]) * static_cast<double>(d[k]);
      }
      worst_length = std::max(worst_length, std::abs(std::sqrt(sq) / 131072 - 1));
    }
  }
  // One Newton step from the 313-entry table, rounded to 2^-17: within a unit per component (the centre's z, 1
  // exactly, saturates to 2^17 - 1).
  EXPECT_LE(worst_component, 1.0);
  EXPECT_LE(worst_length, 2.0 / 131072);
}

// SPEC.md's worked example: the sphere at (0, 0, 400) of radius 64 is a disc of radius about 51.9 pixels whose
// point facing the camera is 0x770.
TEST(Artix, TheSpecsSphereIsItsDisc) {
  const std::vector<UnitSphere> spheres{sphere_at(0, 0, 400, 64)};
  EXPECT_EQ(artix::trace_pixel(320, 240, spheres, 0).colour, core::Rgb444(0x770));
  int hits = 0;
  for (int col = 0; col < core::kScreenWidth; ++col)
    hits += artix::trace_pixel(col, 240, spheres, 0).colour != core::kBackground ? 1 : 0;
  EXPECT_EQ(hits, 2 * 52 - 1);  // columns 269..371 (|x| <= 51)
}

// The sphere unit against double arithmetic on random rays and spheres: the same hits away from the silhouette,
// t within 2^-12 of the exact distance plus a raw unit.
TEST(Artix, QuadraticFollowsTheExactGeometry) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int hits = 0, compared = 0;
  for (int i = 0; i < 20000; ++i) {
    const int col = static_cast<int>(rng() % 640), row = static_cast<int>(rng() % 480);
    // A sphere near the pixel's ray, as often hit as missed.
    const double z = 40 + 4000 * unit(rng);
    const double r = 0.5 + z * 0.3 * unit(rng) * unit(rng);
    const double off = 2 * r * unit(rng);
    const UnitSphere s = sphere_at((col - 320) * z / 320 + off, (row - 240) * z / 320 - off * unit(rng), z, r);
    const UnitRay ray{{}, artix::camera_direction(col, row)};
    const artix::Quadratic q = artix::quadratic(ray, s);
    // Exact geometry of the same (rounded) ray and sphere, in raw units.
    double d[3], oc[3], b = 0, dd = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      d[k] = static_cast<double>(ray.d[k]);
      oc[k] = static_cast<double>(s.c[k]);
      b += d[k] * oc[k];
      dd += d[k] * d[k];
    }
    const double len = std::sqrt(dd);
    b /= len;
    double ff = 0;
    for (std::size_t k = 0; k < 3; ++k) ff += std::pow(oc[k] - b * d[k] / len, 2);
    const double rr = static_cast<double>(s.r);
    const double disc = rr * rr - ff;
    if (std::abs(disc) < rr * rr * 0.01) continue;  // near the silhouette: the scaled f decides
    ++compared;
    const bool exact_hit = disc > 0 && b - std::sqrt(disc) > 0;
    ASSERT_EQ(q.hit(), exact_hit) << "pair " << i;
    if (!exact_hit) continue;
    ++hits;
    const double t = static_cast<double>(q.td) / 131072;
    EXPECT_NEAR(t, b - std::sqrt(disc), 1 + (b - std::sqrt(disc)) / 4096) << "pair " << i;
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(compared, 15000);
}

TEST(Artix, NormalsAreUnitVectors) {
  const std::vector<UnitSphere> spheres{sphere_at(-100, 30, 500, 120), sphere_at(90, -40, 800, 3.5)};
  int checked = 0;
  for (int row = 0; row < 480; row += 3) {
    for (int col = 0; col < 640; col += 3) {
      const UnitRay ray{{}, artix::camera_direction(col, row)};
      const artix::Hit hit = artix::closest_hit(ray, spheres, -1);
      if (hit.index < 0) continue;
      const Vec3i n = artix::normal(ray, spheres[static_cast<std::size_t>(hit.index)]);
      const double len = std::sqrt(static_cast<double>(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])) / 131072;
      EXPECT_NEAR(len, 1.0, 0.002) << col << "," << row;
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
}

// A mirror reflects: the camera ray along the axis onto a mirror's pole comes straight back, the reflected ray's
// origin on the sphere's near point.
TEST(Artix, AMirrorSendsTheAxisRayBack) {
  const UnitSphere mirror = sphere_at(0, 0, 400, 64, true);
  const UnitRay ray{{}, artix::camera_direction(320, 240)};
  const artix::Hit hit = artix::closest_hit(ray, std::vector<UnitSphere>{mirror}, -1);
  ASSERT_EQ(hit.index, 0);
  const UnitRay back = artix::reflect(ray, mirror, hit.td);
  EXPECT_EQ(back.o[0], 0);
  EXPECT_EQ(back.o[1], 0);
  EXPECT_NEAR(static_cast<double>(back.o[2]), 336 * 16, 1);
  EXPECT_EQ(back.d[0], 0);
  EXPECT_EQ(back.d[1], 0);
  EXPECT_NEAR(static_cast<double>(back.d[2]), -131072, 4);  // 18-bit operands: a few units of 2^-17
}

// The cull never drops a sphere a camera ray hits: on random worlds every pixel's closest hit over all spheres
// is in its tile's list.
TEST(Artix, TheCullKeepsEverySphereARayHits) {
  const DevicePreset p = artix_preset();
  std::mt19937_64 rng(77);
  int hits = 0;
  for (int world = 0; world < (core::kSanitized ? 10 : 40); ++world) {
    const artix::UnitWorld w = artix::prepare_world(testing::random_world(p, rng));
    for (int k = 0; k < 12; ++k) {
      const int row = static_cast<int>(rng() % 480);
      const artix::RowTiles tiles = artix::row_tiles(w, row, p.units->tile_columns);
      for (int col = 0; col < 640; ++col) {
        const artix::Hit hit = artix::closest_hit(UnitRay{{}, artix::camera_direction(col, row)}, w.spheres, -1);
        if (hit.index < 0) continue;
        ++hits;
        const auto list = tiles.list(col / p.units->tile_columns);
        ASSERT_TRUE(std::find(list.begin(), list.end(), hit.index) != list.end())
            << "world " << world << " row " << row << " col " << col << " sphere " << hit.index;
      }
    }
  }
  EXPECT_GT(hits, 10000);
}

std::vector<core::PixelTrace> plain_pixels() { return std::vector<core::PixelTrace>(kLineWidth, {core::kBackground, 0}); }

// Worked schedules (docs/device.md, "The artix preset").
TEST(ArtixSchedule, AnEmptyLineTakesAPassOfMinPassCyclesAPixel) {
  const DevicePreset p = artix_preset();  // 9 units: unit 0 has 72 pixels, the others 71
  ASSERT_EQ(p.workers, 9);
  const std::vector<int> tests(kLineWidth, 0);
  const auto finish = artix::unit_finish_cycles(p, 0, plain_pixels(), tests);
  const std::int64_t drain = p.units->hit_latency + p.units->shade_latency;
  EXPECT_EQ(finish[0], 3 + drain);
  EXPECT_EQ(finish[9], 6 + drain);
  EXPECT_EQ(finish[639], 72 * 3 + drain);  // unit 0's last
  EXPECT_EQ(finish[631], 71 * 3 + drain);  // unit 1's last
  EXPECT_EQ(finish[638], 71 * 3 + drain);  // unit 8's last
}

TEST(ArtixSchedule, AReflectedRayWaitsWhileTheUnitTakesItsNextPixel) {
  DevicePreset p = artix_preset();
  p.workers = 320;  // unit u has columns u and u + 320
  auto pixels = plain_pixels();
  pixels[5].bounces = 1;
  const std::vector<int> tests(kLineWidth, 10);
  const auto finish = artix::unit_finish_cycles(p, 10, pixels, tests);
  // Column 5 issues [0, 10), its hit is known at 50 and its reflected ray waits from 70; column 325 issues
  // [10, 20) meanwhile and is done at 60 + 12; the reflected pass issues [70, 80): done at 120 + 12.
  EXPECT_EQ(finish[325], 72);
  EXPECT_EQ(finish[5], 132);
  EXPECT_EQ(finish[6], 62);
}

using Pass = artix::LineChains::Pass;
using Chain = std::vector<Pass>;

// A line's work: column c's chains are columns[c] (none for a column not named), in order.
artix::LineChains line_of(const std::map<int, std::vector<Chain>>& columns) {
  artix::LineChains work;
  for (int c = 0; c < kLineWidth; ++c) {
    work.start.push_back(static_cast<int>(work.chain_start.size()));
    if (const auto it = columns.find(c); it != columns.end()) {
      for (const Chain& chain : it->second) {
        work.chain_start.push_back(static_cast<int>(work.passes.size()));
        work.passes.insert(work.passes.end(), chain.begin(), chain.end());
      }
    }
  }
  work.start.push_back(static_cast<int>(work.chain_start.size()));
  work.chain_start.push_back(static_cast<int>(work.passes.size()));
  return work;
}

// The artix path preset's line: a column's samples are chains of their own, a bounce waits for the bounce stage,
// and a converged pixel takes no issue slot. One unit per two columns, 10 spheres, the artix path preset's
// latencies (hit 40, bounce stage 51, the entry final 2 after the pixel port), each unit with a bounce stage of its
// own.
TEST(ArtixSchedule, SamplesAreChainsAndAConvergedPixelTakesNoSlot) {
  DevicePreset p = artix_path_preset();
  p.workers = 320;
  p.units->shared_bounce = false;
  ASSERT_EQ(p.units->hit_latency, 40);
  ASSERT_EQ(p.units->reflect_latency, 51);
  ASSERT_EQ(p.units->shade_latency, 2);
  ASSERT_TRUE(p.units->pixel_port);
  const Chain escape{{10, 0, true}};  // a sample that meets nothing
  const auto finish = artix::unit_finish_cycles(
      p, line_of({{5, {{{10, 0, true}, {10, 0, true}}, escape}},  // two samples: one bounces once, both then escape
                  {325, {escape}},
                  {326, {escape}}}));
  // Unit 5: column 5's first sample issues [0, 10), its hit is known at 50 and its bounce waits from 101; its
  // second sample issues [10, 20), known at 60, its light out at 111; column 325 issues [20, 30), known at 70,
  // light at 121, final at 123; the bounce issues [101, 111), known at 151, light at 202: column 5 is final at
  // 204, after both its samples.
  EXPECT_EQ(finish[325], 123);
  EXPECT_EQ(finish[5], 204);
  // Unit 6: column 6 traces nothing (converged): its entry is frame memory's, final from the start; 326 issues
  // [0, 10), known at 50, light at 101.
  EXPECT_EQ(finish[6], 0);
  EXPECT_EQ(finish[326], 103);
}

// A bounce that walks the hierarchy is a pass a level: the next level joins the queue as soon as the previous
// level's hits are known (no bounce stage between), and a level known earlier goes before a bounce queued earlier.
TEST(ArtixSchedule, AWalksNextLevelFollowsItsHitsWithoutTheBounceStage) {
  DevicePreset p = artix_path_preset();
  p.workers = 320;
  p.units->shared_bounce = false;
  std::map<int, std::vector<Chain>> columns;
  for (int c = 0; c < kLineWidth; ++c) columns[c] = {{{4, 0, true}}};
  columns[5] = {{{4, 0, true}, {9, 0, false}, {16, 1, true}}};  // the bounce's walk: bounds, then spheres
  const auto finish = artix::unit_finish_cycles(p, line_of(columns));
  // Unit 5: column 5's camera ray issues [0, 4), known at 44; column 325 issues [4, 8), known at 48, light at 99,
  // final at 101. The bounce's bounds wait from 95 and issue [95, 104), known at 144; its spheres' level waits
  // from 145 (walk_wait), reads its first node then (the walk's lead) and issues [146, 162), known at 202, light at
  // 253: final at 255.
  ASSERT_EQ(p.units->walk_wait, 1);
  EXPECT_EQ(finish[325], 101);
  EXPECT_EQ(finish[5], 255);
}

// The units share one bounce stage: unit u's hits enter it only in the line's cycles c = u (mod N), one a cycle,
// in the order they are known; a cut path's hit does not enter it.
TEST(ArtixSchedule, TheSharedBounceStageTakesAUnitsHitsInItsOwnCycles) {
  DevicePreset p = artix_path_preset();
  p.workers = 8;  // unit 1's cycles at the stage: 1, 9, 17, ..., 41, 49, 57, 65, 73
  ASSERT_TRUE(p.units->shared_bounce);
  const Chain escape{{3, 0, true}}, cut{{3, 0, false}};  // a camera ray that escapes; a path cut at its first hit
  const auto finish = artix::unit_finish_cycles(
      p, line_of({{1, {escape}}, {9, {escape}}, {17, {escape}}, {25, {cut}}, {33, {escape}}}));
  // Unit 1's camera rays issue [0, 3), [3, 6), [6, 9), [9, 12) (the cut, column 25), [12, 15): known at 43, 46, 49,
  // 52 and 55. Column 1's enters at 49, column 9's at 57 (49 is taken), column 17's at 65 although it was known in
  // a cycle of the unit's (49), column 33's at 73 (the cut took no cycle of the stage); each entry final 51 + 2
  // later.
  EXPECT_EQ(finish[1], 49 + 53);
  EXPECT_EQ(finish[9], 57 + 53);
  EXPECT_EQ(finish[17], 65 + 53);
  EXPECT_EQ(finish[25], 52 + 2);
  EXPECT_EQ(finish[33], 73 + 53);
}

// A unit holds at most `paths` paths: a camera ray waits for one to end, after the bounce stage's light or the
// cycle after a cut hit. One path a unit here, each unit with a stage of its own.
TEST(ArtixSchedule, ACameraRayWaitsForAPathToEndWhenTheUnitHoldsItsPaths) {
  DevicePreset p = artix_path_preset();
  p.workers = 320;
  p.units->shared_bounce = false;
  ASSERT_EQ(p.units->paths, 32);
  p.units->paths = 1;
  const Chain escape{{10, 0, true}};
  const auto finish = artix::unit_finish_cycles(p, line_of({{5, {{{10, 0, true}, {10, 0, true}}}},  // a bounce
                                                            {6, {{{10, 0, false}}}},  // cut at its first hit
                                                            {325, {escape}},
                                                            {326, {escape}}}));
  // Unit 5: column 5 issues [0, 10), known at 50, its bounce waits from 101 and issues [101, 111), known at 151,
  // light at 202: over. Column 325 then issues [202, 212), known at 252, light at 303.
  EXPECT_EQ(finish[5], 202 + 2);
  EXPECT_EQ(finish[325], 303 + 2);
  // Unit 6: column 6 issues [0, 10), cut at 50: held until 51, when column 326 issues [51, 61), known at 101, light
  // at 152.
  EXPECT_EQ(finish[6], 50 + 2);
  EXPECT_EQ(finish[326], 152 + 2);
}

// A unit's pixel port takes a sample a cycle: the bounce stage's lights in their cycles, each cut in the first cycle
// from its own that neither a light nor an earlier cut took.
TEST(ArtixSchedule, APixelPortTakesLightsInTheirCyclesAndCutsInTheFreeOnes) {
  std::vector<artix::PortEnd> lit{{10, 0}, {11, 1}, {13, 2}, {30, 3}};
  std::vector<artix::PortEnd> cut{{10, 4}, {10, 5}, {20, 6}, {30, 7}, {30, 8}};
  artix::serve_pixel_port(lit, cut);
  std::vector<std::int64_t> at;
  for (const artix::PortEnd& e : cut) at.push_back(e.cycle);
  // 10 and 11 are lights': the first cut waits to 12; the second to 14 (12 its, 13 a light's); 30 a light's.
  EXPECT_EQ(at, (std::vector<std::int64_t>{12, 14, 20, 31, 32}));
  EXPECT_EQ(lit[2].cycle, 13);  // lights keep their cycles
  EXPECT_EQ(cut[1].col, 5);
}

// In the line, a cut known in the cycle its unit's light leaves the stage reaches the pixel port a cycle later, and
// so its column's entry is final a cycle later.
TEST(ArtixSchedule, ACutMeetingALightAtThePixelPortWaitsACycle) {
  DevicePreset p = artix_path_preset();
  p.workers = 8;
  const Chain escape{{3, 0, true}}, cut{{3, 0, false}};
  // Unit 1's camera rays: column 1 issues [0, 3), known at 43, enters the stage at 49 (its cycle), light at 100.
  // Then columns 9, 17, ... are cut: the k-th (column 1 + 8 k) issues [3 k, 3 k + 3), cut at 3 k + 43; k = 19
  // (column 153) at 100, the light's cycle.
  std::map<int, std::vector<Chain>> columns{{1, {escape}}};
  for (int k = 1; k <= 20; ++k) columns[1 + 8 * k] = {cut};
  const auto finish = artix::unit_finish_cycles(p, line_of(columns));
  EXPECT_EQ(finish[1], 102);
  EXPECT_EQ(finish[1 + 8 * 18], 97 + 2);
  EXPECT_EQ(finish[1 + 8 * 19], 101 + 2);  // 100 is the light's
  EXPECT_EQ(finish[1 + 8 * 20], 103 + 2);
}

TEST(ArtixSchedule, AHeavyLineIsLateFromTheLeadOn) {
  const DevicePreset p = artix_preset();
  const std::vector<int> tests(kLineWidth, 400);
  std::array<core::Rgb444, kLineWidth> line{};
  const LineResult r = artix::schedule_units(p, 400, plain_pixels(), tests, line);
  // Pixel k of a unit is done at 400 (k + 1) + 52: seven per unit within 3200.
  EXPECT_EQ(r.late_pixels, kLineWidth - 9 * 7);
  EXPECT_EQ(r.demand_cycles, 72 * 400 + 52);
  EXPECT_EQ(line[0], core::kBackground);
  EXPECT_EQ(line[9 * 7], core::kBlack);
}

TEST(ArtixPreset, ValidateKeepsTheOperandsInTheSlices) {
  DevicePreset p = artix_preset();
  EXPECT_FALSE(p.validate().has_value());
  p.x = {23, 4, true};
  EXPECT_TRUE(p.validate().has_value());
  p = artix_preset();
  p.radius = {22, 4, false};
  EXPECT_TRUE(p.validate().has_value());
  p = artix_preset();
  p.units->tile_columns = 30;
  EXPECT_TRUE(p.validate().has_value());
  EXPECT_FALSE(artix_path_preset().validate().has_value());  // the units path-trace too
  p = artix_path_preset();
  p.x = {23, 4, true};
  EXPECT_TRUE(p.validate().has_value());
}

}  // namespace
}  // namespace tripsitter::device

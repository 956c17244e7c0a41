#include <tripsitter/device/controller.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/link/frame.h>

#include "test_util.h"

namespace tripsitter::device {
namespace {

using testing::kLambertian;
using testing::kMetal;
using testing::with_bounces;

SceneMemory one_sphere(const DevicePreset& p) {
  SceneMemory m;
  m.valid = true;
  m.geometry.push_back({{0, 0, p.z.quantize(400).raw}, p.radius.quantize(64).raw});
  m.surfaces.resize(1);
  return m;
}

TEST(Controller, BoardLeavesColumns580To639Black) {
  const DevicePreset p = board_2023_preset();
  const Controller c(p);
  EXPECT_EQ(c.pixels_in_time(1), 58);
  std::array<core::Rgb444, kLineWidth> line;
  line.fill(core::Rgb444(0xFFF));
  const LineResult r = c.render_line(240, one_sphere(p), line);
  EXPECT_EQ(r.late_pixels, 60);
  for (int col = 580; col < 640; ++col) EXPECT_EQ(line[col], core::kBlack) << col;
  for (int col = 0; col < 580; ++col) EXPECT_NE(line[col], core::kBlack) << col;
}

TEST(Controller, LinePixelsAreTheWorkersPureFunction) {
  const DevicePreset p = wide_preset();
  const Controller c(p);
  const Worker w(p.sqrt_iterations);
  const SceneMemory scene = one_sphere(p);
  std::array<core::Rgb444, kLineWidth> line;
  for (int row : {0, 200, 240, 479}) {
    EXPECT_EQ(c.render_line(row, scene, line).late_pixels, 0);
    for (int col = 0; col < kLineWidth; ++col) ASSERT_EQ(line[col], w.shade(col, row, scene)) << col << "," << row;
  }
}

TEST(Controller, FewerWorkersMeansLatePixelsInEachWorkersTail) {
  DevicePreset p = board_2023_preset();
  p.workers = 20;  // 32 pixels each: all on time
  EXPECT_EQ(Controller(p).pixels_in_time(1), 32);
  p.workers = 5;  // 128 pixels each, 58 on time: columns 5*58 = 290 onwards are late
  const Controller c(p);
  std::array<core::Rgb444, kLineWidth> line;
  EXPECT_EQ(c.render_line(10, one_sphere(p), line).late_pixels, 640 - 5 * 58);
  for (int col = 290; col < 640; ++col) EXPECT_EQ(line[col], core::kBlack);
}

TEST(Controller, CentreOfTheDemoSphereFacesTheCamera) {
  // SPEC.md section B: a sphere at (0, 0, 400) with radius 64, its point facing the camera coloured 0x770.
  const DevicePreset p = wide_preset();
  const Worker w(p.sqrt_iterations);
  EXPECT_EQ(w.shade(320, 240, one_sphere(p)), core::Rgb444(0x770));
  EXPECT_EQ(w.shade(0, 0, one_sphere(p)), core::kBackground);
}

// --- The mirror model (docs/device.md) ---

// A sphere in pixel units, in the preset's raw format, with its surface.
void add_sphere(SceneMemory& m, const DevicePreset& p, double x, double y, double z, double r, std::uint8_t material,
                std::array<std::uint8_t, 3> albedo) {
  m.valid = true;
  m.geometry.push_back({{p.x.quantize(x).raw, p.y.quantize(y).raw, p.z.quantize(z).raw}, p.radius.quantize(r).raw});
  m.surfaces.push_back({material, albedo, 0, 6144});
}

TEST(Mirror, TheCentreOfAMetalSphereReflectsTheBackgroundTinted) {
  // The point facing the camera sends the centre pixel's ray straight back; nothing else is there, so the
  // pixel is the background times the albedo: (0, 3, 6) -> (0, floor(3 * 170 / 255), floor(6 * 128 / 255)).
  const DevicePreset p = wide_preset();
  SceneMemory m;
  add_sphere(m, p, 0, 0, 400, 64, kMetal, {255, 170, 128});
  const core::PixelTrace t = Worker(p).trace(320, 240, m);
  EXPECT_EQ(t.bounces, 1);
  EXPECT_EQ(t.colour, core::Rgb444::from_channels(0, 2, 3));
  EXPECT_EQ(Worker(p).trace(0, 0, m).bounces, 0);  // a miss
  EXPECT_EQ(Worker(p).shade(0, 0, m), core::kBackground);
}

TEST(Mirror, ZeroBouncesShadeMetalsAsTheBoardDid) {
  const DevicePreset p = with_bounces(wide_preset(), 0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  SceneMemory m;
  for (int i = 0; i < 20; ++i)
    add_sphere(m, p, 300 * u(rng), 200 * u(rng), 500 + 200 * u(rng), 30 + 25 * u(rng), i % 2 ? kMetal : kLambertian,
               {200, 100, 50});
  const Worker w(p);
  const FixedArith arith{SqrtUnit(p.sqrt_iterations)};
  const std::span<const core::KernelSphere<std::int64_t>> spheres(m.geometry);
  int metal_pixels = 0;
  for (int row = 0; row < 480; row += 3)
    for (int col = 0; col < 640; col += 3) {
      const core::PixelTrace t = w.trace(col, row, m);
      ASSERT_EQ(t.bounces, 0);
      // Plain normal-map shading of the closest hit, metals included.
      const core::KernelRay<core::Int128> ray{{}, device_ray(col, row)};
      const auto hit = core::closest_hit(arith, ray, spheres);
      ASSERT_EQ(t.colour, hit.index < 0 ? core::kBackground
                                        : core::normal_colour(arith, ray, spheres[static_cast<std::size_t>(hit.index)],
                                                              hit.num));
      metal_pixels += hit.index >= 0 && m.surfaces[static_cast<std::size_t>(hit.index)].material == kMetal;
    }
  EXPECT_GT(metal_pixels, 1000);
}

// Two metal spheres face each other across the camera: the centre pixel's ray bounces between them until
// the cut-off, where the sphere it is on is normal-shaded: A's face towards the camera is (7, 7, 0), B's
// face towards A (7, 7, 14).
TEST(Mirror, TwoFacingMirrorsStopAtTheCutOff) {
  const std::array<std::uint8_t, 3> albedo_a{255, 200, 100}, albedo_b{128, 255, 30};
  for (int max_bounces = 0; max_bounces <= core::kMaxBounces; ++max_bounces) {
    const DevicePreset p = with_bounces(wide_preset(), max_bounces);
    SceneMemory m;
    add_sphere(m, p, 0, 0, 400, 64, kMetal, albedo_a);
    add_sphere(m, p, 0, 0, -400, 64, kMetal, albedo_b);
    const core::PixelTrace t = Worker(p).trace(320, 240, m);
    EXPECT_EQ(t.bounces, max_bounces);
    const std::array<int, 3> base = max_bounces % 2 == 0 ? std::array<int, 3>{7, 7, 0} : std::array<int, 3>{7, 7, 14};
    std::array<int, 3> expected{};
    for (std::size_t k = 0; k < 3; ++k) {
      core::Int128 num = base[k], den = 1;
      for (int i = 0; i < max_bounces; ++i) {  // reflected off A, B, A, ...
        num *= (i % 2 == 0 ? albedo_a : albedo_b)[k];
        den *= 255;
      }
      expected[k] = static_cast<int>(num / den);
    }
    EXPECT_EQ(t.colour, core::Rgb444::from_channels(expected[0], expected[1], expected[2])) << max_bounces;
  }
}

// The data-dependent schedule, by hand. The board's costs (not pipelined, 51 cycles per plain pixel, lead
// 3000) with one bounce and the board's demo sphere made of metal: on row 240 columns 269..371 hit it and
// reflect once (the background), costing 2 + 2 * 45 + 10 + 4 = 106 cycles instead of 51. Workers 9, 0
// and 1 have 11 such pixels in their first 38, the others 10; a worker with B of them finishes n pixels at
// 51 n + 55 B <= 3000 cycles: n = 46 for B = 11, 48 for B = 10. Late: 3 * (64 - 46) + 7 * (64 - 48) = 166.
TEST(Mirror, ReflectingPixelsMakeTheirWorkersLate) {
  const DevicePreset p = with_bounces(board_2023_preset(), 1);
  EXPECT_EQ(p.pixel_occupancy(1, 1), 106);
  SceneMemory m;
  add_sphere(m, p, 0, 0, 400, 64, kMetal, {255, 255, 255});
  const Worker w(p);
  for (int col = 0; col < kLineWidth; ++col)
    ASSERT_EQ(w.trace(col, 240, m).bounces, col >= 269 && col <= 371 ? 1 : 0) << col;
  std::array<core::Rgb444, kLineWidth> line;
  const LineResult r = Controller(p).render_line(240, m, line);
  EXPECT_EQ(r.late_pixels, 166);
  EXPECT_EQ(r.reflections, 103);
  for (int col = 0; col < kLineWidth; ++col) {
    const int worker = col % 10, k = col / 10;
    const int in_time = (worker == 9 || worker == 0 || worker == 1) ? 46 : 48;
    if (k < in_time) {
      EXPECT_EQ(line[col], w.shade(col, 240, m)) << col;
    } else {
      EXPECT_EQ(line[col], core::kBlack) << col;
    }
  }
  // Without reflections the same line is the board's: 60 late.
  EXPECT_EQ(Controller(board_2023_preset()).render_line(240, m, line).late_pixels, 60);
}

// Two nearly flat metal spheres, one in front of the camera and one behind, so every ray bounces between
// them up to the cut-off. The wide preset's pipelined worker with 2 spheres: a pixel with k bounces occupies
// (k + 1) * 2 + k * (31 + 10) cycles, and is ready 35 cycles after. n pixels are on time while
// n * occupancy + 35 <= 3200: k = 0: 2 (all 64); k = 1: 45 (all 64, 70 would fit); k = 2: 88 (35);
// k = 3: 131 (24). Late per line: 0, 0, 640 - 350 = 290, 640 - 240 = 400.
TEST(Mirror, LatePixelsGrowWithTheBounceCutOff) {
  const std::array<int, 4> expected_late{0, 0, 290, 400};
  for (int bounces = 0; bounces <= 3; ++bounces) {
    const DevicePreset p = with_bounces(wide_preset(), bounces);
    SceneMemory m;
    add_sphere(m, p, 0, 0, 100000, 99000, kMetal, {255, 255, 255});
    add_sphere(m, p, 0, 0, -100000, 99000, kMetal, {255, 255, 255});
    const Worker w(p);
    for (int col = 0; col < kLineWidth; col += 13) ASSERT_EQ(w.trace(col, 17, m).bounces, bounces) << col;
    std::array<core::Rgb444, kLineWidth> line;
    EXPECT_EQ(Controller(p).render_line(17, m, line).late_pixels, expected_late[static_cast<std::size_t>(bounces)])
        << bounces;
  }
}

// --- A line's demand (LineResult::demand_cycles) ---

DevicePreset tracing_late(DevicePreset p, bool trace = true) {
  p.trace_late_pixels = trace;
  return p;
}

// The demand of row `row`, counted independently of the schedule: every worker's pixels' occupancies from the
// worker's own bounce counts, plus the drain; the largest over the workers.
std::int64_t demand_by_hand(const DevicePreset& p, const SceneMemory& m, int row) {
  const Worker w(p);
  const auto spheres = static_cast<std::int64_t>(m.geometry.size());
  std::int64_t worst = 0;
  for (int worker = 0; worker < p.workers; ++worker) {
    std::int64_t busy = 0;
    for (int col = worker; col < kLineWidth; col += p.workers) busy += p.pixel_occupancy(spheres, w.trace(col, row, m).bounces);
    worst = std::max(worst, busy + p.drain_cycles());
  }
  return worst;
}

// The board's costs without metal: every pixel takes 2 + spheres * 45 + 4 cycles, back to back, so the worker
// with the most pixels, ceil(640 / workers) of them, sets the demand. Nothing reflects, so the late pixels
// take exactly the least a pixel can, and the lower bound without tracing them is exact too.
TEST(Demand, TheBoardsBusiestWorkerNeedsItsPixelsTimesTheirCycles) {
  for (const int workers : {10, 7, 3, 640}) {
    for (const bool trace : {false, true}) {
      const DevicePreset p = tracing_late([&] {
        DevicePreset b = board_2023_preset();
        b.workers = workers;
        return b;
      }(), trace);
      SceneMemory m;
      add_sphere(m, p, 0, 0, 400, 64, kLambertian, {});
      add_sphere(m, p, -150, 60, 350, 40, kLambertian, {});
      add_sphere(m, p, 120, -80, 500, 100, kMetal, {});  // a metal, shaded as the board did (no bounces)
      EXPECT_EQ(p.pixel_occupancy(3, 0), 2 + 3 * 45 + 4);
      const std::int64_t expected = (640 + workers - 1) / workers * std::int64_t{141};
      std::array<core::Rgb444, kLineWidth> line;
      for (const int row : {0, 240, 300}) {
        const LineResult r = Controller(p).render_line(row, m, line);
        EXPECT_EQ(r.demand_cycles, expected) << workers << " workers, row " << row << (trace ? ", traced" : "");
        EXPECT_EQ(r.demand_cycles, demand_by_hand(p, m, row));
        EXPECT_EQ(r.late_pixels > 0, expected > p.lead_cycles);
      }
    }
  }
}

// The pipelined wide preset without metal: pixel k of a worker is done at (k + 1) * spheres + 35, so a line
// demands 64 * spheres + 35 cycles: 3171 with 49 spheres (on time), 3875 with 60 (late).
TEST(Demand, TheWidePresetsLineDemandsSixtyFourPixelsOfSpheresPlusTheDrain) {
  for (const int count : {1, 49, 60}) {
    for (const bool trace : {false, true}) {
      const DevicePreset p = tracing_late(wide_preset(), trace);
      SceneMemory m;
      for (int i = 0; i < count; ++i) add_sphere(m, p, -300 + 10 * i, 30 * (i % 5), 400 + 5 * i, 20, kLambertian, {});
      std::array<core::Rgb444, kLineWidth> line;
      const LineResult r = Controller(p).render_line(200, m, line);
      EXPECT_EQ(r.demand_cycles, 64 * count + 35) << count << (trace ? ", traced" : "");
      EXPECT_EQ(r.late_pixels == 0, 64 * count + 35 <= 3200) << count;
    }
  }
}

// The board's demo sphere of metal (Mirror.ReflectingPixelsMakeTheirWorkersLate): a worker with 11 of the
// reflecting pixels (106 cycles each, the others 51) needs 64 * 51 + 11 * 55 = 3869 cycles. Its reflecting
// pixels are all among its first 46, on time, so its late pixels take the least a pixel can: the bound without
// tracing them is exact as well.
TEST(Demand, ReflectingPixelsOnTimeCountTheirOwnCycles) {
  for (const bool trace : {false, true}) {
    const DevicePreset p = tracing_late(with_bounces(board_2023_preset(), 1), trace);
    SceneMemory m;
    add_sphere(m, p, 0, 0, 400, 64, kMetal, {255, 255, 255});
    std::array<core::Rgb444, kLineWidth> line;
    const LineResult r = Controller(p).render_line(240, m, line);
    EXPECT_EQ(r.demand_cycles, 64 * 51 + 11 * 55);
    EXPECT_EQ(r.demand_cycles, demand_by_hand(p, m, 240));
    EXPECT_EQ(r.late_pixels, 166);
    EXPECT_EQ(r.reflections, 103);
  }
}

// Two nearly flat mirrors (Mirror.LatePixelsGrowWithTheBounceCutOff): every pixel bounces 3 times, 131 cycles.
// Traced, the line demands 64 * 131 + 35 = 8419 cycles. Untraced, the late pixels (40 of each worker's 64) are
// not known and count 2 cycles each, a pixel without a bounce: 24 * 131 + 40 * 2 + 35 = 3259, a lower bound.
TEST(Demand, WithoutTracingLatePixelsTheDemandIsALowerBound) {
  const auto line_of = [](const DevicePreset& p) {
    SceneMemory m;
    add_sphere(m, p, 0, 0, 100000, 99000, kMetal, {255, 255, 255});
    add_sphere(m, p, 0, 0, -100000, 99000, kMetal, {255, 255, 255});
    std::array<core::Rgb444, kLineWidth> line;
    const LineResult r = Controller(p).render_line(17, m, line);
    EXPECT_EQ(r.demand_cycles, p.trace_late_pixels ? demand_by_hand(p, m, 17) : 3259);
    return std::pair{r, line};
  };
  const auto [off, off_line] = line_of(wide_preset());
  const auto [on, on_line] = line_of(tracing_late(wide_preset()));
  EXPECT_EQ(on.demand_cycles, 64 * 131 + 35);
  EXPECT_GT(off.demand_cycles, 3200);
  EXPECT_LT(off.demand_cycles, on.demand_cycles);
  // Nothing shown changes.
  EXPECT_EQ(off.late_pixels, 400);
  EXPECT_EQ(on.late_pixels, 400);
  EXPECT_EQ(on.reflections, off.reflections);
  EXPECT_EQ(on_line, off_line);
}

// The path preset's schedule: a pixel's demand is its own path_occupancy, whatever its rays and bounces; a
// converged pixel (no rays) is the least, one issue slot.
TEST(Demand, ThePathScheduleSumsEachPixelsOccupancy) {
  DevicePreset p = path_preset();
  p.workers = 2;
  p.lead_cycles = 1000;
  for (const bool trace : {false, true}) {
    p.trace_late_pixels = trace;
    std::vector<AccumEntry> memory(kLineWidth);
    std::array<core::Rgb444, kLineWidth> line;
    int traced = 0;
    // Column col traces col % 3 rays with col % 3 - 1 metal bounces (at least none).
    const LineResult r = schedule_path_line(p, 5, line, memory, [&](int col) {
      ++traced;
      PathPixel px;
      px.rays = col % 3;
      px.bounces.metal = std::max(0, col % 3 - 1);
      return px;
    });
    std::int64_t worst = 0;
    for (int w = 0; w < 2; ++w) {
      std::int64_t busy = 0;
      for (int col = w; col < kLineWidth; col += 2) {
        const int rays = col % 3;
        busy += p.path_occupancy(5, rays, {0, std::max(0, rays - 1), 0});
      }
      worst = std::max(worst, busy + p.path_drain_cycles());
    }
    EXPECT_GT(r.late_pixels, 0);
    if (trace) {
      EXPECT_EQ(r.demand_cycles, worst);
      EXPECT_EQ(traced, kLineWidth);
    } else {
      EXPECT_GT(r.demand_cycles, p.lead_cycles);
      EXPECT_LT(r.demand_cycles, worst);
      EXPECT_LT(traced, kLineWidth);
    }
  }
  EXPECT_EQ(p.path_occupancy(5, 0, {0, 0, 0}), 1);
}

// --- The generalised kernel keeps the board's primary rays bit for bit ---

// The kernel as it was before rays had an origin (a copy, so a change to the kernel cannot hide here).
template <class Arith>
core::KernelHit<typename Arith::Wide> board_closest_hit(const Arith& arith, const core::Vec3<typename Arith::Wide>& d,
                                                        std::span<const core::KernelSphere<typename Arith::Coord>> spheres) {
  using Wide = typename Arith::Wide;
  const Wide a = dot(d, d);
  core::KernelHit<Wide> best;
  for (int i = 0; i < static_cast<int>(spheres.size()); ++i) {
    const auto& s = spheres[static_cast<std::size_t>(i)];
    const core::Vec3<Wide> c{Wide(s.center.x), Wide(s.center.y), Wide(s.center.z)};
    const Wide r = Wide(s.radius);
    const Wide b = Wide(2) * dot(d, c);
    const Wide c_prime = dot(c, c) - r * r;
    const Wide disc = b * b - Wide(4) * a * c_prime;
    if (disc < Wide(0)) continue;
    const Wide num = b - arith.sqrt(disc);
    if (!(num > Wide(0))) continue;
    if (best.index < 0 || num < best.num) best = {i, num};
  }
  return best;
}

template <class Arith>
core::Rgb444 board_normal_colour(const core::Vec3<typename Arith::Wide>& d,
                                 const core::KernelSphere<typename Arith::Coord>& s, typename Arith::Wide num) {
  using Wide = typename Arith::Wide;
  const Wide two_a = Wide(2) * dot(d, d);
  const Wide den = two_a * Wide(s.radius);
  int ch[3];
  for (int k = 0; k < 3; ++k) {
    const Wide n_num = num * d[k] - two_a * Wide(s.center[k]);
    ch[k] = std::clamp(Arith::floor_div(Wide(7) * n_num + Wide(7) * den, den), 0, 14);
  }
  return core::Rgb444::from_channels(ch[0], ch[1], ch[2]);
}

TEST(Mirror, PrimaryRaysAreBitIdenticalToTheBoardsKernel) {
  const DevicePreset p = wide_preset();
  const FixedArith arith{SqrtUnit(p.sqrt_iterations)};
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::int64_t> coord(-2000 * 16, 2000 * 16), depth(-200 * 16, 3000 * 16),
      radius(1, 400 * 16);
  for (int world = 0; world < 6; ++world) {
    SceneMemory m;
    for (int i = 0; i < 16; ++i) {
      m.geometry.push_back({{coord(rng), coord(rng), depth(rng)}, radius(rng)});
      m.surfaces.push_back({kLambertian, {100, 100, 100}, 0, 6144});
    }
    // Two spheres at the same place: the tie goes to the lower index, as before.
    m.geometry.push_back(m.geometry[3]);
    m.surfaces.push_back(m.surfaces[3]);
    const std::span<const core::KernelSphere<std::int64_t>> spheres(m.geometry);
    const Worker w(p);
    for (int row = 0; row < 480; row += 4)
      for (int col = 0; col < 640; col += 4) {
        const auto d = device_ray(col, row);
        const auto old_hit = board_closest_hit(arith, d, spheres);
        const auto hit = core::closest_hit(arith, core::KernelRay<core::Int128>{{}, d}, spheres);
        ASSERT_EQ(hit.index, old_hit.index) << col << "," << row;
        ASSERT_TRUE(hit.num == old_hit.num) << col << "," << row;
        const core::Rgb444 old_colour =
            old_hit.index < 0 ? core::kBackground
                              : board_normal_colour<FixedArith>(d, spheres[static_cast<std::size_t>(old_hit.index)],
                                                                old_hit.num);
        ASSERT_EQ(w.shade(col, row, m), old_colour) << col << "," << row;
      }
  }
}

// --- Every intermediate of the kernel within its documented width (docs/device.md, "Widths") ---

// A 128-bit integer that records the widest value any operation produced.
struct Tracked {
  core::Int128 v = 0;
  static inline int max_bits = 0;

  Tracked() = default;
  template <class T>
  Tracked(T x) : v(static_cast<core::Int128>(x)) { note(v); }  // NOLINT: implicit, as Int128 itself

  static void note(core::Int128 x) {
    const auto m = static_cast<core::UInt128>(x < 0 ? -x : x);
    int bits = 0;
    while (bits < 128 && (m >> bits) != 0) ++bits;
    max_bits = std::max(max_bits, bits);
  }
  static Tracked make(core::Int128 x) {
    Tracked t;
    t.v = x;
    note(x);
    return t;
  }
  friend Tracked operator+(Tracked a, Tracked b) { return make(a.v + b.v); }
  friend Tracked operator-(Tracked a, Tracked b) { return make(a.v - b.v); }
  friend Tracked operator*(Tracked a, Tracked b) { return make(a.v * b.v); }
  friend bool operator<(Tracked a, Tracked b) { return a.v < b.v; }
  friend bool operator>(Tracked a, Tracked b) { return a.v > b.v; }
  friend constexpr bool operator==(Tracked a, Tracked b) { return a.v == b.v; }
};

struct TrackedArith {
  using Coord = std::int64_t;
  using Wide = Tracked;
  FixedArith fixed;
  Wide sqrt(Wide d) const { return Tracked::make(fixed.sqrt(d.v)); }
  static int floor_div(Wide n, Wide d) { return FixedArith::floor_div(n.v, d.v); }
  static Wide round_div(Wide n, Wide d) { return Tracked::make(FixedArith::round_div(n.v, d.v)); }
  static core::Vec3<Wide> scale_direction(const core::Vec3<Wide>& r) {
    const auto s = FixedArith::scale_direction({r.x.v, r.y.v, r.z.v});
    return {Tracked::make(s.x), Tracked::make(s.y), Tracked::make(s.z)};
  }
};

// Worlds at the edges of the wide preset's formats (s24.4 centres, u24.4 radii): spheres as far out and
// as big as the formats allow, all metal, six bounces.
TEST(Mirror, IntermediatesStayWithinTheDocumentedWidths) {
  const DevicePreset p = with_bounces(wide_preset(), core::kMaxBounces);
  const std::int64_t c_max = p.x.max_raw(), r_max = p.radius.max_raw();
  const FixedArith fixed{SqrtUnit(p.sqrt_iterations)};
  const TrackedArith tracked{fixed};
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<std::int64_t> coord(-c_max, c_max), radius(1, r_max);
  Tracked::max_bits = 0;
  int reflections = 0;
  for (int world = 0; world < 40; ++world) {
    std::vector<core::KernelSphere<std::int64_t>> spheres;
    // A giant in front (the camera just outside it) so that every ray hits something far away...
    const std::int64_t r0 = r_max - radius(rng) % 1000;
    spheres.push_back({{coord(rng) % 1000, coord(rng) % 1000, std::min<std::int64_t>(c_max, r0 + 5000)}, r0});
    // ...and spheres anywhere in the format, the camera outside each.
    while (spheres.size() < 8) {
      const core::KernelSphere<std::int64_t> s{{coord(rng), coord(rng), coord(rng)}, radius(rng)};
      const double dist = std::hypot(double(s.center.x), double(s.center.y), double(s.center.z));
      if (dist > double(s.radius) + 16) spheres.push_back(s);
    }
    if (world % 2 == 1) spheres.erase(spheres.begin());  // and worlds with rays that leave to infinity
    const std::span<const core::KernelSphere<std::int64_t>> span(spheres);
    const std::span<const core::KernelSphere<std::int64_t>> tracked_span(spheres);
    const auto metal = [](int) { return core::KernelSurface{true, {255, 255, 255}}; };
    for (int row = 0; row < 480; row += 24)
      for (int col = 0; col < 640; col += 32) {
        const auto d = device_ray(col, row);
        const auto expected = core::trace_pixel(fixed, d, span, metal, core::kBackground, p.max_bounces);
        const core::Vec3<Tracked> td{Tracked(d.x), Tracked(d.y), Tracked(d.z)};
        const auto got = core::trace_pixel(tracked, td, tracked_span, metal, core::kBackground, p.max_bounces);
        ASSERT_EQ(got.colour, expected.colour);
        ASSERT_EQ(got.bounces, expected.bounces);
        reflections += got.bounces;
      }
  }
  EXPECT_GT(reflections, 1000);
  std::printf("widest intermediate with s24.4 / u24.4 at the format limits: %d bits (documented bound 95)\n",
              Tracked::max_bits);
  EXPECT_LE(Tracked::max_bits, 95);
}

}  // namespace
}  // namespace tripsitter::device

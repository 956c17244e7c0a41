#include <tripsitter/device/fast_tracer.h>

#include <algorithm>
#include <array>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/link/wire_v2.h>

namespace tripsitter::device {
namespace {

// Fewer worlds under the sanitizers, which run the whole suite many times slower.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr int kWorldsPerPreset = 60;
#else
constexpr int kWorldsPerPreset = 250;
#endif
constexpr int kRowsPerWorld = 8;

// Formats of 32 bits, the widest validate() allows: coordinates beyond FastTracer::kNarrowLimit are
// possible, so some worlds take the plain worker's path inside the fast model.
DevicePreset wide_32_preset() {
  DevicePreset p = wide_preset();
  p.name = "wide-32";
  p.x = {32, 4, true};
  p.y = {32, 4, true};
  p.z = {32, 4, true};
  p.radius = {32, 4, false};
  return p;
}

// A random world in raw units of the preset: ordinary spheres in view, and the awkward ones — behind the
// camera, across its plane, around it, off screen, huge, tiny (a raw unit or a few), at the formats'
// limits, near the fast model's 64-bit limit; radii of at least one raw unit, as scene memory holds them;
// metals with random albedos, and sometimes no surfaces at all for the last spheres (as v1 words leave them).
SceneMemory random_world(const DevicePreset& p, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double scale = static_cast<double>(std::int64_t{1} << p.frac_bits());
  const auto clamp_to = [](const core::FixedFormat& f, double raw) {
    return std::clamp(static_cast<std::int64_t>(raw), f.min_raw(), f.max_raw());
  };
  // Scene memory never holds a radius of 0 (the receiver rejects it; the shading divides by r).
  const auto radius_of = [&](double raw) { return std::max<std::int64_t>(1, clamp_to(p.radius, raw)); };
  const auto pick = [&](const core::FixedFormat& f) {  // a raw value at or near one of the format's ends
    const std::int64_t edge = unit(rng) < 0.5 ? f.max_raw() : f.min_raw();
    return edge - (edge > 0 ? 1 : -1) * static_cast<std::int64_t>(rng() % 3);
  };
  SceneMemory m;
  m.valid = true;
  const int count = static_cast<int>(rng() % std::min<std::uint64_t>(p.max_spheres + 1, 41));
  for (int i = 0; i < count; ++i) {
    double x = 0, y = 0, z = 0, r = 0;  // pixel units
    const double kind = unit(rng);
    if (kind < 0.45) {  // in view
      z = 60 + 1500 * unit(rng);
      x = (unit(rng) * 2.4 - 1.2) * z;
      y = (unit(rng) * 1.8 - 0.9) * z;
      r = 2 + 150 * unit(rng) * unit(rng);
    } else if (kind < 0.55) {  // behind the camera, or across its plane
      z = -1500 * unit(rng);
      x = (unit(rng) * 2 - 1) * 800;
      y = (unit(rng) * 2 - 1) * 600;
      r = unit(rng) < 0.5 ? -z + (unit(rng) * 4 - 2) : 400 * unit(rng);
    } else if (kind < 0.62) {  // around the camera (it sees the inside)
      x = (unit(rng) * 2 - 1) * 50;
      y = (unit(rng) * 2 - 1) * 50;
      z = (unit(rng) * 2 - 1) * 50;
      r = 80 + 2000 * unit(rng);
    } else if (kind < 0.70) {  // off screen, beside the view frustum
      z = 100 + 800 * unit(rng);
      x = (unit(rng) < 0.5 ? -1 : 1) * (1.1 + unit(rng)) * z;
      y = (unit(rng) * 2 - 1) * z;
      r = 5 + 100 * unit(rng);
    } else if (kind < 0.78) {  // huge and far
      z = 3000 + 20000 * unit(rng);
      x = (unit(rng) * 2 - 1) * z;
      y = (unit(rng) * 2 - 1) * z;
      r = 1000 + 20000 * unit(rng);
    } else if (kind < 0.86) {  // tiny: 1..4 raw units
      z = 20 + 400 * unit(rng);
      x = (unit(rng) * 2 - 1) * z;
      y = (unit(rng) * 2 - 1) * z * 0.75;
      r = static_cast<double>(1 + rng() % 4) / scale;
    } else {  // at the formats' limits (and, in 32-bit formats, at the fast model's limit)
      std::int64_t raw[4] = {pick(p.x), pick(p.y), pick(p.z), unit(rng) < 0.5 ? p.radius.max_raw() : p.radius.max_raw() / 3};
      if (p.x.total_bits > 29 && unit(rng) < 0.5) {
        const std::int64_t lim = FastTracer::kNarrowLimit - 1;
        raw[0] = unit(rng) < 0.5 ? lim : -lim;
        raw[2] = unit(rng) < 0.5 ? lim : static_cast<std::int64_t>(unit(rng) * 4000 * scale);
        raw[3] = unit(rng) < 0.5 ? lim : static_cast<std::int64_t>(unit(rng) * 4000 * scale);
      }
      for (int k = 0; k < 3; ++k)
        if (unit(rng) < 0.5) raw[k] = static_cast<std::int64_t>((unit(rng) * 2 - 1) * 500 * scale);
      m.geometry.push_back({{clamp_to(p.x, static_cast<double>(raw[0])), clamp_to(p.y, static_cast<double>(raw[1])),
                             clamp_to(p.z, static_cast<double>(raw[2]))},
                            radius_of(static_cast<double>(raw[3]))});
      continue;
    }
    m.geometry.push_back({{clamp_to(p.x, x * scale), clamp_to(p.y, y * scale), clamp_to(p.z, z * scale)},
                          radius_of(r * scale)});
  }
  // Surfaces: a third metal, with albedos anywhere in 0..255; sometimes missing for the last spheres.
  const std::size_t with_surface = unit(rng) < 0.15 ? m.geometry.size() / 2 : m.geometry.size();
  for (std::size_t i = 0; i < with_surface; ++i) {
    SurfaceWord s;
    s.material = unit(rng) < 0.35 ? link::kMaterialMetal : link::kMaterialLambertian;
    s.albedo = {static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng())};
    m.surfaces.push_back(s);
  }
  return m;
}

// The presets the fast model is checked in: the two shipped ones, the board's with mirrors, schedules with
// other worker counts and leads, and 32-bit formats.
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
  return {wide_preset(), board_2023_preset(), board_mirrors, wide_7, board_64, wide_32_preset()};
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
    if (p.x.total_bits > 29) {
      EXPECT_GT(fallback_worlds, 0) << p.name;
      EXPECT_LT(fallback_worlds, kWorldsPerPreset) << p.name;
    } else {
      EXPECT_EQ(fallback_worlds, 0) << p.name;
    }
  }
}

// Worlds the random ones rarely hit exactly: spheres tangent to the camera's plane and to column and row
// planes, a sphere through the camera, equal spheres (ties go to the one sent first), an empty world.
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
      ASSERT_EQ(expected, got) << "world " << w << " row " << row;
    }
  }
}

}  // namespace
}  // namespace tripsitter::device

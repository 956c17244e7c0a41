// End-to-end: scenes through host -> link -> device -> VGA signal -> monitor, against the float reference.
#include <tripsitter/board/board.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include <tripsitter/render/normal.h>
#include <tripsitter/scene/builtin.h>

namespace tripsitter::board {
namespace {

TEST(Board, DemoFrameShowsTheBoardsSphere) {
  Board b(*scene::builtin("demo"), {});
  const ShownFrame f = b.show();
  ASSERT_EQ(f.image.width, 640);
  ASSERT_EQ(f.image.height, 480);
  EXPECT_EQ(f.image.at(320, 240), core::Rgb444(0x770));
  EXPECT_EQ(f.image.at(5, 5), core::kBackground);
  EXPECT_EQ(f.device.late_pixels, 0);
  EXPECT_EQ(f.saturations.total(), 0u);
  EXPECT_EQ(f.link_bytes, link::kV3HeaderBytes + link::kSphereBytes + link::kFrameTrailerBytes);
}

TEST(Board, BoardPresetOverV1ShowsTheStripOfTheReport) {
  Board b(*scene::builtin("demo"), {device::board_2023_preset(), link::WireVersion::kV1, {}});
  const ShownFrame f = b.show();
  EXPECT_EQ(f.device.late_pixels, 60 * 480);
  EXPECT_EQ(f.image.at(320, 240), core::Rgb444(0x770));
  for (int row = 0; row < 480; row += 10)
    for (int col = 580; col < 640; ++col) ASSERT_EQ(f.image.at(col, row), core::kBlack) << col << "," << row;
  EXPECT_EQ(f.link_bytes, 8u);
}

// The v1 word of a known sphere draws what an exact ray tracer draws: the hit test of every pixel in
// double precision, away from the silhouette, and the colour at the point facing the camera.
TEST(Board, V1WordOfAKnownSphereDrawsTheExactSilhouette) {
  device::Device dev(device::board_2023_preset(), link::WireVersion::kV1);
  std::vector<std::uint8_t> bytes;
  link::append_v1_bytes(0x0320032025804000u, bytes);  // centre (100, 50, 300), radius 16
  dev.transfer(bytes);
  display::VgaMonitor monitor;
  dev.run_frame([&](const device::VgaSample& s) { monitor.sample(s); });
  const auto img = monitor.take_frame();
  ASSERT_TRUE(img.has_value());
  const double cx = 100, cy = 50, cz = 300, r = 16;
  int inside = 0;
  for (int row = 0; row < 480; ++row)
    for (int col = 0; col < 580; ++col) {  // the board's strip aside
      const double dx = col - 320, dy = row - 240, dz = 320;
      const double a = dx * dx + dy * dy + dz * dz, bb = 2 * (dx * cx + dy * cy + dz * cz);
      const double disc = bb * bb - 4 * a * (cx * cx + cy * cy + cz * cz - r * r);
      const double margin = disc / (bb * bb);
      if (std::abs(margin) < 1e-3) continue;  // on the silhouette: either answer is right
      const bool hit = disc > 0;
      inside += hit;
      ASSERT_EQ(img->at(col, row) != core::kBackground, hit) << col << "," << row;
    }
  EXPECT_GT(inside, 500);
  // The centre projects to (320 + 100 * 320 / 300, 240 + 50 * 320 / 300) = (426.7, 293.3); the ray through
  // the centre meets the sphere where the normal points back along the ray.
  EXPECT_NE(img->at(427, 293), core::kBackground);
  const core::Rgb444 centre = img->at(427, 293);
  EXPECT_LE(centre.r(), 5);  // normal points left (towards the camera's axis)...
  EXPECT_LE(centre.g(), 6);  // ...and up
  EXPECT_LE(centre.b(), 1);  // and back at the camera
}

// The fixed-point board against the float reference of the same view-space world in the same shading
// model (docs/device.md states the bounds and the measured figures). One worker per pixel, so that no pixel
// is late however many spheres and bounces a scene has: this compares the arithmetic, not the schedule.
core::ImageDiff diff_against_reference(const scene::Scene& s, device::DevicePreset preset) {
  preset.workers = device::kLineWidth;
  Board b(s, {preset, link::WireVersion::kV2, {}});
  const ShownFrame f = b.show();
  EXPECT_EQ(f.device.late_pixels, 0) << s.name;
  const core::Image444 ref = render::render_normal(b.host().view(), 640, 480, preset.max_bounces);
  const core::ImageDiff d = core::diff(f.image, ref);
  std::printf("%-12s max_bounces %d: %6zu pixels differ, %5zu by more than one level, at most %2d levels\n",
              s.name.c_str(), preset.max_bounces, d.differing, d.over_one_level, d.max_level_difference);
  return d;
}

// Bounds on the pixels that differ at all and by more than one level, in parts per 10000 of the frame.
// Scenes with more spheres than the wide device draws in time (49) are crowds of small spheres, whose
// many silhouettes differ more often (docs/device.md has the measured figures).
struct Bound {
  std::size_t differing, over_one_level;
};

void expect_within(const scene::Scene& s, const core::ImageDiff& d, Bound small_scene, Bound crowd) {
  const Bound b = s.spheres.size() <= 49 ? small_scene : crowd;
  EXPECT_LE(d.differing * 10000, d.pixels * b.differing) << s.name;
  EXPECT_LE(d.over_one_level * 10000, d.pixels * b.over_one_level) << s.name;
}

// Primary rays only (metals normal-shaded): at most 1% of pixels differ at all and 0.05% by more than one
// level (2% and 0.2% in crowds).
void expect_close_to_reference(const scene::Scene& s) {
  device::DevicePreset preset = device::wide_preset();
  preset.max_bounces = 0;
  expect_within(s, diff_against_reference(s, preset), {100, 5}, {200, 20});
}

// With mirrors (the wide preset's 3 bounces): reflections magnify the fixed-point error of the hit point,
// so 1% and 0.1% (2% and 0.33% in crowds).
void expect_mirrors_close_to_reference(const scene::Scene& s) {
  expect_within(s, diff_against_reference(s, device::wide_preset()), {100, 10}, {200, 33});
}

TEST(Board, FixedPointMatchesTheFloatReferenceOnBuiltinScenes) {
  for (const auto& name : scene::builtin_names()) expect_close_to_reference(*scene::builtin(name));
}

TEST(Board, FixedPointMatchesTheFloatReferenceOnRandomWorlds) {
  for (std::uint32_t seed = 1; seed <= 4; ++seed) expect_close_to_reference(scene::random_spheres(12, seed));
}

TEST(Board, MirrorsMatchTheFloatReferenceOnBuiltinScenes) {
  for (const auto& name : scene::builtin_names()) expect_mirrors_close_to_reference(*scene::builtin(name));
}

TEST(Board, MirrorsMatchTheFloatReferenceOnRandomWorlds) {
  for (std::uint32_t seed = 1; seed <= 8; ++seed) expect_mirrors_close_to_reference(scene::random_spheres(12, seed));
}

// The error split by pixel kind: pixels whose device ray reflected at least once against those it did not,
// over the cluster scene and eight random worlds, worker (fixed point) against the float reference.
TEST(Board, ReflectedPixelsStayCloseToTheFloatReference) {
  struct Count {
    long pixels = 0, differing = 0, over_one_level = 0;
  };
  std::array<Count, 2> counts{};  // [0] primary only, [1] reflected
  std::vector<scene::Scene> scenes{*scene::builtin("cluster")};
  for (std::uint32_t seed = 1; seed <= 8; ++seed) scenes.push_back(scene::random_spheres(12, seed));
  for (const auto& s : scenes) {
    Board b(s, {});
    b.show();
    const device::DevicePreset p = BoardConfig{}.preset;
    const core::Image444 ref = render::render_normal(b.host().view(), 640, 480, p.max_bounces);
    const device::Worker w(p);
    for (int row = 0; row < 480; ++row)
      for (int col = 0; col < 640; ++col) {
        const core::PixelTrace t = w.trace(col, row, *b.device().scene_memory());
        const core::Rgb444 q = ref.at(col, row);
        const int m = std::max({std::abs(t.colour.r() - q.r()), std::abs(t.colour.g() - q.g()),
                                std::abs(t.colour.b() - q.b())});
        Count& c = counts[t.bounces > 0 ? 1 : 0];
        ++c.pixels;
        c.differing += m > 0;
        c.over_one_level += m > 1;
      }
  }
  for (int kind = 0; kind < 2; ++kind) {
    const Count& c = counts[static_cast<std::size_t>(kind)];
    std::printf("%-9s pixels: %7ld, %5ld differ (%.3f%%), %4ld by more than one level (%.3f%%)\n",
                kind ? "reflected" : "primary", c.pixels, c.differing, 100.0 * double(c.differing) / double(c.pixels),
                c.over_one_level, 100.0 * double(c.over_one_level) / double(c.pixels));
  }
  ASSERT_GT(counts[1].pixels, 50000);
  EXPECT_LE(counts[0].differing * 200, counts[0].pixels);        // primary: at most 0.5% differ
  EXPECT_LE(counts[0].over_one_level * 2000, counts[0].pixels);  // and 0.05% by more than one level
  EXPECT_LE(counts[1].differing * 100, counts[1].pixels);        // reflected: at most 1% differ
  EXPECT_LE(counts[1].over_one_level * 300, counts[1].pixels);   // and 0.33% by more than one level
}

// A reflection at a predicted pixel, on both sides. A metal sphere M (centre (0, 0, 400), radius 100,
// albedo (1, 0.5, 1)) is hit by the ray of pixel (380, 262); the test works out in double where that ray
// reflects, puts a small lambertian sphere S 150 units along the reflected ray, and predicts the pixel's
// colour: S's normal-map colour where the reflected ray meets it, green halved (128 / 255).
TEST(Board, AMirrorShowsASphereWhereTheReflectedRayPredictsIt) {
  const int col = 380, row = 262;
  const core::Vec3d d{double(col - 320), double(row - 240), 320.0};
  const core::Vec3d m_centre{0, 0, 400};
  const double m_radius = 100;
  // The hit on M and the mirror direction, in double.
  const auto near_t = [](const core::Vec3d& o, const core::Vec3d& dir, const core::Vec3d& c, double r) {
    const core::Vec3d oc = c - o;
    const double a = dot(dir, dir), b = 2 * dot(dir, oc), cc = dot(oc, oc) - r * r;
    return (b - std::sqrt(b * b - 4 * a * cc)) / (2 * a);
  };
  const core::Vec3d h = d * near_t({}, d, m_centre, m_radius);
  const core::Vec3d n = (h - m_centre) / m_radius;
  const core::Vec3d reflected = core::normalize(d - n * (2 * dot(d, n)));
  // S on the reflected ray, its centre on the device's 1/16 grid.
  const device::DevicePreset p = device::wide_preset();
  core::Vec3d s_centre = h + reflected * 150.0;
  for (int k = 0; k < 3; ++k) s_centre[k] = std::round(s_centre[k] * 16) / 16;
  const double s_radius = 12;
  ASSERT_GT(std::abs(dot(core::normalize(d), core::normalize(s_centre)) - 1), 1e-3);  // S does not block the primary ray
  const core::Vec3d q = h + reflected * near_t(h, reflected, s_centre, s_radius);
  std::array<int, 3> predicted{};
  for (int k = 0; k < 3; ++k) {
    const double v = 7 * (q[k] - s_centre[k]) / s_radius + 7;
    ASSERT_GT(std::abs(v - std::round(v)), 0.1) << "the prediction is too close to a level boundary";
    predicted[static_cast<std::size_t>(k)] = static_cast<int>(std::floor(v));
  }
  predicted[1] = predicted[1] * 128 / 255;
  const core::Rgb444 expected = core::Rgb444::from_channels(predicted[0], predicted[1], predicted[2]);
  ASSERT_NE(expected, core::Rgb444::from_channels(0, 1, 6));  // not what M shows around S's image

  // The float side.
  const std::vector<scene::Sphere> world{
      {m_centre, m_radius, {scene::MaterialType::kMetal, {1.0, 0.5, 1.0}, 0.0, 1.5}},
      {s_centre, s_radius, {scene::MaterialType::kLambertian, {0.5, 0.5, 0.5}, 0.0, 1.5}}};
  const core::Image444 img = render::render_normal(world, 640, 480, 3);
  EXPECT_EQ(img.at(col, row), expected);
  // The device.
  device::SceneMemory memory;
  for (const auto& s : world) {
    memory.geometry.push_back({{p.x.quantize(s.center.x).raw, p.y.quantize(s.center.y).raw, p.z.quantize(s.center.z).raw},
                               p.radius.quantize(s.radius).raw});
    memory.surfaces.push_back({static_cast<std::uint8_t>(s.material.type),
                               {render::albedo_byte(s.material.albedo.x), render::albedo_byte(s.material.albedo.y),
                                render::albedo_byte(s.material.albedo.z)},
                               0, 6144});
  }
  const core::PixelTrace t = device::Worker(p).trace(col, row, memory);
  EXPECT_EQ(t.bounces, 1);
  EXPECT_EQ(t.colour, expected);
  // Far from S's image, M reflects the background, green halved: (0, 1, 6).
  EXPECT_EQ(device::Worker(p).shade(320 - 60, 240, memory), core::Rgb444::from_channels(0, 1, 6));
  EXPECT_EQ(img.at(320 - 60, 240), core::Rgb444::from_channels(0, 1, 6));
}

TEST(Board, CameraMovesChangeTheFrameTheWayTheKeySays) {
  Board b(*scene::builtin("demo"), {});
  const ShownFrame before = b.show();
  b.host().camera().strafe(1.0);  // D: the camera moves right, so the sphere moves left on screen
  const ShownFrame after = b.show();
  EXPECT_EQ(before.image.at(320, 240), core::Rgb444(0x770));
  EXPECT_NE(after.image.at(320, 240), core::Rgb444(0x770));
  EXPECT_EQ(after.image.at(320 - 32 * 320 / 400, 240), core::Rgb444(0x770));
}

// The window's normal mode on the built-in scenes, as the host sends them: the fast renderer draws the reference's
// image, mirrors included (the `field` scene has 488 spheres, metals among them, and a ground 1000 times their size).
TEST(Board, FastNormalFramesEqualTheReferenceOnTheBuiltInScenes) {
  for (const char* name : {"demo", "cluster", "field"}) {
    Board b(*scene::builtin(name), {});
    b.host().camera().orbit(0.3);
    const std::vector<scene::Sphere> spheres = b.host().view();
    for (int bounces : {0, 3}) {
      EXPECT_EQ(render::render_normal_fast(spheres, 320, 240, bounces).pixels,
                render::render_normal(spheres, 320, 240, bounces).pixels)
          << name << ", " << bounces << " bounces";
    }
  }
}

}  // namespace
}  // namespace tripsitter::board

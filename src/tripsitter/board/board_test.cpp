// End-to-end: scenes through host -> link -> device -> VGA signal -> monitor, against the float reference.
#include <tripsitter/board/board.h>

#include <cmath>

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
  EXPECT_EQ(f.link_bytes, link::kV2HeaderBytes + link::kV2SphereBytes + link::kV2TrailerBytes);
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

// The fixed-point board against the float reference on the same view-space world (README states the bound).
void expect_close_to_reference(const scene::Scene& s) {
  Board b(s, {});
  const ShownFrame f = b.show();
  const core::Image444 ref = render::render_normal(b.host().ready().view_spheres, 640, 480);
  const core::ImageDiff d = core::diff(f.image, ref);
  EXPECT_LE(d.differing, d.pixels / 100) << s.name;        // at most 1% of pixels differ at all
  EXPECT_LE(d.over_one_level, d.pixels / 2000) << s.name;  // and at most 0.05% by more than one level
}

TEST(Board, FixedPointMatchesTheFloatReferenceOnBuiltinScenes) {
  for (const auto& name : scene::builtin_names()) expect_close_to_reference(*scene::builtin(name));
}

TEST(Board, FixedPointMatchesTheFloatReferenceOnRandomWorlds) {
  for (std::uint32_t seed = 1; seed <= 4; ++seed) expect_close_to_reference(scene::random_spheres(12, seed));
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

}  // namespace
}  // namespace tripsitter::board

#include <tripsitter/render/normal.h>

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace tripsitter::render {
namespace {

scene::Sphere sphere(double x, double y, double z, double r) { return {{x, y, z}, r, {}}; }

scene::Sphere metal(double x, double y, double z, double r, core::Vec3d albedo) {
  return {{x, y, z}, r, {scene::MaterialType::kMetal, albedo, 0.0, 1.5}};
}

TEST(RenderNormal, TheBoardsDemoSphereIsADiscOfRadius51Point9) {
  const std::vector<scene::Sphere> world{sphere(0, 0, 400, 64)};
  const core::Image444 img = render_normal(world, 640, 480);
  EXPECT_EQ(img.at(320, 240), core::Rgb444(0x770));
  // Angular radius asin(64 / 400); on the image plane z = 320: 320 tan(asin(0.16)) = 51.87 pixels.
  EXPECT_NE(img.at(320 + 51, 240), core::kBackground);
  EXPECT_EQ(img.at(320 + 53, 240), core::kBackground);
  EXPECT_NE(img.at(320, 240 - 51), core::kBackground);
  EXPECT_EQ(img.at(320, 240 - 53), core::kBackground);
  EXPECT_EQ(img.at(0, 0), core::kBackground);
}

TEST(RenderNormal, NormalsColourTheSides) {
  const std::vector<scene::Sphere> world{sphere(0, 0, 400, 64)};
  const core::Image444 img = render_normal(world, 640, 480);
  // Right edge: normal points to +x (red high); top edge: normal points to -y (green low).
  EXPECT_GE(img.at(320 + 50, 240).r(), 11);
  EXPECT_LE(img.at(320, 240 - 50).g(), 3);
  EXPECT_LE(img.at(320 - 50, 240).r(), 3);
}

TEST(RenderNormal, TheNearerSphereHidesTheFarther) {
  const std::vector<scene::Sphere> far_then_near{sphere(0, 0, 800, 200), sphere(0, 0, 300, 20)};
  const core::Image444 img = render_normal(far_then_near, 640, 480);
  EXPECT_EQ(img.at(320, 240), core::Rgb444(0x770));  // the small near sphere's front
  const std::vector<scene::Sphere> only_far{sphere(0, 0, 800, 200)};
  EXPECT_EQ(render_normal(only_far, 640, 480).at(320, 240), core::Rgb444(0x770));
  // Beside the small one, the big one shows with a tilted normal.
  EXPECT_NE(img.at(320 + 40, 240), render_normal(std::vector<scene::Sphere>{sphere(0, 0, 300, 20)}, 640, 480).at(360, 240));
}

TEST(RenderNormal, NothingBehindTheCameraIsDrawn) {
  const std::vector<scene::Sphere> behind{sphere(0, 0, -400, 64)};
  const core::Image444 img = render_normal(behind, 640, 480);
  for (const auto& p : img.pixels) ASSERT_EQ(p, core::kBackground);
}

TEST(RenderNormal, OtherSizesKeepANinetyDegreeHorizontalView) {
  const std::vector<scene::Sphere> world{sphere(0, 0, 400, 64)};
  const core::Image444 img = render_normal(world, 1280, 720);
  EXPECT_EQ(img.width, 1280);
  EXPECT_EQ(img.height, 720);
  EXPECT_EQ(img.at(640, 360), core::Rgb444(0x770));
  EXPECT_NE(img.at(640 + 102, 360), core::kBackground);  // twice the 640-wide radius
  EXPECT_EQ(img.at(640 + 106, 360), core::kBackground);
}

// --- The mirror model (docs/device.md) ---

TEST(RenderMirror, AlbedoBytesRoundAsTheHostSendsThem) {
  EXPECT_EQ(albedo_byte(0.0), 0);
  EXPECT_EQ(albedo_byte(0.5), 128);  // 127.5 rounds away from zero
  EXPECT_EQ(albedo_byte(2.0 / 3.0), 170);
  EXPECT_EQ(albedo_byte(1.0), 255);
  EXPECT_EQ(albedo_byte(1.5), 255);
  EXPECT_EQ(albedo_byte(-0.2), 0);
}

TEST(RenderMirror, TheCentreOfAMetalSphereReflectsTheBackgroundTinted) {
  const std::vector<scene::Sphere> world{metal(0, 0, 400, 64, {1.0, 2.0 / 3.0, 0.5})};
  // (0, 3, 6) times (255, 170, 128) / 255, floored.
  EXPECT_EQ(render_normal(world, 640, 480, 3).at(320, 240), core::Rgb444::from_channels(0, 2, 3));
  EXPECT_EQ(render_normal(world, 640, 480, 0).at(320, 240), core::Rgb444(0x770));  // no bounces: the board's shading
}

TEST(RenderMirror, ZeroBouncesRenderMetalsAsTheBoardDid) {
  const std::vector<scene::Sphere> metals{metal(0, 0, 400, 64, {0.9, 0.1, 0.5}), metal(100, 30, 300, 40, {1, 1, 1}),
                                          sphere(-120, -40, 350, 50)};
  std::vector<scene::Sphere> plain = metals;
  for (auto& s : plain) s.material = {};
  EXPECT_EQ(render_normal(metals, 640, 480).pixels, render_normal(plain, 640, 480).pixels);
  EXPECT_EQ(render_normal(metals, 640, 480, 0).pixels, render_normal(plain, 640, 480, 3).pixels);
  EXPECT_NE(render_normal(metals, 640, 480, 1).pixels, render_normal(plain, 640, 480, 1).pixels);
}

TEST(RenderMirror, TwoFacingMirrorsStopAtTheCutOff) {
  const std::vector<scene::Sphere> world{metal(0, 0, 400, 64, {1, 1, 1}), metal(0, 0, -400, 64, {0.5, 1, 1})};
  // Cut off on A (facing the camera: 0x770) or on B (facing A: 0x77E); each reflection off B halves red.
  EXPECT_EQ(render_normal(world, 640, 480, 0).at(320, 240), core::Rgb444(0x770));
  EXPECT_EQ(render_normal(world, 640, 480, 1).at(320, 240), core::Rgb444(0x77E));
  EXPECT_EQ(render_normal(world, 640, 480, 2).at(320, 240), core::Rgb444(0x370));  // 7 * 128 / 255 = 3.5
  EXPECT_EQ(render_normal(world, 640, 480, 3).at(320, 240), core::Rgb444(0x37E));
  EXPECT_EQ(render_normal(world, 640, 480, 4).at(320, 240), core::Rgb444(0x170));  // 7 * 128^2 / 255^2 = 1.76
}

TEST(RenderMirror, DirectionsAreScaledByPowersOfTwoOnly) {
  const core::Vec3d small{3, -4, 320};
  EXPECT_EQ(DoubleArith::scale_direction(small), small);
  // Largest component 3 * 2^30 < 2^32: shifted by 32 - 20 = 12 bits, as the device shifts its integers.
  const core::Vec3d big{3.0 * 0x1p30, -0x1p10, 0.0};
  EXPECT_EQ(DoubleArith::scale_direction(big), (core::Vec3d{3.0 * 0x1p18, -0x1p-2, 0.0}));
}

TEST(RenderMirror, RejectsABounceCutOffBeyondTheLimit) {
  const std::vector<scene::Sphere> world{sphere(0, 0, 400, 64)};
  EXPECT_THROW(render_normal(world, 64, 48, core::kMaxBounces + 1), std::invalid_argument);
  EXPECT_THROW(render_normal(world, 64, 48, -1), std::invalid_argument);
}

}  // namespace
}  // namespace tripsitter::render

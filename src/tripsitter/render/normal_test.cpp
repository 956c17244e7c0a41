#include <tripsitter/render/normal.h>

#include <cmath>

#include <gtest/gtest.h>

namespace tripsitter::render {
namespace {

scene::Sphere sphere(double x, double y, double z, double r) { return {{x, y, z}, r, {}}; }

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

}  // namespace
}  // namespace tripsitter::render

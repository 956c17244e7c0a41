#include <tripsitter/render/normal.h>

#include <cmath>
#include <random>
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

// --- The fast renderer against the reference ---

// Random view-space worlds of every kind the culling must get right: spheres in front, behind, beside the eye
// (across the plane z = 0, where the screen bounds wrap), around the eye, tiny and far, huge, and metals.
std::vector<scene::Sphere> random_world(std::mt19937& gen) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int n = 1 + static_cast<int>(unit(gen) * 40);
  std::vector<scene::Sphere> world;
  for (int i = 0; i < n; ++i) {
    const double kind = unit(gen);
    scene::Sphere s;
    if (kind < 0.6) {  // in front, any size
      s = sphere(1200 * unit(gen) - 600, 900 * unit(gen) - 450, 2000 * unit(gen) - 100, std::exp(6 * unit(gen)));
    } else if (kind < 0.75) {  // beside or behind the eye
      s = sphere(1200 * unit(gen) - 600, 600 * unit(gen) - 300, 300 * unit(gen) - 250, 5 + 100 * unit(gen));
    } else if (kind < 0.85) {  // tiny and far
      s = sphere(4e4 * unit(gen) - 2e4, 3e4 * unit(gen) - 1.5e4, 1e5 + 1e5 * unit(gen), 0.5 + 20 * unit(gen));
    } else if (kind < 0.95) {  // a huge ground below or above
      s = sphere(0, (unit(gen) < 0.5 ? 1 : -1) * (1e6 + 200 * unit(gen)), 500 * unit(gen), 1e6);
    } else {  // around the eye
      s = sphere(20 * unit(gen) - 10, 20 * unit(gen) - 10, 20 * unit(gen) - 10, 50 + 500 * unit(gen));
    }
    if (unit(gen) < 0.4) s.material = {scene::MaterialType::kMetal, {unit(gen), unit(gen), unit(gen)}, 0.0, 1.5};
    world.push_back(s);
  }
  return world;
}

TEST(RenderNormalFast, EqualsTheReferenceOnRandomWorlds) {
  std::mt19937 gen(20261121);
  struct Size {
    int width, height;
  };
  const Size sizes[] = {{640, 480}, {37, 21}, {64, 48}, {1, 1}, {200, 330}};
  for (int world_index = 0; world_index < 60; ++world_index) {
    const std::vector<scene::Sphere> world = random_world(gen);
    const Size size = sizes[world_index % std::size(sizes)];
    const int bounces = world_index % (core::kMaxBounces + 1);
    const int threads = 1 + world_index % 2;
    ASSERT_EQ(render_normal_fast(world, size.width, size.height, bounces, threads).pixels,
              render_normal(world, size.width, size.height, bounces).pixels)
        << "world " << world_index << " (" << world.size() << " spheres), " << size.width << "x" << size.height
        << ", " << bounces << " bounces";
  }
}

// Spheres whose outline passes exactly through a pixel's ray, where the kernel's discriminant is decided by
// rounding alone; and radii one ulp either side.
TEST(RenderNormalFast, EqualsTheReferenceOnGrazingSpheres) {
  std::vector<scene::Sphere> world;
  for (int k = 0; k < 24; ++k) {
    const core::Vec3d d{double(37 * k % 640 - 320), double(23 * k % 480 - 240), 320.0};  // pixel (37k, 23k)'s ray
    const core::Vec3d c{d.x + 90.0 * (k % 5) - 180.0, d.y + 50.0 * (k % 3) - 50.0, 300.0 + 97.0 * k};
    // The centre's distance from the ray's line: |c x d| / |d|.
    const core::Vec3d cross{c.y * d.z - c.z * d.y, c.z * d.x - c.x * d.z, c.x * d.y - c.y * d.x};
    const double r = std::sqrt(dot(cross, cross) / dot(d, d));
    const double radius = k % 3 == 0 ? r : std::nextafter(r, k % 3 == 1 ? 0.0 : 1e300);
    if (radius > 0) world.push_back(sphere(c.x, c.y, c.z, radius));
  }
  ASSERT_FALSE(world.empty());
  EXPECT_EQ(render_normal_fast(world, 640, 480, 0, 2).pixels, render_normal(world, 640, 480, 0).pixels);
}

TEST(RenderNormalFast, RejectsABounceCutOffBeyondTheLimit) {
  const std::vector<scene::Sphere> world{sphere(0, 0, 400, 64)};
  EXPECT_THROW(render_normal_fast(world, 64, 48, core::kMaxBounces + 1), std::invalid_argument);
}

}  // namespace
}  // namespace tripsitter::render

// The float path tracer in the device's view: its rays, its sky and its determinism, and the linear comparison.
#include <tripsitter/render/device_view.h>

#include <atomic>
#include <stdexcept>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/core/screen.h>

namespace tripsitter::render {
namespace {

constexpr int kWidth = core::kScreenWidth;

// Few samples and bounces: these tests check geometry and plumbing, not convergence.
DeviceViewSettings quick(int threads = 0) {
  DeviceViewSettings s;
  s.spp = 2;
  s.max_depth = 2;
  s.threads = threads;
  return s;
}

const Vec3f& at(const core::ImageRgbF& image, int col, int row) {
  return image.pixels[static_cast<std::size_t>(row) * static_cast<std::size_t>(image.width) +
                      static_cast<std::size_t>(col)];
}

// The sky seen along the device's ray of a pixel: up is -y in view space, +y for Sky.
Vec3f sky_of_pixel(const Sky& sky, int col, int row) {
  const Vec3f d = core::device_ray<float>(col, row);
  return sky.radiance({d.x, -d.y, d.z});
}

scene::Sphere grey_ball(core::Vec3d center, double radius) {
  return {center, radius, {scene::MaterialType::kLambertian, {0.5, 0.5, 0.5}, 0, 1.5}};
}

TEST(DeviceView, EmptySceneIsTheSkyWithUpAtTheTopOfTheScreen) {
  const DeviceViewSettings settings = quick();
  const core::ImageRgbF image = render_device_view({}, settings);
  ASSERT_EQ(image.width, 640);
  ASSERT_EQ(image.height, 480);
  ASSERT_EQ(image.pixels.size(), 640u * 480u);
  // Every sample of a ray that hits nothing is the same, so the mean is exact.
  EXPECT_EQ(at(image, 0, 0), sky_of_pixel(settings.sky, 0, 0));
  EXPECT_EQ(at(image, 639, 479), sky_of_pixel(settings.sky, 639, 479));
  // The default sky is white at the bottom and blue at the top: less red towards the top of the screen.
  EXPECT_LT(at(image, 320, 0).x, at(image, 320, 479).x);
  EXPECT_LT(at(image, 0, 0).x, at(image, 0, 479).x);
}

TEST(DeviceView, SphereStraightAheadCoversTheCentreAtTheDevicesScale) {
  const std::vector<scene::Sphere> spheres{grey_ball({0, 0, 2000}, 500)};
  const DeviceViewSettings settings = quick();
  const core::ImageRgbF image = render_device_view(spheres, settings);
  // A ray (dx, 0, 320) meets the sphere when 2000 sin(angle) <= 500, i.e. |dx| <= 82.6 pixels: column 400 is on the
  // disc, 405 off it. A grey ball lit by a sky no brighter than 1 returns at most half of it, below the sky there.
  for (const int col : {320, 400, 240}) {
    const Vec3f sky = sky_of_pixel(settings.sky, col, 240), p = at(image, col, 240);
    EXPECT_LT(p.x, sky.x) << col;
    EXPECT_LT(p.y, sky.y) << col;
    EXPECT_LT(p.z, sky.z) << col;
  }
  for (const auto& [col, row] : {std::pair{405, 240}, std::pair{235, 240}, std::pair{0, 0}})
    EXPECT_EQ(at(image, col, row), sky_of_pixel(settings.sky, col, row)) << col << "," << row;
}

TEST(DeviceView, SphereBelowTheViewAxisIsDrawnBelowTheScreenCentre) {
  // y grows downwards: a centre at y = 400, z = 2000 projects to row 240 + 320 * 400 / 2000 = 304. Mirroring only
  // the rays, or only the spheres, would draw it at row 176.
  const std::vector<scene::Sphere> spheres{grey_ball({0, 400, 2000}, 100)};
  const DeviceViewSettings settings = quick();
  const core::ImageRgbF image = render_device_view(spheres, settings);
  EXPECT_NE(at(image, 320, 304), sky_of_pixel(settings.sky, 320, 304));
  EXPECT_EQ(at(image, 320, 176), sky_of_pixel(settings.sky, 320, 176));
}

TEST(DeviceView, SameSeedSameImageWhateverTheThreads) {
  const std::vector<scene::Sphere> spheres{grey_ball({0, 0, 2000}, 500), grey_ball({300, 200, 900}, 150)};
  std::atomic<int> rows{0};
  const core::ImageRgbF one = render_device_view(spheres, quick(1));
  const core::ImageRgbF two = render_device_view(spheres, quick(2), [&](int) { ++rows; });
  EXPECT_EQ(rows.load(), 480);
  EXPECT_TRUE(one.pixels == two.pixels);
  // The bounces are random: another seed changes the image, so the equality above is not trivial.
  DeviceViewSettings other = quick(2);
  other.seed = 2;
  EXPECT_FALSE(render_device_view(spheres, other).pixels == one.pixels);
}

TEST(DeviceView, PixelIsTheMeanOfTracePathOverItsOwnStream) {
  // Spheres on the plane y = 0 are their own mirror images; the ray is the device's, mirrored in y.
  const std::vector<scene::Sphere> spheres{grey_ball({0, 0, 2000}, 500)};
  DeviceViewSettings settings = quick();
  settings.spp = 3;
  const core::ImageRgbF image = render_device_view(spheres, settings);
  const int col = 330, row = 250;
  const PathScene scene(spheres);
  Rng rng = RngStreams(settings.seed).stream(static_cast<std::uint64_t>(row) * kWidth + col);
  const Ray ray{{0, 0, 0}, {10, -10, 320}};
  Vec3f sum{0, 0, 0};
  for (int s = 0; s < settings.spp; ++s) sum += trace_path(scene, ray, settings.max_depth, settings.sky, rng);
  EXPECT_EQ(at(image, col, row), sum * (1.0f / 3));
}

core::ImageRgbF tiny(int width, int height, std::vector<Vec3f> pixels) { return {width, height, std::move(pixels)}; }

TEST(CompareLinear, IdenticalImagesDifferByNothing) {
  const core::ImageRgbF image = render_device_view({}, quick());
  const LinearComparison c = compare_linear(image, image);
  EXPECT_EQ(c.mean_relative_bias, 0);
  EXPECT_EQ(c.relmse, 0);
}

TEST(CompareLinear, ScaledImageHasThatBias) {
  const core::ImageRgbF reference = render_device_view({}, quick());
  core::ImageRgbF scaled = reference;
  for (Vec3f& p : scaled.pixels) p = p * 1.1f;
  EXPECT_NEAR(compare_linear(scaled, reference).mean_relative_bias, 0.1, 1e-6);
}

TEST(CompareLinear, MatchesAHandComputation) {
  const core::ImageRgbF reference = tiny(2, 1, {{1, 0, 0}, {0, 0, 0}});
  const core::ImageRgbF image = tiny(2, 1, {{1.5f, 0.25f, 0}, {0, 0, 0}});
  // Six channels: 0.5^2 / (1 + 0.01) + 0.25^2 / (0 + 0.01) = 0.2475... + 6.25, the rest 0; means 1.75 / 6 and 1 / 6.
  const LinearComparison c = compare_linear(image, reference);
  EXPECT_NEAR(c.relmse, (0.25 / 1.01 + 6.25) / 6, 1e-12);
  EXPECT_NEAR(c.mean_relative_bias, 0.75, 1e-12);
  // A black reference has no relative bias; its relmse is the mean of x^2 / 0.01.
  const LinearComparison black = compare_linear(image, tiny(2, 1, {{0, 0, 0}, {0, 0, 0}}));
  EXPECT_EQ(black.mean_relative_bias, 0);
  EXPECT_NEAR(black.relmse, (2.25 + 0.0625) / 0.01 / 6, 1e-9);
}

TEST(CompareLinear, SizeMismatchThrows) {
  const core::ImageRgbF wide = tiny(2, 1, {{0, 0, 0}, {0, 0, 0}});
  const core::ImageRgbF tall = tiny(1, 2, {{0, 0, 0}, {0, 0, 0}});
  EXPECT_THROW(compare_linear(wide, tall), std::invalid_argument);
  EXPECT_THROW(compare_linear(wide, tiny(1, 1, {{0, 0, 0}})), std::invalid_argument);
}

}  // namespace
}  // namespace tripsitter::render

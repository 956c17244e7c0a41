// Statistical and exact checks of the path tracer, not just "it renders".
#include <tripsitter/render/path_tracer.h>

#include <bit>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include <tripsitter/scene/builtin.h>

namespace tripsitter::render {
namespace {

scene::Sphere sphere(core::Vec3d c, double r, scene::Material m) { return {c, r, m}; }
scene::Material lambertian(double a) { return {scene::MaterialType::kLambertian, {a, a, a}, 0, 1.5}; }
scene::Material metal(double a, double fuzz) { return {scene::MaterialType::kMetal, {a, a, a}, fuzz, 1.5}; }
scene::Material glass(double ior) { return {scene::MaterialType::kDielectric, {1, 1, 1}, 0, ior}; }

scene::CameraSettings looking_at_origin() {
  scene::CameraSettings c;
  c.lookfrom = {0, 0, -10};
  c.lookat = {0, 0, 0};
  c.vfov = 30;
  c.focus_dist = 10;
  return c;
}

double mean(const ImageRgbF& img) {
  double sum = 0;
  for (const auto& p : img.pixels) sum += (p.x + p.y + p.z) / 3.0;
  return sum / static_cast<double>(img.pixels.size());
}

double rmse(const ImageRgbF& a, const ImageRgbF& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const Vec3f d = a.pixels[i] - b.pixels[i];
    sum += core::dot(d, d) / 3.0;
  }
  return std::sqrt(sum / static_cast<double>(a.pixels.size()));
}

TEST(Camera, CentreRayLooksAtTheTargetAndTheEdgesSpanTheFieldOfView) {
  scene::CameraSettings s = looking_at_origin();
  s.vfov = 60;
  const ThinLensCamera cam(s, 200, 100);
  const Ray top = cam.centre_ray(100, 0);        // half a pixel below the top edge
  const Ray centre = cam.centre_ray(100, 50);    // half a pixel right of and below the middle
  const double pixel = 2 * std::tan(30 * std::numbers::pi / 180) * 10 / 100;  // on the focus plane, 10 away
  EXPECT_NEAR(centre.dir.x, -pixel / 2, 1e-5);   // screen right is -x
  EXPECT_NEAR(centre.dir.y, -pixel / 2, 1e-5);   // screen down is -y
  EXPECT_NEAR(centre.dir.z, 10, 1e-5);
  const double angle = std::atan2(top.dir.y, top.dir.z) * 180 / std::numbers::pi;
  EXPECT_NEAR(angle, 30 - 0.5 * 60.0 / 100, 0.35);  // vfov / 2, less about half a pixel
  // Screen right is -x when looking along +z with y up (right-handed).
  EXPECT_LT(cam.centre_ray(199, 50).dir.x, 0);
}

// A white (albedo 1) lambertian cluster under a uniform white sky: light is neither made nor lost, so
// every pixel converges to the sky's radiance, 1.
TEST(PathTracer, WhiteLambertianUnderWhiteSkyConvergesToTheSky) {
  const std::vector<scene::Sphere> spheres{sphere({0, 0, 0}, 1.5, lambertian(1.0)), sphere({1.5, 0.8, 0.5}, 1.0, lambertian(1.0)),
                                           sphere({-1.2, -0.9, 0.3}, 1.1, lambertian(1.0))};
  const PathScene scene(spheres);
  PathSettings s{.width = 32, .height = 32, .spp = 64, .max_depth = 200, .seed = 5, .threads = 0, .sky = {}};
  s.sky = {{1, 1, 1}, {1, 1, 1}};
  const ImageRgbF img = render_path(scene, ThinLensCamera(looking_at_origin(), 32, 32), s);
  for (const auto& p : img.pixels) {
    ASSERT_NEAR(p.x, 1.0f, 1e-3f);
    ASSERT_NEAR(p.z, 1.0f, 1e-3f);
  }
}

// A grey lambertian sphere alone under a uniform sky: each hit returns albedo x sky exactly.
TEST(PathTracer, GreySphereUnderUniformSkyIsItsAlbedo) {
  const std::vector<scene::Sphere> spheres{sphere({0, 0, 0}, 2.0, lambertian(0.4))};
  const PathScene scene(spheres);
  Sky sky{{0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}};
  Rng rng(3);
  for (int i = 0; i < 1000; ++i) {
    const Vec3f radiance = trace_path(scene, {{0, 0, -10}, {0.01f * (i % 7), 0.01f * (i % 5), 1}}, 50, sky, rng);
    ASSERT_NEAR(radiance.y, 0.2f, 1e-6f);
  }
}

TEST(PathTracer, DielectricOfIndexOneIsInvisible) {
  std::vector<scene::Sphere> without{sphere({0, -101, 0}, 100, lambertian(0.5)), sphere({1.5, 0, 2}, 1, metal(0.8, 0.2))};
  std::vector<scene::Sphere> with = without;
  with.push_back(sphere({-0.5, 0, 0}, 1.2, glass(1.0)));
  PathSettings s{.width = 48, .height = 32, .spp = 16, .max_depth = 50, .seed = 9, .threads = 0, .sky = {}};
  const ThinLensCamera cam(looking_at_origin(), 48, 32);
  const ImageRgbF a = render_path(PathScene(without), cam, s);
  const ImageRgbF b = render_path(PathScene(with), cam, s);
  // The same random numbers meet the same surfaces: only float rounding of the straight-through rays differs.
  std::size_t same = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const Vec3f d = a.pixels[i] - b.pixels[i];
    same += core::dot(d, d) < 1e-6f;
  }
  EXPECT_GE(same, a.pixels.size() * 99 / 100);
  EXPECT_NEAR(mean(a), mean(b), 2e-3);
}

// A mirror (fuzz 0, albedo 1) returns exactly the sky in the mirrored direction.
TEST(PathTracer, MetalWithoutFuzzReflectsExactly) {
  const std::vector<scene::Sphere> spheres{sphere({0, 0, 0}, 1.0, metal(1.0, 0.0))};
  const PathScene scene(spheres);
  const Sky sky;
  Rng rng(1);
  for (double y0 : {-0.9, -0.5, 0.0, 0.3, 0.7, 0.95}) {
    const Ray ray{{0, static_cast<float>(y0), -5}, {0, 0, 1}};
    // Hit at (0, y0, -sqrt(1 - y0^2)); normal is that point; the mirrored direction in double:
    const double nz = -std::sqrt(1 - y0 * y0);
    const double dn = nz;  // d . n with d = (0, 0, 1)
    const double ry = -2 * dn * y0, rz = 1 - 2 * dn * nz;
    const float a = static_cast<float>(0.5 * (ry / std::sqrt(ry * ry + rz * rz) + 1));
    const Vec3f expected = sky.bottom * (1 - a) + sky.top * a;
    const Vec3f got = trace_path(scene, ray, 50, sky, rng);
    EXPECT_NEAR(got.x, expected.x, 1e-5f) << y0;
    EXPECT_NEAR(got.y, expected.y, 1e-5f) << y0;
    EXPECT_NEAR(got.z, expected.z, 1e-5f) << y0;
  }
}

TEST(PathTracer, ErrorFallsLikeOneOverRootSpp) {
  scene::Scene cluster = *scene::builtin("cluster");
  const PathScene scene(cluster.spheres);
  const ThinLensCamera cam(cluster.camera, 40, 30);
  PathSettings s{.width = 40, .height = 30, .spp = 4096, .max_depth = 20, .seed = 100, .threads = 0, .sky = {}};
  const ImageRgbF reference = render_path(scene, cam, s);
  s.spp = 4;
  s.seed = 1;
  const double e4 = rmse(render_path(scene, cam, s), reference);
  s.spp = 64;
  s.seed = 2;
  const double e64 = rmse(render_path(scene, cam, s), reference);
  // 16 times the samples: a quarter of the error (the reference's own noise is 1/32 of e4).
  EXPECT_GT(e4 / e64, 3.0) << e4 << " " << e64;
  EXPECT_LT(e4 / e64, 5.0) << e4 << " " << e64;
}

TEST(PathTracer, SameSeedSameBytesOnOneAndTwoThreads) {
  scene::Scene field = *scene::builtin("field");
  const PathScene scene(field.spheres);
  const ThinLensCamera cam(field.camera, 64, 36);
  PathSettings s{.width = 64, .height = 36, .spp = 4, .max_depth = 50, .seed = 77, .threads = 1, .sky = {}};
  const core::ImageRgb8 one = to_srgb8(render_path(scene, cam, s));
  s.threads = 2;
  const core::ImageRgb8 two = to_srgb8(render_path(scene, cam, s));
  EXPECT_EQ(one, two);
  s.seed = 78;
  EXPECT_NE(to_srgb8(render_path(scene, cam, s)), two);
}

TEST(PathTracer, RowsSharedInAnyStepGiveTheWholeImagesValues) {
  scene::Scene field = *scene::builtin("field");
  const PathScene scene(field.spheres);
  const ThinLensCamera cam(field.camera, 40, 23);
  const PathSettings s{.width = 40, .height = 23, .spp = 2, .max_depth = 50, .seed = 5, .threads = 1, .sky = {}};
  const ImageRgbF whole = render_path(scene, cam, s);
  for (int step : {1, 2, 3, 4, 30}) {
    ImageRgbF parts{40, 23, std::vector<Vec3f>(40 * 23, Vec3f{-1, -1, -1})};
    for (int first = 0; first < step; ++first) render_path_rows(scene, cam, s, first, step, parts);
    for (std::size_t i = 0; i < whole.pixels.size(); ++i) {
      ASSERT_EQ(parts.pixels[i].x, whole.pixels[i].x) << "step " << step << " pixel " << i;
      ASSERT_EQ(parts.pixels[i].y, whole.pixels[i].y) << "step " << step << " pixel " << i;
      ASSERT_EQ(parts.pixels[i].z, whole.pixels[i].z) << "step " << step << " pixel " << i;
    }
  }
  // Rows of one share leave the others untouched.
  ImageRgbF one_share{40, 23, std::vector<Vec3f>(40 * 23, Vec3f{-1, -1, -1})};
  render_path_rows(scene, cam, s, 1, 2, one_share);
  EXPECT_EQ(one_share.pixels[0].x, -1.0f);
  EXPECT_EQ(one_share.pixels[40].x, whole.pixels[40].x);
}

// The BVH is an acceleration only: testing every sphere for every ray gives the same paths, hence the same image.
TEST(PathTracer, BruteForceQueryTracesTheSameImage) {
  scene::Scene field = *scene::builtin("field");
  const PathScene scene(field.spheres);
  const ThinLensCamera cam(field.camera, 48, 27);
  const PathSettings s{.width = 48, .height = 27, .spp = 2, .max_depth = 50, .seed = 9, .threads = 2, .sky = {}};
  const ImageRgbF ours = render_path(scene, cam, s);
  const ImageRgbF brute = render_path(scene, BruteForceQuery(scene), cam, s);
  ASSERT_EQ(brute.pixels.size(), ours.pixels.size());
  for (std::size_t i = 0; i < ours.pixels.size(); ++i) {
    ASSERT_EQ(brute.pixels[i].x, ours.pixels[i].x) << "pixel " << i;
    ASSERT_EQ(brute.pixels[i].y, ours.pixels[i].y) << "pixel " << i;
    ASSERT_EQ(brute.pixels[i].z, ours.pixels[i].z) << "pixel " << i;
  }
}

TEST(PathTracer, ProgressCountsEverySample) {
  const std::vector<scene::Sphere> spheres{sphere({0, 0, 0}, 1, lambertian(0.5))};
  std::atomic<std::uint64_t> samples{0};
  PathSettings s{.width = 20, .height = 10, .spp = 3, .max_depth = 5, .seed = 1, .threads = 2, .sky = {}};
  render_path(PathScene(spheres), ThinLensCamera(looking_at_origin(), 20, 10), s,
              [&](std::uint64_t n) { samples += n; });
  EXPECT_EQ(samples.load(), 20u * 10u * 3u);
}

TEST(Srgb, EncodesTheStandardCurve) {
  EXPECT_EQ(srgb_encode(0.0f), 0);
  EXPECT_EQ(srgb_encode(1.0f), 255);
  EXPECT_EQ(srgb_encode(2.0f), 255);
  EXPECT_EQ(srgb_encode(-1.0f), 0);
  EXPECT_EQ(srgb_encode(0.5f), 188);        // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354
  EXPECT_EQ(srgb_encode(0.002f), 7);        // linear segment: 12.92 * 0.002 * 255 = 6.6
  EXPECT_EQ(srgb_encode(0.2159f), 128);     // 128 / 255 decodes to 0.21586
}

TEST(Srgb, TheTableEncodesEveryValueAsTheCurveDoes) {
  // Every 97th float in [0, 1] (11 million values, so every level boundary is approached within 97 floats),
  // values outside [0, 1] and NaN.
  ImageRgbF img{1, 0, {}};
  std::vector<float> values;
  for (std::uint32_t bits = 0; bits <= std::bit_cast<std::uint32_t>(1.0f); bits += 97) values.push_back(std::bit_cast<float>(bits));
  for (float v : {-1.0f, 1.5f, INFINITY, -INFINITY, NAN, 1.0f}) values.push_back(v);
  for (std::size_t i = 0; i < values.size(); i += 3)
    img.pixels.push_back({values[i], values[std::min(i + 1, values.size() - 1)], values[std::min(i + 2, values.size() - 1)]});
  img.height = static_cast<int>(img.pixels.size());
  const core::ImageRgb8 out = to_srgb8(img);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) {
    const Vec3f& p = img.pixels[i];
    ASSERT_EQ(out.pixels[3 * i + 0], srgb_encode(p.x)) << p.x;
    ASSERT_EQ(out.pixels[3 * i + 1], srgb_encode(p.y)) << p.y;
    ASSERT_EQ(out.pixels[3 * i + 2], srgb_encode(p.z)) << p.z;
  }
}

}  // namespace
}  // namespace tripsitter::render

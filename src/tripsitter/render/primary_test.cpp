// The primary-ray renderer draws exactly what testing every sphere with every ray draws.
#include <tripsitter/render/primary.h>

#include <cmath>

#include <gtest/gtest.h>

#include <tripsitter/scene/builtin.h>

namespace tripsitter::render {
namespace {

core::ImageRgb8 brute_force(const PathScene& scene, const ThinLensCamera& camera, int width, int height) {
  core::ImageRgb8 image(width, height);
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      const Ray ray = camera.centre_ray(col, row);
      SphereHit hit;
      if (intersect_brute_force(scene.centers(), scene.radii(), ray, 0.0f, INFINITY, hit))
        shade_primary(scene, ray, hit,
                      &image.pixels[3 * (static_cast<std::size_t>(row) * static_cast<std::size_t>(width) +
                                         static_cast<std::size_t>(col))]);
    }
  }
  return image;
}

}  // namespace

TEST(Primary, NormalColoursMapMinusOneToZeroAndOneTo255) {
  std::uint8_t rgb[3];
  normal_to_rgb8({-1.0f, 0.0f, 1.0f}, rgb);
  EXPECT_EQ(rgb[0], 0);
  EXPECT_EQ(rgb[1], 127);
  EXPECT_EQ(rgb[2], 255);
}

TEST(Primary, SameImageAsBruteForceOnBuiltinAndRandomScenes) {
  for (const char* name : {"demo", "cluster", "field", "random-1", "random-16", "random-2000"}) {
    const scene::Scene sc = *scene::builtin(name);
    const PathScene scene(sc.spheres);
    for (const auto& [w, h] : {std::pair{64, 48}, std::pair{37, 23}}) {
      const ThinLensCamera camera(sc.camera, w, h);
      const core::ImageRgb8 fast = render_primary(scene, camera, {.width = w, .height = h, .threads = 2});
      EXPECT_EQ(fast, brute_force(scene, camera, w, h)) << name << " at " << w << "x" << h;
    }
  }
}

TEST(Primary, MissesAreBlackAndHitsAreNot) {
  const std::vector<scene::Sphere> one{{{0, 0, 0}, 1.0, {}}};
  const PathScene scene(one);
  scene::CameraSettings c;
  c.lookfrom = {0, 0, -10};
  c.lookat = {0, 0, 0};
  c.vfov = 30;
  const ThinLensCamera camera(c, 32, 32);
  const core::ImageRgb8 img = render_primary(scene, camera, {.width = 32, .height = 32, .threads = 1});
  EXPECT_EQ(img.pixels[0] + img.pixels[1] + img.pixels[2], 0);  // corner: sky
  const std::size_t centre = 3 * (16 * 32 + 16);
  EXPECT_GT(img.pixels[centre] + img.pixels[centre + 1] + img.pixels[centre + 2], 0);
  // Facing the camera: the normal is close to -z, so blue is low and red and green are near half.
  EXPECT_LT(img.pixels[centre + 2], 20);
  EXPECT_NEAR(img.pixels[centre], 127, 10);
}

}  // namespace tripsitter::render

namespace tripsitter::render {

TEST(Primary, FeatureBuffersAreTheCentreRaysFirstHits) {
  for (const char* name : {"cluster", "field"}) {
    const scene::Scene sc = *scene::builtin(name);
    const PathScene scene(sc.spheres);
    const int w = 37, h = 23;
    const ThinLensCamera camera(sc.camera, w, h);
    Aovs aovs;
    render_primary_aovs(scene, camera, {.width = w, .height = h, .threads = 2}, aovs);
    ASSERT_EQ(aovs.width, w);
    ASSERT_EQ(aovs.depth.size(), static_cast<std::size_t>(w * h));
    int hits = 0, misses = 0;
    for (int row = 0; row < h; ++row) {
      for (int col = 0; col < w; ++col) {
        const std::size_t i = static_cast<std::size_t>(row * w + col);
        const Ray ray = camera.centre_ray(col, row);
        SphereHit hit;
        if (!intersect_brute_force(scene.centers(), scene.radii(), ray, 0.0f, INFINITY, hit)) {
          ++misses;
          EXPECT_TRUE(std::isinf(aovs.depth[i]));
          EXPECT_EQ(aovs.normal[i], Vec3f(0, 0, 0));
          EXPECT_EQ(aovs.albedo[i], Vec3f(1, 1, 1));
          continue;
        }
        ++hits;
        const float distance = hit.t * core::length(ray.dir);
        EXPECT_NEAR(aovs.depth[i], distance, 1e-5f * distance) << name << " " << col << "," << row;
        EXPECT_EQ(aovs.albedo[i], scene.material(hit.sphere).albedo) << name << " " << col << "," << row;
        EXPECT_NEAR(core::length(aovs.normal[i]), 1.0f, 1e-4f);  // the ground sphere: radius 1000 in float
        EXPECT_LT(core::dot(aovs.normal[i], ray.dir), 0.0f);  // facing the camera
      }
    }
    EXPECT_GT(hits, 0) << name;
    EXPECT_GT(misses, 0) << name;
  }
}

}  // namespace tripsitter::render

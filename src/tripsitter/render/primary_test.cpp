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

scene::Sphere sphere(double z, scene::MaterialType type, const core::Vec3d& albedo) {
  return {{0, 0, z}, 1.0, {type, albedo, 0.0, 1.5}};
}

// The guides of the centre pixel of a 9x9 image, camera at the origin looking down -z.
struct CentreGuides {
  Aovs first_hits, guides;
  std::size_t centre = 4 * 9 + 4;
};

CentreGuides centre_guides(const std::vector<scene::Sphere>& spheres, const GuideSettings& guide = {}) {
  scene::CameraSettings c;
  c.lookfrom = {0, 0, 0};
  c.lookat = {0, 0, -1};
  const PathScene scene(spheres);
  CentreGuides out;
  render_primary_guides(scene, ThinLensCamera(c, 9, 9), {.width = 9, .height = 9, .threads = 1}, guide, out.first_hits,
                        out.guides);
  return out;
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

// A mirror 5 units ahead (radius 1) reflects the centre ray straight back, onto a sphere 5 units behind the eye:
// the guides show that sphere, 4 + 8 = 12 units along the chain, tinted by the mirror.
TEST(Primary, GuidesShowWhatAMirrorReflects) {
  using scene::MaterialType;
  const CentreGuides g = centre_guides({sphere(-5, MaterialType::kMetal, {0.8, 0.9, 1.0}),
                                        sphere(5, MaterialType::kLambertian, {0.9, 0.1, 0.2})});
  const std::size_t i = g.centre;
  EXPECT_NEAR(g.first_hits.depth[i], 4.0f, 1e-5f);
  EXPECT_EQ(g.first_hits.albedo[i], Vec3f(0.8f, 0.9f, 1.0f));
  EXPECT_NEAR(g.guides.depth[i], 12.0f, 1e-4f);
  EXPECT_NEAR(g.guides.albedo[i].x, 0.72f, 1e-6f);
  EXPECT_NEAR(g.guides.albedo[i].y, 0.09f, 1e-6f);
  EXPECT_NEAR(g.guides.albedo[i].z, 0.2f, 1e-6f);
  // The far sphere's normal at z = 4, facing the reflected ray (which travels towards +z).
  EXPECT_NEAR(g.guides.normal[i].z, -1.0f, 1e-5f);
  EXPECT_NEAR(g.guides.normal[i].x, 0.0f, 1e-5f);

  // Without the far sphere the mirror shows the sky: white times the mirror's tint, no normal, infinitely far.
  const CentreGuides sky = centre_guides({sphere(-5, MaterialType::kMetal, {0.8, 0.9, 1.0})});
  EXPECT_TRUE(std::isinf(sky.guides.depth[i]));
  EXPECT_EQ(sky.guides.normal[i], Vec3f(0, 0, 0));
  EXPECT_EQ(sky.guides.albedo[i], Vec3f(0.8f, 0.9f, 1.0f));

  // Lambertian and fuzzy metal are not mirrors: their guides are their first hits.
  for (const scene::Sphere& near : {sphere(-5, MaterialType::kLambertian, {0.8, 0.9, 1.0}),
                                    scene::Sphere{{0, 0, -5}, 1.0, {MaterialType::kMetal, {0.8, 0.9, 1.0}, 0.3, 1.5}}}) {
    const CentreGuides plain = centre_guides({near, sphere(5, MaterialType::kLambertian, {0.9, 0.1, 0.2})});
    EXPECT_EQ(plain.guides.depth[i], plain.first_hits.depth[i]);
    EXPECT_EQ(plain.guides.albedo[i], plain.first_hits.albedo[i]);
  }
}

// Two mirrors facing each other, the eye between them: the chain stops after max_bounces reflections, on the
// fifth mirror hit (4 + 4 x 8 units away), tinted by every mirror on the way.
TEST(Primary, GuidesFollowAtMostMaxBouncesMirrors) {
  using scene::MaterialType;
  const CentreGuides g = centre_guides({sphere(-5, MaterialType::kMetal, {0.5, 1.0, 1.0}),
                                        sphere(5, MaterialType::kMetal, {1.0, 0.5, 1.0})},
                                       {.max_fuzz = 0.1f, .max_bounces = 4});
  const std::size_t i = g.centre;
  EXPECT_NEAR(g.guides.depth[i], 36.0f, 1e-3f);
  EXPECT_NEAR(g.guides.albedo[i].x, 0.125f, 1e-6f);  // three hits of the first mirror
  EXPECT_NEAR(g.guides.albedo[i].y, 0.25f, 1e-6f);   // two of the second
  EXPECT_NEAR(g.guides.normal[i].z, 1.0f, 1e-5f);    // the first mirror again, facing the ray from +z
}

// On the built-in scenes: the first hits are render_primary_aovs's, the guides equal them wherever the first hit
// is not a mirror, differ on mirrors, and equal them everywhere when no surface counts as a mirror.
TEST(Primary, GuidesAreTheFirstHitsExceptOnMirrors) {
  for (const char* name : {"cluster", "field"}) {
    const scene::Scene sc = *scene::builtin(name);
    const PathScene scene(sc.spheres);
    const int w = 64, h = 36;
    const ThinLensCamera camera(sc.camera, w, h);
    const PrimarySettings settings{.width = w, .height = h, .threads = 2};
    Aovs aovs, first_hits, guides, none_hits, none;
    render_primary_aovs(scene, camera, settings, aovs);
    render_primary_guides(scene, camera, settings, {}, first_hits, guides);
    render_primary_guides(scene, camera, settings, {.max_fuzz = -1, .max_bounces = 4}, none_hits, none);
    EXPECT_EQ(first_hits.albedo, aovs.albedo);
    EXPECT_EQ(first_hits.normal, aovs.normal);
    EXPECT_EQ(first_hits.depth, aovs.depth);
    EXPECT_EQ(none.albedo, aovs.albedo);
    EXPECT_EQ(none.depth, aovs.depth);
    int mirrors = 0;
    for (int row = 0; row < h; ++row) {
      for (int col = 0; col < w; ++col) {
        const std::size_t i = static_cast<std::size_t>(row * w + col);
        SphereHit hit;
        const bool mirror = intersect_brute_force(scene.centers(), scene.radii(), camera.centre_ray(col, row), 0.0f,
                                                  INFINITY, hit) &&
                            scene.material(hit.sphere).type == scene::MaterialType::kMetal &&
                            scene.material(hit.sphere).fuzz <= 0.1f;
        if (!mirror) {
          EXPECT_EQ(guides.depth[i], aovs.depth[i]) << name << " " << col << "," << row;
          EXPECT_EQ(guides.albedo[i], aovs.albedo[i]) << name << " " << col << "," << row;
          continue;
        }
        ++mirrors;
        EXPECT_GT(guides.depth[i], aovs.depth[i]) << name << " " << col << "," << row;  // the chain goes on
      }
    }
    EXPECT_GT(mirrors, 20) << name;
  }
}

}  // namespace tripsitter::render

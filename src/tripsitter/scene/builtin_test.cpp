#include <tripsitter/scene/builtin.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace tripsitter::scene {
namespace {

using core::Vec3d;

bool Finite(const Vec3d& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The rules every scene loader enforces (docs/scene_format.md), checked on a scene built in code.
void ExpectValid(const Scene& s) {
  EXPECT_TRUE(Finite(s.camera.lookfrom) && Finite(s.camera.lookat) && Finite(s.camera.vup));
  EXPECT_GT(core::length(s.camera.lookat - s.camera.lookfrom), 0);
  const Vec3d forward = core::normalize(s.camera.lookat - s.camera.lookfrom);
  EXPECT_GT(core::length(core::cross(forward, core::normalize(s.camera.vup))), 1e-6);  // vup not along the view
  EXPECT_GT(s.camera.vfov, 0);
  EXPECT_LT(s.camera.vfov, 180);
  EXPECT_GE(s.camera.defocus_angle, 0);
  EXPECT_LT(s.camera.defocus_angle, 180);
  EXPECT_GT(s.camera.focus_dist, 0);
  EXPECT_GE(s.units_per_world, 0);
  EXPECT_TRUE(s.render.width >= 1 && s.render.width <= kMaxImageSide);
  EXPECT_TRUE(s.render.height >= 1 && s.render.height <= kMaxImageSide);
  EXPECT_TRUE(s.render.spp >= 1 && s.render.spp <= kMaxSpp);
  EXPECT_TRUE(s.render.max_depth >= 1 && s.render.max_depth <= kMaxDepth);
  EXPECT_LE(s.spheres.size(), kMaxSpheres);
  for (std::size_t i = 0; i < s.spheres.size(); ++i) {
    SCOPED_TRACE("sphere " + std::to_string(i));
    const Sphere& sp = s.spheres[i];
    EXPECT_TRUE(Finite(sp.center));
    EXPECT_GT(sp.radius, 0);
    EXPECT_TRUE(std::isfinite(sp.radius));
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(sp.material.albedo[c], 0);
      EXPECT_LE(sp.material.albedo[c], 1);
    }
    EXPECT_GE(sp.material.fuzz, 0);
    EXPECT_LE(sp.material.fuzz, 1);
    EXPECT_GT(sp.material.ior, 0);
  }
}

// The view direction's component of p - lookfrom: positive when p is in front of the camera.
double DepthInView(const Scene& s, const Vec3d& p) {
  return core::dot(p - s.camera.lookfrom, core::normalize(s.camera.lookat - s.camera.lookfrom));
}

bool SameSpheres(const Scene& a, const Scene& b) {
  if (a.spheres.size() != b.spheres.size()) return false;
  for (std::size_t i = 0; i < a.spheres.size(); ++i) {
    const Sphere &p = a.spheres[i], &q = b.spheres[i];
    if (!(p.center == q.center) || p.radius != q.radius || p.material.type != q.material.type ||
        !(p.material.albedo == q.material.albedo) || p.material.fuzz != q.material.fuzz ||
        p.material.ior != q.material.ior) {
      return false;
    }
  }
  return true;
}

TEST(Builtin, NamesInHelpOrder) { EXPECT_EQ(builtin_names(), (std::vector<std::string>{"demo", "cluster", "field"})); }

TEST(Builtin, EveryNameHasAValidSceneOfThatName) {
  for (const std::string& name : builtin_names()) {
    SCOPED_TRACE(name);
    const std::optional<Scene> s = builtin(name);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->name, name);
    EXPECT_FALSE(s->spheres.empty());
    ExpectValid(*s);
    for (const Sphere& sp : s->spheres) EXPECT_GT(DepthInView(*s, sp.center) + sp.radius, 0);
  }
}

TEST(Builtin, RandomFamilyByName) {
  const std::optional<Scene> s = builtin("random-100");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->spheres.size(), 100u);
  EXPECT_EQ(s->name, "random-100");
  EXPECT_EQ(builtin("random-0")->spheres.size(), 0u);
  EXPECT_FALSE(builtin("random-").has_value());
  EXPECT_FALSE(builtin("random-1x").has_value());
  EXPECT_FALSE(builtin("random-99999999").has_value());  // above the sphere limit
}

TEST(Builtin, UnknownNamesHaveNoScene) {
  EXPECT_FALSE(builtin("").has_value());
  EXPECT_FALSE(builtin("Demo").has_value());
  EXPECT_FALSE(builtin("demo ").has_value());
  EXPECT_FALSE(builtin("scenes/cluster.json").has_value());
}

TEST(Builtin, DemoIsTheBoardsSphere) {
  const Scene s = *builtin("demo");
  ASSERT_EQ(s.spheres.size(), 1u);
  EXPECT_EQ(s.units_per_world, 32);
  // In the device's view space (camera at the origin, 32 units per world unit): centre (0, 0, 400), radius 64.
  const Sphere& sp = s.spheres[0];
  EXPECT_DOUBLE_EQ((sp.center.z - s.camera.lookfrom.z) * s.units_per_world, 400);
  EXPECT_DOUBLE_EQ(sp.radius * s.units_per_world, 64);
  EXPECT_EQ(sp.center.x, s.camera.lookfrom.x);
  EXPECT_EQ(sp.center.y, s.camera.lookfrom.y);
  EXPECT_NEAR(s.camera.vfov, 2 * std::atan(240.0 / 320.0) * 180 / std::numbers::pi, 1e-9);
}

TEST(Builtin, ClusterHasEightOverlappingSpheres) {
  const Scene s = *builtin("cluster");
  ASSERT_EQ(s.spheres.size(), 8u);
  EXPECT_EQ(s.camera.lookfrom, (Vec3d{0, 1, -12}));
  EXPECT_EQ(s.camera.lookat, (Vec3d{0, 0, 0}));
  std::set<MaterialType> types;
  std::set<double> radii;
  int overlapping_pairs = 0;
  for (std::size_t i = 0; i < s.spheres.size(); ++i) {
    types.insert(s.spheres[i].material.type);
    radii.insert(s.spheres[i].radius);
    for (std::size_t j = i + 1; j < s.spheres.size(); ++j) {
      const double d = core::length(s.spheres[i].center - s.spheres[j].center);
      overlapping_pairs += d < s.spheres[i].radius + s.spheres[j].radius;
    }
  }
  EXPECT_EQ(types.size(), 3u);  // every material
  EXPECT_GE(radii.size(), 6u);
  EXPECT_GE(overlapping_pairs, 1);
}

TEST(RandomSpheres, CountAndValidity) {
  for (const int count : {0, 1, 7, 1000}) {
    SCOPED_TRACE(count);
    const Scene s = random_spheres(count, 12345);
    EXPECT_EQ(s.spheres.size(), static_cast<std::size_t>(count));
    ExpectValid(s);
    for (const Sphere& sp : s.spheres) EXPECT_GT(DepthInView(s, sp.center), 0);  // centres in front of the camera
  }
}

TEST(RandomSpheres, DeterministicInTheSeed) {
  const Scene a = random_spheres(500, 42);
  const Scene b = random_spheres(500, 42);
  EXPECT_TRUE(SameSpheres(a, b));
  EXPECT_EQ(a.name, b.name);
  EXPECT_FALSE(SameSpheres(a, random_spheres(500, 43)));
  // Up to 64 spheres, a longer list starts with the shorter one: sphere i depends only on the seed and i
  // (past 64 the radii shrink with the count).
  const Scene c = random_spheres(30, 42);
  Scene prefix = random_spheres(64, 42);
  prefix.spheres.resize(30);
  EXPECT_TRUE(SameSpheres(prefix, c));
  EXPECT_LT(a.spheres[0].radius, prefix.spheres[0].radius);
}

TEST(RandomSpheres, UsesEveryMaterial) {
  const Scene s = random_spheres(1000, 1);
  std::set<MaterialType> types;
  for (const Sphere& sp : s.spheres) types.insert(sp.material.type);
  EXPECT_EQ(types.size(), 3u);
}

TEST(Builtin, FieldIsTheCoverLayoutOf488Spheres) {
  const Scene s = *builtin("field");
  ASSERT_EQ(s.spheres.size(), 488u);
  EXPECT_DOUBLE_EQ(s.spheres[0].radius, 1000.0);  // the ground
  int kinds[3] = {0, 0, 0};
  for (const auto& sphere : s.spheres) ++kinds[static_cast<int>(sphere.material.type)];
  EXPECT_GT(kinds[0], 300);  // mostly matte
  EXPECT_GT(kinds[1], 20);
  EXPECT_GT(kinds[2], 5);
  EXPECT_EQ(s.render.width, 640);
  EXPECT_EQ(s.render.height, 360);
}

}  // namespace
}  // namespace tripsitter::scene

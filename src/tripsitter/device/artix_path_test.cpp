// The artix path preset's per-sample function (artix_path.h): its geometry against the units' (far roots, the
// normal there, the hit point), its directions, and its samples against the path preset's on the same draws.
#include <tripsitter/device/artix_path.h>

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/device/artix_units.h>
#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/test_util.h>

namespace tripsitter::device::artix {
namespace {

constexpr std::int64_t kUnit = std::int64_t{1} << 4;  // the artix formats' fractional bits

UnitSphere sphere_at(std::int64_t x, std::int64_t y, std::int64_t z, std::int64_t r) {
  return prepare_sphere({{x * kUnit, y * kUnit, z * kUnit}, r * kUnit}, core::KernelSurface{});
}

double length(const Vec3i& v) {
  return std::sqrt(static_cast<double>(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])) / (1 << kDirectionFrac);
}

// A ray through a sphere's centre: in at the near root, out at the far root 2r further; the far root's normal
// points out of the sphere there, the near root's back at the ray.
TEST(ArtixPath, TheFarRootIsTheExitAndItsNormalPointsOut) {
  const UnitSphere s = sphere_at(0, 0, 1000, 200);
  const UnitRay ray{{}, camera_direction(320, 240)};  // (0, 0, 320) normalised: straight ahead
  const Quadratic q = quadratic(ray, s);
  ASSERT_TRUE(q.hit());
  const std::int64_t far = far_td(ray, s);
  EXPECT_NEAR(static_cast<double>(q.td) / (1 << kDirectionFrac), 800.0 * kUnit, 2.0);
  EXPECT_NEAR(static_cast<double>(far) / (1 << kDirectionFrac), 1200.0 * kUnit, 2.0);
  // The camera's direction here is (0, 0, 2^17 - 1), a unit short of 1, and the units' f = oc - b d takes up what
  // that leaves: the normals are within 2^-10 of -z and +z.
  const Vec3i near_n = normal(ray, s), far_n = normal(ray, s, true);
  EXPECT_LT(near_n[2], -(std::int64_t{1} << kDirectionFrac) + 128);  // -z: facing the camera
  EXPECT_GT(far_n[2], (std::int64_t{1} << kDirectionFrac) - 128);    // +z: out through the back
  EXPECT_LT(std::abs(far_n[0]) + std::abs(far_n[1]), 128);
  const Vec3i exit = hit_point(ray, far);
  EXPECT_NEAR(static_cast<double>(exit[2]), 1200.0 * kUnit, 1.0);
  EXPECT_EQ(far_td(UnitRay{{}, camera_direction(0, 0)}, s), -1);  // the corner's ray misses it
}

// A ray that went into a sphere meets its far side unless another sphere inside is nearer; one that did not go in
// never sees the sphere it leaves.
TEST(ArtixPath, ARayInsideItsSphereHitsTheFarSide) {
  const std::vector<UnitSphere> spheres{sphere_at(0, 0, 1000, 200), sphere_at(0, 0, 1100, 20)};
  const UnitRay camera{{}, camera_direction(320, 240)};
  const std::int64_t in_td = quadratic(camera, spheres[0]).td;
  const PathUnitRay inside{{hit_point(camera, in_td), camera.d}, 0, true};
  const PathUnitHit small = with_far_side(inside, closest_hit(inside.ray, spheres, 0), spheres);
  EXPECT_EQ(small.index, 1);  // the small sphere at 1080..1120 comes before the exit at 1200
  EXPECT_FALSE(small.inside);
  const std::vector<UnitSphere> alone{spheres[0]};
  const PathUnitHit exit = with_far_side(inside, closest_hit(inside.ray, alone, 0), alone);
  EXPECT_EQ(exit.index, 0);
  EXPECT_TRUE(exit.inside);
  EXPECT_NEAR(static_cast<double>(exit.td) / (1 << kDirectionFrac), 400.0 * kUnit, 2.0);
  const PathUnitRay outside{inside.ray, 0, false};
  EXPECT_EQ(with_far_side(outside, closest_hit(outside.ray, alone, 0), alone).index, -1);
}

// Scattered directions normalised to the units' 2^17: each component within 4 units of 2^-17 (`tripsitter approx`
// measures the worst at 3.85), and the path preset's 14-bit unit vectors unchanged by the wider option.
TEST(ArtixPath, DirectionsAreUnitVectorsAtTheUnitsWidth) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<std::int64_t> component(-30000, 30000);
  for (int i = 0; i < 20000; ++i) {
    const approx::Unit3 v{component(rng), component(rng), component(rng)};
    if (core::dot(v, v) < 64) continue;
    const Vec3i d = unit_direction(v);
    const double norm = std::sqrt(static_cast<double>(core::dot(v, v)));
    for (std::size_t k = 0; k < 3; ++k)
      ASSERT_NEAR(static_cast<double>(d[k]), static_cast<double>(v[static_cast<int>(k)]) / norm * (1 << kDirectionFrac),
                  4.0)
          << v.x << " " << v.y << " " << v.z;
    ASSERT_NEAR(length(d), 1.0, 6.0 / (1 << kDirectionFrac));
  }
  EXPECT_EQ(approx::unit({3, 4, 0}), (approx::Unit3{9830, 13107, 0}));  // 0.6, 0.8 at 2^14
}

// The same pixels, the same random streams: the artix path preset's samples against the path preset's (its wider
// geometry, num = t 2a over integer directions), on random worlds of every material with spheres in view (not the
// formats' extremes, where each side's roots are approximate in their own way: a sphere of radius 2^21 - 1 that
// grazes the camera is hit by one side's root and missed by the other's). The bounces follow the same rules and
// draws, so every sample takes the same path (the same bounces off the same materials) and comes to the same light
// within 2^-9; measured: 4,800 samples, 1,874 of them bouncing, 597 off a dielectric, the worst difference 66 of
// 65,536.
TEST(ArtixPath, SamplesFollowThePathPresetsOnTheSameDraws) {
  const DevicePreset artix = artix_preset();
  const DevicePreset wide = path_preset();
  const FixedArith arith{SqrtUnit(wide.sqrt_iterations), FixedArith::extra_bits_of(wide)};
  std::mt19937_64 rng(11);
  std::uint64_t samples = 0, bounced = 0, same_path = 0, dielectric = 0;
  std::int64_t worst = 0;
  double sum_artix = 0, sum_path = 0;
  for (int w = 0; w < 12; ++w) {
    const SceneMemory scene = testing::random_path_world(artix, rng, 0);
    const UnitWorld world = prepare_world(scene);
    std::vector<PathSurface> surfaces;
    for (const SurfaceWord& s : scene.surfaces) surfaces.push_back(path_surface(s));
    const std::span<const core::KernelSphere<std::int64_t>> geometry(scene.geometry);
    const auto path_closest = [&](const PathRay& path) {
      return with_far_side(arith, path, core::closest_hit(arith, path.ray, geometry, path.from), geometry);
    };
    for (int k = 0; k < 400; ++k) {
      const int col = static_cast<int>(rng() % 640), row = static_cast<int>(rng() % 480);
      const auto pixel = static_cast<std::uint32_t>(row * 640 + col);
      PathCounters ca, cp;
      PathRng ra = PathRng::for_sample(pixel, 3), rp = PathRng::for_sample(pixel, 3);
      const PathSample a = trace_path_sample(col, row, world.spheres, surfaces, 4, ra, ca);
      const PathSample p = device::trace_path_sample(arith, device_ray(col, row), geometry, surfaces, 4, rp, cp,
                                                     path_closest);
      ++samples;
      bounced += p.rays > 1;
      dielectric += p.bounces.dielectric > 0;
      same_path += a.rays == p.rays && a.bounces.lambertian == p.bounces.lambertian &&
                   a.bounces.metal == p.bounces.metal && a.bounces.dielectric == p.bounces.dielectric;
      for (std::size_t c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(a.light[c] - p.light[c]));
        sum_artix += static_cast<double>(a.light[c]);
        sum_path += static_cast<double>(p.light[c]);
      }
    }
  }
  EXPECT_GT(bounced, samples / 4);
  EXPECT_GT(dielectric, samples / 20);
  EXPECT_EQ(same_path, samples);
  EXPECT_LE(worst, 128);
  EXPECT_NEAR(sum_artix / sum_path, 1.0, 1e-4);
}

}  // namespace
}  // namespace tripsitter::device::artix

namespace tripsitter::device::artix {
namespace {

// A ray from anywhere in the world's formats: every other from a point on sphere `from` (a bounce's origin), the
// others from anywhere; every fourth grazing a sphere's rim; directions at random.
UnitRay random_ray(std::mt19937_64& rng, std::span<const UnitSphere> spheres, int from, int k) {
  std::uniform_int_distribution<std::int64_t> coordinate(-(std::int64_t{1} << 21) + 1, (std::int64_t{1} << 21) - 1);
  std::uniform_int_distribution<std::int64_t> component(-30000, 30000);
  UnitRay ray;
  if (from >= 0 && k % 2 == 0) {
    ray.o = testing::point_on(spheres[static_cast<std::size_t>(from)], rng);
  } else {
    ray.o = {coordinate(rng), coordinate(rng), coordinate(rng)};
  }
  approx::Unit3 v{component(rng), component(rng), component(rng)};
  if (from >= 0 && k % 4 == 1) {  // grazing a sphere's rim: towards c + r w, w across the line of sight
    const UnitSphere& s = spheres[static_cast<std::size_t>(rng() % spheres.size())];
    const double sx = static_cast<double>(s.c[0] - ray.o[0]), sy = static_cast<double>(s.c[1] - ray.o[1]),
                 sz = static_cast<double>(s.c[2] - ray.o[2]);
    const double wx = -sy, wy = sx, norm = std::hypot(wx, wy) + 1e-9;
    const double r = static_cast<double>(s.r) + static_cast<double>(static_cast<int>(rng() % 9) - 4);
    const double tx = sx + r * wx / norm, ty = sy + r * wy / norm, tz = sz, len = std::sqrt(tx * tx + ty * ty + tz * tz);
    if (len > 0) v = {std::llround(tx / len * 16384), std::llround(ty / len * 16384), std::llround(tz / len * 16384)};
  }
  if (core::dot(v, v) < 64) v = {0, 0, 1000};
  ray.d = unit_direction(v);
  return ray;
}

// The fast model's search through the balls finds the plain search's hit, for rays from anywhere in the world's
// formats on random worlds of every kind (in view, behind, around the camera, huge, tiny, at the formats' limits).
TEST(ArtixPath, TheBallsFindThePlainSearchsHit) {
  std::mt19937_64 rng(19);
  const DevicePreset p = artix_path_preset();
  int hits = 0, rays = 0;
  for (int w = 0; w < 60; ++w) {
    const SceneMemory scene = testing::random_path_world(p, rng, 40);
    UnitWorld world = prepare_world(scene);
    world.balls = build_balls(world.spheres);
    for (int k = 0; k < 2000; ++k) {
      const int from = world.spheres.empty() ? -1 : static_cast<int>(rng() % world.spheres.size());
      const UnitRay ray = random_ray(rng, world.spheres, from, k);
      const int excluded = k % 3 == 0 ? -1 : from;
      const Hit want = closest_hit(ray, world.spheres, excluded);
      const Hit got = closest_hit(ray, world.spheres, world.balls, excluded);
      ASSERT_EQ(got.index, want.index) << "world " << w << " ray " << k;
      ASSERT_EQ(got.td, want.td) << "world " << w << " ray " << k;
      hits += want.index >= 0;
      ++rays;
    }
  }
  EXPECT_GT(hits, rays / 10);
}

// The walk of the hierarchy the host sends finds the plain search's hit on the same worlds and rays, so its bounds
// hold everything the units can hit (their margin is enough), and it tests fewer pairs than the plain search.
TEST(ArtixPath, TheHierarchysWalkFindsThePlainSearchsHit) {
  std::mt19937_64 rng(20);
  const DevicePreset p = artix_path_preset();
  int hits = 0, rays = 0, walked_worlds = 0;
  std::int64_t walked = 0, plain = 0;
  for (int w = 0; w < 60; ++w) {
    const SceneMemory scene = testing::with_hierarchy(p, testing::random_path_world(p, rng, 40));
    if (scene.hierarchy.empty()) continue;
    ++walked_worlds;
    const UnitWorld world = prepare_world(scene);
    std::vector<int> passes;
    for (int k = 0; k < 2000; ++k) {
      const int from = static_cast<int>(rng() % world.spheres.size());
      const UnitRay ray = random_ray(rng, world.spheres, from, k);
      const int excluded = k % 3 == 0 ? -1 : from;
      const Hit want = closest_hit(ray, world.spheres, excluded);
      passes.clear();
      const Hit got = walk_closest_hit(ray, world, excluded, passes);
      ASSERT_EQ(got.index, want.index) << "world " << w << " ray " << k;
      ASSERT_EQ(got.td, want.td) << "world " << w << " ray " << k;
      ASSERT_FALSE(passes.empty());
      ASSERT_LE(static_cast<int>(passes.size()), 2) << "the host's hierarchy has two levels";
      for (const int n : passes) walked += n;
      plain += static_cast<std::int64_t>(world.spheres.size());
      hits += want.index >= 0;
      ++rays;
    }
  }
  EXPECT_GT(walked_worlds, 40);
  EXPECT_GT(hits, rays / 10);
  EXPECT_LT(walked, plain * 3 / 4) << "the walk tests " << walked << " pairs where the plain search tests " << plain;
}

}  // namespace
}  // namespace tripsitter::device::artix

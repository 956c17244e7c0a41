// The SIMD kernel (sphere_lanes.h) included here, in a test compiled for baseline x86-64, against the scalar
// kernel compiled into the render library (for x86-64-v3 where the build does so): both instruction sets' code in
// one program, as isa.h allows, giving the same t bit for bit and the same closest hits as brute force.
#include <tripsitter/render/bvh.h>
#include <tripsitter/render/sphere_lanes.h>
#include <tripsitter/render/test_util.h>

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace tripsitter::render {
namespace {

using simd::F8;
using testing::kInf;
using testing::uniform;
using testing::uniform_in_box;

constexpr int kLanes = 8;

// The lanes round as the scalar kernel only without fused multiply-adds; this file is compiled without
// -ffp-contract=off, so the comparison needs a target without FMA (the tests are built for baseline x86-64).
#if defined(__FMA__)
constexpr bool kMayFuse = true;
#else
constexpr bool kMayFuse = false;
#endif

// Small spheres near the origin, huge ones far away (as ground planes), and some exact copies for ties.
struct World {
  std::vector<Vec3f> centers;
  std::vector<float> radii;
};

World random_world(std::mt19937& rng, int count) {
  World w;
  for (int i = 0; i < count; ++i) {
    if (i % 7 == 6) {
      const auto copy = static_cast<std::size_t>(rng() % w.centers.size());
      w.centers.push_back(w.centers[copy]);
      w.radii.push_back(w.radii[copy]);
    } else if (i % 11 == 10) {
      w.centers.push_back({uniform(rng, -10, 10), -1000.5f, uniform(rng, -10, 10)});
      w.radii.push_back(1000.0f);
    } else {
      w.centers.push_back(uniform_in_box(rng, -5, 5));
      w.radii.push_back(uniform(rng, 0.05f, 2.0f));
    }
  }
  return w;
}

// A ray towards `target`, from anywhere around the spheres, with a direction of any length.
Ray ray_towards(std::mt19937& rng, const Vec3f& target) {
  const Vec3f origin = uniform_in_box(rng, -12, 12);
  return {origin, (target - origin) * uniform(rng, 0.1f, 10.0f)};
}

// One ray against eight spheres, one per lane, as a BVH leaf tests them.
TEST(SphereLanes, OneRayEightSpheresGiveTheScalarKernelsBits) {
  if (kMayFuse) GTEST_SKIP() << "compiled with FMA: lanes may round differently from the scalar kernel";
  std::mt19937 rng(20240611);
  int hits = 0;
  for (int round = 0; round < 2000; ++round) {
    const World w = random_world(rng, kLanes);
    // Aimed near one of the small spheres, so that most rounds hit something.
    const Ray ray = ray_towards(rng, w.centers[round % 6] + uniform_in_box(rng, -1, 1) * w.radii[round % 6]);
    const float t_min = round % 3 == 0 ? 0.5f : 0.0f;
    alignas(32) float cx[kLanes], cy[kLanes], cz[kLanes], r2[kLanes];
    for (int k = 0; k < kLanes; ++k) {
      cx[k] = w.centers[k].x;
      cy[k] = w.centers[k].y;
      cz[k] = w.centers[k].z;
      r2[k] = w.radii[k] * w.radii[k];
    }
    const float a = dot(ray.dir, ray.dir);
    const simd::LaneRoots roots = sphere_lanes(
        F8::set1(ray.origin.x) - F8::load(cx), F8::set1(ray.origin.y) - F8::load(cy),
        F8::set1(ray.origin.z) - F8::load(cz), F8::set1(ray.dir.x), F8::set1(ray.dir.y), F8::set1(ray.dir.z),
        F8::set1(a), F8::set1(1.0f / a), F8::load(r2), F8::set1(t_min));
    alignas(32) float t[kLanes];
    roots.t.store(t);
    const int mask = roots.hit.bits();
    for (int k = 0; k < kLanes; ++k) {
      float scalar_t = 0;
      const bool scalar = intersect_sphere(ray, w.centers[k], w.radii[k], t_min, kInf, scalar_t);
      ASSERT_EQ(scalar, (mask >> k & 1) != 0) << "round " << round << " lane " << k;
      if (!scalar) continue;
      ++hits;
      EXPECT_EQ(std::bit_cast<std::uint32_t>(scalar_t), std::bit_cast<std::uint32_t>(t[k]))
          << "round " << round << " lane " << k;
    }
  }
  EXPECT_GT(hits, 1000);  // the rounds exercise hits, not only misses
}

// Eight rays, one per lane, against every sphere in index order, as primary.cpp's tiles and packets do: the
// closest hits (keep_nearest) are brute force's, ties to the lower index included.
TEST(SphereLanes, EightRaysKeepBruteForcesClosestHits) {
  if (kMayFuse) GTEST_SKIP() << "compiled with FMA: lanes may round differently from the scalar kernel";
  std::mt19937 rng(7);
  int hits = 0;
  for (int round = 0; round < 200; ++round) {
    const World w = random_world(rng, 40);
    Ray rays[kLanes];
    alignas(32) float ox[kLanes], oy[kLanes], oz[kLanes], dx[kLanes], dy[kLanes], dz[kLanes], a[kLanes],
        inv_a[kLanes];
    for (int k = 0; k < kLanes; ++k) {
      rays[k] = ray_towards(rng, uniform_in_box(rng, -5, 5));  // into the cloud of spheres
      ox[k] = rays[k].origin.x;
      oy[k] = rays[k].origin.y;
      oz[k] = rays[k].origin.z;
      dx[k] = rays[k].dir.x;
      dy[k] = rays[k].dir.y;
      dz[k] = rays[k].dir.z;
      a[k] = dot(rays[k].dir, rays[k].dir);
      inv_a[k] = 1.0f / a[k];
    }
    alignas(32) float best_t[kLanes], best_id[kLanes] = {};
    F8::set1(kInf).store(best_t);
    int found = 0;
    for (std::size_t i = 0; i < w.centers.size(); ++i) {
      const Vec3f& c = w.centers[i];
      const simd::LaneRoots roots =
          sphere_lanes(F8::load(ox) - F8::set1(c.x), F8::load(oy) - F8::set1(c.y), F8::load(oz) - F8::set1(c.z),
                       F8::load(dx), F8::load(dy), F8::load(dz), F8::load(a), F8::load(inv_a),
                       F8::set1(w.radii[i] * w.radii[i]), F8::set1(0.0f));
      found |= keep_nearest(roots.hit, roots.t, static_cast<std::uint32_t>(i), best_t, best_id);
    }
    for (int k = 0; k < kLanes; ++k) {
      SphereHit hit;
      const bool brute = intersect_brute_force(w.centers, w.radii, rays[k], 0.0f, kInf, hit);
      ASSERT_EQ(brute, (found >> k & 1) != 0) << "round " << round << " lane " << k;
      if (!brute) continue;
      ++hits;
      EXPECT_EQ(hit.sphere, std::bit_cast<std::uint32_t>(best_id[k])) << "round " << round << " lane " << k;
      EXPECT_EQ(std::bit_cast<std::uint32_t>(hit.t), std::bit_cast<std::uint32_t>(best_t[k]))
          << "round " << round << " lane " << k;
    }
  }
  EXPECT_GT(hits, 800);
}

}  // namespace
}  // namespace tripsitter::render

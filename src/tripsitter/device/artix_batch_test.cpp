// The fast model's filter (artix_batch.h) against the sphere units' integer arithmetic (artix_kernel.h), entry by
// entry, on random worlds and rays and on the pairs at the edge of the units' 18-bit F; and the units' square root
// and bound test, which the filter's callers take inline (artix_kernel.h), against the integer square root and the
// far root.
#include <tripsitter/device/artix_batch.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/core/isqrt.h>
#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/artix_units.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/test_util.h>

namespace tripsitter::device::artix {
namespace {

// A ray in the world's formats: from the camera along a pixel's direction, from a point on a sphere, or from
// anywhere; aimed at random, at a sphere's centre, or grazing its rim.
UnitRay random_ray(std::mt19937_64& rng, std::span<const UnitSphere> spheres) {
  std::uniform_int_distribution<std::int64_t> coordinate(-(std::int64_t{1} << 21) + 1, (std::int64_t{1} << 21) - 1);
  std::uniform_int_distribution<std::int64_t> component(-30000, 30000);
  UnitRay ray;
  const int kind = static_cast<int>(rng() % 4);
  if (kind == 0 || spheres.empty()) {
    return {{}, camera_direction(static_cast<int>(rng() % 640), static_cast<int>(rng() % 480))};
  }
  if (kind == 1) {
    ray.o = testing::point_on(spheres[rng() % spheres.size()], rng);
  } else {
    ray.o = {coordinate(rng), coordinate(rng), coordinate(rng)};
  }
  approx::Unit3 v{component(rng), component(rng), component(rng)};
  const UnitSphere& s = spheres[rng() % spheres.size()];
  const double sx = static_cast<double>(s.c[0] - ray.o[0]), sy = static_cast<double>(s.c[1] - ray.o[1]),
               sz = static_cast<double>(s.c[2] - ray.o[2]);
  const auto aim = [&](double tx, double ty, double tz) {
    const double len = std::sqrt(tx * tx + ty * ty + tz * tz);
    if (len > 0) v = {std::llround(tx / len * 16384), std::llround(ty / len * 16384), std::llround(tz / len * 16384)};
  };
  if (rng() % 3 == 0) {
    aim(sx, sy, sz);
  } else if (rng() % 2 == 0) {  // the rim: towards c + r w, w across the line of sight
    const double wx = -sy, wy = sx, norm = std::hypot(wx, wy) + 1e-9;
    const double r = static_cast<double>(s.r) + static_cast<double>(static_cast<int>(rng() % 9) - 4);
    aim(sx + r * wx / norm, sy + r * wy / norm, sz);
  }
  if (core::dot(v, v) < 64) v = {0, 0, 1000};
  ray.d = unit_direction(v);
  return ray;
}

// Spheres at the edge of F's 18 bits for the ray from the origin along +z: F = (x, 0, 0) with |x| = 2^17 - 1 (the
// largest the units keep: with r = 2^17 - 1, disc = 0) and 2^17 (saturated: a miss), and r one less.
std::vector<UnitSphere> edge_spheres() {
  std::vector<UnitSphere> out;
  for (const std::int64_t x : {(std::int64_t{1} << 17) - 1, std::int64_t{1} << 17})
    for (const std::int64_t sign : {1, -1})
      for (const std::int64_t r : {(std::int64_t{1} << 17) - 1, (std::int64_t{1} << 17) - 2})
        out.push_back(prepare_sphere({{sign * x, 0, 1000}, r}, core::KernelSurface{}));
  return out;
}

// The filter over block entries first .. first + n - 1 against the units' arithmetic, with the units' square root
// and far root on the way.
void expect_filter_is_the_units(const UnitRay& ray, std::span<const UnitSphere> spheres, const SphereBlock& block,
                                std::size_t first, std::size_t n, int& meets) {
  std::vector<std::uint8_t> bytes(meets_room(n));
  meets_line(ray, block, first, n, bytes.data());
  for (std::size_t j = 0; j < n; ++j) {
    const UnitSphere& s = spheres[first + j];
    const Quadratic q = quadratic(ray, s);
    ASSERT_EQ(bytes[j] != 0, q.disc >= 0) << "entry " << first + j;
    meets += q.disc >= 0;
    if (q.disc >= 0) {
      ASSERT_EQ(q.s, static_cast<std::int64_t>(core::isqrt(static_cast<std::uint64_t>(q.disc))));
    }
    ASSERT_EQ(enters(ray, s), far_td(ray, s) > 0) << "entry " << first + j;
  }
}

TEST(ArtixBatch, TheBlocksAreTheUnitsArithmeticOnRandomWorlds) {
  std::mt19937_64 rng(41);
  const DevicePreset p = artix_path_preset();
  int meets = 0, queries = 0;
  for (int w = 0; w < 60; ++w) {
    const SceneMemory scene = testing::with_hierarchy(p, testing::random_path_world(p, rng, 40));
    const UnitWorld world = prepare_world(scene);
    // The spheres, and the hierarchy's bounds (radii up to 2^21: the widest scales), built whole and entry by entry.
    std::vector<UnitSphere> entries = world.spheres;
    for (std::size_t i = 1; i < world.nodes.size(); ++i) entries.push_back(world.nodes[i].bound);
    const SphereBlock whole(entries);
    SphereBlock grown;
    for (const UnitSphere& s : entries) grown.push_back(s);
    ASSERT_EQ(whole.size(), entries.size());
    ASSERT_EQ(grown.size(), entries.size());
    for (int k = 0; k < 1500; ++k) {
      const UnitRay ray = random_ray(rng, entries);
      // A run anywhere in the block, so that a run's last vector holds entries past it.
      const std::size_t first = rng() % entries.size();
      const std::size_t n = k % 4 == 0 ? entries.size() - first : rng() % (entries.size() - first + 1);
      expect_filter_is_the_units(ray, entries, k % 2 == 0 ? whole : grown, first, n, meets);
      if (::testing::Test::HasFatalFailure()) {
        ADD_FAILURE() << "world " << w << " ray " << k << " first " << first << " n " << n;
        return;
      }
      ++queries;
    }
  }
  EXPECT_GT(meets, queries);
  std::printf("%d queries, %d entries met\n", queries, meets);
}

TEST(ArtixBatch, TheEdgeOfTheUnitsFIsKept) {
  const std::vector<UnitSphere> spheres = edge_spheres();
  const SphereBlock block(spheres);
  const UnitRay ray{{}, {0, 0, kDirectionMax}};
  int meets = 0;
  expect_filter_is_the_units(ray, spheres, block, 0, spheres.size(), meets);
  EXPECT_EQ(meets, 2) << "F = 2^17 - 1 with r = 2^17 - 1 on either side, disc 0";
  for (std::size_t j = 0; j < spheres.size(); ++j) expect_filter_is_the_units(ray, spheres, block, j, 1, meets);
}

// The units' square root (artix::kernel_detail::root_of, in doubles) is core::isqrt on every disc a pair can have
// (below 2^34), checked at and around every square.
TEST(ArtixBatch, TheSquareRootIsTheIntegerOne) {
  const auto root = [](std::int64_t v) {
    Quadratic q;
    q.disc = v;
    return kernel_detail::root_of(q);
  };
  for (std::int64_t k = 0; k <= std::int64_t{1} << 17; ++k) {
    for (const std::int64_t v : {k * k - 1, k * k, k * k + 1, k * k + k, k * k + 2 * k}) {
      if (v < 0 || v >= std::int64_t{1} << 34) continue;
      ASSERT_EQ(root(v), static_cast<std::int64_t>(core::isqrt(static_cast<std::uint64_t>(v)))) << v;
    }
  }
}

}  // namespace
}  // namespace tripsitter::device::artix

// The fixed-point invariant checks (worker.h, TRIPSITTER_CHECK_FIXED): none fires on valid worlds, even at
// the formats' limits with every bounce; each fires on a world that breaks its bound. Without the checks
// compiled in (Release builds), the tests that need a check to fire are skipped.
#include <tripsitter/device/worker.h>

#include <array>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/device/controller.h>
#include <tripsitter/device/fast_tracer.h>

#include "test_util.h"

namespace tripsitter::device {
namespace {

using core::Int128;
using testing::random_world;
using testing::wide_32_preset;
using testing::with_bounces;

// Worlds at the formats' limits: a giant around the camera and the largest, farthest spheres the formats
// hold, every one a mirror, six bounces.
SceneMemory limit_world(const DevicePreset& p, std::mt19937_64& rng) {
  std::uniform_int_distribution<std::int64_t> x(p.x.min_raw(), p.x.max_raw()), y(p.y.min_raw(), p.y.max_raw()),
      z(p.z.min_raw(), p.z.max_raw()), radius(1, p.radius.max_raw());
  SceneMemory m;
  m.valid = true;
  m.geometry.push_back({{0, 0, p.z.max_raw() / 2}, p.radius.max_raw()});
  for (int i = 0; i < 12; ++i) m.geometry.push_back({{x(rng), y(rng), z(rng)}, radius(rng)});
  m.surfaces.assign(m.geometry.size(), SurfaceWord{link::kMaterialMetal, {255, 255, 255}, 0, 6144});
  return m;
}

TEST(FixedChecks, NoneFiresOnValidWorlds) {
  // Without the checks compiled in nothing could fire, and the test could not fail.
  if (!kCheckFixed) GTEST_SKIP() << "built without TRIPSITTER_CHECK_FIXED";
  std::mt19937_64 rng(8);
  for (const DevicePreset& p : {with_bounces(wide_preset(), core::kMaxBounces), board_2023_preset(),
                                with_bounces(board_2023_preset(), 2), with_bounces(wide_32_preset(), core::kMaxBounces)}) {
    const Worker worker(p);
    FastTracer fast(p);
    for (int world = 0; world < 12; ++world) {
      const SceneMemory scene = world % 2 == 0 ? limit_world(p, rng) : random_world(p, rng);
      EXPECT_NO_THROW(fast.load(scene)) << p.name;
      for (int i = 0; i < 400; ++i) {
        const int col = static_cast<int>(rng() % 640), row = static_cast<int>(rng() % 480);
        ASSERT_NO_THROW(worker.trace(col, row, scene)) << p.name << " world " << world << " " << col << "," << row;
      }
      std::array<core::Rgb444, kLineWidth> line;
      ASSERT_NO_THROW(fast.render_line(static_cast<int>(rng() % 480), line)) << p.name << " world " << world;
    }
  }
}

TEST(FixedChecks, EachBoundIsTheDocumentedWidth) {
  if (!kCheckFixed) GTEST_SKIP() << "built without TRIPSITTER_CHECK_FIXED";
  const FixedArith wide{SqrtUnit(16), FixedArith::extra_bits_of(wide_preset())};
  EXPECT_NO_THROW(wide.check((Int128{1} << 95) - 1, core::Width::kSquare));
  EXPECT_THROW(wide.check(Int128{1} << 95, core::Width::kSquare), core::FixedPointOverflow);
  EXPECT_THROW(wide.check(-(Int128{1} << 95), core::Width::kSquare), core::FixedPointOverflow);
  EXPECT_NO_THROW(wide.check(Int128{1} << 20, core::Width::kDirection));
  EXPECT_THROW(wide.check(Int128{1} << 21, core::Width::kDirection), core::FixedPointOverflow);
  EXPECT_THROW(wide.check(0, core::Width::kShadeDen), core::FixedPointOverflow);
  EXPECT_THROW(wide.check(0, core::Width::kRadius), core::FixedPointOverflow);
  // 32-bit formats: 8 more bits per length, 16 more for a product of two.
  const FixedArith wide_32{SqrtUnit(16), FixedArith::extra_bits_of(wide_32_preset())};
  EXPECT_EQ(wide_32.extra_bits, 8);
  EXPECT_NO_THROW(wide_32.check((Int128{1} << 111) - 1, core::Width::kSquare));
  EXPECT_THROW(wide_32.check(Int128{1} << 111, core::Width::kSquare), core::FixedPointOverflow);
}

// A world scene memory can never hold (the receiver rejects it), each breaking one bound, and the check
// that catches it in the plain worker and in the fast model.
TEST(FixedChecks, FireOnWorldsBeyondTheFormats) {
  if (!kCheckFixed) GTEST_SKIP() << "built without TRIPSITTER_CHECK_FIXED";
  const DevicePreset p = wide_preset();
  const Worker worker(p);
  FastTracer fast(p);
  const auto world = [](core::KernelSphere<std::int64_t> s) {
    SceneMemory m;
    m.valid = true;
    m.geometry.push_back(s);
    m.surfaces.push_back({link::kMaterialMetal, {255, 255, 255}, 0, 6144});
    return m;
  };
  // A centre beyond s24.4: 2^30 raw units.
  const SceneMemory far = world({{std::int64_t{1} << 30, 0, 6400}, 1024});
  EXPECT_THROW(worker.trace(320, 240, far), core::FixedPointOverflow);
  EXPECT_THROW(fast.load(far), core::FixedPointOverflow);
  // A radius beyond u24.4.
  const SceneMemory huge = world({{0, 0, 6400}, std::int64_t{1} << 26});
  EXPECT_THROW(worker.trace(320, 240, huge), core::FixedPointOverflow);
  EXPECT_THROW(fast.load(huge), core::FixedPointOverflow);
  // A radius of 0 on a pixel's ray: the shading would divide by den = 2ar = 0.
  const SceneMemory point = world({{-220 * 16, -200 * 16, 320 * 16}, 0});
  EXPECT_THROW(worker.trace(100, 40, point), core::FixedPointOverflow);
  EXPECT_THROW(fast.load(point), core::FixedPointOverflow);
}

// The fast model's arithmetic checks the kernel's intermediates as the plain worker's does, products in 128
// bits included.
TEST(FixedChecks, FireInTheFastModelsArithmetic) {
  if (!kCheckFixed) GTEST_SKIP() << "built without TRIPSITTER_CHECK_FIXED";
  const NarrowArith narrow{FixedArith{SqrtUnit(16), FixedArith::extra_bits_of(wide_preset())}};
  const std::int64_t a = std::int64_t{1} << 43, c_prime = std::int64_t{1} << 50;
  EXPECT_NO_THROW(core::hit_num(narrow, std::int64_t{1000}, std::int64_t{1} << 47, c_prime));
  EXPECT_THROW(core::hit_num(narrow, std::int64_t{1000}, std::int64_t{1} << 48, c_prime), core::FixedPointOverflow);
  EXPECT_THROW(core::hit_num(narrow, std::int64_t{1000}, std::int64_t{1000}, std::int64_t{1} << 51),
               core::FixedPointOverflow);
  EXPECT_NO_THROW(core::hit_num(narrow, a - 1, std::int64_t{1000}, c_prime));
  EXPECT_THROW(core::hit_num(narrow, a, std::int64_t{1000}, c_prime), core::FixedPointOverflow);  // 4ac' = 2^95
}

// A reflected ray whose direction was not scaled down breaks the direction's bound in the next pass.
TEST(FixedChecks, FireOnAnUnscaledDirection) {
  if (!kCheckFixed) GTEST_SKIP() << "built without TRIPSITTER_CHECK_FIXED";
  const FixedArith arith{SqrtUnit(16)};
  const std::vector<core::KernelSphere<std::int64_t>> spheres{{{0, 0, 6400}, 1024}};
  const core::KernelRay<Int128> ray{{0, 0, 0}, {0, 0, Int128{1} << 30}};
  EXPECT_THROW(core::closest_hit(arith, ray, std::span<const core::KernelSphere<std::int64_t>>(spheres)),
               core::FixedPointOverflow);
}

}  // namespace
}  // namespace tripsitter::device

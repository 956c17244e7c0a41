#include <tripsitter/render/temporal.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/core/colour.h>
#include <tripsitter/render/rng.h>

namespace tripsitter::render {
namespace {

constexpr int kW = 24, kH = 16;
constexpr double kWall = 10;  // the wall's distance ahead of the camera, which is also the focus distance

scene::CameraSettings looking_along_z(double x) {
  scene::CameraSettings c;
  c.lookfrom = {x, 0, 0};
  c.lookat = {x, 0, 1};
  c.vup = {0, 1, 0};
  c.vfov = 40;
  c.focus_dist = kWall;
  return c;
}

std::vector<Vec3f> random_pass(std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Vec3f> pass(Aovs::pixels(kW, kH));
  for (Vec3f& p : pass) p = {rng.uniform(), rng.uniform(), rng.uniform()};
  return pass;
}

// The feature buffers of a camera facing the wall z = kWall (normal -z) square on.
Aovs wall(const ThinLensCamera::Pinhole& view) {
  Aovs a(kW, kH);
  for (int row = 0; row < kH; ++row) {
    for (int col = 0; col < kW; ++col) {
      const std::size_t i = static_cast<std::size_t>(row * kW + col);
      const Vec3f ray = core::normalize(view.pixel00 + view.du * static_cast<float>(col) +
                                        view.dv * static_cast<float>(row) - view.origin);
      a.depth[i] = static_cast<float>(kWall) / ray.z;
      a.normal[i] = {0, 0, -1};
      a.albedo[i] = {0.5f, 0.5f, 0.5f};
    }
  }
  return a;
}

TEST(Temporal, AStillCameraIsPlainAccumulationBitForBit) {
  const ThinLensCamera camera(looking_along_z(0), kW, kH);
  const Aovs aovs = wall(camera.pinhole());
  TemporalAccumulator acc(TemporalSettings{.max_history_moving = 16, .depth_tolerance = 0.05f,
                                           .normal_cosine = 0.8f, .threads = 3});
  std::vector<Vec3f> sum(Aovs::pixels(kW, kH));
  std::vector<float> squares(sum.size());
  for (std::uint64_t k = 1; k <= 6; ++k) {
    const std::vector<Vec3f> pass = random_pass(k);
    acc.add(pass, aovs, camera.pinhole());
    for (std::size_t i = 0; i < sum.size(); ++i) {
      sum[i] += pass[i];
      squares[i] += core::luminance(pass[i]) * core::luminance(pass[i]);
    }
    EXPECT_EQ(acc.reprojected(), 0u);
  }
  for (std::size_t i = 0; i < sum.size(); ++i) {
    ASSERT_EQ(acc.sum()[i], sum[i]) << "pixel " << i;
    ASSERT_EQ(acc.luminance_square_sum()[i], squares[i]);
    ASSERT_EQ(acc.count()[i], 6.0f);
  }
}

// The camera moves right by one pixel's width on the wall: pixel col now sees what pixel col + 1 saw.
TEST(Temporal, ASidewaysMoveCarriesEachPixelsHistoryOver) {
  const ThinLensCamera before(looking_along_z(0), kW, kH);
  const ThinLensCamera after(looking_along_z(before.pinhole().du.x), kW, kH);  // du: one pixel right on the wall
  TemporalAccumulator acc;
  const std::vector<Vec3f> first = random_pass(1), second = random_pass(2);
  acc.add(first, wall(before.pinhole()), before.pinhole());
  acc.add(second, wall(after.pinhole()), after.pinhole());
  EXPECT_EQ(acc.reprojected(), static_cast<std::size_t>((kW - 1) * kH));
  for (int row = 0; row < kH; ++row) {
    for (int col = 0; col < kW; ++col) {
      const std::size_t i = static_cast<std::size_t>(row * kW + col);
      if (col == kW - 1) {
        // Its surface was off the screen before.
        EXPECT_EQ(acc.count()[i], 1.0f);
        EXPECT_EQ(acc.sum()[i], second[i]);
        continue;
      }
      const Vec3f expected = first[i + 1] + second[i];
      EXPECT_NEAR(acc.count()[i], 2.0f, 1e-3f) << col << "," << row;
      EXPECT_NEAR(acc.sum()[i].x, expected.x, 1e-3f) << col << "," << row;
      EXPECT_NEAR(acc.sum()[i].y, expected.y, 1e-3f);
      EXPECT_NEAR(acc.sum()[i].z, expected.z, 1e-3f);
    }
  }
}

TEST(Temporal, ADisoccludedSurfaceStartsAfresh) {
  const ThinLensCamera before(looking_along_z(0), kW, kH);
  const ThinLensCamera after(looking_along_z(before.pinhole().du.x), kW, kH);
  // Before the move, something nearer covered columns 10 to 12: the wall behind it was not seen there.
  Aovs occluded = wall(before.pinhole());
  for (int row = 0; row < kH; ++row)
    for (int col = 10; col <= 12; ++col) occluded.depth[static_cast<std::size_t>(row * kW + col)] *= 0.5f;
  TemporalAccumulator acc;
  acc.add(random_pass(1), occluded, before.pinhole());
  acc.add(random_pass(2), wall(after.pinhole()), after.pinhole());
  for (int row = 0; row < kH; ++row) {
    for (int col = 0; col < kW - 1; ++col) {
      const float n = acc.count()[static_cast<std::size_t>(row * kW + col)];
      // Pixel col takes its history from col + 1 (and bilinear neighbours within rounding of it).
      if (col + 1 >= 10 && col + 1 <= 12) EXPECT_EQ(n, 1.0f) << col << "," << row;
      else EXPECT_NEAR(n, 2.0f, 1e-3f) << col << "," << row;
    }
  }
}

TEST(Temporal, ASurfaceFacingAnotherWayIsNotTheSameSurface) {
  const ThinLensCamera before(looking_along_z(0), kW, kH);
  const ThinLensCamera after(looking_along_z(before.pinhole().du.x), kW, kH);
  Aovs turned = wall(before.pinhole());
  for (Vec3f& n : turned.normal) n = {1, 0, 0};
  TemporalAccumulator acc;
  acc.add(random_pass(1), turned, before.pinhole());
  acc.add(random_pass(2), wall(after.pinhole()), after.pinhole());
  EXPECT_EQ(acc.reprojected(), 0u);
}

TEST(Temporal, SkyCarriesOverOnlyFromSky) {
  const ThinLensCamera before(looking_along_z(0), kW, kH);
  const ThinLensCamera after(looking_along_z(before.pinhole().du.x), kW, kH);
  Aovs sky_before(kW, kH), sky_after(kW, kH);  // depth infinity everywhere: nothing hit
  TemporalAccumulator acc;
  acc.add(random_pass(1), sky_before, before.pinhole());
  acc.add(random_pass(2), sky_after, after.pinhole());
  // A sideways move does not move the sky: every pixel keeps its own history.
  EXPECT_EQ(acc.reprojected(), static_cast<std::size_t>(kW * kH));
  acc.add(random_pass(3), wall(after.pinhole()), after.pinhole());  // still: plain accumulation
  const ThinLensCamera back(looking_along_z(0), kW, kH);
  acc.add(random_pass(4), sky_before, back.pinhole());
  EXPECT_EQ(acc.reprojected(), 0u);  // the wall's history is not the sky's
}

TEST(Temporal, NothingBehindTheCameraComesBack) {
  const ThinLensCamera before(looking_along_z(0), kW, kH);
  scene::CameraSettings turned = looking_along_z(0);
  turned.lookat = {0, 0, -1};
  const ThinLensCamera after(turned, kW, kH);
  TemporalAccumulator acc;
  acc.add(random_pass(1), wall(before.pinhole()), before.pinhole());
  Aovs behind = wall(before.pinhole());  // the same distances, now behind the first view
  acc.add(random_pass(2), behind, after.pinhole());
  EXPECT_EQ(acc.reprojected(), 0u);
}

TEST(Temporal, TheHistoryIsCappedAfterAMove) {
  const ThinLensCamera before(looking_along_z(0), kW, kH);
  const ThinLensCamera after(looking_along_z(before.pinhole().du.x), kW, kH);
  TemporalAccumulator acc(TemporalSettings{.max_history_moving = 4, .depth_tolerance = 0.05f, .normal_cosine = 0.8f,
                                           .threads = 1});
  for (std::uint64_t k = 1; k <= 10; ++k) acc.add(random_pass(k), wall(before.pinhole()), before.pinhole());
  acc.add(random_pass(11), wall(after.pinhole()), after.pinhole());
  EXPECT_NEAR(acc.count()[0], 5.0f, 1e-4f);
  EXPECT_EQ(acc.count()[kW - 1], 1.0f);
}

TEST(Temporal, APassOnEveryOtherRowAddsToThoseRowsAlone) {
  const ThinLensCamera before(looking_along_z(0), kW, kH);
  const ThinLensCamera after(looking_along_z(before.pinhole().du.x), kW, kH);
  TemporalAccumulator acc;
  const std::vector<Vec3f> pass = random_pass(1);
  acc.add(pass, wall(before.pinhole()), before.pinhole(), 1, 2);  // rows 1, 3, 5, ...
  for (int row = 0; row < kH; ++row) {
    const std::size_t i = static_cast<std::size_t>(row * kW + 3);
    EXPECT_EQ(acc.count()[i], row % 2 == 1 ? 1.0f : 0.0f) << row;
    EXPECT_EQ(acc.sum()[i], row % 2 == 1 ? pass[i] : Vec3f{}) << row;
  }
  // After a move, rows 0, 2, ... get their first samples; rows 1, 3, ... keep their history and add nothing.
  acc.add(random_pass(2), wall(after.pinhole()), after.pinhole(), 0, 2);
  for (int row = 0; row < kH; ++row) {
    const std::size_t i = static_cast<std::size_t>(row * kW + 3);
    EXPECT_NEAR(acc.count()[i], 1.0f, 1e-3f) << row;
    if (row % 2 == 1) {
      EXPECT_NEAR(acc.sum()[i].x, pass[i + 1].x, 1e-3f) << row;
    }
  }
}

TEST(Temporal, MeanVarianceIsTheVarianceOfTheMeanLuminance) {
  const ThinLensCamera camera(looking_along_z(0), kW, kH);
  const Aovs aovs = wall(camera.pinhole());
  TemporalAccumulator acc;
  std::vector<float> variance(Aovs::pixels(kW, kH));
  acc.add(std::vector<Vec3f>(variance.size(), Vec3f{1, 1, 1}), aovs, camera.pinhole());
  acc.mean_variance(variance);
  EXPECT_EQ(variance[0], 0.0f);  // one sample: unknown
  acc.add(std::vector<Vec3f>(variance.size(), Vec3f{3, 3, 3}), aovs, camera.pinhole());
  acc.mean_variance(variance);
  // Luminances 1 and 3: E[l^2] - E[l]^2 = 5 - 4 = 1, over 2 samples.
  EXPECT_NEAR(variance[5], 0.5f, 1e-5f);
}

}  // namespace
}  // namespace tripsitter::render

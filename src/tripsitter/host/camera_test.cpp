#include <tripsitter/host/camera.h>

#include <gtest/gtest.h>

namespace tripsitter::host {
namespace {

void expect_near(const Vec3d& a, const Vec3d& b, double tol = 1e-9) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

Camera looking_along_z() { return Camera({0, 0, -10}, {0, 0, 0}, {0, 1, 0}); }

TEST(Camera, StartsLookingAtItsTarget) {
  const Camera c({1, 2, 3}, {4, 6, 3}, {0, 1, 0});
  expect_near(c.target(), {4, 6, 3});
  expect_near(c.forward(), {0.6, 0.8, 0});
  EXPECT_NEAR(c.pitch_deg(), 53.130102354155978, 1e-9);
}

TEST(Camera, CameraFromWorldPutsTheTargetStraightAheadAndUpUpTheScreen) {
  const Camera c({3, -2, 7}, {-1, 5, 2}, {0, 1, 0});
  const Mat4 m = c.camera_from_world();
  const Vec3d t = m.apply_point(c.target());
  EXPECT_NEAR(t.x, 0, 1e-9);
  EXPECT_NEAR(t.y, 0, 1e-9);
  EXPECT_NEAR(t.z, core::length(Vec3d{-4, 7, -5}), 1e-9);
  expect_near(m.apply_point(c.position()), {0, 0, 0});
  // A point above the camera's position (world up) is above the centre of the screen: negative y.
  EXPECT_LT(m.apply_point(c.position() + c.up()).y, 0);
  // Screen right.
  EXPECT_GT(m.apply_point(c.position() + c.right()).x, 0);
}

TEST(Camera, MoveAndStrafeCarryTheTargetAlong) {
  Camera c = looking_along_z();
  c.move(2);
  expect_near(c.position(), {0, 0, -8});
  expect_near(c.target(), {0, 0, 2});
  c.strafe(1);
  expect_near(c.position(), c.right() + Vec3d{0, 0, -8});
  // Right-handed with y up: looking along +z, screen right is -x.
  expect_near(c.right(), {-1, 0, 0});
}

TEST(Camera, LookTurnsAndPitchIsClamped) {
  Camera c = looking_along_z();
  c.look(90, 0);
  expect_near(c.forward(), {-1, 0, 0});  // turned right
  c.look(0, 200);
  EXPECT_DOUBLE_EQ(c.pitch_deg(), kMaxPitchDeg);
  c.look(0, -500);
  EXPECT_DOUBLE_EQ(c.pitch_deg(), -kMaxPitchDeg);
  EXPECT_NEAR(core::length(c.forward()), 1.0, 1e-12);
}

TEST(Camera, OrbitCirclesTheTargetAndKeepsLookingAtIt) {
  Camera c({0, 3, -10}, {0, 0, 0}, {0, 1, 0});
  const Vec3d target = c.target();
  const double radius = core::length(c.position() - target);
  for (int step = 0; step < 8; ++step) {
    c.orbit(45);
    expect_near(c.target(), target, 1e-9);
    EXPECT_NEAR(core::length(c.position() - target), radius, 1e-9);
    EXPECT_NEAR(c.position().y, 3, 1e-9);
    expect_near(c.forward(), core::normalize(target - c.position()), 1e-9);
  }
  expect_near(c.position(), {0, 3, -10}, 1e-9);  // full circle
  c.orbit(90);
  EXPECT_NEAR(std::abs(c.position().x), 10, 1e-9);
}

}  // namespace
}  // namespace tripsitter::host

#include <tripsitter/core/mat4.h>

#include <gtest/gtest.h>

namespace tripsitter::core {
namespace {

void expect_near(const Vec3d& a, const Vec3d& b) {
  EXPECT_NEAR(a.x, b.x, 1e-12);
  EXPECT_NEAR(a.y, b.y, 1e-12);
  EXPECT_NEAR(a.z, b.z, 1e-12);
}

TEST(Mat4, TranslationMovesPointsNotVectors) {
  const Mat4 t = Mat4::translation({1, 2, 3});
  expect_near(t.apply_point({1, 1, 1}), {2, 3, 4});
  expect_near(t.apply_vector({1, 1, 1}), {1, 1, 1});
}

TEST(Mat4, CompositionAppliesRightToLeft) {
  const Mat4 scale_from_moved = Mat4::scale({2, 2, 2});
  const Mat4 moved_from_world = Mat4::translation({1, 0, 0});
  const Mat4 combined = scale_from_moved * moved_from_world;
  expect_near(combined.apply_point({1, 1, 1}), {4, 2, 2});
  expect_near(combined.apply_point({1, 1, 1}), scale_from_moved.apply_point(moved_from_world.apply_point({1, 1, 1})));
}

TEST(Mat4, RowsGiveCoordinatesAlongANewBasis) {
  const Mat4 m = Mat4::from_rows({0, 1, 0}, {0, 0, 1}, {1, 0, 0});
  expect_near(m.apply_point({1, 2, 3}), {2, 3, 1});
  expect_near((Mat4::identity() * m).apply_point({1, 2, 3}), {2, 3, 1});
}

}  // namespace
}  // namespace tripsitter::core

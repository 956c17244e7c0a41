// 4x4 homogeneous matrices, row-major, acting on column vectors (p' = M p).
// Transforms are named destination_from_source (view_from_world), so that
// composition reads right to left: view_from_world = view_from_camera * camera_from_world.
#pragma once

#include <array>

#include <tripsitter/core/vec.h>

namespace tripsitter::core {

struct Mat4 {
  std::array<std::array<double, 4>, 4> m{};

  static constexpr Mat4 identity() {
    Mat4 r;
    for (int i = 0; i < 4; ++i) r.m[i][i] = 1.0;
    return r;
  }
  static constexpr Mat4 translation(const Vec3d& t) {
    Mat4 r = identity();
    r.m[0][3] = t.x;
    r.m[1][3] = t.y;
    r.m[2][3] = t.z;
    return r;
  }
  static constexpr Mat4 scale(const Vec3d& s) {
    Mat4 r = identity();
    r.m[0][0] = s.x;
    r.m[1][1] = s.y;
    r.m[2][2] = s.z;
    return r;
  }
  // Rows are the images of the new basis: the matrix maps a point to its coordinates along (x_axis, y_axis, z_axis).
  static constexpr Mat4 from_rows(const Vec3d& x_axis, const Vec3d& y_axis, const Vec3d& z_axis) {
    Mat4 r = identity();
    for (int j = 0; j < 3; ++j) {
      r.m[0][j] = x_axis[j];
      r.m[1][j] = y_axis[j];
      r.m[2][j] = z_axis[j];
    }
    return r;
  }

  constexpr Mat4 operator*(const Mat4& o) const {
    Mat4 r;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        double s = 0.0;
        for (int k = 0; k < 4; ++k) s += m[i][k] * o.m[k][j];
        r.m[i][j] = s;
      }
    return r;
  }

  // Applies the matrix to the point (p, 1); REQUIRES an affine matrix (last row 0 0 0 1).
  constexpr Vec3d apply_point(const Vec3d& p) const {
    Vec3d r;
    for (int i = 0; i < 3; ++i) r[i] = m[i][0] * p.x + m[i][1] * p.y + m[i][2] * p.z + m[i][3];
    return r;
  }
  // Applies the linear part only (direction vectors).
  constexpr Vec3d apply_vector(const Vec3d& v) const {
    Vec3d r;
    for (int i = 0; i < 3; ++i) r[i] = m[i][0] * v.x + m[i][1] * v.y + m[i][2] * v.z;
    return r;
  }
};

}  // namespace tripsitter::core

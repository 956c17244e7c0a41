// The float reference: the device's rays and normal-map shading (SPEC.md section B) in double precision,
// with the same kernel the device runs in fixed point (core/sphere_kernel.h).
#pragma once

#include <cmath>
#include <span>

#include <tripsitter/core/image.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::render {

struct DoubleArith {
  using Coord = double;
  using Wide = double;
  double sqrt(double d) const { return std::sqrt(d); }
  static int floor_div(double n, double d) {
    const double q = std::floor(n / d);
    return q > 1e9 ? 1'000'000'000 : (q < -1e9 ? -1'000'000'000 : static_cast<int>(q));
  }
};

// Renders view-space spheres (pixel units, as the host computes them). The pixel in column col and row
// row shoots (col - width/2, row - height/2, width/2) (integer halves): for 640x480 exactly the device's
// rays, and a 90 degree horizontal field of view at every size.
core::Image444 render_normal(std::span<const scene::Sphere> view_spheres, int width, int height);

}  // namespace tripsitter::render

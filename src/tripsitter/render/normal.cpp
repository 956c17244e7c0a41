#include <tripsitter/render/normal.h>

#include <vector>

#include <tripsitter/core/sphere_kernel.h>

namespace tripsitter::render {

core::Image444 render_normal(std::span<const scene::Sphere> view_spheres, int width, int height) {
  std::vector<core::KernelSphere<double>> spheres;
  spheres.reserve(view_spheres.size());
  for (const auto& s : view_spheres) spheres.push_back({s.center, s.radius});
  core::Image444 image(width, height);
  const DoubleArith arith;
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      const core::Vec3d d{double(col - width / 2), double(row - height / 2), double(width / 2)};
      image.at(col, row) = core::normal_shade_pixel(arith, d, std::span<const core::KernelSphere<double>>(spheres),
                                                    core::kBackground);
    }
  }
  return image;
}

}  // namespace tripsitter::render

#include <tripsitter/render/normal.h>

#include <stdexcept>
#include <vector>

namespace tripsitter::render {

core::Image444 render_normal(std::span<const scene::Sphere> view_spheres, int width, int height, int max_bounces) {
  if (max_bounces < 0 || max_bounces > core::kMaxBounces) throw std::invalid_argument("max bounces must be 0 to 6");
  std::vector<core::KernelSphere<double>> spheres;
  std::vector<core::KernelSurface> surfaces;
  spheres.reserve(view_spheres.size());
  surfaces.reserve(view_spheres.size());
  for (const auto& s : view_spheres) {
    spheres.push_back({s.center, s.radius});
    const core::Vec3d& a = s.material.albedo;
    surfaces.push_back({s.material.type == scene::MaterialType::kMetal,
                        {albedo_byte(a.x), albedo_byte(a.y), albedo_byte(a.z)}});
  }
  const auto surface_of = [&surfaces](int i) { return surfaces[static_cast<std::size_t>(i)]; };
  core::Image444 image(width, height);
  const DoubleArith arith;
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      const core::Vec3d d{double(col - width / 2), double(row - height / 2), double(width / 2)};
      image.at(col, row) = core::trace_pixel(arith, d, std::span<const core::KernelSphere<double>>(spheres), surface_of,
                                             core::kBackground, max_bounces)
                               .colour;
    }
  }
  return image;
}

}  // namespace tripsitter::render

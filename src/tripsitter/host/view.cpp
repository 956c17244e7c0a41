#include <tripsitter/host/view.h>

#include <algorithm>

#include <tripsitter/core/screen.h>

namespace tripsitter::host {

double units_per_world(const scene::Scene& scene) {
  if (scene.units_per_world > 0) return scene.units_per_world;
  return core::kImagePlaneZ / core::length(scene.camera.lookat - scene.camera.lookfrom);
}

core::Mat4 view_from_world(const Camera& camera, double units_per_world) {
  const double s = units_per_world;
  return core::Mat4::scale({s, s, s}) * camera.camera_from_world();
}

std::vector<scene::Sphere> view_spheres(std::span<const scene::Sphere> world, const Camera& camera,
                                        double units_per_world) {
  const core::Mat4 m = view_from_world(camera, units_per_world);
  std::vector<scene::Sphere> view;
  view.reserve(world.size());
  for (scene::Sphere s : world) {
    s.center = m.apply_point(s.center);
    s.radius *= units_per_world;
    view.push_back(s);
  }
  return view;
}

std::size_t spheres_carried(std::size_t count, const link::SceneFormats& formats, link::WireVersion wire) {
  return wire == link::WireVersion::kV1 ? count : std::min<std::size_t>(count, formats.max_spheres);
}

}  // namespace tripsitter::host

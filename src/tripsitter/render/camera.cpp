#include <tripsitter/render/camera.h>

#include <cmath>
#include <numbers>

namespace tripsitter::render {
namespace {

Vec3f to_f(const core::Vec3d& v) { return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)}; }

}  // namespace

ThinLensCamera::ThinLensCamera(const scene::CameraSettings& s, int width, int height) {
  const double deg = std::numbers::pi / 180.0;
  // Camera frame: w points back from the view direction, u to screen right, v up.
  const core::Vec3d w = core::normalize(s.lookfrom - s.lookat);
  const core::Vec3d u = core::normalize(core::cross(s.vup, w));
  const core::Vec3d v = core::cross(w, u);
  // The viewport lies on the focus plane, so that defocus blur is zero there.
  const double viewport_h = 2.0 * std::tan(s.vfov * deg / 2.0) * s.focus_dist;
  const double viewport_w = viewport_h * static_cast<double>(width) / static_cast<double>(height);
  const core::Vec3d du = u * (viewport_w / width);
  const core::Vec3d dv = -v * (viewport_h / height);
  const core::Vec3d top_left = s.lookfrom - w * s.focus_dist - u * (viewport_w / 2) + v * (viewport_h / 2);
  origin_ = to_f(s.lookfrom);
  pixel00_ = to_f(top_left + (du + dv) * 0.5);
  pixel_du_ = to_f(du);
  pixel_dv_ = to_f(dv);
  const double lens_radius = s.focus_dist * std::tan(s.defocus_angle * deg / 2.0);
  lens_u_ = to_f(u * lens_radius);
  lens_v_ = to_f(v * lens_radius);
  defocus_ = s.defocus_angle > 0;
}

Ray ThinLensCamera::centre_ray(int col, int row) const {
  const Vec3f target = pixel00_ + pixel_du_ * static_cast<float>(col) + pixel_dv_ * static_cast<float>(row);
  return {origin_, target - origin_};
}

}  // namespace tripsitter::render

#include <tripsitter/host/camera.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tripsitter::host {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

}  // namespace

Camera::Camera(const Vec3d& lookfrom, const Vec3d& lookat, const Vec3d& vup)
    : world_up_(core::normalize(vup)), position_(lookfrom) {
  const Vec3d dir = lookat - lookfrom;
  distance_ = core::length(dir);
  const Vec3d d = dir / distance_;
  ref_forward_ = core::normalize(d - world_up_ * core::dot(d, world_up_));
  // Right-handed with y up: looking along +z, screen right is -x (the convention of the float renderer).
  ref_right_ = core::cross(ref_forward_, world_up_);
  pitch_deg_ = std::asin(std::clamp(core::dot(d, world_up_), -1.0, 1.0)) / kRadPerDeg;
  pitch_deg_ = std::clamp(pitch_deg_, -kMaxPitchDeg, kMaxPitchDeg);
}

Vec3d Camera::forward() const {
  const double yaw = yaw_deg_ * kRadPerDeg;
  const double pitch = pitch_deg_ * kRadPerDeg;
  const Vec3d level = ref_forward_ * std::cos(yaw) + ref_right_ * std::sin(yaw);
  return level * std::cos(pitch) + world_up_ * std::sin(pitch);
}

Vec3d Camera::right() const { return core::normalize(core::cross(forward(), world_up_)); }

Vec3d Camera::up() const { return core::cross(right(), forward()); }

void Camera::move(double distance) { position_ += forward() * distance; }

void Camera::strafe(double distance) { position_ += right() * distance; }

void Camera::look(double yaw_deg, double pitch_deg) {
  yaw_deg_ = std::remainder(yaw_deg_ + yaw_deg, 360.0);
  pitch_deg_ = std::clamp(pitch_deg_ + pitch_deg, -kMaxPitchDeg, kMaxPitchDeg);
}

void Camera::orbit(double degrees) {
  const Vec3d centre = target();
  const Vec3d offset = position_ - centre;
  // Rotate the offset about the up axis through the target (Rodrigues, axis ⟂ part only changes).
  const double a = degrees * kRadPerDeg;
  const Vec3d along = world_up_ * core::dot(offset, world_up_);
  const Vec3d across = offset - along;
  const Vec3d rotated = across * std::cos(a) + core::cross(world_up_, across) * std::sin(a) + along;
  position_ = centre + rotated;
  yaw_deg_ = std::remainder(yaw_deg_ - degrees, 360.0);  // rotating by +a about up turns the view by -a in yaw
}

Mat4 Camera::camera_from_world() const {
  const Vec3d f = forward();
  const Vec3d r = right();
  const Vec3d u = core::cross(r, f);
  return Mat4::from_rows(r, -u, f) * Mat4::translation(-position_);
}

}  // namespace tripsitter::host

// The host's camera, driven by the board's controls (SPEC.md section B).
//
// The camera keeps a position, a yaw and a pitch (degrees) in a frame built from the scene's up vector,
// and a target that always lies straight ahead at the look-at distance: moving carries the target along,
// looking swings it around the camera, orbiting swings the camera around it.
#pragma once

#include <tripsitter/core/mat4.h>
#include <tripsitter/core/vec.h>

namespace tripsitter::host {

using core::Mat4;
using core::Vec3d;

inline constexpr double kMaxPitchDeg = 89.0;

class Camera {
 public:
  // REQUIRES lookfrom != lookat and vup not parallel to lookat - lookfrom.
  Camera(const Vec3d& lookfrom, const Vec3d& lookat, const Vec3d& vup);

  // W/S: along the view direction. A/D: sideways (positive to the right on screen).
  void move(double distance);
  void strafe(double distance);
  // I/K and J/L: positive yaw turns right, positive pitch looks up; pitch is clamped to +-89 degrees.
  void look(double yaw_deg, double pitch_deg);
  // Q/E: the camera circles the target about the up axis and keeps looking at it.
  void orbit(double degrees);

  const Vec3d& position() const { return position_; }
  Vec3d target() const { return position_ + forward() * distance_; }
  double yaw_deg() const { return yaw_deg_; }
  double pitch_deg() const { return pitch_deg_; }
  Vec3d forward() const;
  Vec3d right() const;  // screen right
  Vec3d up() const;     // screen up

  // Camera space: x to screen right, y down the screen, z ahead (the device's view space, before scaling).
  Mat4 camera_from_world() const;

 private:
  Vec3d world_up_, ref_forward_, ref_right_;  // fixed frame: yaw 0, pitch 0 looks along ref_forward_
  Vec3d position_;
  double yaw_deg_ = 0, pitch_deg_ = 0;
  double distance_ = 1;  // from the camera to its target
};

}  // namespace tripsitter::host

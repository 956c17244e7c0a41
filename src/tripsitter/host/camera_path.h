// A camera path: how the camera moves from one world to the next when the host prepares a series of worlds ahead
// (`link encode --worlds N --orbit DEG`, the board's ROM image: rom_image.h).
#pragma once

#include <tripsitter/host/camera.h>

namespace tripsitter::host {

struct CameraPath {
  enum class Kind {
    kOrbit,  // around its target about the scene's up axis, `amount` degrees over the path (Q/E)
    kWalk,   // along its view direction, `amount` scene units over the path (W/S)
  };
  Kind kind = Kind::kOrbit;
  double amount = 360;
};

// Moves the camera from one world of a path of `worlds` to the next: amount / worlds further on, so that the first
// world is the scene's own view and each one after is as far from the one before. REQUIRES worlds >= 1.
inline void step_camera(Camera& camera, const CameraPath& path, int worlds) {
  const double step = path.amount / worlds;
  switch (path.kind) {
    case CameraPath::Kind::kOrbit: camera.orbit(step); break;
    case CameraPath::Kind::kWalk: camera.move(step); break;
  }
}

}  // namespace tripsitter::host

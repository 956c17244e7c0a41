// The host (the report's microcontroller): keeps the world and the camera in floating point, applies the
// view transform (view.h), converts to the device's fixed point and encodes a world for the link.
//
// Two copies of the world: the edited one (scene spheres and camera, changed by the controls) and the
// ready one (fixed point, encoded), rebuilt by update() and complete whenever the link reads it.
#pragma once

#include <cstdint>
#include <vector>

#include <tripsitter/core/mat4.h>
#include <tripsitter/host/camera.h>
#include <tripsitter/host/view.h>
#include <tripsitter/link/wire.h>
#include <tripsitter/link/wire_v1.h>
#include <tripsitter/link/frame.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::host {

struct Saturations {
  std::uint64_t coordinates = 0;  // centre coordinates clamped to the format's range
  std::uint64_t radii = 0;        // radii clamped (or, on v1, outside 2^0..2^63)
  std::uint64_t iors = 0;         // dielectrics' indices of refraction clamped to the device's range
  std::uint64_t total() const { return coordinates + radii + iors; }
  // Every kind added: the one place where counts of several worlds are summed.
  Saturations& operator+=(const Saturations& o) {
    coordinates += o.coordinates;
    radii += o.radii;
    iors += o.iors;
    return *this;
  }
};

// What one update produced.
struct ReadyWorld {
  // The encoded world, ready for the link, which numbers it as it goes out (session and sequence 0 here).
  std::vector<std::uint8_t> bytes;
  std::size_t spheres = 0;                    // in it
  Saturations saturations;
  std::size_t spheres_dropped = 0;            // beyond the device's scene memory (never sent)
};

class Host {
 public:
  // REQUIRES the scene's camera to be valid (see scene_json.h: lookfrom != lookat, vup not parallel).
  Host(scene::Scene scene, link::SceneFormats formats, link::WireVersion wire);

  Camera& camera() { return camera_; }
  const Camera& camera() const { return camera_; }
  // R: world and camera as loaded.
  void reset();

  // Pixel units per world unit in view space.
  double units_per_world() const { return units_per_world_; }
  // The spheres the next update sends, in view space, floating point (view.h): what the float reference of
  // the device's shading takes.
  std::vector<scene::Sphere> view() const;

  // Rebuilds the ready copy from the edited world and camera.
  const ReadyWorld& update();
  const ReadyWorld& ready() const { return ready_; }
  const Saturations& total_saturations() const { return total_saturations_; }

 private:
  scene::Scene initial_;
  std::vector<scene::Sphere> world_;  // the edited copy
  Camera camera_;
  double units_per_world_;
  link::SceneFormats formats_;
  link::WireVersion wire_;
  ReadyWorld ready_;
  Saturations total_saturations_;
};

// Rounding to the v1 word's fields; counts what saturated into `sat`.
link::V1Sphere to_v1(const scene::Sphere& view_sphere, Saturations& sat);
// Rounding to a v2 sphere record in `formats`; counts what saturated into `sat`.
link::WireSphere to_wire(const scene::Sphere& view_sphere, const link::SceneFormats& formats, Saturations& sat);

}  // namespace tripsitter::host

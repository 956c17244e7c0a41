// The same primary-ray images as render_primary, traced by Intel Embree (Debian's libembree-dev) for
// `tripsitter bench` to compare against. Built only where CMake finds Embree (TRIPSITTER_HAVE_EMBREE).
#pragma once

#include <memory>
#include <string>

#include <tripsitter/render/primary.h>

namespace tripsitter::render {

// How Embree is asked: one ray per call, or packets of 8 (4x2 pixels) or 16 (4x4 pixels).
enum class EmbreePacket { k1, k8, k16 };
std::string to_string(EmbreePacket p);

// The Embree version built in, such as "3.13.5".
std::string embree_version();

class EmbreePrimary {
 public:
  // One Embree scene holding one geometry of type sphere-point with the scene's spheres; `threads` limits
  // Embree's own build threads (0: all).
  EmbreePrimary(const PathScene& scene, int threads);
  ~EmbreePrimary();
  EmbreePrimary(const EmbreePrimary&) = delete;
  EmbreePrimary& operator=(const EmbreePrimary&) = delete;

  // Pixels as render_primary defines them: the camera's centre ray, shaded by shade_primary.
  core::ImageRgb8 render(const ThinLensCamera& camera, const PrimarySettings& settings, EmbreePacket packet) const;

 private:
  struct State;
  const PathScene& scene_;
  std::unique_ptr<State> state_;
};

}  // namespace tripsitter::render

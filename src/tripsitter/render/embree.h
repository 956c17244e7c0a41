// Intel Embree (Debian's libembree-dev) tracing the same work as TripSitter, for `tripsitter bench` to compare
// against: the primary-ray images of render_primary, and the path tracer's closest-hit queries. Built only where
// CMake finds Embree (TRIPSITTER_HAVE_EMBREE).
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

class EmbreeScene final : public HitQuery {
 public:
  // One Embree scene holding one geometry of type sphere-point with the scene's spheres; `threads` limits
  // Embree's own build threads (0: all).
  EmbreeScene(const PathScene& scene, int threads);
  ~EmbreeScene() override;
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Pixels as render_primary defines them: the camera's centre ray, shaded by shade_primary.
  core::ImageRgb8 render_primary(const ThinLensCamera& camera, const PrimarySettings& settings,
                                 EmbreePacket packet) const;

  // One ray by rtcIntersect1, for render_path(scene, query, ...): the path tracer's own work, Embree's hits.
  bool intersect(const Ray& ray, float t_min, float t_max, SphereHit& hit) const override;

 private:
  struct State;
  const PathScene& scene_;
  std::unique_ptr<State> state_;
};

}  // namespace tripsitter::render

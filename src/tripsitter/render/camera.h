// The float renderer's thin-lens camera (SPEC.md section C).
#pragma once

#include <tripsitter/render/ray.h>
#include <tripsitter/render/rng.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::render {

class ThinLensCamera {
 public:
  // REQUIRES settings valid as the scene loader checks them (lookfrom != lookat, vup not parallel),
  // width, height >= 1.
  ThinLensCamera(const scene::CameraSettings& settings, int width, int height);

  // A ray through a uniformly jittered point of pixel (col, row), row 0 at the top, starting on the lens.
  // Inline: the path tracer draws one per sample.
  Ray ray(int col, int row, Rng& rng) const { return ray(col, row, rng, rng); }
  // The same with the jitter from `jitter` (its symmetric_pair) and the lens point from `lens` (its in_unit_disk,
  // taken only with defocus, after the jitter): an Rng, or a SquareSample each (sampler.h).
  template <class Jitter, class Lens>
  Ray ray(int col, int row, Jitter&& jitter, Lens&& lens) const;
  // Whether rays start on a disk (defocus_angle > 0), so that ray() takes a lens point.
  bool defocus() const { return defocus_; }
  // The ray through the pixel's centre from the lens centre (no jitter, no defocus).
  Ray centre_ray(int col, int row) const;

  // What centre_ray computes from: the eye, the top-left pixel's centre and one pixel right and down.
  struct Pinhole {
    Vec3f origin, pixel00, du, dv;
  };
  Pinhole pinhole() const { return {origin_, pixel00_, pixel_du_, pixel_dv_}; }

 private:
  Vec3f origin_;
  Vec3f pixel00_;          // centre of the top-left pixel on the focus plane
  Vec3f pixel_du_, pixel_dv_;  // one pixel right, one pixel down
  Vec3f lens_u_, lens_v_;      // the defocus disk's radius vectors
  bool defocus_ = false;
};

template <class Jitter, class Lens>
inline Ray ThinLensCamera::ray(int col, int row, Jitter&& jitter, Lens&& lens) const {
  // Both jitters from one draw, uniform in [-0.5, 0.5).
  const Rng::Pair offset = jitter.symmetric_pair(0.5f);
  const Vec3f target = pixel00_ + pixel_du_ * (static_cast<float>(col) + offset.a) +
                       pixel_dv_ * (static_cast<float>(row) + offset.b);
  Vec3f from = origin_;
  if (defocus_) {
    const Vec3f d = lens.in_unit_disk();
    from = origin_ + lens_u_ * d.x + lens_v_ * d.y;
  }
  return {from, target - from};
}

}  // namespace tripsitter::render

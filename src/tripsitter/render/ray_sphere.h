// The float ray-sphere kernel: the one sequence of float operations that decides where a ray meets a sphere in
// the float renderers. intersect_sphere (ray_sphere.cpp), brute force (brute_force.cpp) and the BVH's per-ray
// set-up (bvh_traversal.cpp) call it; the SIMD copy (sphere_lanes.h), which the BVH's leaves and packets and the
// primary-ray tiles use, repeats it lane by lane. With -ffp-contract=off (render/CMakeLists.txt) no copy fuses a
// multiply-add, so every caller gets the same t for a sphere, bit for bit.
//
// Defined here, inline, so that the hot loops calling it (brute force over every sphere) inline it as they did
// when it was file-static. Internal to the render library: bvh.h is the public contract. In the instruction set's
// namespace (isa.h), so it is safe to include from code compiled for another instruction set.
#pragma once

#include <cmath>
#include <utility>

#include <tripsitter/render/isa.h>
#include <tripsitter/render/ray.h>

namespace tripsitter::render {
inline namespace TRIPSITTER_RENDER_ISA {

// Per-ray constants of the sphere kernel. Every caller computes them through make_kernel_ray, so every caller
// performs the same float operations for a given sphere.
struct KernelRay {
  Vec3f origin;
  Vec3f dir;
  float dir_len2;      // |dir|^2, the a of the quadratic
  float inv_dir_len2;  // 1 / |dir|^2 (inf for a zero direction, which the kernel then rejects)
};

inline KernelRay make_kernel_ray(const Ray& ray) {
  const float a = dot(ray.dir, ray.dir);
  return {ray.origin, ray.dir, a, 1.0f / a};
}

// The root chosen by t_min alone: the near root if it lies beyond t_min, else the far root if that does.
// Callers then require t < t_max; since far >= near this equals choosing within (t_min, t_max) directly,
// and it lets the BVH compare against a t_max that shrinks without changing which root a sphere offers.
// sphere_lanes.h repeats these operations lane by lane, in this order.
inline bool sphere_root(const KernelRay& ray, const Vec3f& center, float radius, float t_min, float& t) {
  // Solve a t^2 + 2 b t + c = 0, a = |d|^2, b = oc.d, c = |oc|^2 - r^2. The quarter discriminant b^2 - a c is
  // rewritten as a (r^2 - |f|^2), f = oc - (b/a) d being the vector from the centre to the ray's closest approach:
  // b^2 and a c are huge and nearly equal for a sphere far larger or farther away than its distance to the line,
  // whereas f is small and accurate there.
  const Vec3f oc = ray.origin - center;
  const float b = dot(oc, ray.dir);
  const Vec3f f = oc - ray.dir * (b * ray.inv_dir_len2);
  const float r2 = radius * radius;
  const float disc = ray.dir_len2 * (r2 - dot(f, f));
  if (!(disc >= 0.0f)) return false;  // a miss, or NaN from a zero direction
  // Roots without cancellation: q adds two terms of the same sign; the roots are q/a and c/q.
  const float q = -(b + std::copysign(std::sqrt(disc), b));
  const float c = dot(oc, oc) - r2;
  float t_near = q * ray.inv_dir_len2;
  float t_far = q != 0.0f ? c / q : 0.0f;  // q == 0: the ray only touches the sphere, at its origin
  if (t_far < t_near) std::swap(t_near, t_far);
  if (t_near > t_min) {
    t = t_near;
    return true;
  }
  if (t_far > t_min) {
    t = t_far;
    return true;
  }
  return false;
}

}  // namespace TRIPSITTER_RENDER_ISA
}  // namespace tripsitter::render

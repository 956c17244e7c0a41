// The float ray-sphere kernel (ray_sphere.h, sphere_root) in SIMD lanes, for any mix of rays and spheres across
// the lanes (a leaf's spheres against one ray, one sphere against a packet or a tile's row of rays), and the
// closest-hit bookkeeping of many rays at once. Each lane performs sphere_root's float operations in its order, so a
// lane's t is bit for bit the scalar kernel's, where compiled with -ffp-contract=off as the render library is (see
// simd8.h).
//
// Safe to include anywhere: like F8 (simd8.h), everything here lives in tripsitter::render::simd, in the inline
// namespace of the instruction set it is compiled for (isa.h).
#pragma once

#include <bit>
#include <cstdint>

#include <tripsitter/render/isa.h>
#include <tripsitter/render/simd8.h>

namespace tripsitter::render::simd {
inline namespace TRIPSITTER_RENDER_ISA {

// The lanes that offer a root beyond t_min (`hit`, a mask) and that root (`t`): the near root if it lies beyond
// t_min, else the far one. Both all zero when no lane has a real root.
struct LaneRoots {
  F8 hit, t;
};

// Lane by lane: oc = ray origin - sphere centre, d the ray direction, dir_len2 = |d|^2 and inv_dir_len2 =
// 1 / |d|^2 (as make_kernel_ray computes them), r2 = radius^2.
inline LaneRoots sphere_lanes(F8 ocx, F8 ocy, F8 ocz, F8 dx, F8 dy, F8 dz, F8 dir_len2, F8 inv_dir_len2, F8 r2,
                              F8 t_min) {
  const F8 b = ocx * dx + ocy * dy + ocz * dz;
  const F8 scale = b * inv_dir_len2;
  const F8 fx = ocx - dx * scale, fy = ocy - dy * scale, fz = ocz - dz * scale;
  const F8 disc = dir_len2 * (r2 - (fx * fx + fy * fy + fz * fz));
  const F8 zero = F8::set1(0.0f);
  const F8 real = disc >= zero;  // false for NaN, as !(disc >= 0) in sphere_root
  if (real.bits() == 0) return {zero, zero};
  const F8 q = (b + copysign(sqrt(disc), b)) ^ F8::set1(-0.0f);
  const F8 c = (ocx * ocx + ocy * ocy + ocz * ocz) - r2;
  const F8 q_near = q * inv_dir_len2;
  const F8 q_far = (q != zero) & (c / q);  // q == 0: the ray only touches the sphere, at its origin
  const F8 swap = q_far < q_near;
  const F8 t_near = select(swap, q_far, q_near), t_far = select(swap, q_near, q_far);
  const F8 t = select(t_near > t_min, t_near, t_far);
  return {real & (t > t_min), t};
}

// Closest hits of eight rays, one per lane, as sphere `index` offers `t` in the lanes of `valid`: a lane takes it
// when it is nearer than best_t, or as near with a lower index (as testing every sphere in index order does).
// best_t and best_id (the index's bits as a float) are arrays of one float per lane, 32-byte aligned. Returns the
// lanes whose t came nearer.
inline int keep_nearest(F8 valid, F8 t, std::uint32_t index, float* best_t, float* best_id) {
  const F8 best = F8::load(best_t);
  const F8 closer = valid & (t < best);
  const int nearer = closer.bits();
  if (nearer != 0) {
    select(closer, t, best).store(best_t);
    select(closer, F8::set1(std::bit_cast<float>(index)), F8::load(best_id)).store(best_id);
  }
  if (const int ties = (valid & (t == best)).bits(); ties != 0) {
    for (int k = 0; k < 8; ++k) {  // F8's lanes
      if ((ties >> k & 1) && index < std::bit_cast<std::uint32_t>(best_id[k])) best_id[k] = std::bit_cast<float>(index);
    }
  }
  return nearer;
}

}  // namespace TRIPSITTER_RENDER_ISA
}  // namespace tripsitter::render::simd

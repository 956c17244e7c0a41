// Bvh::intersect and Bvh::intersect_packet (bvh.h): the tree walked by one ray, nearest entered child first, and by
// eight rays at once through Bvh::traverse.
//
// Nodes test their eight children's boxes, and leaves their up to eight spheres, in one SIMD step (simd8.h: AVX where
// compiled for it, else two SSE halves). The sphere test is the float kernel lane by lane (sphere_lanes.h), fed the
// per-ray constants of make_kernel_ray (ray_sphere.h), so a lane gives the t that the scalar kernel gives. Culling is
// conservative: the builder pads boxes beyond the spheres' rounding (bvh_builder.cpp), and slab exits are padded as
// in Ize, "Robust BVH Ray Traversal", 2013 (kExitPad below); bvh.h says what that guarantees.
#include <tripsitter/render/bvh.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>

#include <tripsitter/render/ray_sphere.h>
#include <tripsitter/render/simd8.h>
#include <tripsitter/render/sphere_lanes.h>

namespace tripsitter::render {
namespace {

using namespace simd;  // F8 and the lane kernel (sphere_lanes, LaneRoots, keep_nearest)

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kWidth = Bvh::kWidth;

// Widens slab exits by the worst rounding of (plane - origin) * inv_dir, so culling never drops a box the ray
// enters (Ize 2013: 1 + 2 gamma(3)).
constexpr float kExitPad = 1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);

// Per-ray constants of the slab test. For each axis, the rows of Node::bounds holding the planes the ray meets
// first and last: lo then hi when moving towards +, hi then lo when moving towards -.
struct SlabRay {
  F8 origin[3];
  F8 inv_dir[3];  // 1/0 = +-inf: see enter_children
  int near[3], far[3];
};

SlabRay make_slab_ray(const Ray& ray) {
  SlabRay r;
  for (int a = 0; a < 3; ++a) {
    r.origin[a] = F8::set1(ray.origin[a]);
    r.inv_dir[a] = F8::set1(1.0f / ray.dir[a]);
    const int negative = std::signbit(ray.dir[a]) ? 1 : 0;
    r.near[a] = 2 * a + negative;
    r.far[a] = 2 * a + 1 - negative;
  }
  return r;
}

// Which of a node's children boxes the ray enters within [t_min, t_max] (bit k for child k), and where.
// A zero direction component makes its slab distances +-inf (outside or inside that slab), or NaN (0 * inf) when
// the origin lies on a plane of the slab; max/min below ignore NaN, treating the ray as inside: conservative.
// Empty slots (lo = +inf, hi = -inf) are never entered.
inline unsigned enter_children(const float (*bounds)[kWidth], const SlabRay& r, F8 t_min, float t_max,
                               float t_enter[kWidth]) {
  // max(x, acc) and min(x, acc) return acc when x is NaN.
  F8 t0 = t_min, t1 = F8::set1(t_max);
  const F8 pad = F8::set1(kExitPad);
  for (int a = 0; a < 3; ++a) {
    const F8 near = F8::load(bounds[r.near[a]]);
    const F8 far = F8::load(bounds[r.far[a]]);
    t0 = max((near - r.origin[a]) * r.inv_dir[a], t0);
    t1 = min((far - r.origin[a]) * r.inv_dir[a] * pad, t1);
  }
  t0.store(t_enter);
  return static_cast<unsigned>((t0 <= t1).bits());
}

// The kernel ray's terms broadcast to every lane, once per ray rather than once per leaf.
struct KernelRay8 {
  F8 ox, oy, oz, dx, dy, dz, dir_len2, inv_dir_len2, t_min;
};

KernelRay8 broadcast(const KernelRay& r, float t_min) {
  return {F8::set1(r.origin.x), F8::set1(r.origin.y), F8::set1(r.origin.z),
          F8::set1(r.dir.x),    F8::set1(r.dir.y),    F8::set1(r.dir.z),
          F8::set1(r.dir_len2), F8::set1(r.inv_dir_len2), F8::set1(t_min)};
}

// sphere_root on a leaf's spheres at once: bit k of the result is set when sphere k offers a root beyond t_min,
// which is then t[k]. Unused lanes (NaN centres) never hit.
inline unsigned sphere_roots(const KernelRay8& ray, const Bvh::Leaf& leaf, float t[kWidth]) {
  const F8 radius = F8::load(leaf.radius);
  const LaneRoots roots = sphere_lanes(ray.ox - F8::load(leaf.cx), ray.oy - F8::load(leaf.cy),
                                       ray.oz - F8::load(leaf.cz), ray.dx, ray.dy, ray.dz, ray.dir_len2,
                                       ray.inv_dir_len2, radius * radius, ray.t_min);
  roots.t.store(t);
  return static_cast<unsigned>(roots.hit.bits());
}

// A packet's rays, one per lane: the slab test's and the sphere kernel's per-ray terms, computed with the same
// operations as make_slab_ray and make_kernel_ray.
struct RayPacket {
  F8 origin[3], dir[3];
  F8 inv_dir[3];
  F8 negative[3];  // all ones where the direction component's sign bit is set
  F8 dir_len2, inv_dir_len2;
};

RayPacket make_packet(const Ray (&rays)[kWidth]) {
  alignas(32) float v[3][2][kWidth];
  for (int k = 0; k < kWidth; ++k) {
    for (int a = 0; a < 3; ++a) {
      v[a][0][k] = rays[k].origin[a];
      v[a][1][k] = rays[k].dir[a];
    }
  }
  RayPacket p;
  const F8 one = F8::set1(1.0f);
  for (int a = 0; a < 3; ++a) {
    p.origin[a] = F8::load(v[a][0]);
    p.dir[a] = F8::load(v[a][1]);
    p.inv_dir[a] = one / p.dir[a];
    // 1 / -0 = -inf: negative exactly where the sign bit is set, as std::signbit in make_slab_ray.
    p.negative[a] = p.inv_dir[a] < F8::set1(0.0f);
  }
  p.dir_len2 = p.dir[0] * p.dir[0] + p.dir[1] * p.dir[1] + p.dir[2] * p.dir[2];
  p.inv_dir_len2 = one / p.dir_len2;
  return p;
}

}  // namespace

const char* simd_instruction_set() {
#if defined(__AVX2__)
  return "AVX2 (x86-64-v3)";
#else
  return "SSE2 (x86-64)";
#endif
}

bool Bvh::intersect(const Ray& ray, float t_min, float t_max, SphereHit& hit) const {
  if (nodes_.empty()) return false;
  const KernelRay8 kray = broadcast(make_kernel_ray(ray), t_min);
  const SlabRay sray = make_slab_ray(ray);
  float best_t = t_max;
  std::uint32_t best = 0;  // original index of the best sphere
  bool found = false;

  const auto visit_leaf = [&](std::uint32_t leaf_index) {
    const Leaf& leaf = leaves_[leaf_index];
    alignas(32) float t[kWidth];
    for (unsigned hits = sphere_roots(kray, leaf, t); hits != 0; hits &= hits - 1) {
      const int k = __builtin_ctz(hits);
      const std::uint32_t original = leaf.original[k];
      // Equal t goes to the lower original index, as in brute force.
      if (t[k] < best_t || (found && t[k] == best_t && original < best)) {
        best_t = t[k];
        best = original;
        found = true;
      }
    }
  };

  // Nodes waiting to be visited and the t at which the ray enters their boxes; leaves are tested when met.
  struct Pending {
    std::uint32_t node;
    float t_enter;
  };
  Pending stack[(kWidth - 1) * kMaxDepth + 1];
  int size = 0;
  std::uint32_t node = 0;
  for (;;) {
    // Each visit tests the node's children, the leaves among them at once, and moves on to the next node.
    const Node& n = nodes_[node];
    alignas(32) float t_enter[kWidth];
    // Inclusive of best_t so that exact ties are still seen.
    unsigned enters = enter_children(n.bounds, sray, kray.t_min, best_t, t_enter);
    int order[kWidth];  // the children that are nodes, farthest first
    int nodes = 0;
    for (; enters != 0; enters &= enters - 1) {
      const int k = __builtin_ctz(enters);
      if (n.count[k] != Node::kInner) {
        if (t_enter[k] <= best_t) visit_leaf(n.first[k]);
        continue;
      }
#if defined(__GNUC__)
      // Start fetching the node while the others are sorted: most node visits miss the cache on big scenes.
      __builtin_prefetch(&nodes_[n.first[k]]);
#endif
      int j = nodes++;
      for (; j > 0 && t_enter[order[j - 1]] < t_enter[k]; --j) order[j] = order[j - 1];
      order[j] = k;
    }
    // The nearest node next, the others later; a leaf just tested may have moved best_t closer than them all.
    for (int j = 0; j + 1 < nodes; ++j) {
      assert(size < (kWidth - 1) * kMaxDepth + 1);
      stack[size++] = {n.first[order[j]], t_enter[order[j]]};
    }
    if (nodes > 0 && t_enter[order[nodes - 1]] <= best_t) {
      node = n.first[order[nodes - 1]];
      continue;
    }
    // Otherwise resume with the nearest pending node still in range.
    while (size > 0 && stack[size - 1].t_enter > best_t) --size;
    if (size == 0) break;
    node = stack[--size].node;
  }
  if (found) hit = {best_t, best};
  return found;
}

unsigned Bvh::intersect_packet(const Ray (&rays)[kWidth], float t_min, float t_max, SphereHit (&hits)[kWidth]) const {
  const RayPacket p = make_packet(rays);
  const F8 vt_min = F8::set1(t_min), pad = F8::set1(kExitPad);
  alignas(32) float best_t[kWidth];
  F8::set1(t_max).store(best_t);
  alignas(32) float best_id[kWidth] = {};  // original index of each lane's best sphere, as float bits
  unsigned found = 0;                       // lanes that hit

  // The tree walked once for all lanes (traverse): a box is entered when some lane enters it, its distance the
  // nearest entry among those lanes, and skipped when every lane has a hit nearer than that.
  const auto reach = [&](const float lo[3], const float hi[3]) {
    // The slab method lane by lane, the planes chosen by each lane's direction signs as make_slab_ray chooses
    // them, NaN (0 * inf) ignored as in enter_children.
    F8 t0 = vt_min, t1 = F8::load(best_t);
    for (int a = 0; a < 3; ++a) {
      const F8 near = select(p.negative[a], F8::set1(hi[a]), F8::set1(lo[a]));
      const F8 far = select(p.negative[a], F8::set1(lo[a]), F8::set1(hi[a]));
      t0 = max((near - p.origin[a]) * p.inv_dir[a], t0);
      t1 = min((far - p.origin[a]) * p.inv_dir[a] * pad, t1);
    }
    return select(t0 <= t1, t0, F8::set1(kInf)).min_lane();  // t0 is never NaN: max ignores NaN
  };
  const auto limit = [&] { return *std::max_element(best_t, best_t + kWidth); };
  // Each sphere of a leaf against every lane's ray.
  const auto leaf = [&](const Leaf& l, std::uint32_t count) {
    for (std::uint32_t i = 0; i < count; ++i) {
      const LaneRoots roots = sphere_lanes(p.origin[0] - F8::set1(l.cx[i]), p.origin[1] - F8::set1(l.cy[i]),
                                           p.origin[2] - F8::set1(l.cz[i]), p.dir[0], p.dir[1], p.dir[2],
                                           p.dir_len2, p.inv_dir_len2, F8::set1(l.radius[i] * l.radius[i]), vt_min);
      if (roots.hit.bits() != 0)
        found |= static_cast<unsigned>(keep_nearest(roots.hit, roots.t, l.original[i], best_t, best_id));
    }
  };
  traverse(reach, limit, leaf);
  for (int k = 0; k < kWidth; ++k) {
    if (found >> k & 1) hits[k] = {best_t[k], std::bit_cast<std::uint32_t>(best_id[k])};
  }
  return found;
}

}  // namespace tripsitter::render

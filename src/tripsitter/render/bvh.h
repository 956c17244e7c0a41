// Closest-hit queries over many spheres: a bounding volume hierarchy and the brute-force reference. This header is
// the contract; the code is split by job:
//   ray_sphere.h       the float ray-sphere kernel (sphere_root), inline; internal to the render library
//   ray_sphere.cpp     intersect_sphere: the kernel on one sphere
//   brute_force.cpp    intersect_brute_force: the kernel on every sphere in index order, the reference
//   bvh_builder.cpp    Bvh::build: binned-SAH binary tree, leaves as structures of arrays, collapse to 8-wide nodes
//   bvh_traversal.cpp  Bvh::intersect and Bvh::intersect_packet: the SIMD walks of one ray and of eight rays
//   simd8.h            eight floats at a time (F8), and sphere_lanes.h, the kernel lane by lane: both in the
//                      namespace of the instruction set they are compiled for (isa.h), safe to include anywhere
//
// Agreement with brute force. Every query performs the kernel's float operations in one order, per ray constants
// included (the SIMD lanes too: the render library is compiled with -ffp-contract=off), so each sphere gets the
// same t everywhere, and the BVH breaks exact ties towards the lower original index as brute force does. Box
// culling is conservative (boxes padded beyond the spheres' rounding, slab exits padded as in Ize, "Robust BVH Ray
// Traversal", 2013), so the BVH returns brute force's answer. The exceptions are hits decided by rounding alone:
// two spheres whose t differ by no more than float rounding (either may be returned), or a ray grazing a sphere at
// one of its box's faces (the hit may be dropped).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <tripsitter/render/ray.h>

namespace tripsitter::render {

struct SphereHit {
  float t = 0;
  std::uint32_t sphere = 0;  // index into the arrays the structure was built from
};

// The near intersection of ray and sphere with t in (t_min, t_max), else the far one in that range.
// Accurate for spheres far larger or farther away than the ray's scale (ground planes of radius 1e3..1e6).
bool intersect_sphere(const Ray& ray, const Vec3f& center, float radius, float t_min, float t_max, float& t);

// Closest hit by testing every sphere, the reference the BVH is tested against. Ties go to the lower index.
bool intersect_brute_force(std::span<const Vec3f> centers, std::span<const float> radii, const Ray& ray,
                           float t_min, float t_max, SphereHit& hit);

// What the render library's SIMD code was compiled for: "AVX2 (x86-64-v3)" or "SSE2 (x86-64)" (CMake option
// TRIPSITTER_X86_64_V3).
const char* simd_instruction_set();

class Bvh {
 public:
  // Children per node, spheres per leaf and rays per packet: one AVX register of floats (two SSE registers without
  // AVX).
  static constexpr int kWidth = 8;

  // Builds over spheres (REQUIRES centers.size() == radii.size(), radii > 0). Copies what it needs.
  static Bvh build(std::span<const Vec3f> centers, std::span<const float> radii);

  // Closest hit with t in (t_min, t_max): the same sphere and t as intersect_brute_force, ties aside.
  bool intersect(const Ray& ray, float t_min, float t_max, SphereHit& hit) const;

  // The closest hits of kWidth rays at once, each as intersect(rays[k], t_min, t_max, hits[k]) finds it, ties
  // aside; bit k of the result is set when rays[k] hits. For rays that travel together, such as a row of camera
  // rays, or start near each other, such as their bounces: they share one walk of the tree and each step serves
  // all of them.
  unsigned intersect_packet(const Ray (&rays)[kWidth], float t_min, float t_max, SphereHit (&hits)[kWidth]) const;

  // The closest hits of the rays of the lanes in `live` (bit k: rays[k]), each as intersect finds it: one packet
  // while kMinPacket or more lanes live (dead lanes trace a copy of a live lane's ray), else ray by ray. Returns the
  // lanes that hit, a subset of `live`; hits[k] holds the hit of each. For rays that started near each other, such
  // as a group's bounces, after some of them ended.
  static constexpr int kMinPacket = 6;  // on `field`'s bounced rays, 4 traced slower and 8 no faster
  unsigned intersect_live(unsigned live, const Ray (&rays)[kWidth], float t_min, float t_max,
                          SphereHit (&hits)[kWidth]) const;

  std::size_t sphere_count() const;
  std::size_t node_count() const;
  std::size_t memory_bytes() const;  // of everything the structure holds

  // The spheres of one leaf, a structure of arrays so that one SIMD load takes a coordinate of all of them. Lanes
  // past the leaf's count have NaN centres and radius 0: no ray hits them.
  struct alignas(32) Leaf {
    float cx[kWidth], cy[kWidth], cz[kWidth], radius[kWidth];
    std::uint32_t original[kWidth];  // index in the arrays the BVH was built from
  };

  // Depth-first traversal for queries other than one ray (a tile of rays, say). `reach(lo, hi)` returns the
  // distance at which the query reaches the box [lo, hi], or +inf when it cannot; of two children the nearer is
  // visited first, and a box is skipped when its distance exceeds `limit()` at the time it comes up. `leaf(leaf,
  // count)` gets a leaf and its number of spheres (lanes 0 .. count - 1).
  template <class Reach, class Limit, class LeafVisit>
  void traverse(Reach&& reach, Limit&& limit, LeafVisit&& leaf) const;

  // The deepest a BVH gets (see bvh_builder.cpp); a depth-first traversal keeps at most kWidth - 1 pending
  // children per level.
  static constexpr int kMaxDepth = 64;

 private:
  // Implementation state, free to change; see bvh_builder.cpp and bvh_traversal.cpp for the layout's reasons and
  // invariants.

  // A node holds the boxes of its up to kWidth children, one axis and side per row, so that one SIMD operation
  // tests all of them against a ray. A child is another node or a leaf. Built as a binary tree and collapsed
  // (see bvh_builder.cpp).
  struct alignas(64) Node {
    static constexpr std::uint32_t kInner = 0xffffffff;  // count of a child that is a node
    float bounds[6][kWidth];        // [2 * axis + side][child], side 0 = lo, 1 = hi; empty slots: lo = +inf, hi = -inf
    std::uint32_t first[kWidth];    // node child: its node index; leaf child: its index in leaves_
    std::uint32_t count[kWidth];    // kInner, the leaf's number of spheres, or 0 for an empty slot
  };
  std::vector<Node> nodes_;    // nodes_[0] is the root; empty when built over no spheres
  std::vector<Leaf> leaves_;
  std::size_t spheres_ = 0;
};

template <class Reach, class Limit, class LeafVisit>
void Bvh::traverse(Reach&& reach, Limit&& limit, LeafVisit&& leaf) const {
  if (nodes_.empty()) return;
  struct Pending {
    std::uint32_t first, count;
    float distance;
  };
  Pending stack[(kWidth - 1) * kMaxDepth + 1];
  int size = 0;
  stack[size++] = {0, Node::kInner, -std::numeric_limits<float>::infinity()};  // the root is always visited
  while (size > 0) {
    const Pending p = stack[--size];
    if (p.distance > limit()) continue;
    if (p.count != Node::kInner) {
      leaf(leaves_[p.first], p.count);
      continue;
    }
    const Node& n = nodes_[p.first];
    float distance[kWidth];
    int order[kWidth];
    int hits = 0;
    for (int k = 0; k < kWidth; ++k) {
      if (n.count[k] == 0) continue;
      const float lo[3] = {n.bounds[0][k], n.bounds[2][k], n.bounds[4][k]};
      const float hi[3] = {n.bounds[1][k], n.bounds[3][k], n.bounds[5][k]};
      distance[k] = reach(lo, hi);
      if (!(distance[k] < std::numeric_limits<float>::infinity())) continue;
      // Insertion by distance, farthest first, so that the nearest is pushed last and visited next.
      int j = hits++;
      for (; j > 0 && distance[order[j - 1]] < distance[k]; --j) order[j] = order[j - 1];
      order[j] = k;
    }
    for (int j = 0; j < hits; ++j) stack[size++] = {n.first[order[j]], n.count[order[j]], distance[order[j]]};
  }
}

// Inline: the path tracer calls it once per round of bounces of a group.
inline unsigned Bvh::intersect_live(unsigned live, const Ray (&rays)[kWidth], float t_min, float t_max,
                                    SphereHit (&hits)[kWidth]) const {
  if (std::popcount(live) < kMinPacket) {
    unsigned found = 0;
    for (; live != 0; live &= live - 1) {
      const int i = std::countr_zero(live);
      found |= intersect(rays[i], t_min, t_max, hits[i]) ? 1u << i : 0u;
    }
    return found;
  }
  const Ray& spare = rays[std::countr_zero(live)];
  Ray packet[kWidth];
  for (int i = 0; i < kWidth; ++i) packet[i] = live >> i & 1 ? rays[i] : spare;
  return intersect_packet(packet, t_min, t_max, hits) & live;
}

}  // namespace tripsitter::render

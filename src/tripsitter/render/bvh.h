// Closest-hit queries over many spheres: a bounding volume hierarchy and the brute-force reference.
#pragma once

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

class Bvh {
 public:
  // Builds over spheres (REQUIRES centers.size() == radii.size(), radii > 0). Copies what it needs.
  static Bvh build(std::span<const Vec3f> centers, std::span<const float> radii);

  // Closest hit with t in (t_min, t_max): the same sphere and t as intersect_brute_force, ties aside.
  bool intersect(const Ray& ray, float t_min, float t_max, SphereHit& hit) const;

  std::size_t sphere_count() const;
  std::size_t node_count() const;
  std::size_t memory_bytes() const;  // of everything the structure holds

  struct Sphere {
    Vec3f center;
    float radius;
  };

  // Depth-first traversal for queries other than one ray (a tile of rays, say). `reach(lo, hi)` returns the
  // distance at which the query reaches the box [lo, hi], or +inf when it cannot; of two children the nearer is
  // visited first, and a box is skipped when its distance exceeds `limit()` at the time it comes up. `leaf(spheres,
  // original, count)` gets `count` spheres in leaf order and their indices in the arrays the BVH was built from.
  template <class Reach, class Limit, class Leaf>
  void traverse(Reach&& reach, Limit&& limit, Leaf&& leaf) const;

  // The deepest a BVH gets (see bvh.cpp): depth-first traversals keep at most this many pending children.
  static constexpr int kMaxDepth = 64;

 private:
  // Implementation state, free to change; see bvh.cpp for the layout's reasons and invariants.

  // An inner node holds the boxes of both its children, so one 64-byte cache line answers which children a ray
  // enters. A child is either another inner node or a leaf: a run of spheres in leaf order.
  struct alignas(64) Node {
    static constexpr std::uint32_t kInner = 0xffffffff;  // count of a child that is an inner node
    float bounds[12];          // [4 * axis + 2 * side + child], side 0 = lo, 1 = hi
    std::uint32_t first[2];    // inner child: its node index; leaf child: its first sphere in leaf order
    std::uint32_t count[2];    // kInner, or the leaf's number of spheres (0 only for the empty child of a 1-sphere root)
  };
  std::vector<Node> nodes_;            // nodes_[0] is the root; empty when built over no spheres
  std::vector<Sphere> spheres_;        // in leaf order
  std::vector<std::uint32_t> index_;   // leaf order -> original index
};

template <class Reach, class Limit, class Leaf>
void Bvh::traverse(Reach&& reach, Limit&& limit, Leaf&& leaf) const {
  if (nodes_.empty()) return;
  struct Pending {
    std::uint32_t first, count;
    float distance;
  };
  Pending stack[kMaxDepth + 1];
  int size = 0;
  stack[size++] = {0, Node::kInner, 0.0f};
  while (size > 0) {
    const Pending p = stack[--size];
    if (p.distance > limit()) continue;
    if (p.count != Node::kInner) {
      leaf(&spheres_[p.first], &index_[p.first], p.count);
      continue;
    }
    const Node& n = nodes_[p.first];
    float distance[2];
    for (int k = 0; k < 2; ++k) {
      const float lo[3] = {n.bounds[k], n.bounds[4 + k], n.bounds[8 + k]};
      const float hi[3] = {n.bounds[2 + k], n.bounds[6 + k], n.bounds[10 + k]};
      distance[k] = n.count[k] == 0 ? std::numeric_limits<float>::infinity() : reach(lo, hi);
    }
    // The farther child is pushed first, so the nearer one is visited next.
    const int near = distance[1] < distance[0] ? 1 : 0;
    for (int k : {1 - near, near}) {
      if (distance[k] < std::numeric_limits<float>::infinity()) stack[size++] = {n.first[k], n.count[k], distance[k]};
    }
  }
}

}  // namespace tripsitter::render

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

  // The deepest a BVH gets (see bvh.cpp); a depth-first traversal keeps at most 3 pending children per level.
  static constexpr int kMaxDepth = 64;

 private:
  // Implementation state, free to change; see bvh.cpp for the layout's reasons and invariants.

  // A node holds the boxes of its up to four children, one axis and side per 16 bytes, so that one SSE
  // operation tests all four against a ray. A child is another node or a leaf: a run of up to four spheres in
  // leaf order. Built as a binary tree and collapsed (see bvh.cpp).
  struct alignas(64) Node {
    static constexpr std::uint32_t kInner = 0xffffffff;  // count of a child that is a node
    float bounds[6][4];        // [2 * axis + side][child], side 0 = lo, 1 = hi; empty slots: lo = +inf, hi = -inf
    std::uint32_t first[4];    // node child: its node index; leaf child: its first sphere in leaf order
    std::uint32_t count[4];    // kInner, the leaf's number of spheres, or 0 for an empty slot
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
  Pending stack[3 * kMaxDepth + 1];
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
    float distance[4];
    int order[4];
    int hits = 0;
    for (int k = 0; k < 4; ++k) {
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

}  // namespace tripsitter::render

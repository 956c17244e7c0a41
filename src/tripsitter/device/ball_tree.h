// A hierarchy of balls around groups of spheres: the fast models' search for rays that are not the camera's
// (FastTracer's reflected and bounced rays, and the artix path preset's bounced rays, artix_units.h). A ray whose
// line misses a ball, or that finds the ball wholly behind its origin, meets none of the spheres inside, so the
// search tests only the spheres of the balls a ray may meet and finds the same closest hit as testing them all.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <tripsitter/core/fixed.h>
#include <tripsitter/core/isqrt.h>

namespace tripsitter::device {

struct BallTree {
  // A ball (integer centre, radius squared) holding every member whole: a leaf's spheres are
  // order[first, first + count); an inner node's two halves are nodes[left] and nodes[left + 1].
  struct Ball {
    std::array<std::int64_t, 3> c{};
    std::int64_t r2 = 0;
    int first = 0, count = 0;  // count == 0 for an inner node
    int left = 0;
  };
  std::vector<Ball> nodes;  // nodes[0] the root
  std::vector<int> order;   // the sphere indices grouped by leaf
};

namespace ball_tree_detail {

inline constexpr int kLeafSpheres = 4;

// nodes[node] around order[first, first + count), and its subtree. The ball's centre is the middle of the members'
// bounding box (radii included), its radius the largest ceil(|c_i - centre|) + r_i; the split is at the median
// centre along the axis where the centres spread most. REQUIRES centres within (-2^29, 2^29), radii below 2^30.
template <class Centre, class Radius>
void build(BallTree& t, const Centre& centre, const Radius& radius, std::size_t node, int first, int count) {
  constexpr std::int64_t kFar = std::int64_t{1} << 40;
  std::array<std::int64_t, 3> lo{kFar, kFar, kFar}, hi{-kFar, -kFar, -kFar};
  std::array<std::int64_t, 3> centre_lo = lo, centre_hi = hi;
  const auto member = [&](int j) { return t.order[static_cast<std::size_t>(j)]; };
  for (int j = first; j < first + count; ++j) {
    const std::array<std::int64_t, 3> c = centre(member(j));
    const std::int64_t r = radius(member(j));
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], c[k] - r);
      hi[k] = std::max(hi[k], c[k] + r);
      centre_lo[k] = std::min(centre_lo[k], c[k]);
      centre_hi[k] = std::max(centre_hi[k], c[k]);
    }
  }
  BallTree::Ball ball;
  for (std::size_t k = 0; k < 3; ++k) ball.c[k] = lo[k] + (hi[k] - lo[k]) / 2;
  std::int64_t r = 0;
  for (int j = first; j < first + count; ++j) {
    const std::array<std::int64_t, 3> c = centre(member(j));
    const std::int64_t ox = c[0] - ball.c[0], oy = c[1] - ball.c[1], oz = c[2] - ball.c[2];
    const auto squared = static_cast<std::uint64_t>(ox * ox + oy * oy + oz * oz);
    r = std::max(r, static_cast<std::int64_t>(core::ceil_isqrt(squared)) + radius(member(j)));
  }
  ball.r2 = r * r;
  ball.first = first;
  if (count <= kLeafSpheres) {
    ball.count = count;
    t.nodes[node] = ball;
    return;
  }
  std::size_t axis = 0;
  for (std::size_t k = 1; k < 3; ++k)
    if (centre_hi[k] - centre_lo[k] > centre_hi[axis] - centre_lo[axis]) axis = k;
  const auto begin = t.order.begin() + first;
  std::nth_element(begin, begin + count / 2, begin + count, [&](int a, int b) { return centre(a)[axis] < centre(b)[axis]; });
  ball.left = static_cast<int>(t.nodes.size());
  t.nodes[node] = ball;
  t.nodes.resize(t.nodes.size() + 2);
  build(t, centre, radius, static_cast<std::size_t>(ball.left), first, count / 2);
  build(t, centre, radius, static_cast<std::size_t>(ball.left) + 1, first + count / 2, count - count / 2);
}

}  // namespace ball_tree_detail

// The hierarchy around n spheres, sphere i with centre centre(i) (std::array<std::int64_t, 3>) and radius
// radius(i): the radius a ray's line must come within for a hit (the sphere's own, or a search's reach beyond it).
template <class Centre, class Radius>
BallTree build_ball_tree(std::size_t n, const Centre& centre, const Radius& radius) {
  BallTree t;
  t.order.resize(n);
  for (std::size_t i = 0; i < n; ++i) t.order[i] = static_cast<int>(i);
  t.nodes.assign(1, BallTree::Ball{});
  if (n > 0) ball_tree_detail::build(t, centre, radius, 0, 0, static_cast<int>(n));
  return t;
}

// Calls sphere(i) for every sphere of every leaf whose ball the ray from o along d (a = d.d) may meet, depth first.
// REQUIRES |o_k|, |c_k| below 2^30 and |d_k| below 2^21 (so d.(c - o) and |c - o|^2 fit 64 bits).
template <class Sphere>
void for_each_ball_member(const BallTree& t, const std::array<std::int64_t, 3>& o, const std::array<std::int64_t, 3>& d,
                          std::int64_t a, const Sphere& sphere) {
  using core::Int128;
  std::array<int, 64> stack;  // the hierarchy is at most 20 levels deep for a million spheres
  std::size_t top = 0;
  if (!t.order.empty()) stack[top++] = 0;
  while (top > 0) {
    const BallTree::Ball& ball = t.nodes[static_cast<std::size_t>(stack[--top])];
    const std::int64_t bx = ball.c[0] - o[0], by = ball.c[1] - o[1], bz = ball.c[2] - o[2];
    const std::int64_t u = d[0] * bx + d[1] * by + d[2] * bz;
    const Int128 u2 = Int128{u} * u;
    if (u <= 0 && u2 >= Int128{a} * ball.r2) continue;  // the ball is wholly behind the origin
    if (u2 < Int128{a} * (bx * bx + by * by + bz * bz - ball.r2)) continue;  // the line misses the ball
    if (ball.count == 0) {
      stack[top++] = ball.left;
      stack[top++] = ball.left + 1;
      continue;
    }
    for (int j = ball.first; j < ball.first + ball.count; ++j) sphere(t.order[static_cast<std::size_t>(j)]);
  }
}

}  // namespace tripsitter::device

// Closest-hit queries over spheres: the float ray-sphere kernel, the brute-force reference and a binned-SAH BVH.
//
// Agreement with brute force. Brute force, the BVH leaves and intersect_sphere all call one compiled kernel with the
// same per-ray constants, so each sphere gets bit-identical t everywhere, and the BVH breaks exact ties towards the lower
// original index as brute force does. Box culling is conservative (boxes padded beyond the spheres' rounding, slab
// exits padded as in Ize, "Robust BVH Ray Traversal", 2013), so the BVH returns brute force's answer. The exceptions
// are hits decided by rounding alone: two spheres whose t differ by no more than float rounding (either may be
// returned), or a ray grazing a sphere at one of its box's faces (the hit may be dropped).
#include <tripsitter/render/bvh.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace tripsitter::render {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Per-ray constants of the sphere kernel. Every caller computes them through make_kernel_ray, so every caller
// performs the same float operations for a given sphere.
struct KernelRay {
  Vec3f origin;
  Vec3f dir;
  float dir_len2;      // |dir|^2, the a of the quadratic
  float inv_dir_len2;  // 1 / |dir|^2 (inf for a zero direction, which the kernel then rejects)
};

KernelRay make_kernel_ray(const Ray& ray) {
  const float a = dot(ray.dir, ray.dir);
  return {ray.origin, ray.dir, a, 1.0f / a};
}

// The root chosen by t_min alone: the near root if it lies beyond t_min, else the far root if that does.
// Callers then require t < t_max; since far >= near this equals choosing within (t_min, t_max) directly,
// and it lets the BVH compare against a t_max that shrinks without changing which root a sphere offers.
// Kept out of line so that one compiled copy serves every caller: inlined copies may be contracted into FMAs
// differently (-ffp-contract=fast with -march=native), and then brute force and BVH would round near-ties apart.
// Costs ~1.5% of BVH throughput.
[[gnu::noinline]] bool sphere_root(const KernelRay& ray, const Vec3f& center, float radius, float t_min, float& t) {
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

// ---------------------------------------------------------------------------------------------------------------
// Build: binned SAH (Wald, "On fast construction of SAH-based bounding volume hierarchies", 2007) over the centroids,
// binning all three axes in one pass, depth-first so that a parent and its first subtree sit together in memory.

constexpr std::uint32_t kMaxLeafSize = 4;
constexpr int kBins = 16;
// SAH costs relative to one sphere test. A node visit (two boxes, often a cache miss) costs about two sphere tests
// on the scenes we measured (RTOW cover, a million spheres); 1 gives mostly 1-sphere leaves and ~40% more nodes.
constexpr float kTraversalCost = 2.0f;
constexpr float kSphereCost = 1.0f;
// Below this depth splits follow the SAH; deeper, at the median, which halves the count. Depth therefore stays
// under kMaxSahDepth + log2(2^32 / kMaxLeafSize) <= 62 < kStackSize, whatever the distribution.
constexpr std::uint32_t kMaxSahDepth = 32;
constexpr int kStackSize = Bvh::kMaxDepth;

struct Box {
  Vec3f lo{kInf, kInf, kInf};
  Vec3f hi{-kInf, -kInf, -kInf};

  void grow(const Vec3f& p) { grow(p, p); }
  void grow(const Box& b) { grow(b.lo, b.hi); }
  void grow(const Vec3f& l, const Vec3f& h) {
    lo = {std::min(lo.x, l.x), std::min(lo.y, l.y), std::min(lo.z, l.z)};
    hi = {std::max(hi.x, h.x), std::max(hi.y, h.y), std::max(hi.z, h.z)};
  }
  float half_area() const {
    const Vec3f e = hi - lo;
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

// A sphere during the build. The radius is padded by a few ulps of the sphere's coordinates so that the box
// c +- radius, rounded to float, still holds the sphere.
struct PrimRef {
  Vec3f center;
  float radius;
  std::uint32_t index;

  Box box() const { return {center - Vec3f{radius, radius, radius}, center + Vec3f{radius, radius, radius}}; }
};

float padded_radius(const Vec3f& c, float r) {
  const float scale = std::max({std::abs(c.x), std::abs(c.y), std::abs(c.z), r});
  return r + scale * 0x1p-22f;
}

struct Bin {
  Box box;
  std::uint32_t count = 0;
};

// The bin of a centroid coordinate. Binning and partitioning both call this, so they agree exactly.
inline int bin_of(float x, float lo, float scale) {
  return std::min(static_cast<int>((x - lo) * scale), kBins - 1);
}

struct Split {
  float cost = kInf;     // SAH cost relative to kSphereCost per sphere of the parent; kInf: median split
  int axis = 0;
  int bin = 0;           // spheres in bins < bin go left
  float lo = 0, scale = 0;
  Box left, right;
};

// Builds the node array over refs, reordering refs into leaf order. A template over the node type only because
// Bvh::Node is private to Bvh; it is instantiated once, from Bvh::build.
template <class Node>
class Builder {
 public:
  Builder(std::vector<PrimRef>& refs, std::vector<Node>& nodes) : refs_(refs), nodes_(nodes) {}

  void run() {
    const auto n = static_cast<std::uint32_t>(refs_.size());
    Box all;
    for (const PrimRef& r : refs_) all.grow(r.box());
    nodes_.reserve(n / 8 * 5 + 1);  // typically 0.45 n to 0.6 n inner nodes; shrunk to fit afterwards
    nodes_.emplace_back();
    if (n == 1) {
      // The root is always an inner node; a lone sphere gets a leaf and an empty child whose box no ray enters.
      set_child(0, 0, all, 0, 1);
      set_child(0, 1, Box{}, 0, 0);
      return;
    }
    split_into(0, 0, n, all, 0);
    while (!tasks_.empty()) {
      const Task task = tasks_.back();
      tasks_.pop_back();
      const std::uint32_t count = task.end - task.begin;
      const Split split = count > 1 ? find_split(task.begin, task.end, task.box, task.depth) : Split{};
      const bool sah_prefers_leaf = split.cost >= kSphereCost * static_cast<float>(count);
      if (count <= kMaxLeafSize && sah_prefers_leaf) {
        set_child(task.node, task.slot, task.box, task.begin, count);
        continue;
      }
      const auto node = static_cast<std::uint32_t>(nodes_.size());
      nodes_.emplace_back();
      set_child(task.node, task.slot, task.box, node, Node::kInner);
      apply(split, node, task.begin, task.end, task.depth + 1);
    }
  }

 private:
  // A range of refs waiting to become child `slot` of `node`.
  struct Task {
    std::uint32_t node, slot, begin, end, depth;
    Box box;
  };

  // Splits refs[begin, end) (at least 2) into the two children of `node`.
  void split_into(std::uint32_t node, std::uint32_t begin, std::uint32_t end, const Box& box, std::uint32_t depth) {
    apply(find_split(begin, end, box, depth), node, begin, end, depth + 1);
  }

  void apply(const Split& split, std::uint32_t node, std::uint32_t begin, std::uint32_t end,
             std::uint32_t child_depth) {
    assert(child_depth < static_cast<std::uint32_t>(kStackSize));
    std::uint32_t mid;
    Box left = split.left, right = split.right;
    if (split.cost < kInf) {
      const auto first_right =
          std::partition(refs_.begin() + begin, refs_.begin() + end, [&split](const PrimRef& r) {
            return bin_of(r.center[split.axis], split.lo, split.scale) < split.bin;
          });
      mid = static_cast<std::uint32_t>(first_right - refs_.begin());
    } else {
      mid = median_split(begin, end, left, right);
    }
    assert(begin < mid && mid < end);
    // Pushed right first so that the left subtree is built, and laid out, right after its parent.
    tasks_.push_back({node, 1, mid, end, child_depth, right});
    tasks_.push_back({node, 0, begin, mid, child_depth, left});
  }

  // The best SAH split of refs[begin, end) over 3 x kBins bins, or a median split (cost kInf) when no binned split
  // separates the spheres (coincident centroids) or the tree is already deep.
  Split find_split(std::uint32_t begin, std::uint32_t end, const Box& box, std::uint32_t depth) const {
    Split best;
    if (depth >= kMaxSahDepth) return best;
    Box centroids;
    for (std::uint32_t i = begin; i < end; ++i) centroids.grow(refs_[i].center);
    float scale[3];
    for (int a = 0; a < 3; ++a) {
      const float extent = centroids.hi[a] - centroids.lo[a];
      scale[a] = extent > 0.0f ? kBins / extent : 0.0f;
      if (!(scale[a] < kInf)) scale[a] = 0.0f;  // subnormal extent: treat as flat
    }
    Bin bins[3][kBins];
    for (std::uint32_t i = begin; i < end; ++i) {
      const PrimRef& r = refs_[i];
      const Box b = r.box();
      for (int a = 0; a < 3; ++a) {
        Bin& bin = bins[a][bin_of(r.center[a], centroids.lo[a], scale[a])];
        bin.box.grow(b);
        ++bin.count;
      }
    }
    const float inv_parent_area = 1.0f / box.half_area();
    for (int a = 0; a < 3; ++a) {
      if (scale[a] == 0.0f) continue;
      // Sweep from the right to get the cost of every right side, then from the left to evaluate each plane.
      float right_cost[kBins];
      Box right_box[kBins];
      Box acc;
      std::uint32_t acc_count = 0;
      for (int k = kBins - 1; k > 0; --k) {
        acc.grow(bins[a][k].box);
        acc_count += bins[a][k].count;
        right_box[k] = acc;
        right_cost[k] = acc_count ? acc.half_area() * static_cast<float>(acc_count) : 0.0f;
      }
      acc = Box{};
      acc_count = 0;
      const std::uint32_t total = end - begin;
      for (int k = 1; k < kBins; ++k) {
        acc.grow(bins[a][k - 1].box);
        acc_count += bins[a][k - 1].count;
        if (acc_count == 0 || acc_count == total) continue;  // one side empty: not a split
        const float cost =
            kTraversalCost + kSphereCost * (acc.half_area() * static_cast<float>(acc_count) + right_cost[k]) *
                                 inv_parent_area;
        if (cost < best.cost) {
          best = {cost, a, k, centroids.lo[a], scale[a], acc, right_box[k]};
        }
      }
    }
    return best;
  }

  // Splits at the median centroid of the widest centroid axis; returns the first index of the right half.
  std::uint32_t median_split(std::uint32_t begin, std::uint32_t end, Box& left, Box& right) {
    Box centroids;
    for (std::uint32_t i = begin; i < end; ++i) centroids.grow(refs_[i].center);
    const Vec3f e = centroids.hi - centroids.lo;
    const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(refs_.begin() + begin, refs_.begin() + mid, refs_.begin() + end,
                     [axis](const PrimRef& p, const PrimRef& q) { return p.center[axis] < q.center[axis]; });
    left = right = Box{};
    for (std::uint32_t i = begin; i < mid; ++i) left.grow(refs_[i].box());
    for (std::uint32_t i = mid; i < end; ++i) right.grow(refs_[i].box());
    return mid;
  }

  void set_child(std::uint32_t node, int slot, const Box& box, std::uint32_t first, std::uint32_t count) {
    Node& n = nodes_[node];
    for (int a = 0; a < 3; ++a) {
      n.bounds[4 * a + slot] = box.lo[a];
      n.bounds[4 * a + 2 + slot] = box.hi[a];
    }
    n.first[slot] = first;
    n.count[slot] = count;
  }

  std::vector<PrimRef>& refs_;
  std::vector<Node>& nodes_;
  std::vector<Task> tasks_;
};

// Widens slab exits by the worst rounding of (plane - origin) * inv_dir, so culling never drops a box the ray
// enters (Ize 2013: 1 + 2 gamma(3)).
constexpr float kExitPad = 1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);

// Per-ray constants of the slab test. For each axis, offsets into Node::bounds of the pair of planes (one per child)
// the ray meets first and last: lo then hi when moving towards +, hi then lo when moving towards -.
struct SlabRay {
  float origin[3];
  float inv_dir[3];  // 1/0 = +-inf: see enter_children
  int near[3], far[3];
};

SlabRay make_slab_ray(const Ray& ray) {
  SlabRay r;
  for (int a = 0; a < 3; ++a) {
    r.origin[a] = ray.origin[a];
    r.inv_dir[a] = 1.0f / ray.dir[a];
    const int negative = std::signbit(ray.dir[a]) ? 1 : 0;
    r.near[a] = 4 * a + 2 * negative;
    r.far[a] = 4 * a + 2 * (1 - negative);
  }
  return r;
}

// Which of a node's two child boxes the ray enters within [t_min, t_max] (bit k for child k), and where.
// A zero direction component makes its slab distances +-inf (outside or inside that slab), or NaN (0 * inf) when
// the origin lies on a plane of the slab; the max/min below ignore NaN, treating the ray as inside: conservative.
inline unsigned enter_children(const float* bounds, const SlabRay& r, float t_min, float t_max, float t_enter[2]) {
#if defined(__SSE2__) && !defined(TRIPSITTER_BVH_NO_SIMD)
  // Both children in lanes 0 and 1. _mm_max_ps(x, acc) and _mm_min_ps(x, acc) return acc when x is NaN.
  __m128 t0 = _mm_set1_ps(t_min), t1 = _mm_set1_ps(t_max);
  const __m128 pad = _mm_set1_ps(kExitPad);
  for (int a = 0; a < 3; ++a) {
    const __m128 o = _mm_set1_ps(r.origin[a]), inv = _mm_set1_ps(r.inv_dir[a]);
    const __m128 near = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(bounds + r.near[a])));
    const __m128 far = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(bounds + r.far[a])));
    t0 = _mm_max_ps(_mm_mul_ps(_mm_sub_ps(near, o), inv), t0);
    t1 = _mm_min_ps(_mm_mul_ps(_mm_mul_ps(_mm_sub_ps(far, o), inv), pad), t1);
  }
  _mm_storel_pi(reinterpret_cast<__m64*>(t_enter), t0);
  return static_cast<unsigned>(_mm_movemask_ps(_mm_cmple_ps(t0, t1))) & 3u;
#else
  unsigned mask = 0;
  for (int k = 0; k < 2; ++k) {
    float t0 = t_min, t1 = t_max;
    for (int a = 0; a < 3; ++a) {
      const float near = (bounds[r.near[a] + k] - r.origin[a]) * r.inv_dir[a];
      const float far = (bounds[r.far[a] + k] - r.origin[a]) * r.inv_dir[a] * kExitPad;
      t0 = near > t0 ? near : t0;  // NaN ignored
      t1 = far < t1 ? far : t1;
    }
    t_enter[k] = t0;
    mask |= (t0 <= t1 ? 1u : 0u) << k;
  }
  return mask;
#endif
}

}  // namespace

bool intersect_sphere(const Ray& ray, const Vec3f& center, float radius, float t_min, float t_max, float& t) {
  float root;
  if (!sphere_root(make_kernel_ray(ray), center, radius, t_min, root) || !(root < t_max)) return false;
  t = root;
  return true;
}

bool intersect_brute_force(std::span<const Vec3f> centers, std::span<const float> radii, const Ray& ray,
                           float t_min, float t_max, SphereHit& hit) {
  assert(centers.size() == radii.size());
  const KernelRay kray = make_kernel_ray(ray);
  bool found = false;
  for (std::size_t i = 0; i < centers.size(); ++i) {
    float t;
    if (sphere_root(kray, centers[i], radii[i], t_min, t) && t < t_max) {  // strict: ties keep the lower index
      t_max = t;
      hit = {t, static_cast<std::uint32_t>(i)};
      found = true;
    }
  }
  return found;
}

Bvh Bvh::build(std::span<const Vec3f> centers, std::span<const float> radii) {
  assert(centers.size() == radii.size());
  assert(centers.size() < std::size_t{Node::kInner});
  Bvh bvh;
  const std::size_t n = centers.size();
  if (n == 0) return bvh;
  std::vector<PrimRef> refs(n);
  for (std::size_t i = 0; i < n; ++i) {
    refs[i] = {centers[i], padded_radius(centers[i], radii[i]), static_cast<std::uint32_t>(i)};
  }
  Builder<Node>(refs, bvh.nodes_).run();
  bvh.nodes_.shrink_to_fit();
  bvh.spheres_.resize(n);
  bvh.index_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t original = refs[i].index;
    bvh.spheres_[i] = {centers[original], radii[original]};
    bvh.index_[i] = original;
  }
  return bvh;
}

bool Bvh::intersect(const Ray& ray, float t_min, float t_max, SphereHit& hit) const {
  if (nodes_.empty()) return false;
  const KernelRay kray = make_kernel_ray(ray);
  const SlabRay sray = make_slab_ray(ray);

  bool found = false;
  float best_t = t_max;
  std::uint32_t best = 0;  // original index of the best sphere
  const auto visit_leaf = [&](std::uint32_t first, std::uint32_t count) {
    for (std::uint32_t i = first; i < first + count; ++i) {
      float t;
      if (!sphere_root(kray, spheres_[i].center, spheres_[i].radius, t_min, t)) continue;
      // Equal t goes to the lower original index, as in brute force.
      if (t < best_t || (found && t == best_t && index_[i] < best)) {
        best_t = t;
        best = index_[i];
        found = true;
      }
    }
  };

  // Children waiting to be visited: a node or leaf reference and the t at which the ray enters its box.
  struct Pending {
    std::uint32_t first, count;
    float t_enter;
  };
  Pending stack[kStackSize];
  int size = 0;
  std::uint32_t node = 0;
  for (;;) {
    const Node& n = nodes_[node];
#if defined(__GNUC__)
    // Start fetching the inner children while the boxes are tested: +25% on a million spheres, where most node
    // visits miss the cache.
    for (int k = 0; k < 2; ++k) {
      if (n.count[k] == Node::kInner) __builtin_prefetch(&nodes_[n.first[k]]);
    }
#endif
    float t_enter[2];
    // Inclusive of best_t so that exact ties are still seen.
    const unsigned enters = enter_children(n.bounds, sray, t_min, best_t, t_enter);
    // Nearer child first; the other waits on the stack unless both are leaves, which are simply tested in order.
    bool descended = false;
    if (enters != 0) {
      const int c0 = enters == 3 ? (t_enter[1] < t_enter[0] ? 1 : 0) : (enters == 2 ? 1 : 0);
      const int c1 = 1 - c0;
      if (n.count[c0] != Node::kInner) {
        visit_leaf(n.first[c0], n.count[c0]);
      } else {
        node = n.first[c0];
        descended = true;
      }
      if (enters == 3 && t_enter[c1] <= best_t) {
        if (descended) {
          assert(size < kStackSize);
          stack[size++] = {n.first[c1], n.count[c1], t_enter[c1]};
        } else if (n.count[c1] != Node::kInner) {
          visit_leaf(n.first[c1], n.count[c1]);
        } else {
          node = n.first[c1];
          descended = true;
        }
      }
    }
    // Otherwise resume with the nearest pending child still in range; leaves are tested on the way.
    while (!descended) {
      if (size == 0) {
        if (found) hit = {best_t, best};
        return found;
      }
      const Pending p = stack[--size];
      if (p.t_enter > best_t) continue;
      if (p.count != Node::kInner) {
        visit_leaf(p.first, p.count);
      } else {
        node = p.first;
        descended = true;
      }
    }
  }
}

std::size_t Bvh::sphere_count() const { return spheres_.size(); }
std::size_t Bvh::node_count() const { return nodes_.size(); }
std::size_t Bvh::memory_bytes() const {
  return sizeof(*this) + nodes_.capacity() * sizeof(Node) + spheres_.capacity() * sizeof(Sphere) +
         index_.capacity() * sizeof(std::uint32_t);
}

}  // namespace tripsitter::render

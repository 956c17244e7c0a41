// Closest-hit queries over spheres: the float ray-sphere kernel, the brute-force reference and a binned-SAH BVH.
//
// Agreement with brute force. Brute force, the BVH leaves and intersect_sphere all call one compiled kernel with the
// same per-ray constants, so each sphere gets bit-identical t everywhere, and the BVH breaks exact ties towards the lower
// original index as brute force does. Box culling is conservative (boxes padded beyond the spheres' rounding, slab
// exits padded as in Ize, "Robust BVH Ray Traversal", 2013), so the BVH returns brute force's answer. The exceptions
// are hits decided by rounding alone: two spheres whose t differ by no more than float rounding (either may be
// returned), or a ray grazing a sphere at one of its box's faces (the hit may be dropped).
//
// Nodes test their eight children's boxes, and leaves their up to eight spheres, in one SIMD step (simd8.h: AVX
// where compiled for it, else two SSE halves). Each lane performs the scalar kernel's operations in its order (the
// render library is compiled with -ffp-contract=off, so no multiply-add is ever fused), so lanes and scalar calls
// give the same t.
#include <tripsitter/render/bvh.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>

namespace tripsitter::render {
namespace {

#include <tripsitter/render/simd8.h>
#include <tripsitter/render/sphere_lanes.h>

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
// sphere_roots (below) and primary.cpp's tiles repeat these operations lane by lane; with -ffp-contract=off for
// the whole library no copy fuses a multiply-add, so every copy rounds alike.
bool sphere_root(const KernelRay& ray, const Vec3f& center, float radius, float t_min, float& t) {
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

constexpr std::uint32_t kMaxLeafSize = Bvh::kWidth;
constexpr int kWidth = Bvh::kWidth;
constexpr int kBins = 16;
// SAH costs relative to one leaf test, which takes up to kWidth spheres in one SIMD step: n spheres cost
// ceil(n / kWidth) leaf tests wherever they end up. A node visit is one SIMD step too. With these costs a split
// never beats a leaf of up to kWidth spheres, so leaves are as full as the tree allows: on `field`, leaves of at
// most 2, 3, 4 or 6 spheres all traced slower than full ones (bench --scene field --mode path, one thread).
constexpr float kTraversalCost = 1.0f;
inline float leaf_tests(std::uint32_t n) { return static_cast<float>((n + kWidth - 1) / kWidth); }
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
  float cost = kInf;     // SAH cost in leaf tests; kInf: median split
  int axis = 0;
  int bin = 0;           // spheres in bins < bin go left
  float lo = 0, scale = 0;
  Box left, right;
};

// A node of the binary tree the builder makes, collapsed into Bvh::Node afterwards.
struct BinaryNode {
  static constexpr std::uint32_t kInner = 0xffffffff;
  Box box[2];
  std::uint32_t first[2];
  std::uint32_t count[2];  // kInner, or the leaf's number of spheres (0 only for the empty child of a 1-sphere root)
};

// Builds the binary tree over refs, reordering refs into leaf order.
class Builder {
 public:
  using Node = BinaryNode;

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
      const bool sah_prefers_leaf = split.cost >= leaf_tests(count);
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
        right_cost[k] = acc_count ? acc.half_area() * leaf_tests(acc_count) : 0.0f;
      }
      acc = Box{};
      acc_count = 0;
      const std::uint32_t total = end - begin;
      for (int k = 1; k < kBins; ++k) {
        acc.grow(bins[a][k - 1].box);
        acc_count += bins[a][k - 1].count;
        if (acc_count == 0 || acc_count == total) continue;  // one side empty: not a split
        const float cost =
            kTraversalCost + (acc.half_area() * leaf_tests(acc_count) + right_cost[k]) * inv_parent_area;
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
    n.box[slot] = box;
    n.first[slot] = first;
    n.count[slot] = count;
  }

  std::vector<PrimRef>& refs_;
  std::vector<Node>& nodes_;
  std::vector<Task> tasks_;
};

// Collapses the binary tree into kWidth-wide nodes: a node takes its binary node's two children and, while it has
// room, replaces the inner child of largest surface area by that child's two children.
struct Slot {
  Box box;
  std::uint32_t first, count;  // as in BinaryNode
};

int expand(const std::vector<BinaryNode>& binary, std::uint32_t node, Slot slots[kWidth]) {
  int used = 0;
  const BinaryNode& b = binary[node];
  for (int k = 0; k < 2; ++k) slots[used++] = {b.box[k], b.first[k], b.count[k]};
  while (used < kWidth) {
    int widest = -1;
    for (int k = 0; k < used; ++k) {
      if (slots[k].count == BinaryNode::kInner && (widest < 0 || slots[k].box.half_area() > slots[widest].box.half_area()))
        widest = k;
    }
    if (widest < 0) break;
    const BinaryNode& child = binary[slots[widest].first];
    slots[widest] = {child.box[0], child.first[0], child.count[0]};
    slots[used++] = {child.box[1], child.first[1], child.count[1]};
  }
  return used;
}

template <class Node>
void collapse(const std::vector<BinaryNode>& binary, std::vector<Node>& nodes) {
  // First count the nodes, so that the array is allocated once at its final size (a million spheres: the binary
  // tree and the wide one are both alive here, at the peak of the build's memory).
  std::size_t count = 1;
  std::vector<std::uint32_t> pending{0};
  while (!pending.empty()) {
    const std::uint32_t b = pending.back();
    pending.pop_back();
    Slot slots[kWidth];
    const int used = expand(binary, b, slots);
    for (int k = 0; k < used; ++k) {
      if (slots[k].count == BinaryNode::kInner) {
        ++count;
        pending.push_back(slots[k].first);
      }
    }
  }
  nodes.reserve(count);
  struct Task {
    std::uint32_t binary, node;
  };
  std::vector<Task> tasks{{0, 0}};
  nodes.emplace_back();
  while (!tasks.empty()) {
    const Task task = tasks.back();
    tasks.pop_back();
    Slot slots[kWidth];
    const int used = expand(binary, task.binary, slots);
    for (int k = 0; k < kWidth; ++k) {
      const Slot slot = k < used ? slots[k] : Slot{Box{}, 0, 0};
      std::uint32_t first = slot.first;
      if (slot.count == BinaryNode::kInner) {
        first = static_cast<std::uint32_t>(nodes.size());
        nodes.emplace_back();
        tasks.push_back({slot.first, first});
      }
      Node& n = nodes[task.node];
      for (int a = 0; a < 3; ++a) {
        n.bounds[2 * a][k] = slot.count == 0 ? kInf : slot.box.lo[a];
        n.bounds[2 * a + 1][k] = slot.count == 0 ? -kInf : slot.box.hi[a];
      }
      n.first[k] = first;
      n.count[k] = slot.count == BinaryNode::kInner ? Node::kInner : slot.count;
    }
  }
  assert(nodes.size() == count);
}

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

// Leaves in a structure of arrays, one per leaf child of the binary tree, replacing that child's `first` (a range
// of refs) by the leaf's index.
std::vector<Bvh::Leaf> make_leaves(std::vector<BinaryNode>& binary, const std::vector<PrimRef>& refs,
                                   std::span<const Vec3f> centers, std::span<const float> radii) {
  std::size_t count = 0;
  for (const BinaryNode& b : binary) {
    for (int k = 0; k < 2; ++k) count += b.count[k] != BinaryNode::kInner && b.count[k] > 0 ? 1 : 0;
  }
  std::vector<Bvh::Leaf> leaves;
  leaves.reserve(count);
  for (BinaryNode& b : binary) {
    for (int k = 0; k < 2; ++k) {
      if (b.count[k] == BinaryNode::kInner || b.count[k] == 0) continue;
      Bvh::Leaf& leaf = leaves.emplace_back();
      for (int lane = 0; lane < kWidth; ++lane) {
        if (static_cast<std::uint32_t>(lane) < b.count[k]) {
          const std::uint32_t original = refs[b.first[k] + static_cast<std::uint32_t>(lane)].index;
          const Vec3f& c = centers[original];
          leaf.cx[lane] = c.x;
          leaf.cy[lane] = c.y;
          leaf.cz[lane] = c.z;
          leaf.radius[lane] = radii[original];
          leaf.original[lane] = original;
        } else {
          leaf.cx[lane] = leaf.cy[lane] = leaf.cz[lane] = std::numeric_limits<float>::quiet_NaN();
          leaf.radius[lane] = 0.0f;
          leaf.original[lane] = 0;
        }
      }
      b.first[k] = static_cast<std::uint32_t>(leaves.size() - 1);
    }
  }
  return leaves;
}

}  // namespace

const char* simd_instruction_set() {
#if defined(__AVX2__)
  return "AVX2 (x86-64-v3)";
#else
  return "SSE2 (x86-64)";
#endif
}

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
  bvh.spheres_ = n;
  std::vector<PrimRef> refs(n);
  for (std::size_t i = 0; i < n; ++i) {
    refs[i] = {centers[i], padded_radius(centers[i], radii[i]), static_cast<std::uint32_t>(i)};
  }
  std::vector<BinaryNode> binary;
  Builder(refs, binary).run();
  // Each temporary array is freed as soon as it has served: a million spheres must build within 200 MB.
  bvh.leaves_ = make_leaves(binary, refs, centers, radii);
  std::vector<PrimRef>().swap(refs);
  collapse(binary, bvh.nodes_);
  return bvh;
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
  Pending stack[(kWidth - 1) * kStackSize + 1];
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
      assert(size < (kWidth - 1) * kStackSize + 1);
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

namespace {

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

std::size_t Bvh::sphere_count() const { return spheres_; }
std::size_t Bvh::node_count() const { return nodes_.size(); }
std::size_t Bvh::memory_bytes() const {
  return sizeof(*this) + nodes_.capacity() * sizeof(Node) + leaves_.capacity() * sizeof(Leaf);
}

}  // namespace tripsitter::render

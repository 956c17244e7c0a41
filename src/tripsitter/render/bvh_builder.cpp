// Bvh::build (bvh.h): a binary tree by binned SAH (Wald, "On fast construction of SAH-based bounding volume
// hierarchies", 2007) over the spheres' centroids, binning all three axes in one pass, depth-first so that a parent
// and its first subtree sit together in memory; its leaves laid out as structures of arrays (Bvh::Leaf); then the
// tree collapsed into Bvh::kWidth-wide nodes. Boxes hold each sphere with a margin beyond rounding (padded_radius),
// which the traversal's culling relies on (bvh_traversal.cpp).
#include <tripsitter/render/bvh.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace tripsitter::render {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

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
// under kMaxSahDepth + log2(2^32 / kMaxLeafSize) <= 62 < Bvh::kMaxDepth, whatever the distribution.
constexpr std::uint32_t kMaxSahDepth = 32;

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
    assert(child_depth < static_cast<std::uint32_t>(Bvh::kMaxDepth));
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

std::size_t Bvh::sphere_count() const { return spheres_; }
std::size_t Bvh::node_count() const { return nodes_.size(); }
std::size_t Bvh::memory_bytes() const {
  return sizeof(*this) + nodes_.capacity() * sizeof(Node) + leaves_.capacity() * sizeof(Leaf);
}

}  // namespace tripsitter::render

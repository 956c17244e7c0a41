#include <tripsitter/host/hierarchy.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>

namespace tripsitter::host {
namespace {

constexpr std::int64_t kLargeRatio = 8;    // a radius above this many medians stays at the root
constexpr std::size_t kMaxChildren = 255;  // a node's children and spheres are counted in a byte

link::Ball ball_of(const link::WireSphere& s) { return {s.x, s.y, s.z, s.radius}; }

// The bound of `members` (header comment), or none if it does not fit the device's formats.
std::optional<link::Ball> bound_of(std::span<const link::WireSphere> spheres, std::span<const std::size_t> members,
                                   const link::SceneFormats& formats) {
  std::array<std::int64_t, 3> lo{INT64_MAX, INT64_MAX, INT64_MAX};
  std::array<std::int64_t, 3> hi{INT64_MIN, INT64_MIN, INT64_MIN};
  for (const std::size_t i : members) {
    const link::Ball b = ball_of(spheres[i]);
    const std::array<std::int64_t, 3> c{b.x, b.y, b.z};
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], c[k] - b.radius);
      hi[k] = std::max(hi[k], c[k] + b.radius);
    }
  }
  link::Ball bound;
  bound.x = (lo[0] + hi[0]) >> 1;
  bound.y = (lo[1] + hi[1]) >> 1;
  bound.z = (lo[2] + hi[2]) >> 1;
  double reach = 0.0;
  for (const std::size_t i : members) {
    const link::Ball b = ball_of(spheres[i]);
    const double dx = static_cast<double>(b.x - bound.x), dy = static_cast<double>(b.y - bound.y),
                 dz = static_cast<double>(b.z - bound.z);
    reach = std::max(reach, std::sqrt(dx * dx + dy * dy + dz * dz) + static_cast<double>(b.radius));
  }
  bound.radius = static_cast<std::int64_t>(std::ceil(reach));
  // The double's rounding is a few units at most: settle it in integers, as the receiver will check.
  while (!std::all_of(members.begin(), members.end(),
                      [&](std::size_t i) { return link::encloses(bound, ball_of(spheres[i])); }))
    ++bound.radius;
  bound.radius += (bound.radius >> 8) + 16;
  if (!formats.x.contains(bound.x) || !formats.y.contains(bound.y) || !formats.z.contains(bound.z) ||
      !formats.radius.contains(bound.radius) || bound.radius > INT32_MAX)
    return std::nullopt;
  return bound;
}

struct Leaf {
  std::vector<std::size_t> members;  // ascending
  link::Ball bound;
};

// Groups `members` into leaves of at most `leaf_size`, halving at the median centre along the longest side of
// their box; a sphere whose own bound does not fit the formats goes to `root`.
void group(std::span<const link::WireSphere> spheres, std::vector<std::size_t> members, std::size_t leaf_size,
           const link::SceneFormats& formats, std::vector<Leaf>& leaves, std::vector<std::size_t>& root) {
  if (members.size() <= leaf_size) {
    std::sort(members.begin(), members.end());
    if (const std::optional<link::Ball> bound = bound_of(spheres, members, formats)) {
      leaves.push_back({std::move(members), *bound});
      return;
    }
    if (members.size() == 1) {
      root.push_back(members[0]);
      return;
    }
  }
  const auto centre = [&](std::size_t i, std::size_t axis) {
    const link::WireSphere& s = spheres[i];
    return axis == 0 ? s.x : axis == 1 ? s.y : s.z;
  };
  std::size_t axis = 0;
  std::int64_t widest = -1;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto [lo, hi] = std::minmax_element(members.begin(), members.end(), [&](std::size_t a, std::size_t b) {
      return centre(a, k) < centre(b, k);
    });
    const std::int64_t width = std::int64_t{centre(*hi, k)} - centre(*lo, k);
    if (width > widest) {
      widest = width;
      axis = k;
    }
  }
  const auto mid = members.begin() + static_cast<std::ptrdiff_t>(members.size() / 2);
  std::nth_element(members.begin(), mid, members.end(), [&](std::size_t a, std::size_t b) {
    return centre(a, axis) != centre(b, axis) ? centre(a, axis) < centre(b, axis) : a < b;
  });
  group(spheres, std::vector<std::size_t>(members.begin(), mid), leaf_size, formats, leaves, root);
  group(spheres, std::vector<std::size_t>(mid, members.end()), leaf_size, formats, leaves, root);
}

}  // namespace

Hierarchy build_hierarchy(std::span<const link::WireSphere> spheres, const link::SceneFormats& formats) {
  const std::size_t n = spheres.size();
  if (n <= kFlatWorldSpheres) return {};
  std::vector<std::uint32_t> radii;
  radii.reserve(n);
  for (const auto& s : spheres) radii.push_back(s.radius);
  const auto median_at = radii.begin() + static_cast<std::ptrdiff_t>(n / 2);
  std::nth_element(radii.begin(), median_at, radii.end());
  const std::int64_t large = kLargeRatio * std::int64_t{*median_at};
  std::vector<std::size_t> root;
  std::vector<std::size_t> rest;
  for (std::size_t i = 0; i < n; ++i) (spheres[i].radius > large ? root : rest).push_back(i);
  const auto leaf_size =
      std::max<std::size_t>(4, static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(rest.size())))));
  std::vector<Leaf> leaves;
  if (!rest.empty()) group(spheres, std::move(rest), leaf_size, formats, leaves, root);
  std::sort(root.begin(), root.end());
  const std::size_t nodes = 1 + leaves.size();
  if (leaves.empty() || leaves.size() > kMaxChildren || root.size() > kMaxChildren || leaf_size > kMaxChildren ||
      nodes > std::max<std::size_t>(formats.max_spheres, 1))
    return {};
  Hierarchy h;
  h.order = root;
  link::WireNode top;
  top.first_child = 1;
  top.children = static_cast<std::uint8_t>(leaves.size());
  top.sphere_count = static_cast<std::uint8_t>(root.size());
  h.nodes.push_back(top);
  for (const Leaf& leaf : leaves) {
    link::WireNode v;
    v.x = static_cast<std::int32_t>(leaf.bound.x);
    v.y = static_cast<std::int32_t>(leaf.bound.y);
    v.z = static_cast<std::int32_t>(leaf.bound.z);
    v.radius = static_cast<std::uint32_t>(leaf.bound.radius);
    v.sphere_count = static_cast<std::uint8_t>(leaf.members.size());
    v.first_sphere = static_cast<std::uint32_t>(h.order.size());
    h.order.insert(h.order.end(), leaf.members.begin(), leaf.members.end());
    h.nodes.push_back(v);
  }
  return h;
}

void attach_hierarchy(link::World& world, const Hierarchy& hierarchy) {
  if (hierarchy.nodes.empty()) return;
  std::vector<link::WireSphere> ordered;
  ordered.reserve(hierarchy.order.size());
  for (const std::size_t i : hierarchy.order) ordered.push_back(world.spheres[i]);
  world.spheres = std::move(ordered);
  world.nodes = hierarchy.nodes;
}

}  // namespace tripsitter::host

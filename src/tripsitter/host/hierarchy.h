// The host's hierarchy of bounding spheres for the v3 wire (docs/link_format.md, "The hierarchy"), which the
// artix path preset's device walks for its bounced rays instead of testing every sphere.
//
// Two levels. The root holds, untested, the spheres that would make a poor leaf (a radius more than 8 times the
// median, such as a ground sphere, or one whose bound would not fit the device's formats) and one child per leaf;
// a leaf holds up to max(4, ceil(sqrt(n))) spheres that lie together, grouped by halving at the median centre
// along the longest side of their box until a group is small enough. A leaf's bound is centred on the box of its
// spheres and encloses them exactly (checked in integers, as the receiver checks it), grown by R / 256 + 16 raw
// units: more than the sphere units' rounding can move a ray's distance to a centre (docs/device.md), so that a
// ray the units find hitting a sphere also enters the leaf that holds it.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <tripsitter/link/frame.h>
#include <tripsitter/link/wire.h>

namespace tripsitter::host {

struct Hierarchy {
  std::vector<std::size_t> order;      // the wire's sphere i is spheres[order[i]]
  std::vector<link::WireNode> nodes;   // empty: none is sent
};

// Worlds of at most this many spheres are sent without a hierarchy: a leaf's test costs what a sphere's does.
inline constexpr std::size_t kFlatWorldSpheres = 8;

// The hierarchy of `spheres` (already in the device's formats), or none for a small world or one that two levels
// of at most 255 children cannot hold. Whatever it returns keeps link::hierarchy_error's rules.
Hierarchy build_hierarchy(std::span<const link::WireSphere> spheres, const link::SceneFormats& formats);

// The world's spheres put in the hierarchy's order, and its nodes attached.
void attach_hierarchy(link::World& world, const Hierarchy& hierarchy);

}  // namespace tripsitter::host

#include <tripsitter/host/hierarchy.h>

#include <algorithm>
#include <numeric>

#include <gtest/gtest.h>

#include <tripsitter/host/host.h>
#include <tripsitter/scene/builtin.h>

namespace tripsitter::host {
namespace {

// The artix path preset's formats: s22.4 centres, u21.4 radii, 256 spheres, and a hierarchy wanted.
link::SceneFormats artix_formats() {
  link::SceneFormats f{{22, 4, true}, {22, 4, true}, {22, 4, true}, {21, 4, false}, 256};
  f.hierarchy = true;
  return f;
}

link::World world_of(const char* scene_name, const link::SceneFormats& formats) {
  Host h(*scene::builtin(scene_name), formats, link::WireVersion::kV3);
  const auto decoded = link::decode_frame(link::WireVersion::kV3, h.update().bytes, formats.max_spheres);
  EXPECT_TRUE(decoded.ok()) << decoded.error().detail;
  return decoded.value();
}

TEST(Hierarchy, TheHostSendsOneThatKeepsTheWiresRules) {
  for (const char* name : {"random-16", "random-64", "field"}) {
    const link::World world = world_of(name, artix_formats());
    SCOPED_TRACE(name);
    ASSERT_GT(world.spheres.size(), kFlatWorldSpheres);
    ASSERT_FALSE(world.nodes.empty());
    EXPECT_FALSE(link::hierarchy_error(world).has_value());  // decode_frame checked it too
    // Two levels: the root's children are leaves of at most max(4, ceil(sqrt(n))) spheres.
    const link::WireNode& root = world.nodes[0];
    EXPECT_EQ(root.children, world.nodes.size() - 1);
    const auto leaf_size = std::max<std::size_t>(4, static_cast<std::size_t>(std::ceil(std::sqrt(world.spheres.size()))));
    for (std::size_t i = 1; i < world.nodes.size(); ++i) {
      EXPECT_EQ(world.nodes[i].children, 0);
      EXPECT_LE(world.nodes[i].sphere_count, leaf_size);
    }
  }
}

TEST(Hierarchy, TheGroundStaysAtTheRootAndTheSpheresAreAllSent) {
  const link::SceneFormats formats = artix_formats();
  Host h(*scene::builtin("random-64"), formats, link::WireVersion::kV3);
  link::SceneFormats flat = formats;
  flat.hierarchy = false;
  Host plain(*scene::builtin("random-64"), flat, link::WireVersion::kV3);
  const link::World with = link::decode_frame(link::WireVersion::kV3, h.update().bytes, 256).value();
  const link::World without = link::decode_frame(link::WireVersion::kV3, plain.update().bytes, 256).value();
  EXPECT_TRUE(without.nodes.empty());
  // The same spheres, reordered.
  auto key = [](const link::WireSphere& s) { return std::tuple(s.x, s.y, s.z, s.radius, s.material); };
  std::vector<std::tuple<int, int, int, unsigned, int>> a, b;
  for (const auto& s : with.spheres) a.push_back(key(s));
  for (const auto& s : without.spheres) b.push_back(key(s));
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
}

// A ground, far the largest sphere, is tested by every bounced ray rather than making a leaf that every ray enters.
TEST(Hierarchy, AGroundStaysAtTheRoot) {
  std::vector<link::WireSphere> spheres;
  for (int i = 0; i < 20; ++i) {
    link::WireSphere s;
    s.x = (i % 5) * 800 - 1600;
    s.z = 8000 + (i / 5) * 800;
    s.radius = 200 + 10 * static_cast<std::uint32_t>(i);
    s.ior = 6144;
    spheres.push_back(s);
  }
  spheres[7] = {0, -(1 << 20), 8000, (1u << 20) - 200, 0, {}, 0, 6144};
  const Hierarchy h = build_hierarchy(spheres, artix_formats());
  ASSERT_FALSE(h.nodes.empty());
  EXPECT_EQ(h.nodes[0].sphere_count, 1);
  EXPECT_EQ(h.order[0], 7u);
}

TEST(Hierarchy, SmallWorldsAndOtherWiresGoWithout) {
  EXPECT_TRUE(world_of("demo", artix_formats()).nodes.empty());
  Host v2(*scene::builtin("random-64"), artix_formats(), link::WireVersion::kV2);
  const auto decoded = link::decode_frame(link::WireVersion::kV2, v2.update().bytes, 256);
  ASSERT_TRUE(decoded.ok());
  EXPECT_TRUE(decoded.value().nodes.empty());
}

// A leaf whose bound would not fit the device's radius format is split, and a sphere alone too large for one
// stays at the root: everything the host sends, the receiver takes.
TEST(Hierarchy, BoundsThatWouldNotFitTheFormatsAreNotSent) {
  link::SceneFormats formats = artix_formats();
  std::vector<link::WireSphere> spheres;
  for (int i = 0; i < 12; ++i) {
    link::WireSphere s;
    s.x = (i % 2 == 0 ? -1 : 1) * (1 << 20);  // two far groups: together they need a radius beyond 2^21
    s.y = i * 64;
    s.z = 1 << 16;
    s.radius = 32;
    s.ior = 6144;
    spheres.push_back(s);
  }
  spheres[3].radius = (1u << 21) - 8;  // a sphere near the radius limit: no room for a bound's margin
  spheres[3].x = 0;
  const Hierarchy h = build_hierarchy(spheres, formats);
  ASSERT_FALSE(h.nodes.empty());
  link::World world;
  world.frac_bits = 4;
  world.spheres = spheres;
  attach_hierarchy(world, h);
  EXPECT_FALSE(link::hierarchy_error(world).has_value());
  for (std::size_t i = 1; i < world.nodes.size(); ++i) EXPECT_TRUE(formats.radius.contains(world.nodes[i].radius));
  std::vector<std::size_t> order = h.order;
  std::sort(order.begin(), order.end());
  std::vector<std::size_t> all(spheres.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  EXPECT_EQ(order, all);
  EXPECT_EQ(world.spheres[0].radius, (1u << 21) - 8) << "the large sphere is the root's";
}

}  // namespace
}  // namespace tripsitter::host

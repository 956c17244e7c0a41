// Tests of the v3 wire's hierarchy (docs/link_format.md, "The hierarchy"): its bytes, and each of its rules
// refusing the whole frame, at the field that breaks it, as a frame that arrived intact.
#include <tripsitter/link/frame.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace tripsitter::link {
namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr std::uint32_t kSceneMemory = 4096;

TEST(WireHierarchy, WorkedExampleOfTheDocument) {
  World w;
  w.session = 42;
  w.sequence = 1;
  w.frac_bits = 4;
  w.spheres.push_back({0, 0, 6400, 1024, kMaterialLambertian, {204, 77, 77}, 0, 6144});
  w.nodes.push_back({0, 0, 0, 0, 1, 1, 0, 0});       // the root: no bound, one child
  w.nodes.push_back({0, 0, 6400, 1040, 0, 0, 1, 0});  // a leaf holding sphere 0
  const Bytes expected = {
      0x54, 0x53, 0x57, 0x33, 0x03, 0x04, 0x01, 0x00, 0x00, 0x00, 0x00, 0x2A, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00,
      0x00, 0x01, 0x00, 0x00, 0x00, 0x48, 0x32, 0xD1, 0xBA, 0xEC, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x19, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0xCC, 0x4D, 0x4D, 0x00, 0x00, 0x18, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x01, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x19, 0x00, 0x00, 0x00,
      0x04, 0x10, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x11, 0xE8, 0x6E, 0x89};
  EXPECT_EQ(encode_frame(WireVersion::kV3, w), expected);
  EXPECT_EQ(frame_bytes(WireVersion::kV3, 1, 2), expected.size());
  const auto back = decode_frame(WireVersion::kV3, expected, kSceneMemory);
  ASSERT_TRUE(back.ok()) << back.error().detail;
  EXPECT_EQ(back.value(), w);
}

TEST(WireHierarchy, OnlyV3CarriesOne) {
  World w;
  w.spheres.push_back({0, 0, 6400, 1024, kMaterialLambertian, {}, 0, 6144});
  w.nodes.push_back({0, 0, 0, 0, 0, 0, 1, 0});
  EXPECT_THROW(encode_frame(WireVersion::kV2, w), std::invalid_argument);
}

// Four spheres in two leaves of two under the root: the world every rule below breaks once.
World two_leaves() {
  World w;
  w.frac_bits = 4;
  for (int i = 0; i < 4; ++i)
    w.spheres.push_back({1000 * (i / 2) + 100 * (i % 2), 0, 6400, 50, kMaterialLambertian, {}, 0, 6144});
  w.nodes.push_back({0, 0, 0, 0, 1, 2, 0, 0});
  w.nodes.push_back({50, 0, 6400, 110, 0, 0, 2, 0});
  w.nodes.push_back({1050, 0, 6400, 110, 0, 0, 2, 2});
  return w;
}

struct Broken {
  const char* rule;
  std::function<void(World&)> damage;
  std::size_t node;   // the record the problem is reported in
  std::size_t field;  // and its field's offset in the record
  const char* words;  // in the sentence
};

TEST(WireHierarchy, EachBrokenRuleRefusesTheWholeFrameAtItsField) {
  ASSERT_FALSE(hierarchy_error(two_leaves()).has_value());
  const std::vector<Broken> cases = {
      {"the root carries a bound", [](World& w) { w.nodes[0].radius = 5; }, 0, 12, "root (node 0) carries no bound"},
      {"a bound of radius 0", [](World& w) { w.nodes[2].radius = 0; }, 2, 12, "radius 0"},
      {"a child index out of range", [](World& w) { w.nodes[0].children = 3; }, 0, 16, "names nodes 1..3"},
      {"a leaf naming a sphere that does not exist", [](World& w) { w.nodes[2].first_sphere = 3; }, 2, 20,
       "names spheres 3..4 but the world has 4 spheres"},
      {"a cycle", [](World& w) { w.nodes[1].first_child = 1, w.nodes[1].children = 1; }, 1, 16,
       "a cycle, or a node with two parents"},
      {"a cycle through the root", [](World& w) { w.nodes[2].first_child = 0, w.nodes[2].children = 1; }, 2, 16,
       "names node 0 as a child"},
      {"a node no path reaches", [](World& w) { w.nodes.push_back({50, 0, 6400, 110, 0, 0, 1, 0}); }, 3, 0,
       "node 3 is not reached from the root"},
      {"a sphere in two nodes", [](World& w) { w.nodes[2].first_sphere = 1; }, 2, 20, "sphere 1 is in node 1 and in node 2"},
      {"a sphere in no node", [](World& w) { w.nodes[2].sphere_count = 1; }, 0, 0, "sphere 3 is in no node"},
      {"a node that holds nothing", [](World& w) { w.nodes[2].sphere_count = 0, w.nodes[2].first_sphere = 0; }, 2, 18,
       "holds neither nodes nor spheres"},
      {"a bound that does not enclose its spheres", [](World& w) { w.nodes[1].radius = 99; }, 1, 12,
       "does not enclose sphere 0"},
      {"a bound off centre", [](World& w) { w.nodes[2].x = 1039; }, 2, 12, "does not enclose sphere 3"},
      {"a bound that does not enclose its child's", [](World& w) {
         w.nodes[0].children = 1;
         w.nodes[1].first_child = 2, w.nodes[1].children = 1;
       }, 1, 12, "does not enclose the bound of node 2"},
  };
  for (const Broken& c : cases) {
    SCOPED_TRACE(c.rule);
    World w = two_leaves();
    c.damage(w);
    const auto problem = hierarchy_error(w);
    ASSERT_TRUE(problem.has_value());
    EXPECT_EQ(problem->offset, c.node * kNodeBytes + c.field) << problem->detail;
    EXPECT_NE(problem->detail.find(c.words), std::string::npos) << problem->detail;
    // The decoder refuses the frame with the same words, at the field's offset in the frame, as an intact one.
    const Bytes bytes = encode_frame(WireVersion::kV3, w);
    const auto decoded = decode_frame(WireVersion::kV3, bytes, kSceneMemory);
    ASSERT_FALSE(decoded.ok());
    EXPECT_EQ(decoded.error().error, FrameError::kBadHierarchy);
    EXPECT_EQ(decoded.error().offset, kV3HeaderBytes + w.spheres.size() * kSphereBytes + problem->offset);
    EXPECT_EQ(decoded.error().detail, problem->detail);
    EXPECT_TRUE(decoded.error().intact.has_value());
  }
}

TEST(WireHierarchy, AtMostEightLevelsBelowTheRoot) {
  World w;
  w.frac_bits = 4;
  w.spheres.push_back({0, 0, 6400, 50, kMaterialLambertian, {}, 0, 6144});
  w.nodes.push_back({0, 0, 0, 0, 1, 1, 0, 0});
  for (int level = 1; level <= 9; ++level) {
    const bool last = level == 9;
    w.nodes.push_back({0, 0, 6400, static_cast<std::uint32_t>(100 - level), static_cast<std::uint16_t>(last ? 0 : level + 1),
                       static_cast<std::uint8_t>(last ? 0 : 1), static_cast<std::uint8_t>(last ? 1 : 0), 0});
  }
  const auto nine = hierarchy_error(w);
  ASSERT_TRUE(nine.has_value());
  EXPECT_NE(nine->detail.find("node 9 lies 9 levels below the root; at most 8"), std::string::npos) << nine->detail;
  // Eight levels are fine: the eighth node holds the sphere.
  w.nodes.pop_back();
  w.nodes[8].first_child = 0, w.nodes[8].children = 0, w.nodes[8].sphere_count = 1;
  EXPECT_FALSE(hierarchy_error(w).has_value());
}

TEST(WireHierarchy, TheHeaderSaysWhatThePayloadHolds) {
  const World w = two_leaves();
  Bytes bytes = encode_frame(WireVersion::kV3, w);
  ASSERT_EQ(bytes[6], kContentHierarchy);
  const auto refuse = [](const Bytes& b, std::uint32_t limit = kSceneMemory) {
    const auto r = decode_frame(WireVersion::kV3, b, limit);
    return r.ok() ? FrameError::kTrailingBytes : r.error().error;
  };
  const auto restamp = [](Bytes b) {
    restamp_frame(WireVersion::kV3, b, 0, 0);
    return b;
  };
  Bytes unknown = bytes;
  unknown[6] = 2;
  EXPECT_EQ(refuse(restamp(unknown)), FrameError::kBadHeader);
  Bytes spheres_only = bytes;  // content 0 with the nodes still in the payload: the length is wrong for it
  spheres_only[6] = kContentSpheres;
  EXPECT_EQ(refuse(restamp(spheres_only)), FrameError::kBadLength);
  // No more nodes than the receiver holds spheres, checked from the header before anything is allocated.
  EXPECT_EQ(refuse(bytes, 4), FrameError::kTrailingBytes) << "3 nodes within a memory of 4 spheres";
  World many = two_leaves();
  for (int i = 0; i < 2; ++i) many.spheres.push_back(many.spheres[0]);
  many.nodes[1].sphere_count = 4;
  many.nodes[1].radius = 200;
  many.nodes[2].first_sphere = 4;
  many.nodes.push_back({1050, 0, 6400, 110, 0, 0, 0, 0});  // an extra node: 4 for a memory of 6 is fine...
  many.nodes[0].children = 3;
  many.nodes[3].sphere_count = 0;
  Bytes over = encode_frame(WireVersion::kV3, many);
  EXPECT_EQ(refuse(over, 3), FrameError::kTooManySpheres);
  const auto r = decode_frame(WireVersion::kV3, over, 6);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().error, FrameError::kBadHierarchy) << "...but node 3 holds nothing";
}

TEST(WireHierarchy, AReceiverThatWalksNoneRefusesOneAtTheContentByte) {
  const Bytes bytes = encode_frame(WireVersion::kV3, two_leaves());
  const auto r = decode_frame(WireVersion::kV3, bytes, kSceneMemory, false);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().error, FrameError::kBadHeader);
  EXPECT_EQ(r.error().offset, 6u);
  World flat = two_leaves();
  flat.nodes.clear();
  EXPECT_TRUE(decode_frame(WireVersion::kV3, encode_frame(WireVersion::kV3, flat), kSceneMemory, false).ok());
}

TEST(WireHierarchy, TheStreamDropsABadHierarchyWholeAndTakesTheNextFrame) {
  World bad = two_leaves();
  bad.nodes[0].children = 3;
  World good = two_leaves();
  good.sequence = 2;
  const Bytes first = encode_frame(WireVersion::kV3, bad);
  const Bytes second = encode_frame(WireVersion::kV3, good);
  Bytes stream = first;
  stream.insert(stream.end(), second.begin(), second.end());
  std::vector<World> frames;
  std::vector<std::pair<FrameError, std::size_t>> errors;
  FrameStreamDecoder decoder(WireVersion::kV3, kSceneMemory,
                             {.on_frame = [&](World&& w) { frames.push_back(std::move(w)); },
                              .on_error = [&](const FrameFailure& f, std::size_t dropped) {
                                errors.emplace_back(f.error, dropped);
                              }});
  decoder.push(stream);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0], std::make_pair(FrameError::kBadHierarchy, first.size()));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0], good);
}

TEST(WireHierarchy, RoundTripOfRandomHierarchies) {
  std::mt19937 rng(34);
  for (int trial = 0; trial < 200; ++trial) {
    World w;
    w.session = static_cast<std::uint32_t>(rng());
    w.frac_bits = 4;
    const std::size_t leaves = 1 + rng() % 6;
    const std::size_t root_spheres = rng() % 3;
    w.nodes.push_back({0, 0, 0, 0, 1, static_cast<std::uint8_t>(leaves), static_cast<std::uint8_t>(root_spheres), 0});
    for (std::size_t i = 0; i < root_spheres; ++i)
      w.spheres.push_back({static_cast<std::int32_t>(rng() % 4000), 0, 6400, 1 + static_cast<std::uint32_t>(rng() % 900),
                           kMaterialMetal, {}, 0, 6144});
    for (std::size_t leaf = 0; leaf < leaves; ++leaf) {
      const auto cx = static_cast<std::int32_t>(rng() % 100000) - 50000;
      const std::size_t n = 1 + rng() % 5;
      WireNode v{cx, 0, 6400, 1000, 0, 0, static_cast<std::uint8_t>(n), static_cast<std::uint32_t>(w.spheres.size())};
      for (std::size_t i = 0; i < n; ++i)
        w.spheres.push_back({cx + static_cast<std::int32_t>(rng() % 400) - 200, 0, 6400, 1 + static_cast<std::uint32_t>(rng() % 500),
                             kMaterialDielectric, {}, 0, 6144});
      w.nodes.push_back(v);
    }
    if (root_spheres == 0) w.nodes[0].first_sphere = 0;
    ASSERT_FALSE(hierarchy_error(w).has_value()) << hierarchy_error(w)->detail;
    const auto back = decode_frame(WireVersion::kV3, encode_frame(WireVersion::kV3, w), kSceneMemory);
    ASSERT_TRUE(back.ok()) << back.error().detail;
    EXPECT_EQ(back.value(), w);
  }
}

}  // namespace
}  // namespace tripsitter::link

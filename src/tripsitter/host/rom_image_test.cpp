#include <tripsitter/host/rom_image.h>

#include <gtest/gtest.h>

#include <tripsitter/link/frame.h>
#include <tripsitter/scene/builtin.h>

namespace tripsitter::host {
namespace {

const link::SceneFormats kArtixLike{{22, 4, true}, {22, 4, true}, {22, 4, true}, {21, 4, false}, 256};

RomImage cluster_rom(int worlds, CameraPath path) {
  Host h(*scene::builtin("cluster"), kArtixLike, link::WireVersion::kV2);
  return make_rom_image(h, path, worlds, link::Numbering(link::WireVersion::kV2, 0));
}

TEST(RomImage, HoldsTheNumberedWorldsOfThePathBehindItsTable) {
  const RomImage rom = cluster_rom(3, {CameraPath::Kind::kOrbit, 90});
  EXPECT_EQ(rom.worlds, 3u);
  EXPECT_EQ(rom.spheres, 8u);
  const auto worlds = rom_worlds(rom.bytes);
  ASSERT_TRUE(worlds.ok()) << worlds.error();
  ASSERT_EQ(worlds.value().size(), 3u);
  EXPECT_EQ(worlds.value()[0].data(), rom.bytes.data() + 4 * 5) << "world 0 follows the count and 4 offsets";
  std::vector<std::int32_t> first_x;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto w = link::decode_frame(link::WireVersion::kV2, worlds.value()[k], 256);
    ASSERT_TRUE(w.ok()) << "world " << k;
    EXPECT_EQ(w.value().sequence, k + 1);
    ASSERT_EQ(w.value().spheres.size(), 8u);
    first_x.push_back(w.value().spheres[1].x);  // sphere 0 is the target the camera circles
  }
  // Each world is a step further round the orbit: the same sphere is elsewhere in view.
  EXPECT_NE(first_x[0], first_x[1]);
  EXPECT_NE(first_x[1], first_x[2]);
  // The first world is the scene's own view, as the host sends it unmoved.
  Host h(*scene::builtin("cluster"), kArtixLike, link::WireVersion::kV2);
  std::vector<std::uint8_t> own = h.update().bytes;
  link::Numbering(link::WireVersion::kV2, 0).stamp(own);
  EXPECT_TRUE(std::equal(own.begin(), own.end(), worlds.value()[0].begin(), worlds.value()[0].end()));
}

TEST(RomImage, AWalkMovesTowardsTheScene) {
  const RomImage rom = cluster_rom(2, {CameraPath::Kind::kWalk, 4});
  const auto worlds = rom_worlds(rom.bytes);
  ASSERT_TRUE(worlds.ok()) << worlds.error();
  const auto a = link::decode_frame(link::WireVersion::kV2, worlds.value()[0], 256);
  const auto b = link::decode_frame(link::WireVersion::kV2, worlds.value()[1], 256);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_LT(b.value().spheres[0].z, a.value().spheres[0].z) << "two units on, the first sphere is nearer";
}

TEST(RomImage, ReadmemhIsOneByteALineAfterTheComments) {
  const std::vector<std::uint8_t> bytes = {0x00, 0x0a, 0xff};
  EXPECT_EQ(to_readmemh(bytes, {"made here"}), "// made here\n00\n0a\nff\n");
}

// Each way a table can be wrong, one image each.
TEST(RomImage, ABrokenTableIsNamed) {
  const RomImage rom = cluster_rom(2, {});
  const auto with = [&](std::size_t at, std::uint8_t value) {
    std::vector<std::uint8_t> b = rom.bytes;
    b[at] = value;
    return b;
  };
  struct Case {
    std::vector<std::uint8_t> image;
    std::string error;
  };
  std::vector<std::uint8_t> trailing = rom.bytes;
  trailing.push_back(0);
  const Case cases[] = {
      {{0, 0}, "shorter than the world count"},
      {with(3, 0), "a world count of 0"},
      {with(0, 0x40), "does not fit"},
      {with(7, 0), "not after the table"},
      {with(9, 0xff), "world 0 ends at"},
      {trailing, "1 bytes after the last world"},
  };
  for (const Case& c : cases) {
    const auto worlds = rom_worlds(c.image);
    ASSERT_FALSE(worlds.ok()) << c.error;
    EXPECT_NE(worlds.error().find(c.error), std::string::npos) << worlds.error();
  }
}

}  // namespace
}  // namespace tripsitter::host

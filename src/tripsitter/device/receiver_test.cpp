#include <tripsitter/device/receiver.h>

#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "test_util.h"

namespace tripsitter::device {
namespace {

using testing::frame_of;

TEST(Receiver, AcceptsAWorldAndSwapsItOnlyWhenAsked) {
  const DevicePreset p = wide_preset();
  Receiver rx(p, link::WireVersion::kV2);
  EXPECT_TRUE(rx.ready());
  rx.receive(frame_of(p, 7, {{0, 0, 400, 64}, {10, 20, 300, 8}}));
  EXPECT_FALSE(rx.ready());  // a world waits for vertical blanking
  SceneMemory front;
  EXPECT_TRUE(rx.swap_if_pending(front));
  EXPECT_TRUE(rx.ready());
  EXPECT_TRUE(front.valid);
  EXPECT_EQ(front.sequence, 7u);
  ASSERT_EQ(front.geometry.size(), 2u);
  EXPECT_EQ(front.geometry[1].center.z, 300 * 16);
  EXPECT_FALSE(rx.swap_if_pending(front));
}

TEST(Receiver, DamagedFrameIsCountedAndTheLastGoodWorldStays) {
  const DevicePreset p = wide_preset();
  Receiver rx(p, link::WireVersion::kV2);
  SceneMemory front;
  rx.receive(frame_of(p, 1, {{0, 0, 400, 64}}));
  rx.swap_if_pending(front);
  auto bad = frame_of(p, 2, {{50, 0, 400, 64}});
  bad[30] ^= 0x10;  // a flipped bit in the payload
  rx.receive(bad);
  EXPECT_TRUE(rx.ready());
  EXPECT_FALSE(rx.swap_if_pending(front));
  EXPECT_EQ(front.sequence, 1u);
  EXPECT_EQ(rx.stats().frames_rejected, 1u);
  EXPECT_GT(rx.stats().bytes_dropped, 0u);
  EXPECT_NE(rx.stats().last_error.find("CRC"), std::string::npos) << rx.stats().last_error;
}

TEST(Receiver, RejectsAFrameInAnotherFormat) {
  const DevicePreset wide = wide_preset();
  Receiver rx(board_2023_preset(), link::WireVersion::kV2);
  rx.receive(frame_of(wide, 1, {{0, 0, 400, 64}}));  // 4 fractional bits; the board's memory has 3
  EXPECT_TRUE(rx.ready());
  EXPECT_EQ(rx.stats().frames_rejected, 1u);
  EXPECT_NE(rx.stats().last_error.find("format"), std::string::npos);
}

TEST(Receiver, RejectsCoordinatesOutsideTheDevicesFormats) {
  const DevicePreset board = board_2023_preset();
  DevicePreset roomy = board;
  roomy.z = {24, 3, true};
  Receiver rx(board, link::WireVersion::kV2);
  rx.receive(frame_of(roomy, 1, {{0, 0, 5000, 64}}));  // z = 5000 needs more than s15.3
  EXPECT_EQ(rx.stats().frames_rejected, 1u);
  EXPECT_TRUE(rx.ready());
}

TEST(Receiver, ANewerWorldReplacesOneWaitingForTheSwap) {
  const DevicePreset p = wide_preset();
  Receiver rx(p, link::WireVersion::kV2);
  rx.receive(frame_of(p, 1, {{0, 0, 400, 64}}));
  rx.receive(frame_of(p, 2, {{0, 0, 500, 64}}));
  SceneMemory front;
  rx.swap_if_pending(front);
  EXPECT_EQ(front.sequence, 2u);
  EXPECT_EQ(rx.stats().worlds_replaced, 1u);
}

TEST(Receiver, V1ShowsTheLatestWord) {
  const DevicePreset p = board_2023_preset();
  Receiver rx(p, link::WireVersion::kV1);
  std::vector<std::uint8_t> bytes;
  link::append_v1_bytes(0x0320032025804000u, bytes);  // (100, 50, 300), radius 16
  link::append_v1_bytes(link::encode_v1_word({0, 0, 3200, 6, 0x770}), bytes);  // (0, 0, 400), radius 64
  for (std::uint8_t b : bytes) rx.receive(std::span<const std::uint8_t>(&b, 1));
  SceneMemory front;
  ASSERT_TRUE(rx.swap_if_pending(front));
  ASSERT_EQ(front.geometry.size(), 1u);
  EXPECT_EQ(front.geometry[0].center.z, 3200);
  EXPECT_EQ(front.geometry[0].radius, 64 * 8);
  EXPECT_EQ(front.surfaces[0].albedo[0], 0x77);
}

TEST(Receiver, V1WordsAreRescaledToTheWidePreset) {
  const DevicePreset p = wide_preset();
  Receiver rx(p, link::WireVersion::kV1);
  std::vector<std::uint8_t> bytes;
  link::append_v1_bytes(0x0320032025804000u, bytes);
  rx.receive(bytes);
  SceneMemory front;
  ASSERT_TRUE(rx.swap_if_pending(front));
  EXPECT_EQ(front.geometry[0].center.x, 100 * 16);
  EXPECT_EQ(front.geometry[0].center.y, 50 * 16);
  EXPECT_EQ(front.geometry[0].radius, 16 * 16);
}

TEST(Receiver, HostGoingAwayMidFrameIsCounted) {
  const DevicePreset p = wide_preset();
  Receiver rx(p, link::WireVersion::kV2);
  auto frame = frame_of(p, 1, {{0, 0, 400, 64}});
  rx.receive(std::span<const std::uint8_t>(frame).first(frame.size() / 2));
  rx.end_of_stream();
  EXPECT_EQ(rx.stats().frames_rejected, 1u);
  EXPECT_TRUE(rx.ready());
  rx.receive(frame);  // the next host's world arrives intact
  EXPECT_FALSE(rx.ready());
}

TEST(Receiver, SkippedSequenceNumbersCountMissingWorlds) {
  const DevicePreset p = wide_preset();
  Receiver rx(p, link::WireVersion::kV2);
  rx.receive(frame_of(p, 100, {{0, 0, 400, 64}}));
  EXPECT_EQ(rx.stats().worlds_missing, 0u);  // the first world only sets where counting starts
  auto damaged = frame_of(p, 101, {{10, 0, 400, 64}});
  damaged[25] ^= 0x01;
  rx.receive(damaged);
  rx.receive(frame_of(p, 102, {{20, 0, 400, 64}}));
  EXPECT_EQ(rx.stats().frames_rejected, 1u);
  EXPECT_EQ(rx.stats().worlds_missing, 1u);  // world 101
  rx.receive(frame_of(p, 106, {{30, 0, 400, 64}}));
  EXPECT_EQ(rx.stats().worlds_missing, 4u);  // and 103 to 105, which never came at all
}

TEST(Receiver, AWorldRejectedUnderAGoodCrcIsRejectedNotMissing) {
  const DevicePreset p = board_2023_preset();
  Receiver rx(p, link::WireVersion::kV2);
  rx.receive(frame_of(p, 1, {{0, 0, 400, 64}}));
  rx.receive(frame_of(wide_preset(), 2, {{0, 0, 400, 64}}));  // another format
  rx.receive(frame_of(p, 3, {{0, 0, 400, 64}}));
  EXPECT_EQ(rx.stats().frames_rejected, 1u);
  EXPECT_EQ(rx.stats().worlds_missing, 0u) << "world 2 arrived; the link lost nothing";
}

TEST(Receiver, ARepeatOrAHostStartingAgainSkipsNothing) {
  const DevicePreset p = wide_preset();
  Receiver rx(p, link::WireVersion::kV2);
  for (const std::uint32_t sequence : {5u, 5u, 1u, 2u}) rx.receive(frame_of(p, sequence, {{0, 0, 400, 64}}));
  EXPECT_EQ(rx.stats().worlds_accepted, 4u);
  EXPECT_EQ(rx.stats().worlds_missing, 0u);
  rx.receive(frame_of(p, 4, {{0, 0, 400, 64}}));  // counted from the new host's world 2
  EXPECT_EQ(rx.stats().worlds_missing, 1u);
}

TEST(Receiver, V3NeverShowsAReplayAndTakesARestartedHostFromItsFirstWorld) {
  const DevicePreset p = wide_preset();
  Receiver rx(p, link::WireVersion::kV3);
  SceneMemory front;
  const auto world = [&p](std::uint32_t session, std::uint32_t sequence, double z) {
    return testing::frame_on(link::WireVersion::kV3, p, session, sequence, {{0, 0, z, 64}});
  };
  rx.receive(world(7, 1, 400));
  rx.receive(world(7, 2, 410));
  ASSERT_TRUE(rx.swap_if_pending(front));
  EXPECT_EQ(front.sequence, 2u);
  rx.receive(world(7, 2, 410));  // a duplicated transfer
  rx.receive(world(7, 1, 400));  // an old frame sent again
  EXPECT_FALSE(rx.swap_if_pending(front));
  EXPECT_EQ(rx.stats().worlds_replayed, 2u);
  EXPECT_TRUE(rx.ready()) << "a replay does not lower the ready line";
  rx.receive(world(9, 1, 500));  // the host restarted with a new session
  ASSERT_TRUE(rx.swap_if_pending(front));
  EXPECT_EQ(front.sequence, 1u);
  EXPECT_EQ(front.geometry[0].center.z, p.z.quantize(500).raw);
  rx.receive(world(7, 3, 420));  // the old session has ended
  EXPECT_FALSE(rx.swap_if_pending(front));
  EXPECT_EQ(rx.stats().worlds_replayed, 3u);
  EXPECT_EQ(rx.stats().sessions, 2u);
  EXPECT_EQ(rx.stats().worlds_missing, 0u);
  EXPECT_EQ(rx.stats().worlds_accepted, 3u);
  EXPECT_EQ(rx.stats().frames_rejected, 0u);
}

TEST(Receiver, V3CountsExactlyTheWorldsTheLinkLost) {
  const DevicePreset p = wide_preset();
  Receiver rx(p, link::WireVersion::kV3);
  for (const std::uint32_t sequence : {1u, 2u, 5u, 6u, 9u}) {  // 3, 4, 7 and 8 lost
    rx.receive(testing::frame_on(link::WireVersion::kV3, p, 3, sequence, {{0, 0, 400, 64}}));
  }
  rx.receive(testing::frame_on(link::WireVersion::kV3, board_2023_preset(), 3, 10, {{0, 0, 400, 64}}));
  rx.receive(testing::frame_on(link::WireVersion::kV3, p, 3, 11, {{0, 0, 400, 64}}));
  EXPECT_EQ(rx.stats().worlds_missing, 4u) << "world 10 arrived intact; rejected for its format, not lost";
  EXPECT_EQ(rx.stats().frames_rejected, 1u);
}

TEST(Receiver, V1CountsNoMissingWorlds) {
  const DevicePreset p = board_2023_preset();
  Receiver rx(p, link::WireVersion::kV1);
  const auto word = link::encode_v1_word({.x_raw = 0, .y_raw = 0, .z_raw = 3200, .radius_log2 = 3, .colour = 0xFFF});
  std::vector<std::uint8_t> bytes;
  link::append_v1_bytes(word, bytes);
  rx.receive(bytes);
  rx.receive(std::span<const std::uint8_t>(bytes).first(5));
  rx.end_of_stream();
  rx.receive(bytes);
  EXPECT_EQ(rx.stats().worlds_accepted, 2u);
  EXPECT_EQ(rx.stats().frames_rejected, 1u);
  EXPECT_EQ(rx.stats().worlds_missing, 0u);  // v1 words carry no sequence number
}

// A world's hierarchy comes into scene memory with it; a malformed one (here each of the wire's rules broken in
// turn) or one whose bounds the device's formats cannot hold refuses the whole world, counted as a rejected
// frame that arrived intact (nothing missing), and the last good world stays.
TEST(Receiver, AMalformedHierarchyRefusesTheWholeWorldAndTheLastGoodOneStays) {
  const DevicePreset p = artix_path_preset();
  std::mt19937_64 rng(7);
  const SceneMemory scene = testing::with_hierarchy(p, testing::random_path_world(p, rng, 30));
  ASSERT_FALSE(scene.hierarchy.empty());
  Receiver rx(p, link::WireVersion::kV3);
  SceneMemory front;
  rx.receive(testing::frame_of_scene(p, 1, scene, link::WireVersion::kV3, 9));
  ASSERT_TRUE(rx.swap_if_pending(front));
  ASSERT_EQ(front.hierarchy.size(), scene.hierarchy.size());
  EXPECT_EQ(front.hierarchy[1].bound.radius, scene.hierarchy[1].bound.radius);
  const std::uint32_t content = front.content;
  SceneMemory flat = scene;
  flat.hierarchy.clear();
  EXPECT_NE(testing::frame_of_scene(p, 1, flat, link::WireVersion::kV3, 9),
            testing::frame_of_scene(p, 1, scene, link::WireVersion::kV3, 9));
  const std::vector<std::pair<const char*, std::function<void(SceneMemory&)>>> breaks = {
      {"names nodes", [](SceneMemory& m) { m.hierarchy[0].children += 1; }},                  // a child out of range
      {"a cycle", [](SceneMemory& m) { m.hierarchy[1].first_child = 1, m.hierarchy[1].children = 1; }},
      {"names spheres", [](SceneMemory& m) { m.hierarchy.back().first_sphere += 1; }},         // beyond the last
      {"does not enclose", [](SceneMemory& m) { m.hierarchy[1].bound.radius /= 2; }},
      {"outside the device's number formats", [](SceneMemory& m) { m.hierarchy[1].bound.radius = std::int64_t{1} << 22; }},
  };
  std::uint32_t sequence = 2;
  for (const auto& [words, damage] : breaks) {
    SCOPED_TRACE(words);
    SceneMemory bad = scene;
    damage(bad);
    const std::uint64_t rejected = rx.stats().frames_rejected;
    rx.receive(testing::frame_of_scene(p, sequence++, bad, link::WireVersion::kV3, 9));
    EXPECT_EQ(rx.stats().frames_rejected, rejected + 1);
    EXPECT_NE(rx.stats().last_error.find(words), std::string::npos) << rx.stats().last_error;
    EXPECT_TRUE(rx.ready());
    EXPECT_FALSE(rx.swap_if_pending(front));
    EXPECT_EQ(front.sequence, 1u);
    EXPECT_EQ(front.content, content);
  }
  EXPECT_EQ(rx.stats().worlds_missing, 0u) << "every refused world arrived intact";
  rx.receive(testing::frame_of_scene(p, sequence, scene, link::WireVersion::kV3, 9));
  EXPECT_TRUE(rx.swap_if_pending(front));
}

// A device that walks no hierarchy (every preset but artix-path) refuses a world that carries one at its header's
// content byte, as the RTL receiver does, and hunts on from the next byte.
TEST(Receiver, APresetThatWalksNoHierarchyRefusesOneAtTheHeader) {
  const DevicePreset p = artix_preset();
  std::mt19937_64 rng(8);
  const SceneMemory scene = testing::with_hierarchy(artix_path_preset(), testing::random_path_world(p, rng, 30));
  ASSERT_FALSE(scene.hierarchy.empty());
  Receiver rx(p, link::WireVersion::kV3);
  const auto bytes = testing::frame_of_scene(p, 1, scene, link::WireVersion::kV3, 9);
  rx.receive(bytes);
  EXPECT_TRUE(rx.ready());
  EXPECT_EQ(rx.stats().worlds_accepted, 0u);
  EXPECT_GE(rx.stats().frames_rejected, 1u);
  EXPECT_EQ(rx.stats().last_error.rfind("bad header: content byte is 1", 0), 0u) << rx.stats().last_error;
}

}  // namespace
}  // namespace tripsitter::device

#include <tripsitter/host/host.h>

#include <gtest/gtest.h>

#include <tripsitter/link/frame.h>
#include <tripsitter/link/sequence.h>
#include <tripsitter/scene/builtin.h>

namespace tripsitter::host {
namespace {

const link::SceneFormats kWide{{24, 4, true}, {24, 4, true}, {24, 4, true}, {24, 4, false}, 4096};

TEST(Host, DemoSceneIsTheBoardsSphereInViewSpace) {
  Host h(*scene::builtin("demo"), kWide, link::WireVersion::kV2);
  const std::vector<scene::Sphere> view = h.view();
  ASSERT_EQ(view.size(), 1u);
  EXPECT_NEAR(view[0].center.x, 0, 1e-9);
  EXPECT_NEAR(view[0].center.y, 0, 1e-9);
  EXPECT_NEAR(view[0].center.z, 400, 1e-9);
  EXPECT_NEAR(view[0].radius, 64, 1e-9);
  const ReadyWorld& w = h.update();
  EXPECT_EQ(w.spheres, 1u);
  EXPECT_EQ(w.saturations.total(), 0u);
  const auto decoded = link::decode_frame(link::WireVersion::kV2, w.bytes, 4096);
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded.value().spheres[0].z, 400 * 16);
  EXPECT_EQ(decoded.value().spheres[0].radius, 64u * 16u);
  EXPECT_EQ(decoded.value().sequence, 0u) << "numbers are the link's to give, as a world goes out";
}

TEST(Host, EncodesV3FramesForTheLinkToNumber) {
  Host h(*scene::builtin("demo"), kWide, link::WireVersion::kV3);
  std::vector<std::uint8_t> bytes = h.update().bytes;
  const auto unnumbered = link::decode_frame(link::WireVersion::kV3, bytes, 4096);
  ASSERT_TRUE(unnumbered.ok());
  EXPECT_EQ(unnumbered.value().session, 0u);
  EXPECT_EQ(unnumbered.value().sequence, 0u);
  link::Numbering numbering(link::WireVersion::kV3, 77);
  numbering.stamp(bytes);
  numbering.stamp(bytes);
  const auto numbered = link::decode_frame(link::WireVersion::kV3, bytes, 4096);
  ASSERT_TRUE(numbered.ok()) << numbered.error().detail;
  EXPECT_EQ(numbered.value().session, 77u);
  EXPECT_EQ(numbered.value().sequence, 2u);
  EXPECT_EQ(numbered.value().spheres, unnumbered.value().spheres);
}

// Each kind of clamp is counted in the update's saturations and in the totals over updates (link encode prints
// the totals): a coordinate, a radius and a dielectric's index of refraction out of the formats' ranges.
TEST(Host, TotalsCountEveryKindOfSaturation) {
  scene::Scene s = *scene::builtin("demo");
  s.spheres[0].radius = 1e9;  // beyond the radius format
  scene::Sphere far = s.spheres[0];
  far.radius = 1;
  far.center = {1e9, 0, 0};  // its x beyond the coordinate format
  s.spheres.push_back(far);
  scene::Sphere glass = s.spheres[0];
  glass.radius = 1;
  glass.material.type = scene::MaterialType::kDielectric;
  glass.material.ior = 3.0;  // above the device's range below
  s.spheres.push_back(glass);
  link::SceneFormats formats = kWide;
  formats.ior_max = static_cast<std::uint16_t>(2.0 * link::kIorScale);
  Host h(s, formats, link::WireVersion::kV2);
  const Saturations first = h.update().saturations;
  EXPECT_EQ(first.coordinates, 1u);
  EXPECT_EQ(first.radii, 1u);
  EXPECT_EQ(first.iors, 1u);
  h.update();
  EXPECT_EQ(h.total_saturations().coordinates, 2u);
  EXPECT_EQ(h.total_saturations().radii, 2u);
  EXPECT_EQ(h.total_saturations().iors, 2u);
  EXPECT_EQ(h.total_saturations().total(), 6u);
}

TEST(Host, WorldUpIsScreenUp) {
  scene::Scene s = *scene::builtin("demo");
  s.spheres[0].center = {0, 1, 0};  // above the look-at point
  Host h(s, kWide, link::WireVersion::kV2);
  EXPECT_LT(h.view()[0].center.y, 0);  // view y grows downwards
}

TEST(Host, UnitsPerWorldAreDerivedFromTheLookAtDistance) {
  scene::Scene s = *scene::builtin("demo");
  s.units_per_world = 0;
  s.camera.lookfrom = {0, 0, -5};
  Host h(s, kWide, link::WireVersion::kV2);
  EXPECT_DOUBLE_EQ(h.units_per_world(), 64.0);
  EXPECT_NEAR(view_from_world(h.camera(), h.units_per_world()).apply_point(s.camera.lookat).z, 320.0, 1e-9);
}

TEST(HostView, IsThePureFunctionOfWorldAndCamera) {
  scene::Scene s = *scene::builtin("cluster");
  Host h(s, kWide, link::WireVersion::kV2);
  h.camera().orbit(30);
  h.camera().move(0.5);
  const std::vector<scene::Sphere> view = view_spheres(s.spheres, h.camera(), units_per_world(s));
  ASSERT_EQ(view.size(), s.spheres.size());
  EXPECT_EQ(h.view().size(), view.size());
  for (std::size_t i = 0; i < view.size(); ++i) {
    EXPECT_EQ(h.view()[i].center, view[i].center);
    EXPECT_EQ(h.view()[i].radius, view[i].radius);
  }
  // The update encodes exactly that world.
  const auto decoded = link::decode_frame(link::WireVersion::kV2, h.update().bytes, 4096);
  ASSERT_TRUE(decoded.ok());
  ASSERT_EQ(decoded.value().spheres.size(), view.size());
  EXPECT_EQ(decoded.value().spheres[2].z, kWide.z.quantize(view[2].center.z).raw);
}

TEST(HostView, AV2WorldCarriesAtMostTheSceneMemory) {
  EXPECT_EQ(spheres_carried(100, kWide, link::WireVersion::kV2), 100u);
  link::SceneFormats small = kWide;
  small.max_spheres = 64;
  EXPECT_EQ(spheres_carried(100, small, link::WireVersion::kV2), 64u);
  EXPECT_EQ(spheres_carried(100, small, link::WireVersion::kV1), 100u);
}

TEST(Host, SaturationsAreCountedNotHidden) {
  scene::Scene s = *scene::builtin("demo");
  s.spheres.push_back({{0, 0, 1e6}, 1.0, {}});  // far beyond s24.4 at 32 units per world unit
  Host h(s, kWide, link::WireVersion::kV2);
  const ReadyWorld& w = h.update();
  EXPECT_EQ(w.saturations.coordinates, 1u);
  EXPECT_EQ(h.total_saturations().coordinates, 1u);
  h.update();
  EXPECT_EQ(h.total_saturations().coordinates, 2u);
}

TEST(Host, AnIndexOfRefractionBeyondTheDevicesRangeIsSaturatedAndCounted) {
  scene::Scene s = *scene::builtin("demo");
  s.spheres[0].material.type = scene::MaterialType::kDielectric;
  s.spheres[0].material.ior = 12.0;
  link::SceneFormats narrow = kWide;
  narrow.ior_min = 1024;   // 0.25
  narrow.ior_max = 32768;  // 8
  Host h(s, narrow, link::WireVersion::kV2);
  const ReadyWorld& w = h.update();
  EXPECT_EQ(w.saturations.iors, 1u);
  EXPECT_EQ(w.saturations.total(), 1u);
  EXPECT_EQ(link::decode_frame(link::WireVersion::kV2, w.bytes, 1).value().spheres[0].ior, 32768);
  // The wire's own range takes it as it is.
  EXPECT_EQ(Host(s, kWide, link::WireVersion::kV2).update().saturations.total(), 0u);
}

TEST(Host, V1SendsOneWordPerSphereWithPowerOfTwoRadii) {
  scene::Scene s = *scene::builtin("demo");
  s.spheres[0].radius = 2.2;  // 70.4 pixel units: nearest power of two in log scale is 64
  Host h(s, kWide, link::WireVersion::kV1);
  const ReadyWorld& w = h.update();
  ASSERT_EQ(w.bytes.size(), 8u);
  std::uint64_t word = 0;
  for (auto b : w.bytes) word = word << 8 | b;
  const link::V1Sphere v = link::decode_v1_word(word);
  EXPECT_EQ(v.radius_log2, 6);
  EXPECT_EQ(v.z_raw, 400 * 8);
}

TEST(Host, SpheresBeyondSceneMemoryAreDroppedAndCounted) {
  link::SceneFormats small = kWide;
  small.max_spheres = 3;
  Host h(scene::random_spheres(10, 1), small, link::WireVersion::kV2);
  const ReadyWorld& w = h.update();
  EXPECT_EQ(w.spheres_dropped, 7u);
  EXPECT_EQ(link::decode_frame(link::WireVersion::kV2, w.bytes, 3).value().spheres.size(), 3u);
}

TEST(Host, ResetRestoresTheCamera) {
  Host h(*scene::builtin("demo"), kWide, link::WireVersion::kV2);
  const auto before = h.update().bytes;
  h.camera().move(3);
  h.camera().look(20, 10);
  EXPECT_NE(h.update().bytes, before);
  h.reset();
  auto after = h.update().bytes;
  // Same world; only the sequence number (bytes 8..11) and the CRC differ.
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t i = 12; i + 4 < after.size(); ++i) EXPECT_EQ(after[i], before[i]) << i;
}

}  // namespace
}  // namespace tripsitter::host

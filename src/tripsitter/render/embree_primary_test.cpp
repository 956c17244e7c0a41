// Embree traces the same pictures as render_primary: the benchmark compares like with like.
#include <tripsitter/render/embree_primary.h>

#include <cstdlib>

#include <gtest/gtest.h>

#include <tripsitter/scene/builtin.h>

namespace tripsitter::render {
namespace {

// Pixels whose channels differ by more than `levels` somewhere.
int pixels_apart(const core::ImageRgb8& a, const core::ImageRgb8& b, int levels) {
  int n = 0;
  for (std::size_t i = 0; i < a.pixels.size(); i += 3) {
    for (std::size_t k = 0; k < 3; ++k) {
      if (std::abs(int{a.pixels[i + k]} - int{b.pixels[i + k]}) > levels) {
        ++n;
        break;
      }
    }
  }
  return n;
}

}  // namespace

TEST(EmbreePrimary, EveryPacketSizeDrawsWhatRenderPrimaryDraws) {
  for (const char* name : {"field", "random-300"}) {
    const scene::Scene sc = *scene::builtin(name);
    const PathScene scene(sc.spheres);
    // 90 x 70: blocks of 4 x 4 pixels do not divide it, so partial packets are exercised.
    const PrimarySettings s{.width = 90, .height = 70, .threads = 2};
    const ThinLensCamera camera(sc.camera, s.width, s.height);
    const core::ImageRgb8 ours = render_primary(scene, camera, s);
    const EmbreePrimary embree(scene, 2);
    for (EmbreePacket p : {EmbreePacket::k1, EmbreePacket::k8, EmbreePacket::k16}) {
      const core::ImageRgb8 theirs = embree.render(camera, s, p);
      ASSERT_EQ(theirs.width, s.width);
      // Different sphere formulas round differently: a level here and there, a silhouette pixel (measured: at most
      // 1 pixel of 6300 differs at all, none by more than 2 levels).
      EXPECT_LE(pixels_apart(ours, theirs, 2), 2) << name << ", " << to_string(p);
      EXPECT_LE(pixels_apart(ours, theirs, 0), s.width * s.height / 100) << name << ", " << to_string(p);
    }
  }
}

}  // namespace tripsitter::render

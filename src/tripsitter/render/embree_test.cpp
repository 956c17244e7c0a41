// Embree does the same work as TripSitter: the benchmark compares like with like.
#include <tripsitter/render/embree.h>

#include <cmath>
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

TEST(EmbreeScene, EveryPacketSizeDrawsWhatRenderPrimaryDraws) {
  for (const char* name : {"field", "random-300"}) {
    const scene::Scene sc = *scene::builtin(name);
    const PathScene scene(sc.spheres);
    // 90 x 70: blocks of 4 x 4 pixels do not divide it, so partial packets are exercised.
    const PrimarySettings s{.width = 90, .height = 70, .threads = 2};
    const ThinLensCamera camera(sc.camera, s.width, s.height);
    const core::ImageRgb8 ours = render_primary(scene, camera, s);
    const EmbreeScene embree(scene, 2);
    for (EmbreePacket p : {EmbreePacket::k1, EmbreePacket::k8, EmbreePacket::k16}) {
      const core::ImageRgb8 theirs = embree.render_primary(camera, s, p);
      ASSERT_EQ(theirs.width, s.width);
      // Different sphere formulas round differently: a level here and there, a silhouette pixel (measured: at most
      // 1 pixel of 6300 differs at all, none by more than 2 levels).
      EXPECT_LE(pixels_apart(ours, theirs, 2), 2) << name << ", " << to_string(p);
      EXPECT_LE(pixels_apart(ours, theirs, 0), s.width * s.height / 100) << name << ", " << to_string(p);
    }
  }
}

// The path tracer over Embree's hits: Embree rounds differently, so paths part ways now and then, but the picture is
// the same in distribution: the mean and the pixel-to-pixel error against ours are what two seeds of ours give.
TEST(EmbreeScene, PathTracerOverEmbreeMatchesOursInDistribution) {
  const scene::Scene sc = *scene::builtin("field");
  const PathScene scene(sc.spheres);
  const ThinLensCamera camera(sc.camera, 64, 36);
  PathSettings s{.width = 64, .height = 36, .spp = 16, .max_depth = 50, .seed = 3, .threads = 2, .sky = {}};
  const core::ImageRgbF ours = render_path(scene, camera, s);
  const EmbreeScene embree(scene, 2);
  const core::ImageRgbF theirs = render_path(scene, embree, camera, s);
  s.seed = 4;
  const core::ImageRgbF other_seed = render_path(scene, camera, s);
  const auto mean = [](const core::ImageRgbF& img) {
    double sum = 0;
    for (const auto& p : img.pixels) sum += (p.x + p.y + p.z) / 3.0;
    return sum / static_cast<double>(img.pixels.size());
  };
  const auto rmse = [](const core::ImageRgbF& a, const core::ImageRgbF& b) {
    double sum = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
      const Vec3f d = a.pixels[i] - b.pixels[i];
      sum += core::dot(d, d) / 3.0;
    }
    return std::sqrt(sum / static_cast<double>(a.pixels.size()));
  };
  EXPECT_NEAR(mean(theirs), mean(ours), 0.01);
  // Same seed: most paths agree, so Embree's picture is nearer ours than another seed's is.
  EXPECT_LT(rmse(theirs, ours), rmse(other_seed, ours));
}

}  // namespace tripsitter::render

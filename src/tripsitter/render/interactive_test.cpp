#include <tripsitter/render/interactive.h>

#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/scene/builtin.h>

namespace tripsitter::render {
namespace {

constexpr int kWidth = 48, kHeight = 27;

struct Field {
  scene::Scene sc = *scene::builtin("field");
  PathScene scene{sc.spheres};
  PathSettings path() const {
    PathSettings s{.width = kWidth, .height = kHeight, .spp = 1, .max_depth = 8, .seed = 3, .threads = 2, .sky = {}};
    return s;
  }
  ThinLensCamera camera(double orbit_x = 0) const {
    scene::CameraSettings c = sc.camera;
    c.lookfrom.x += orbit_x;
    return ThinLensCamera(c, kWidth, kHeight);
  }
};

InteractiveSettings plain() {
  InteractiveSettings s;
  s.denoise = false;
  return s;
}

TEST(Interactive, AStillCameraWithoutTheDenoiserIsPlainAccumulation) {
  const Field f;
  InteractivePath loop(f.scene, f.path(), plain());
  std::vector<Vec3f> sum(static_cast<std::size_t>(kWidth * kHeight));
  for (std::uint32_t k = 0; k < 3; ++k) {
    PathSettings s = f.path();
    s.first_sample = k;
    const core::ImageRgbF pass = render_path(f.scene, f.camera(), s);
    for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += pass.pixels[i];
    const core::ImageRgbF& picture = loop.frame(f.camera());
    for (std::size_t i = 0; i < sum.size(); ++i)
      ASSERT_EQ(picture.pixels[i], sum[i] * (1.0f / static_cast<float>(k + 1))) << "frame " << k << " pixel " << i;
  }
  EXPECT_EQ(loop.frames(), 3u);
  EXPECT_DOUBLE_EQ(loop.mean_samples(), 3.0);
}

TEST(Interactive, RowsTakeTurnsAndTogetherMakeTheWholePass) {
  const Field f;
  InteractiveSettings settings = plain();
  settings.row_step = 2;
  InteractivePath loop(f.scene, f.path(), settings);
  loop.frame(f.camera());
  EXPECT_DOUBLE_EQ(loop.mean_samples(), static_cast<double>((kHeight + 1) / 2) / kHeight);  // rows 0, 2, ...
  const core::ImageRgbF& picture = loop.frame(f.camera());
  const core::ImageRgbF whole = render_path(f.scene, f.camera(), f.path());  // sample 0 of every pixel
  EXPECT_EQ(picture.pixels, whole.pixels);
}

TEST(Interactive, AMoveKeepsHistoryWithReuseAndStartsOverWithout) {
  const Field f;
  for (bool reuse : {true, false}) {
    InteractiveSettings settings = plain();
    settings.reuse = reuse;
    settings.temporal.max_history_moving = 3;
    InteractivePath loop(f.scene, f.path(), settings);
    for (int k = 0; k < 4; ++k) loop.frame(f.camera());
    loop.frame(f.camera(0.02));
    if (reuse) {
      // Most pixels still see their surface: their history, worth 3 samples, and the new one.
      EXPECT_GT(loop.mean_samples(), 3.0);
      EXPECT_LE(loop.mean_samples(), 4.0);
      EXPECT_EQ(loop.frames(), 5u);
    } else {
      EXPECT_DOUBLE_EQ(loop.mean_samples(), 1.0);
      EXPECT_EQ(loop.frames(), 1u);
    }
  }
}

TEST(Interactive, TheSameBytesOnAnyThreadCount) {
  const Field f;
  std::vector<std::vector<Vec3f>> pictures;
  for (int threads : {1, 2, 3}) {
    PathSettings s = f.path();
    s.threads = threads;
    InteractivePath loop(f.scene, s, InteractiveSettings{});
    for (int k = 0; k < 3; ++k) loop.frame(f.camera(0.01 * k));
    pictures.push_back(loop.frame(f.camera(0.05)).pixels);
  }
  EXPECT_EQ(pictures[0], pictures[1]);
  EXPECT_EQ(pictures[0], pictures[2]);
}

TEST(Interactive, RestartForgetsTheHistory) {
  const Field f;
  InteractivePath loop(f.scene, f.path(), plain());
  loop.frame(f.camera());
  loop.frame(f.camera());
  loop.restart();
  loop.frame(f.camera());
  EXPECT_EQ(loop.frames(), 1u);
  EXPECT_DOUBLE_EQ(loop.mean_samples(), 1.0);
}

// The filter's luminance term tightens as samples gather (sigma_luminance_1spp / sqrt(samples)): on the first
// frame the schedule filters as a constant sigma of sigma_luminance_1spp does, bit for bit; after 32 frames the
// picture stays closer to what plain accumulation gives than under that constant sigma.
TEST(Interactive, TheFilterLetsMoreThroughAsSamplesGather) {
  const Field f;
  InteractiveSettings constant;
  constant.sigma_luminance_min = constant.sigma_luminance_1spp;
  InteractivePath scheduled(f.scene, f.path(), InteractiveSettings{}), fixed(f.scene, f.path(), constant),
      accumulated(f.scene, f.path(), plain());
  EXPECT_EQ(scheduled.frame(f.camera()).pixels, fixed.frame(f.camera()).pixels);
  accumulated.frame(f.camera());
  std::vector<Vec3f> a, b, c;
  for (int k = 1; k < 32; ++k) {
    a = scheduled.frame(f.camera()).pixels;
    b = fixed.frame(f.camera()).pixels;
    c = accumulated.frame(f.camera()).pixels;
  }
  const auto distance = [&c](const std::vector<Vec3f>& picture) {
    double d = 0;
    for (std::size_t i = 0; i < c.size(); ++i) d += static_cast<double>(core::length(picture[i] - c[i]));
    return d / static_cast<double>(c.size());
  };
  EXPECT_LT(distance(a), 0.8 * distance(b));
}

}  // namespace
}  // namespace tripsitter::render

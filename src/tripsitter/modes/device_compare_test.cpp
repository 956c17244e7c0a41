// The path-tracing device against the float path tracer of its own rays, and the hw source accumulating while the
// camera is still.
#include <tripsitter/modes/device_compare.h>

#include <cmath>

#include <gtest/gtest.h>

#include <tripsitter/link/frame.h>
#include <tripsitter/scene/builtin.h>

namespace tripsitter::modes {
namespace {

SourceConfig path_config(int spp = 1, int depth = 4) {
  SourceConfig c;
  c.mode = Mode::kHw;
  c.board.preset = device::path_preset();
  c.board.preset.path->spp = spp;
  c.board.preset.path->depth = depth;
  c.board.device_threads = 2;
  return c;
}

TEST(DeviceCompare, SceneMemoryReadsBackInPixelUnitsAndMaterials) {
  device::SceneMemory memory;
  memory.valid = true;
  memory.geometry = {{{48, -8, 5120}, 160}, {{-16, 0, 1600}, 8}, {{0, 32, 3200}, 1}};
  memory.surfaces = {{link::kMaterialLambertian, {255, 0, 51}, 0, 4096},
                     {link::kMaterialMetal, {128, 128, 128}, 65535, 4096},
                     {link::kMaterialDielectric, {255, 255, 255}, 0, 6144}};
  const std::vector<scene::Sphere> s = scene_memory_spheres(memory, 4);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].center.x, 3.0);
  EXPECT_EQ(s[0].center.y, -0.5);
  EXPECT_EQ(s[0].center.z, 320.0);
  EXPECT_EQ(s[0].radius, 10.0);
  EXPECT_EQ(s[0].material.type, scene::MaterialType::kLambertian);
  EXPECT_EQ(s[0].material.albedo.x, 1.0);
  EXPECT_EQ(s[0].material.albedo.y, 0.0);
  EXPECT_DOUBLE_EQ(s[0].material.albedo.z, 0.2);
  EXPECT_EQ(s[1].material.type, scene::MaterialType::kMetal);
  EXPECT_EQ(s[1].material.fuzz, 1.0);
  EXPECT_EQ(s[1].radius, 0.5);
  EXPECT_EQ(s[2].material.type, scene::MaterialType::kDielectric);
  EXPECT_EQ(s[2].material.ior, 1.5);
  EXPECT_EQ(s[2].radius, 1.0 / 16);
}

TEST(DeviceCompare, AccumulatedImageIsTheMeanAndCountsPixelsWithoutSamples) {
  device::FrameMemory memory;
  memory.row(0)[0] = {{512, 256, 0}, 2, 1};    // means 0.5, 0.25, 0
  memory.row(479)[639] = {{511, 511, 511}, 1, 1};
  const AccumulatedImage image = accumulated_image(memory);
  EXPECT_EQ(image.without_samples, 640u * 480u - 2u);
  EXPECT_EQ(image.min_count, 1);
  EXPECT_EQ(image.max_count, 2);
  EXPECT_EQ(image.counts[0], 2);
  EXPECT_EQ(image.counts[1], 0);
  EXPECT_FLOAT_EQ(image.mean.pixels[0].x, 0.5f);
  EXPECT_FLOAT_EQ(image.mean.pixels[0].y, 0.25f);
  EXPECT_FLOAT_EQ(image.mean.pixels.back().z, 511.0f / 512);
  EXPECT_EQ(image.mean.pixels[1].x, 0.0f);
}

TEST(DeviceCompare, HwSourceWithThePathPresetAccumulatesWhileStillAndRestartsWhenSteered) {
  const scene::Scene scene = *scene::builtin("demo");
  auto source = make_frame_source(scene, path_config(2));
  const HwFrame* f = &std::get<HwFrame>(source->draw());
  ASSERT_NE(f->frame_memory, nullptr);
  ASSERT_NE(f->scene_memory, nullptr);
  EXPECT_EQ(f->samples, 2);
  EXPECT_TRUE(source->refining());
  f = &std::get<HwFrame>(source->draw());
  EXPECT_EQ(f->samples, 4);
  EXPECT_EQ(accumulated_image(*f->frame_memory).max_count, 4);
  source->steer().orbit(10);
  f = &std::get<HwFrame>(source->draw());
  EXPECT_EQ(f->samples, 2);  // a world of other content starts over

  // Frame memory holds at most 255 samples per pixel: after one frame of 128 another would not fit, so nothing
  // more is added. (An empty world and one ray per path, so that the samples cost little; and one worker, so that
  // only the pixels at the start of each line (24 of 640) are on time and traced: the frame counts, refining() and
  // the 255-sample limit do not depend on how many pixels a frame traces, and the one worker still puts 128 samples
  // into thousands of pixels. With the preset's 64 workers the first frames of these two sources traced about 70
  // million samples, most of this test's time.)
  SourceConfig full_config = path_config(128, 1);
  full_config.board.preset.workers = 1;
  auto full = make_frame_source(scene::random_spheres(0, 1), full_config);
  f = &std::get<HwFrame>(full->draw());
  EXPECT_EQ(f->samples, 128);
  EXPECT_FALSE(full->refining());
  const AccumulatedImage full_first = accumulated_image(*f->frame_memory);
  EXPECT_EQ(full_first.max_count, 128);
  EXPECT_GT(640u * 480u - full_first.without_samples, 1000u);
  f = &std::get<HwFrame>(full->draw());
  EXPECT_EQ(f->samples, 128);
  // Pixels late in the first frame may take their 128 now; those that have 128 take nothing.
  const AccumulatedImage full_second = accumulated_image(*f->frame_memory);
  EXPECT_EQ(full_second.max_count, 128);
  std::size_t changed = 0;
  for (std::size_t i = 0; i < full_first.counts.size(); ++i) {
    const render::Vec3f& a = full_first.mean.pixels[i];
    const render::Vec3f& b = full_second.mean.pixels[i];
    changed += full_first.counts[i] != 0 &&
               (full_second.counts[i] != full_first.counts[i] || a.x != b.x || a.y != b.y || a.z != b.z);
  }
  EXPECT_EQ(changed, 0u);
  SourceConfig nearly_config = path_config(100, 1);
  nearly_config.board.preset.workers = 1;
  auto nearly = make_frame_source(scene::random_spheres(0, 1), nearly_config);
  nearly->draw();
  EXPECT_TRUE(nearly->refining());  // 200 fit

  // Presets that trace one ray per pixel, and v1 words, do not accumulate.
  SourceConfig wide;
  auto still = make_frame_source(scene, wide);
  EXPECT_EQ(std::get<HwFrame>(still->draw()).frame_memory, nullptr);
  EXPECT_FALSE(still->refining());
  SourceConfig v1 = path_config();
  v1.board.wire = link::WireVersion::kV1;
  auto words = make_frame_source(scene, v1);
  words->draw();
  EXPECT_FALSE(words->refining());
}

// The device's mean after 16 samples per pixel against the float path tracer at 64: the same world, sky and
// depth, so the two agree up to noise and the device's fixed-point approximations. Deterministic: the device's
// random numbers are a function of pixel and sample, the reference's of its seed.
TEST(DeviceCompare, TheDeviceAgreesWithTheFloatPathTracerOfItsRays) {
  const scene::Scene scene = *scene::builtin("cluster");
  // 2 samples per frame: at 8, the dielectric's costly pixels are late in every frame and never get a sample.
  const SourceConfig config = path_config(2);
  auto source = make_frame_source(scene, config);
  const HwFrame* f = nullptr;
  for (int i = 0; i < 8; ++i) f = &std::get<HwFrame>(source->draw());
  ASSERT_EQ(f->samples, 16);
  PathComparisonSettings settings;
  settings.reference_spp = 64;
  settings.threads = 2;
  const PathComparison c = compare_device_path(*f, config.board.preset, settings);
  EXPECT_EQ(c.device_spp, 16);
  EXPECT_EQ(c.max_spp, 16);
  EXPECT_GE(c.min_spp, 14);  // a pixel late in a frame has the others' samples only
  EXPECT_EQ(c.reference_spp, 64);
  EXPECT_EQ(c.depth, 4);
  EXPECT_EQ(c.pixels, 640u * 480u);
  EXPECT_EQ(c.pixels_compared + c.pixels_without_samples, c.pixels);
  EXPECT_LT(std::abs(c.figures.mean_relative_bias), 0.02) << c.figures.mean_relative_bias;
  EXPECT_LT(c.figures.relmse, 0.05) << c.figures.relmse;
  // By first hit: every compared pixel in one part; cluster has spheres of all three materials.
  std::size_t parts = c.sky.pixels;
  for (const PartComparison& m : c.material) {
    EXPECT_GT(m.pixels, 1000u);
    EXPECT_LT(std::abs(m.figures.mean_relative_bias), 0.05) << m.figures.mean_relative_bias;
    parts += m.pixels;
  }
  EXPECT_EQ(parts, c.pixels_compared);
  EXPECT_GT(c.sky.pixels, c.pixels / 2);
}

TEST(DeviceCompare, NeedsAFrameWithFrameMemory) {
  const scene::Scene scene = *scene::builtin("demo");
  auto source = make_frame_source(scene, SourceConfig{});
  EXPECT_THROW(compare_device_path(std::get<HwFrame>(source->draw()), device::path_preset(), {}), std::invalid_argument);
  EXPECT_THROW(compare_device_path(std::get<HwFrame>(source->draw()), device::wide_preset(), {}), std::invalid_argument);
}

}  // namespace
}  // namespace tripsitter::modes

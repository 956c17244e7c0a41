// Each mode's frame source against the road it replaces: the board, the float reference of the host's view,
// the path tracer from the scene's camera.
#include <tripsitter/modes/frame_source.h>

#include <gtest/gtest.h>

#include <tripsitter/board/board.h>
#include <tripsitter/core/colour.h>
#include <tripsitter/host/view.h>
#include <tripsitter/modes/animation.h>
#include <tripsitter/render/camera.h>
#include <tripsitter/render/normal.h>
#include <tripsitter/scene/builtin.h>

namespace tripsitter::modes {
namespace {

SourceConfig config(Mode mode, int width = 640, int height = 480) {
  SourceConfig c;
  c.mode = mode;
  c.width = width;
  c.height = height;
  c.threads = 2;
  c.max_depth = 8;
  return c;
}

TEST(Mode, NamesRoundTripAndNothingElseParses) {
  for (Mode m : {Mode::kHw, Mode::kNormal, Mode::kPath}) EXPECT_EQ(mode_by_name(mode_name(m)), m);
  EXPECT_FALSE(mode_by_name("HW"));
  EXPECT_FALSE(mode_by_name(""));
  EXPECT_FALSE(mode_by_name("paths"));
}

TEST(FrameSource, HwIsWhatTheBoardShows) {
  const scene::Scene scene = *scene::builtin("cluster");
  auto source = make_frame_source(scene, config(Mode::kHw));
  board::Board board(scene, {});
  source->steer().orbit(20);
  board.host().camera().orbit(20);
  const Frame& frame = source->draw();
  const board::ShownFrame shown = board.show();
  EXPECT_EQ(frame.vga, shown.image);
  EXPECT_EQ(frame.link_bytes, shown.link_bytes);
  EXPECT_EQ(frame.device.late_pixels, shown.device.late_pixels);
  EXPECT_TRUE(frame.rgb.pixels.empty());
}

TEST(FrameSource, NormalIsTheFloatReferenceOfTheHostsView) {
  const scene::Scene scene = *scene::builtin("cluster");
  auto source = make_frame_source(scene, config(Mode::kNormal, 200, 150));
  source->steer().move(0.7);
  const auto view = host::view_spheres(scene.spheres, source->camera(), host::units_per_world(scene));
  EXPECT_EQ(source->draw().vga, render::render_normal(view, 200, 150, device::wide_preset().max_bounces));
}

TEST(FrameSource, NormalRendersTheWorldTheDeviceWouldHold) {
  const scene::Scene field = *scene::builtin("field");
  ASSERT_GT(field.spheres.size(), 64u);
  SourceConfig c = config(Mode::kNormal, 160, 120);
  c.preset = *device::preset_by_name("board-2023");  // scene memory of 64 spheres
  ASSERT_EQ(c.preset.max_spheres, 64u);
  const host::Camera camera(field.camera.lookfrom, field.camera.lookat, field.camera.vup);
  const auto first = host::view_spheres(std::span(field.spheres).first(64), camera, host::units_per_world(field));
  const auto all = host::view_spheres(field.spheres, camera, host::units_per_world(field));
  const core::Image444 expected = render::render_normal(first, 160, 120, c.preset.max_bounces);
  ASSERT_NE(expected, render::render_normal(all, 160, 120, c.preset.max_bounces));  // the limit shows
  EXPECT_EQ(make_frame_source(field, c)->draw().vga, expected);
  c.wire = link::WireVersion::kV1;  // a stream of words carries every sphere
  EXPECT_EQ(make_frame_source(field, c)->draw().vga, render::render_normal(all, 160, 120, c.preset.max_bounces));
}

TEST(FrameSource, ResetShowsTheFirstPictureAgain) {
  const scene::Scene scene = *scene::builtin("cluster");
  for (Mode mode : {Mode::kHw, Mode::kNormal, Mode::kPath}) {
    auto source = make_frame_source(scene, config(mode, 64, 48));
    const core::ImageRgb8 first = source->draw().rgb8();
    source->steer().strafe(1.5);
    EXPECT_NE(source->draw().rgb8(), first) << mode_name(mode);
    source->reset();
    EXPECT_EQ(source->draw().rgb8(), first) << mode_name(mode);
  }
}

TEST(FrameSource, PathIsThePathTracerFromTheScenesCamera) {
  const scene::Scene scene = *scene::builtin("cluster");
  SourceConfig c = config(Mode::kPath, 80, 60);
  c.spp = 3;
  c.seed = 9;
  const render::PathScene path_scene(scene.spheres);
  const core::ImageRgbF expected =
      render::render_path(path_scene, render::ThinLensCamera(scene.camera, 80, 60), path_settings(c));
  const auto source = make_frame_source(scene, c);
  const Frame& frame = source->draw();  // lives as long as the source
  EXPECT_EQ(frame.rgb, core::to_srgb8(expected));
  EXPECT_EQ(frame.samples, 3);
  EXPECT_TRUE(frame.vga.pixels.empty());
}

TEST(FrameSource, ProgressivePathAddsASamplePerDrawUntilTheCameraMoves) {
  const scene::Scene scene = *scene::builtin("cluster");
  SourceConfig c = config(Mode::kPath, 64, 48);
  c.progressive = true;
  auto source = make_frame_source(scene, c);
  EXPECT_EQ(source->draw().samples, 1);
  EXPECT_EQ(source->draw().samples, 2);
  EXPECT_TRUE(source->refining());
  // A move keeps the history that still shows the same surfaces (render/interactive.h): the count of still frames
  // starts over, the picture's samples do not.
  source->steer().look(1, 0);
  const Frame& moved = source->draw();
  EXPECT_EQ(moved.samples, 1);
  EXPECT_GT(moved.mean_samples, 1.5);
  // Without reuse a move starts the picture over.
  c.reuse = false;
  auto fresh = make_frame_source(scene, c);
  fresh->draw();
  fresh->draw();
  fresh->steer().look(1, 0);
  EXPECT_EQ(fresh->draw().mean_samples, 1.0);
}

TEST(FrameSource, AnimationFramesDoNotDependOnWhichFramesWereDrawn) {
  const scene::Scene scene = *scene::builtin("cluster");
  for (Mode mode : {Mode::kHw, Mode::kNormal, Mode::kPath}) {
    std::vector<core::ImageRgb8> all;
    auto every = make_frame_source(scene, config(mode, 48, 36));
    animate(*every, 4, 90, {}, [&](int, const Frame* f) { all.push_back(f->rgb8()); });
    ASSERT_EQ(all.size(), 4u);
    EXPECT_NE(all[0], all[3]);
    auto some = make_frame_source(scene, config(mode, 48, 36));
    int drawn = 0;
    animate(*some, 4, 90, [](int i) { return i == 3; }, [&](int i, const Frame* f) {
      EXPECT_EQ(f != nullptr, i == 3);
      if (f == nullptr) return;
      ++drawn;
      EXPECT_EQ(f->rgb8(), all[3]) << mode_name(mode);
    });
    EXPECT_EQ(drawn, 1);
  }
}

}  // namespace
}  // namespace tripsitter::modes

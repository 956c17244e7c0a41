// Each mode's frame source against the road it replaces: the board, the float reference of the host's view,
// the path tracer from the scene's camera.
#include <tripsitter/modes/frame_source.h>

#include <filesystem>

#include <gtest/gtest.h>

#include <tripsitter/board/board.h>
#include <tripsitter/core/colour.h>
#include <tripsitter/display/png.h>
#include <tripsitter/host/view.h>
#include <tripsitter/modes/animation.h>
#include <tripsitter/render/camera.h>
#include <tripsitter/render/denoise.h>
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

TEST(FrameSource, HwIsWhatTheBoardShows) {
  const scene::Scene scene = *scene::builtin("cluster");
  auto source = make_frame_source(scene, config(Mode::kHw));
  board::Board board(scene, {});
  source->steer().orbit(20);
  board.host().camera().orbit(20);
  ASSERT_TRUE(std::holds_alternative<HwFrame>(source->draw()));
  const HwFrame& frame = std::get<HwFrame>(source->draw());
  const board::ShownFrame shown = board.show();
  EXPECT_EQ(frame.vga, shown.image);
  EXPECT_EQ(frame.link_bytes, shown.link_bytes);
  EXPECT_EQ(frame.device.late_pixels, shown.device.late_pixels);
}

TEST(FrameSource, NormalIsTheFloatReferenceOfTheHostsView) {
  const scene::Scene scene = *scene::builtin("cluster");
  auto source = make_frame_source(scene, config(Mode::kNormal, 200, 150));
  source->steer().move(0.7);
  const auto view = host::view_spheres(scene.spheres, source->camera(), host::units_per_world(scene));
  EXPECT_EQ(std::get<NormalFrame>(source->draw()).vga, render::render_normal(view, 200, 150, device::wide_preset().max_bounces));
}

TEST(FrameSource, NormalRendersTheWorldTheDeviceWouldHold) {
  const scene::Scene field = *scene::builtin("field");
  ASSERT_GT(field.spheres.size(), 64u);
  SourceConfig c = config(Mode::kNormal, 160, 120);
  c.board.preset = *device::preset_by_name("board-2023");  // scene memory of 64 spheres
  ASSERT_EQ(c.board.preset.max_spheres, 64u);
  const host::Camera camera(field.camera.lookfrom, field.camera.lookat, field.camera.vup);
  const auto first = host::view_spheres(std::span(field.spheres).first(64), camera, host::units_per_world(field));
  const auto all = host::view_spheres(field.spheres, camera, host::units_per_world(field));
  const core::Image444 expected = render::render_normal(first, 160, 120, c.board.preset.max_bounces);
  ASSERT_NE(expected, render::render_normal(all, 160, 120, c.board.preset.max_bounces));  // the limit shows
  EXPECT_EQ(std::get<NormalFrame>(make_frame_source(field, c)->draw()).vga, expected);
  c.board.wire = link::WireVersion::kV1;  // a stream of words carries every sphere
  EXPECT_EQ(std::get<NormalFrame>(make_frame_source(field, c)->draw()).vga,
            render::render_normal(all, 160, 120, c.board.preset.max_bounces));
}

TEST(FrameSource, ResetShowsTheFirstPictureAgain) {
  const scene::Scene scene = *scene::builtin("cluster");
  for (Mode mode : {Mode::kHw, Mode::kNormal, Mode::kPath}) {
    auto source = make_frame_source(scene, config(mode, 64, 48));
    const core::ImageRgb8 first = rgb8(source->draw());
    source->steer().strafe(1.5);
    EXPECT_NE(rgb8(source->draw()), first) << mode_name(mode);
    source->reset();
    EXPECT_EQ(rgb8(source->draw()), first) << mode_name(mode);
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
  const PathFrame& frame = std::get<PathFrame>(source->draw());  // lives as long as the source
  EXPECT_EQ(frame.rgb, core::to_srgb8(expected));
  EXPECT_EQ(frame.samples, 3);
  EXPECT_EQ(frame.aovs, nullptr);  // not asked for
}

TEST(FrameSource, DenoisedPathStillIsRenderDenoisedStill) {
  const scene::Scene scene = *scene::builtin("cluster");
  for (int spp : {1, 4}) {
    SourceConfig c = config(Mode::kPath, 40, 30);
    c.spp = spp;
    c.denoise = true;
    const render::PathScene path_scene(scene.spheres);
    const render::ThinLensCamera lens(scene.camera, 40, 30);
    render::Denoiser denoiser;
    render::Aovs aovs;
    const core::ImageRgbF expected = render::denoised_still(path_settings(c), [&](const render::PathSettings& s, render::Aovs* a) {
      return render::render_path(path_scene, lens, s, {}, a);
    }, denoiser, aovs);
    const auto source = make_frame_source(scene, c);
    const PathFrame& frame = std::get<PathFrame>(source->draw());
    EXPECT_EQ(frame.rgb, core::to_srgb8(expected)) << spp;
    ASSERT_NE(frame.aovs, nullptr);
    EXPECT_EQ(frame.aovs->depth, aovs.depth) << spp;
  }
}

TEST(FrameSource, ProgressivePathAddsASamplePerDrawUntilTheCameraMoves) {
  const scene::Scene scene = *scene::builtin("cluster");
  SourceConfig c = config(Mode::kPath, 64, 48);
  c.progressive = true;
  auto source = make_frame_source(scene, c);
  EXPECT_EQ(std::get<PathFrame>(source->draw()).samples, 1);
  EXPECT_EQ(std::get<PathFrame>(source->draw()).samples, 2);
  EXPECT_TRUE(source->refining());
  // A move keeps the history that still shows the same surfaces (render/interactive.h): the count of still frames
  // starts over, the picture's samples do not.
  source->steer().look(1, 0);
  const PathFrame& moved = std::get<PathFrame>(source->draw());
  EXPECT_EQ(moved.samples, 1);
  EXPECT_GT(moved.mean_samples, 1.5);
  // Without reuse a move starts the picture over.
  c.reuse = false;
  auto fresh = make_frame_source(scene, c);
  fresh->draw();
  fresh->draw();
  fresh->steer().look(1, 0);
  EXPECT_EQ(std::get<PathFrame>(fresh->draw()).mean_samples, 1.0);
}

TEST(FrameSource, AnimationFramesDoNotDependOnWhichFramesWereDrawn) {
  const scene::Scene scene = *scene::builtin("cluster");
  for (Mode mode : {Mode::kHw, Mode::kNormal, Mode::kPath}) {
    std::vector<core::ImageRgb8> all;
    auto every = make_frame_source(scene, config(mode, 48, 36));
    animate(*every, 4, 90, {}, [&](int, const Frame* f) { all.push_back(rgb8(*f)); });
    ASSERT_EQ(all.size(), 4u);
    EXPECT_NE(all[0], all[3]);
    auto some = make_frame_source(scene, config(mode, 48, 36));
    int drawn = 0;
    animate(*some, 4, 90, [](int i) { return i == 3; }, [&](int i, const Frame* f) {
      EXPECT_EQ(f != nullptr, i == 3);
      if (f == nullptr) return;
      ++drawn;
      EXPECT_EQ(rgb8(*f), all[3]) << mode_name(mode);
    });
    EXPECT_EQ(drawn, 1);
  }
}

// A 12-bit picture is written as PNG; it has no linear light for an EXR file, which is refused with nothing
// written.
TEST(FrameSource, ATwelveBitPictureIsWrittenAsPngOnly) {
  const std::filesystem::path dir = testing::TempDir();
  const Frame frame = NormalFrame{core::Image444(3, 2, core::Rgb444(0x0f0))};
  EXPECT_EQ(picture_size(frame).width, 3);
  const auto png = write_image((dir / "frame_source_12bit.png").string(), frame);
  ASSERT_TRUE(png.ok()) << png.error().message;
  EXPECT_EQ(display::read_png((dir / "frame_source_12bit.png").string()).value(), std::get<NormalFrame>(frame).vga);
  const auto exr = write_image((dir / "frame_source_12bit.exr").string(), frame);
  ASSERT_FALSE(exr.ok());
  EXPECT_NE(exr.error().message.find("no linear light"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "frame_source_12bit.exr"));
  std::filesystem::remove(dir / "frame_source_12bit.png");
}

}  // namespace
}  // namespace tripsitter::modes

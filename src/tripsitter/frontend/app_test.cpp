// The interactive board driven by synthetic input, as the window would drive it.
#include <tripsitter/frontend/app.h>

#include <filesystem>

#include <gtest/gtest.h>

#include <tripsitter/display/png.h>
#include <tripsitter/frontend/window.h>
#include <tripsitter/scene/builtin.h>

namespace tripsitter::frontend {
namespace {

namespace fs = std::filesystem;

AppConfig config(Mode mode, const std::string& scene = "demo") {
  AppConfig c;
  c.scene = *scene::builtin(scene);
  c.source.mode = mode;
  c.screenshot_dir = fs::temp_directory_path().string();
  return c;
}

// Mean column of pixels whose colour differs from the background: where the sphere is on screen.
double sphere_column(const core::ImageRgb8& img) {
  double sum = 0;
  int count = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const std::size_t i = 3 * (static_cast<std::size_t>(y) * img.width + x);
      if (img.pixels[i] != 0x00 || img.pixels[i + 1] != 0x33 || img.pixels[i + 2] != 0x66) {
        sum += x;
        ++count;
      }
    }
  return count ? sum / count : -1;
}

void hold(App& app, host::Key key, double seconds) {
  app.handle({Input::Kind::kKeyDown, key});
  for (int i = 0; i < 10; ++i) app.advance(seconds / 10);
  app.handle({Input::Kind::kKeyUp, key});
}

// A key held for one frame, for the tests that only need the camera to have moved: every frame costs a whole
// picture through the board or the path tracer, and hold makes ten.
void tap(App& app, host::Key key, double seconds) {
  app.handle({Input::Kind::kKeyDown, key});
  app.advance(seconds);
  app.handle({Input::Kind::kKeyUp, key});
}

TEST(App, HoldingDMovesTheCameraRightSoTheSphereMovesLeft) {
  App app(config(Mode::kHw));
  const double before = sphere_column(app.frame());
  EXPECT_NEAR(before, 320, 1.0);
  hold(app, host::Key::kD, 0.25);  // 1 world unit at 4 units/s: 25.6 pixels at the sphere's depth
  const double after = sphere_column(app.frame());
  EXPECT_NEAR(after, 320 - 25.6, 2.0);
}

// A held for 0.1 s at 100 frames per second and at 10: ten frames against one, the same picture. (0.1 s moves the
// camera 0.4 world units, about 10 pixels at the sphere's depth: the first assertion holds it to having moved.)
TEST(App, MovementDependsOnHoldTimeNotOnFrameRate) {
  App fast(config(Mode::kHw)), slow(config(Mode::kHw));
  const core::ImageRgb8 before = fast.frame();
  fast.handle({Input::Kind::kKeyDown, host::Key::kA});
  for (int i = 0; i < 10; ++i) fast.advance(0.01);
  slow.handle({Input::Kind::kKeyDown, host::Key::kA});
  slow.advance(0.1);
  EXPECT_NE(fast.frame(), before);
  EXPECT_EQ(fast.frame(), slow.frame());
}

TEST(App, NothingHeldNothingRedrawnAndResetRestores) {
  App app(config(Mode::kHw));
  const core::ImageRgb8 first = app.frame();
  const auto serial = app.frame_serial();
  app.advance(0.1);
  EXPECT_EQ(app.frame_serial(), serial);
  tap(app, host::Key::kW, 0.5);
  EXPECT_NE(app.frame(), first);  // closer: a bigger sphere
  app.handle({Input::Kind::kKeyDown, host::Key::kR});
  app.advance(0.01);
  EXPECT_EQ(app.frame(), first);
}

TEST(App, F12WritesTheDisplayedFrame) {
  App app(config(Mode::kHw, "cluster"));
  hold(app, host::Key::kJ, 0.2);
  app.handle({Input::Kind::kScreenshot});
  const auto message = app.take_message();
  ASSERT_TRUE(message.has_value());
  const std::string prefix = "screenshot written to ";
  ASSERT_EQ(message->rfind(prefix, 0), 0u) << *message;
  const std::string path = message->substr(prefix.size());
  const auto png = display::read_png(path);
  ASSERT_TRUE(png.ok());
  EXPECT_EQ(core::to_rgb8(png.value()), app.frame());
  fs::remove(path);
}

TEST(App, OverlayAndHelpToggle) {
  App app(config(Mode::kNormal));
  EXPECT_FALSE(app.overlay());
  app.handle({Input::Kind::kToggleOverlay});
  EXPECT_TRUE(app.overlay());
  app.handle({Input::Kind::kToggleHelp});
  EXPECT_TRUE(app.help());
  app.handle({Input::Kind::kQuit});
  EXPECT_TRUE(app.quit());
}

TEST(App, NormalModeShowsTheFloatReference) {
  App app(config(Mode::kNormal));
  EXPECT_NEAR(sphere_column(app.frame()), 320, 1.0);
  EXPECT_EQ(app.info().spheres, 1u);
}

TEST(App, PathModeRefinesWhileStillAndRestartsOnMovement) {
  AppConfig c = config(Mode::kPath, "cluster");
  c.source.threads = 2;
  App app(std::move(c));
  EXPECT_EQ(app.info().samples, 1);
  app.advance(0.01);
  app.advance(0.01);
  EXPECT_EQ(app.info().samples, 3);
  tap(app, host::Key::kL, 0.05);
  EXPECT_EQ(app.info().samples, 1);
}

// hw with the path preset: the device accumulates while the camera is still (the host keeps sending the same
// world), and a move starts it over; Tab's figures say how far it got.
TEST(App, HwPathPresetAccumulatesWhileStillAndRestartsOnMovement) {
  AppConfig c = config(Mode::kHw, "cluster");
  c.source.board.preset = device::path_preset();
  c.source.board.preset.path->spp = 2;
  c.source.board.preset.workers = 32;
  App app(std::move(c));
  EXPECT_EQ(app.info().samples, 2);
  EXPECT_TRUE(app.info().device_path);
  const auto serial = app.frame_serial();
  app.advance(0.01);  // nothing held: still a new frame, two more samples per pixel
  app.advance(0.01);
  EXPECT_EQ(app.frame_serial(), serial + 2);
  EXPECT_EQ(app.info().samples, 6);
  tap(app, host::Key::kL, 0.05);
  EXPECT_EQ(app.info().samples, 2);
  const std::vector<std::string> lines = overlay_text(app.info(), Mode::kHw);
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[2].rfind("late lines ", 0), 0u) << lines[2];
  EXPECT_EQ(lines[5], "2 samples per pixel, 32 workers");
}

}  // namespace
}  // namespace tripsitter::frontend

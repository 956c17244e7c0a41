// The SDL window with SDL's offscreen video driver: no display needed.
#include <tripsitter/frontend/run.h>
#include <tripsitter/frontend/window.h>
#include <tripsitter/scene/builtin.h>

#include <SDL.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include <gtest/gtest.h>

namespace tripsitter::frontend {
namespace {

void push_key(SDL_Scancode sc, bool down, bool repeat = false) {
  SDL_Event e{};
  e.type = down ? SDL_KEYDOWN : SDL_KEYUP;
  e.key.keysym.scancode = sc;
  e.key.repeat = repeat ? 1 : 0;
  e.key.timestamp = SDL_GetTicks();
  SDL_PushEvent(&e);
}

class WindowTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    setenv("SDL_VIDEODRIVER", "offscreen", 1);
    // SDL's software renderer, and its window surface kept in plain memory (by default SDL presents a software
    // surface through an OpenGL texture): no OpenGL, so no Mesa worker threads for the thread sanitizer to report.
    setenv("SDL_RENDER_DRIVER", "software", 1);
    setenv("SDL_FRAMEBUFFER_ACCELERATION", "0", 1);
  }
};

TEST_F(WindowTest, KeysBecomeBoardInput) {
  Window w("test", 1);
  push_key(SDL_SCANCODE_W, true);
  push_key(SDL_SCANCODE_W, true, true);  // auto-repeat: dropped
  push_key(SDL_SCANCODE_W, false);
  push_key(SDL_SCANCODE_F12, true);
  push_key(SDL_SCANCODE_TAB, true);
  push_key(SDL_SCANCODE_ESCAPE, true);
  push_key(SDL_SCANCODE_Z, true);        // not a board key: ignored
  const auto in = w.poll();
  ASSERT_EQ(in.size(), 5u);
  EXPECT_EQ(in[0].input.kind, Input::Kind::kKeyDown);
  EXPECT_EQ(in[0].input.key, host::Key::kW);
  EXPECT_EQ(in[1].input.kind, Input::Kind::kKeyUp);
  EXPECT_EQ(in[2].input.kind, Input::Kind::kScreenshot);
  EXPECT_EQ(in[3].input.kind, Input::Kind::kToggleOverlay);
  EXPECT_EQ(in[4].input.kind, Input::Kind::kQuit);
}

TEST_F(WindowTest, PresentsFramesWithAndWithoutOverlay) {
  Window w("test", 2);
  core::ImageRgb8 frame(App::kWidth, App::kHeight);
  w.present(frame, 1, {});
  w.present(frame, 1, overlay_text(FrameInfo{}, Mode::kHw));
  w.present(frame, 2, help_text());
  EXPECT_FALSE(help_text().empty());
  EXPECT_EQ(overlay_text(FrameInfo{}, Mode::kHw).size(), 5u);
}

// The whole loop through SDL: key events pushed into SDL's queue reach the App, which answers a held key
// with a new frame, F12 with a screenshot and Esc by quitting.
TEST_F(WindowTest, ScriptedKeysDriveTheLoop) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("tripsitter_window_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  AppConfig config;
  config.scene = *scene::builtin("demo");
  config.screenshot_dir = dir.string();

  ASSERT_EQ(SDL_InitSubSystem(SDL_INIT_VIDEO), 0) << SDL_GetError();
  push_key(SDL_SCANCODE_D, true);  // held for the whole run
  LatencyStats moved = run_window(config, {1, 5});
  EXPECT_EQ(moved.samples, 1);  // the press was answered by a new frame
  SDL_QuitSubSystem(SDL_INIT_VIDEO);

  ASSERT_EQ(SDL_InitSubSystem(SDL_INIT_VIDEO), 0) << SDL_GetError();
  push_key(SDL_SCANCODE_F12, true);
  push_key(SDL_SCANCODE_ESCAPE, true);
  run_window(config, {1, 1000});  // Esc ends it long before 1000 frames
  SDL_QuitSubSystem(SDL_INIT_VIDEO);
  EXPECT_TRUE(fs::exists(dir / "tripsitter-1.png"));
  fs::remove_all(dir);
}

// run --preset path: the loop keeps drawing while the device accumulates, with no key pressed, and Tab's figures
// (samples per pixel, late lines, workers) are drawn over the frames.
TEST_F(WindowTest, ThePathPresetRefinesInTheLoopWithTheOverlayShown) {
  AppConfig config;
  config.scene = *scene::builtin("demo");
  config.source.board.preset = device::path_preset();
  config.source.board.preset.path->depth = 2;
  ASSERT_EQ(SDL_InitSubSystem(SDL_INIT_VIDEO), 0) << SDL_GetError();
  push_key(SDL_SCANCODE_TAB, true);
  const LatencyStats stats = run_window(config, {1, 4});  // four frames drawn, none answering a key
  SDL_QuitSubSystem(SDL_INIT_VIDEO);
  EXPECT_EQ(stats.samples, 0);
  FrameInfo info;
  info.device_path = true;
  info.samples = 4;
  info.workers = 64;
  const auto lines = overlay_text(info, Mode::kHw);
  EXPECT_EQ(lines.back(), "4 samples per pixel, 64 workers");
}

}  // namespace
}  // namespace tripsitter::frontend

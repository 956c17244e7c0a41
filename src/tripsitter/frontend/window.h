// The VGA monitor as a desktop window (SDL2): shows 640x480 frames scaled by an integer factor, aspect
// kept when resized, and turns the keyboard into Input. The only code that knows SDL.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <tripsitter/core/image.h>
#include <tripsitter/frontend/app.h>

struct SDL_Window;
struct SDL_Renderer;
struct SDL_Texture;
typedef struct _TTF_Font TTF_Font;

namespace tripsitter::frontend {

struct PolledInput {
  Input input;
  std::uint32_t sdl_ticks_ms = 0;  // when SDL received the event
};

class Window {
 public:
  // Throws std::runtime_error with SDL's message when no window can be opened.
  Window(const std::string& title, int scale);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // Every pending event, translated; key repeats are dropped (held keys are tracked by the App).
  std::vector<PolledInput> poll();
  // Shows the frame (re-uploaded only when `serial` changed), with the overlay lines and the help text
  // drawn on top when given.
  void present(const core::ImageRgb8& frame, std::uint64_t serial, const std::vector<std::string>& overlay_lines);
  void set_title(const std::string& title);
  // Sleeps until an event arrives or `ms` milliseconds pass, whichever is first.
  void wait(int ms);
  // Milliseconds since SDL started, the clock of PolledInput::sdl_ticks_ms.
  static std::uint32_t ticks_ms();
  bool has_font() const { return font_ != nullptr; }

 private:
  SDL_Window* window_ = nullptr;
  SDL_Renderer* renderer_ = nullptr;
  SDL_Texture* texture_ = nullptr;
  TTF_Font* font_ = nullptr;
  std::uint64_t uploaded_serial_ = ~std::uint64_t{0};
};

// The text of the overlay (Tab) and of the key help (H).
std::vector<std::string> overlay_text(const FrameInfo& info, Mode mode);
std::vector<std::string> help_text();

}  // namespace tripsitter::frontend

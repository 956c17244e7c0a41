#include <tripsitter/frontend/window.h>

#include <SDL.h>
#include <SDL_ttf.h>

#include <cstdio>
#include <optional>
#include <stdexcept>

namespace tripsitter::frontend {
namespace {

// Debian's fonts-dejavu-core; without it the overlay and help go to the window title and stderr.
constexpr const char* kFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf";
constexpr int kFontSize = 14;

std::optional<host::Key> board_key(SDL_Scancode sc) {
  switch (sc) {
    case SDL_SCANCODE_W: return host::Key::kW;
    case SDL_SCANCODE_A: return host::Key::kA;
    case SDL_SCANCODE_S: return host::Key::kS;
    case SDL_SCANCODE_D: return host::Key::kD;
    case SDL_SCANCODE_I: return host::Key::kI;
    case SDL_SCANCODE_K: return host::Key::kK;
    case SDL_SCANCODE_J: return host::Key::kJ;
    case SDL_SCANCODE_L: return host::Key::kL;
    case SDL_SCANCODE_Q: return host::Key::kQ;
    case SDL_SCANCODE_E: return host::Key::kE;
    case SDL_SCANCODE_R: return host::Key::kR;
    default: return std::nullopt;
  }
}

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what + ": " + SDL_GetError()); }

}  // namespace

Window::Window(const std::string& title, int scale) {
  if (SDL_Init(SDL_INIT_VIDEO) != 0) fail("cannot start SDL video");
  window_ = SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, App::kWidth * scale,
                             App::kHeight * scale, SDL_WINDOW_RESIZABLE);
  if (window_ == nullptr) fail("cannot open a window");
  renderer_ = SDL_CreateRenderer(window_, -1, 0);
  if (renderer_ == nullptr) fail("cannot create a renderer");
  // The picture keeps its 4:3 aspect at an integer scale, centred, when the window is resized.
  SDL_RenderSetLogicalSize(renderer_, App::kWidth, App::kHeight);
  SDL_RenderSetIntegerScale(renderer_, SDL_TRUE);
  SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "nearest");
  texture_ = SDL_CreateTexture(renderer_, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING, App::kWidth, App::kHeight);
  if (texture_ == nullptr) fail("cannot create a texture");
  if (TTF_Init() == 0) font_ = TTF_OpenFont(kFontPath, kFontSize);
}

Window::~Window() {
  if (font_ != nullptr) TTF_CloseFont(font_);
  if (TTF_WasInit()) TTF_Quit();
  if (texture_ != nullptr) SDL_DestroyTexture(texture_);
  if (renderer_ != nullptr) SDL_DestroyRenderer(renderer_);
  if (window_ != nullptr) SDL_DestroyWindow(window_);
  SDL_Quit();
}

std::uint32_t Window::ticks_ms() { return SDL_GetTicks(); }

std::vector<PolledInput> Window::poll() {
  std::vector<PolledInput> out;
  SDL_Event e;
  while (SDL_PollEvent(&e)) {
    if (e.type == SDL_QUIT) {
      out.push_back({{Input::Kind::kQuit}, e.quit.timestamp});
      continue;
    }
    if (e.type != SDL_KEYDOWN && e.type != SDL_KEYUP) continue;
    if (e.key.repeat != 0) continue;
    const bool down = e.type == SDL_KEYDOWN;
    const std::uint32_t t = e.key.timestamp;
    if (auto key = board_key(e.key.keysym.scancode)) {
      out.push_back({{down ? Input::Kind::kKeyDown : Input::Kind::kKeyUp, *key}, t});
    } else if (down) {
      switch (e.key.keysym.scancode) {
        case SDL_SCANCODE_ESCAPE: out.push_back({{Input::Kind::kQuit}, t}); break;
        case SDL_SCANCODE_F12: out.push_back({{Input::Kind::kScreenshot}, t}); break;
        case SDL_SCANCODE_TAB: out.push_back({{Input::Kind::kToggleOverlay}, t}); break;
        case SDL_SCANCODE_H: out.push_back({{Input::Kind::kToggleHelp}, t}); break;
        case SDL_SCANCODE_N: out.push_back({{Input::Kind::kToggleDenoise}, t}); break;
        default: break;
      }
    }
  }
  return out;
}

void Window::wait(int ms) { SDL_WaitEventTimeout(nullptr, ms); }

void Window::set_title(const std::string& title) { SDL_SetWindowTitle(window_, title.c_str()); }

void Window::present(const core::ImageRgb8& frame, std::uint64_t serial, const std::vector<std::string>& overlay_lines) {
  if (serial != uploaded_serial_) {
    SDL_UpdateTexture(texture_, nullptr, frame.pixels.data(), frame.width * 3);
    uploaded_serial_ = serial;
  }
  SDL_SetRenderDrawColor(renderer_, 0, 0, 0, 255);
  SDL_RenderClear(renderer_);
  SDL_RenderCopy(renderer_, texture_, nullptr, nullptr);
  if (!overlay_lines.empty() && font_ != nullptr) {
    int y = 6;
    for (const auto& line : overlay_lines) {
      SDL_Surface* text = TTF_RenderUTF8_Shaded(font_, line.c_str(), {255, 255, 255, 255}, {0, 0, 0, 255});
      if (text == nullptr) continue;
      if (SDL_Texture* t = SDL_CreateTextureFromSurface(renderer_, text)) {
        const SDL_Rect where{6, y, text->w, text->h};
        SDL_RenderCopy(renderer_, t, nullptr, &where);
        SDL_DestroyTexture(t);
      }
      y += text->h;
      SDL_FreeSurface(text);
    }
  }
  SDL_RenderPresent(renderer_);
}

std::vector<std::string> overlay_text(const FrameInfo& info, Mode mode) {
  char buf[160];
  std::vector<std::string> lines;
  std::snprintf(buf, sizeof buf, "%.1f frames/s, %.1f ms per frame", info.fps, info.frame_ms);
  lines.emplace_back(buf);
  std::snprintf(buf, sizeof buf, "%zu spheres", info.spheres);
  lines.emplace_back(buf);
  if (mode == Mode::kHw) {
    std::snprintf(buf, sizeof buf, "late lines %d", info.late_lines);
    lines.emplace_back(buf);
    std::snprintf(buf, sizeof buf, "link %zu bytes per world, %.3f ms", info.link_bytes, info.link_ms);
    lines.emplace_back(buf);
    // Values the host clamped to the device's fixed point: only the world the board shows has any.
    std::snprintf(buf, sizeof buf, "saturations %llu", static_cast<unsigned long long>(info.saturations));
    lines.emplace_back(buf);
    if (info.device_path) {
      // Frame memory accumulates while the camera is still; late pixels get no sample in their frame.
      std::snprintf(buf, sizeof buf, "%d samples per pixel, %d workers", info.samples, info.workers);
      lines.emplace_back(buf);
    }
  }
  if (mode == Mode::kPath) {
    std::snprintf(buf, sizeof buf, "%.1f samples per pixel (%d frames still), denoiser %s", info.mean_samples,
                  info.samples, info.denoise ? "on" : "off");
    lines.emplace_back(buf);
  }
  return lines;
}

std::vector<std::string> help_text() {
  return {"W/S  forward/back     A/D  left/right",
          "I/K  look up/down     J/L  look left/right",
          "Q/E  orbit the target R    reset",
          "Tab  figures          F12  screenshot",
          "N    denoiser (path)  H    this help",
          "Esc  quit"};
}

}  // namespace tripsitter::frontend

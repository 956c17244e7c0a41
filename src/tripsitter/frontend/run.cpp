#include <tripsitter/frontend/run.h>

#include <algorithm>
#include <chrono>
#include <iostream>

#include <tripsitter/frontend/window.h>

namespace tripsitter::frontend {

LatencyStats run_window(AppConfig config, const RunOptions& options) {
  const Mode mode = config.source.mode;
  const std::string title = "TripSitter - " + config.scene.name;
  Window window(title, options.scale);
  App app(std::move(config));
  if (!window.has_font()) std::cerr << "no DejaVu Sans Mono font: overlay and help go to the window title\n";

  LatencyStats stats;
  double latency_sum = 0;
  std::uint32_t pending_key_ms = 0;  // SDL time of the oldest key press no frame has answered yet
  bool key_pending = false;
  auto last = std::chrono::steady_clock::now();
  for (std::uint64_t frames = 0; !app.quit() && (options.max_frames == 0 || frames < options.max_frames); ++frames) {
    for (const PolledInput& p : window.poll()) {
      app.handle(p.input);
      if (p.input.kind == Input::Kind::kKeyDown && !key_pending) {
        key_pending = true;
        pending_key_ms = p.sdl_ticks_ms;
      }
    }
    if (auto message = app.take_message()) std::cerr << *message << "\n";
    const auto now = std::chrono::steady_clock::now();
    const double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    const std::uint64_t serial_before = app.frame_serial();
    app.advance(dt);
    std::vector<std::string> lines;
    if (app.overlay()) lines = overlay_text(app.info(), mode);
    if (app.help()) {
      const auto help = help_text();
      lines.insert(lines.end(), help.begin(), help.end());
    }
    if (!window.has_font()) {
      window.set_title(lines.empty() ? title : title + " | " + lines.front());
      lines.clear();
    }
    window.present(app.frame(), app.frame_serial(), lines);
    if (key_pending && app.frame_serial() != serial_before) {
      const double latency = static_cast<double>(Window::ticks_ms() - pending_key_ms);
      ++stats.samples;
      latency_sum += latency;
      stats.max_ms = std::max(stats.max_ms, latency);
      key_pending = false;
    }
    // Nothing changed: sleep until the next event rather than spin (a held key keeps frames coming).
    if (app.frame_serial() == serial_before) window.wait(10);
  }
  if (stats.samples > 0) stats.mean_ms = latency_sum / stats.samples;
  return stats;
}

}  // namespace tripsitter::frontend

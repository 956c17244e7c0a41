// The interactive loop: window events into the App, the App's frames onto the window.
#pragma once

#include <cstdint>
#include <string>

#include <tripsitter/frontend/app.h>

namespace tripsitter::frontend {

// Key-to-photon latency: from SDL receiving a key press to the present of the first frame made after it.
struct LatencyStats {
  int samples = 0;
  double mean_ms = 0;
  double max_ms = 0;
};

struct RunOptions {
  int scale = 1;
  // Stop after this many frames (0: run until the user quits); for tests and measurements.
  std::uint64_t max_frames = 0;
};

// Opens the window and runs until Esc, closing the window, or max_frames. Throws std::runtime_error when
// no window can be opened.
LatencyStats run_window(AppConfig config, const RunOptions& options);

}  // namespace tripsitter::frontend

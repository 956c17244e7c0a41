// A sweep run: its points measured in parallel (one point per thread: each runs the board on its own thread),
// with progress, and stoppable between points so that an interrupted sweep keeps what it finished.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <tripsitter/explore/evaluate.h>
#include <tripsitter/explore/point.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::explore {

struct RunSettings {
  int threads = 0;  // points measured at once (0: every core)
  EvaluateSettings evaluate;
  const std::atomic<bool>* stop = nullptr;       // set: no further point starts (the ones running finish)
  std::function<void(const Point&)> on_point;    // each point as it finishes, from the threads, one at a time
};

struct RunResult {
  std::vector<Point> points;  // the points finished, in the sweep's order, each with index = its place here
  std::size_t planned = 0;
  bool interrupted = false;   // stop was set before every point had started
  double seconds = 0;
};

// Measures every configuration over its scene (scenes[config.scene]). The first exception a point throws stops
// the run and is rethrown.
RunResult run_sweep(const std::vector<Configuration>& configs, const std::map<std::string, scene::Scene>& scenes,
                    const RunSettings& settings);

}  // namespace tripsitter::explore

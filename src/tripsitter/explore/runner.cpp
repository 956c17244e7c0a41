#include <tripsitter/explore/runner.h>

#include <algorithm>
#include <chrono>
#include <mutex>

#include <tripsitter/core/parallel.h>

namespace tripsitter::explore {

RunResult run_sweep(const std::vector<Configuration>& configs, const std::map<std::string, scene::Scene>& scenes,
                    const RunSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  RunResult result;
  result.planned = configs.size();
  ReferenceCache references;
  std::mutex mutex;
  std::atomic<bool> skipped{false};
  core::parallel_for(0, static_cast<int>(configs.size()), settings.threads, [&](int i) {
    if (settings.stop != nullptr && settings.stop->load()) {
      skipped = true;
      return;
    }
    const Configuration& config = configs[static_cast<std::size_t>(i)];
    Point point = evaluate(config, scenes.at(config.scene), settings.evaluate, references);
    point.index = i;
    const std::lock_guard lock(mutex);
    if (settings.on_point) settings.on_point(point);
    result.points.push_back(std::move(point));
  });
  std::sort(result.points.begin(), result.points.end(), [](const Point& a, const Point& b) { return a.index < b.index; });
  // Renumbered in order, so that an interrupted sweep's points index its own list.
  for (std::size_t i = 0; i < result.points.size(); ++i) result.points[i].index = static_cast<int>(i);
  result.interrupted = skipped.load();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace tripsitter::explore

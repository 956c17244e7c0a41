// A progress bar on stderr for long work: silent for the first second, then redrawn a few times a second
// with the rate and the time left; a closing line with the total when it finishes.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <ostream>
#include <string>
#include <thread>

namespace tripsitter::core {

class ProgressBar {
 public:
  // `total` units of work, counted with add(); `unit` names them ("samples"). A disabled bar prints nothing.
  ProgressBar(std::string label, std::uint64_t total, std::string unit, bool enabled, std::ostream& out);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Thread-safe.
  void add(std::uint64_t units) { done_.fetch_add(units, std::memory_order_relaxed); }
  // Stops the bar; prints the closing line if the bar was ever shown. Called by the destructor too.
  void finish();

 private:
  void draw(bool final_line);
  void run();

  std::string label_, unit_;
  std::uint64_t total_;
  std::ostream& out_;
  std::atomic<std::uint64_t> done_{0};
  std::chrono::steady_clock::time_point start_;
  bool shown_ = false;
  bool stop_ = false;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread thread_;
};

}  // namespace tripsitter::core

#include <tripsitter/core/progress.h>

#include <algorithm>
#include <cstdio>

namespace tripsitter::core {
namespace {

constexpr auto kQuietPeriod = std::chrono::seconds(1);
constexpr auto kRedraw = std::chrono::milliseconds(250);

// 12.3 M, 456 k, 78
std::string scaled(double v) {
  char buf[32];
  if (v >= 1e9) std::snprintf(buf, sizeof buf, "%.2f G", v / 1e9);
  else if (v >= 1e6) std::snprintf(buf, sizeof buf, "%.2f M", v / 1e6);
  else if (v >= 1e3) std::snprintf(buf, sizeof buf, "%.2f k", v / 1e3);
  else std::snprintf(buf, sizeof buf, "%.0f ", v);
  return buf;
}

}  // namespace

ProgressBar::ProgressBar(std::string label, std::uint64_t total, std::string unit, bool enabled, std::ostream& out)
    : label_(std::move(label)), unit_(std::move(unit)), total_(std::max<std::uint64_t>(total, 1)), out_(out),
      start_(std::chrono::steady_clock::now()) {
  if (enabled) thread_ = std::thread([this] { run(); });
}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::run() {
  std::unique_lock lock(mutex_);
  if (wake_.wait_for(lock, kQuietPeriod, [this] { return stop_; })) return;
  while (!stop_) {
    draw(false);
    wake_.wait_for(lock, kRedraw, [this] { return stop_; });
  }
}

void ProgressBar::draw(bool final_line) {
  const std::uint64_t done = std::min(done_.load(std::memory_order_relaxed), total_);
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0;
  const double fraction = static_cast<double>(done) / static_cast<double>(total_);
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(fraction * kWidth);
  std::string bar(static_cast<std::size_t>(filled), '=');
  bar.resize(kWidth, ' ');
  char line[256];
  if (final_line) {
    std::snprintf(line, sizeof line, "\r%s: [%s] done in %.1f s, %s%s/s\n", label_.c_str(), bar.c_str(), elapsed,
                  scaled(rate).c_str(), unit_.c_str());
  } else {
    const double left = rate > 0 ? static_cast<double>(total_ - done) / rate : 0;
    std::snprintf(line, sizeof line, "\r%s: [%s] %3.0f%%  %s%s/s  %.0f s left ", label_.c_str(), bar.c_str(),
                  100 * fraction, scaled(rate).c_str(), unit_.c_str(), left);
  }
  out_ << line << std::flush;
  shown_ = true;
}

void ProgressBar::finish() {
  {
    std::lock_guard lock(mutex_);
    if (stop_) return;
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (shown_) draw(true);
}

}  // namespace tripsitter::core

// The test bench of ts_scanout (controller, line buffers and VGA block): drives the Verilated RTL one device cycle
// at a time and plays its N workers in C++ by the worker contract of ts_controller.sv: a pixel started in cycle
// s with occupancy o makes its worker ready again in cycle s + o and pulses done, with its column and colour, in
// cycle s + o + drain - 1. What a pixel is (its colour and occupancy) comes from the test, which takes it from the
// C++ device model. The bench reports every VGA sample (at vga_strobe, with the beam position it belongs to) and
// every line's late count.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <set>
#include <type_traits>
#include <vector>

#include <verilated.h>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/device/vga_signal.h>

namespace tripsitter::rtl::testing {

// Bits lsb .. lsb + width - 1 (width <= 32) of a Verilated port: an integer for up to 64 bits, VlWide above.
template <class T>
std::uint32_t get_field(const T& port, int lsb, int width) {
  const std::uint64_t mask = (std::uint64_t{1} << width) - 1;
  if constexpr (std::is_integral_v<T>) {
    return static_cast<std::uint32_t>((static_cast<std::uint64_t>(port) >> lsb) & mask);
  } else {
    constexpr int kWords = static_cast<int>(sizeof(T) / sizeof(EData));
    const int word = lsb / 32;
    std::uint64_t chunk = port.data()[word];
    if (word + 1 < kWords) chunk |= static_cast<std::uint64_t>(port.data()[word + 1]) << 32;
    return static_cast<std::uint32_t>((chunk >> (lsb % 32)) & mask);
  }
}

template <class T>
void set_field(T& port, int lsb, int width, std::uint32_t value) {
  const std::uint64_t mask = (std::uint64_t{1} << width) - 1;
  const std::uint64_t v = value & mask;
  if constexpr (std::is_integral_v<T>) {
    const auto u = static_cast<std::uint64_t>(port);
    port = static_cast<T>((u & ~(mask << lsb)) | (v << lsb));
  } else {
    constexpr int kWords = static_cast<int>(sizeof(T) / sizeof(EData));
    const int word = lsb / 32;
    const int shift = lsb % 32;
    std::uint64_t chunk = port.data()[word];
    if (word + 1 < kWords) chunk |= static_cast<std::uint64_t>(port.data()[word + 1]) << 32;
    chunk = (chunk & ~(mask << shift)) | (v << shift);
    port.data()[word] = static_cast<EData>(chunk);
    if (word + 1 < kWords) port.data()[word + 1] = static_cast<EData>(chunk >> 32);
  }
}

// One pixel as the emulated worker computes it: its colour and how many cycles it keeps the worker
// (DevicePreset::pixel_occupancy of its spheres and reflections).
struct Job {
  core::Rgb444 colour;
  std::int64_t occupancy = 1;
};

// A VGA sample with the beam position the RTL says it belongs to.
struct PlacedSample {
  int line = 0;
  int column = 0;
  device::VgaSample sample;
};

// The configuration the Verilated model was built with (its parameters) and how its workers behave.
struct BenchConfig {
  int workers = 10;
  int lead_cycles = 3000;
  std::int64_t drain = 0;
  bool flush = false;  // the RTL's FLUSH parameter; the emulated workers honour flush when it is set
  // Workers that take pixels ahead of the model's schedule, as the pipelined ts_worker does: ready again
  // least_cycles after a start (as if the pixel did not reflect), done pulses where the model's schedule puts them
  // (the window's first start plus the occupancies so far, plus drain - 1). Needs flush.
  bool speculative = false;
};

template <class V>
class ScanoutBench {
 public:
  // job(row, col): the pixel a worker is handed. least(row): least_cycles while the window of `row` is open.
  // REQUIRES config.workers <= 64.
  ScanoutBench(const BenchConfig& config, std::function<Job(int, int)> job, std::function<std::uint16_t(int)> least)
      : config_(config), job_(std::move(job)), least_(std::move(least)),
        workers_(static_cast<std::size_t>(config.workers)) {
    Verilated::randReset(2);  // registers and memories start random: reset must make that irrelevant
    Verilated::randSeed(20);
    model_ = std::make_unique<V>();
    model_->clk = 0;
    model_->rst = 1;
    model_->least_cycles = 1;
    for (int i = 0; i < 4; ++i) {
      model_->clk = 0;
      model_->eval();
      model_->clk = 1;
      model_->eval();
    }
    model_->rst = 0;
  }
  ~ScanoutBench() { model_->final(); }
  ScanoutBench(const ScanoutBench&) = delete;
  ScanoutBench& operator=(const ScanoutBench&) = delete;

  std::function<void(const PlacedSample&)> on_sample;  // every pixel clock, at vga_strobe
  std::function<void(int)> on_late;                    // each window's late pixels (late_valid)

  // Runs `cycles` device cycles.
  void run(std::int64_t cycles) {
    for (std::int64_t k = 0; k < cycles; ++k) step();
  }
  // Runs until `samples` more VGA samples have been reported.
  void run_samples(std::int64_t samples) {
    const std::int64_t until = samples_ + samples;
    while (samples_ < until) step();
  }

  std::int64_t cycle() const { return cycle_; }
  bool protocol_error() const { return model_->protocol_error != 0; }
  // Starts the RTL made while the worker was not ready (never, if the RTL keeps the contract), and jobs the bench
  // cannot play (occupancy below 1, or a done pulse in the cycle of its start).
  int bad_starts() const { return bad_starts_; }
  // Rows whose window opened with some worker still busy (only without flush: the model's schedule assumes idle
  // workers then, so those rows may differ from the model).
  const std::set<int>& busy_at_open() const { return busy_at_open_; }
  std::int64_t pixels_started() const { return started_; }
  // Speculative workers: the cycles by which starts came before the model's, summed.
  std::int64_t cycles_ahead() const { return ahead_; }

 private:
  struct Pending {
    std::int64_t done_at;
    int col;
    core::Rgb444 colour;
  };
  struct Worker {
    std::int64_t ready_at = 0;
    std::deque<Pending> pending;
    std::int64_t model_next = -1;  // speculative: the model's start of the next pixel; -1 before a window's first
  };

  void step() {
    V& m = *model_;
    const int line = m.line;
    const int line_cycle = m.column * 4 + cycle_in_pixel();
    const int row = line == 524 ? 0 : line + 1;
    if (row < 480) m.least_cycles = least_(row);
    // A window opens: the model starts every worker idle.
    if ((line == 524 || line < 479) && line_cycle == 3200 - config_.lead_cycles) {
      for (const Worker& w : workers_)
        if (cycle_ < w.ready_at) busy_at_open_.insert(row);
    }
    // The workers' outputs for this cycle: ready and done as bit masks (N <= 64), the done fields where a done is.
    std::uint64_t ready = 0, done = 0;
    for (int i = 0; i < config_.workers; ++i) {
      const Worker& w = workers_[static_cast<std::size_t>(i)];
      if (cycle_ >= w.ready_at) ready |= std::uint64_t{1} << i;
      if (!w.pending.empty() && w.pending.front().done_at == cycle_) {
        done |= std::uint64_t{1} << i;
        set_field(m.done_col, i * 10, 10, static_cast<std::uint32_t>(w.pending.front().col));
        set_field(m.colour, i * 12, 12, w.pending.front().colour.packed);
      }
    }
    m.ready = static_cast<decltype(+m.ready)>(ready);
    m.done = static_cast<decltype(+m.done)>(done);
    m.clk = 0;
    m.eval();
    // What the RTL asks of them.
    for (std::uint64_t start = static_cast<std::uint64_t>(m.start); start != 0; start &= start - 1) {
      const int i = std::countr_zero(start);
      Worker& w = workers_[static_cast<std::size_t>(i)];
      if (cycle_ < w.ready_at) ++bad_starts_;
      const int col = static_cast<int>(get_field(m.col, i * 10, 10));
      const int r = static_cast<int>(get_field(m.row, i * 9, 9));
      const Job job = job_(r, col);
      if (job.occupancy < 1 || job.occupancy + config_.drain < 2) ++bad_starts_;  // the bench needs o + drain >= 2
      if (config_.speculative) {
        if (w.model_next < 0) w.model_next = cycle_;
        if (w.model_next < cycle_) ++bad_starts_;  // never after the model's start
        w.model_next += job.occupancy;
        w.ready_at = cycle_ + least_(r);
        w.pending.push_back({w.model_next + config_.drain - 1, col, job.colour});
        ahead_ += w.model_next - job.occupancy - cycle_;
      } else {
        w.ready_at = cycle_ + job.occupancy;
        w.pending.push_back({cycle_ + job.occupancy + config_.drain - 1, col, job.colour});
      }
      ++started_;
    }
    if (m.flush && config_.flush) {
      // Every pixel whose done pulse would come after this cycle is dropped; the worker is ready next cycle.
      for (Worker& w : workers_) {
        while (!w.pending.empty() && w.pending.back().done_at > cycle_) w.pending.pop_back();
        w.ready_at = std::min(w.ready_at, cycle_ + 1);
        w.model_next = -1;
      }
    }
    if (m.vga_strobe && on_sample) {
      ++samples_;
      on_sample({static_cast<int>(m.line), static_cast<int>(m.column),
                 {m.vga_hsync_n != 0, m.vga_vsync_n != 0, core::Rgb444(static_cast<std::uint16_t>(m.vga_rgb))}});
    }
    if (m.late_valid && on_late) on_late(static_cast<int>(m.late_pixels));
    for (std::uint64_t d = done; d != 0; d &= d - 1) workers_[static_cast<std::size_t>(std::countr_zero(d))].pending.pop_front();
    m.clk = 1;
    m.eval();
    ++cycle_;
  }

  // The device cycle within the pixel clock: the bench counts it from reset (the RTL's phase is internal).
  int cycle_in_pixel() const { return static_cast<int>(cycle_ % 4); }

  BenchConfig config_;
  std::function<Job(int, int)> job_;
  std::function<std::uint16_t(int)> least_;
  std::unique_ptr<V> model_;
  std::vector<Worker> workers_;
  std::int64_t cycle_ = 0;
  std::int64_t samples_ = 0;
  std::int64_t started_ = 0;
  std::int64_t ahead_ = 0;
  int bad_starts_ = 0;
  std::set<int> busy_at_open_;
};

}  // namespace tripsitter::rtl::testing

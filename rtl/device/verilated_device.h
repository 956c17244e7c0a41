// The Verilated top (ts_device.sv) of any build behind the device back-end interface: rtl_device.cpp makes one for
// each build the program has; a test may make one of its own build (a planted bug).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

// Verilator's headers are not warning-free under -Wextra: included first, with that warning off.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <verilated.h>
#include <verilated_vcd_c.h>
#pragma GCC diagnostic pop

#include <tripsitter/device/backend.h>
#include <tripsitter/device/device.h>
#include <tripsitter/device/vga.h>

#include "rtl_device.h"

namespace tripsitter::rtl {

inline constexpr int kFrameSamples = device::kVga640x480.h_total() * device::kVga640x480.v_total();
inline constexpr int kLineSamples = device::kVga640x480.h_total();
// Clock cycles the receiver may take after a transfer to check a frame and write scene memory (a 4096-sphere world is
// 64 Ki bytes written a word at a time: far less than this).
inline constexpr int kSettleCycles = 4'000'000;

// `worker_scope`: the VCD scope of the worker whose signals options.vcd also gets, empty for none.
template <class Top>
class RtlDevice final : public device::Backend {
 public:
  RtlDevice(int half_bit, const RtlOptions& options, const std::string& worker_scope)
      : half_bit_(half_bit),
        vcd_strobes_(static_cast<std::uint64_t>(options.vcd_lines) * kLineSamples),
        ctx_(std::make_unique<VerilatedContext>()) {
    ctx_->randReset(2);  // random power-up state: the reset makes it irrelevant
    if (!options.vcd.empty()) ctx_->traceEverOn(true);
    top_ = std::make_unique<Top>(ctx_.get());
    if (!options.vcd.empty()) {
      vcd_ = std::make_unique<VerilatedVcdC>();
      top_->trace(vcd_.get(), 99);
      vcd_->dumpvars(1, "TOP");  // the pins and the simulation outputs
      if (!worker_scope.empty()) vcd_->dumpvars(99, worker_scope);
      vcd_->set_time_unit("1ns");
      vcd_->set_time_resolution("1ns");
      vcd_->open(options.vcd.c_str());
    }
    top_->clk = 0;
    top_->rst = 1;
    top_->spi_cs_n = 1;
    top_->spi_sclk = 0;
    top_->spi_mosi = 0;
    top_->end_of_stream = 0;
    for (int i = 0; i < 4; ++i) tick();
    top_->rst = 0;
    read_counters();
    watching_ = false;
  }
  RtlDevice(const RtlDevice&) = delete;
  RtlDevice& operator=(const RtlDevice&) = delete;
  ~RtlDevice() override {
    top_->final();
    if (vcd_) vcd_->close();
  }

  bool ready() const override { return top_->spi_ready != 0; }

  // Chip select low, the bytes most significant bit first (MOSI changes while SCLK is low and is sampled on its rising
  // edge), chip select high; then clocks until the receiver has dealt with every byte.
  void transfer(std::span<const std::uint8_t> bytes) override {
    watching_ = true;
    top_->spi_cs_n = 0;
    ticks(half_bit_);
    for (const std::uint8_t byte : bytes) {
      for (int bit = 7; bit >= 0; --bit) {
        top_->spi_mosi = (byte >> bit) & 1;
        ticks(half_bit_);
        top_->spi_sclk = 1;
        ticks(half_bit_);
        top_->spi_sclk = 0;
      }
    }
    ticks(half_bit_);
    top_->spi_cs_n = 1;
    settle();
  }

  void end_of_stream() override {
    watching_ = true;
    top_->end_of_stream = 1;
    tick();
    top_->end_of_stream = 0;
    settle();
  }

  device::FrameStats run_frame_lines(const std::function<void(std::span<const device::VgaSample>)>& line_sink) override {
    to_frame_start();
    watching_ = true;
    device::FrameStats stats;
    stats.demand_known = false;
    std::vector<device::VgaSample> line(kLineSamples);
    std::size_t at = 0;
    for (int taken = 0; taken < kFrameSamples;) {
      tick();
      if (top_->late_valid && top_->late_pixels > 0) {
        stats.late_pixels += top_->late_pixels;
        ++stats.late_lines;
      }
      if (!top_->vga_strobe) continue;
      line[at++] = {top_->vga_hsync_n != 0, top_->vga_vsync_n != 0,
                    core::Rgb444::from_channels(top_->vga_r, top_->vga_g, top_->vga_b)};
      ++taken;
      if (at == line.size()) {
        line_sink(line);
        at = 0;
      }
    }
    watching_ = false;
    stats.has_world = top_->shown_valid != 0;
    stats.sequence = stats.has_world ? top_->shown_sequence : 0;
    read_counters();
    return stats;
  }

  const device::ReceiverStats& receiver_stats() const override { return stats_; }
  bool has_world() const override { return top_->shown_valid != 0; }
  const device::SceneMemory* scene_memory() const override { return nullptr; }
  const device::FrameMemory* frame_memory() const override { return nullptr; }

 private:
  void tick() {
    top_->clk = 1;
    top_->eval();
    if (vcd_ && watching_) vcd_->dump(time_ns_ + 5);
    top_->clk = 0;
    top_->eval();
    time_ns_ += 10;
    if (vcd_ && watching_) vcd_->dump(time_ns_);
    if (top_->vga_strobe && frame_origin_) ++strobes_;
    if (vcd_ && frame_origin_ && strobes_ >= vcd_strobes_) {
      vcd_->close();
      vcd_.reset();
    }
  }
  void ticks(int n) {
    for (int i = 0; i < n; ++i) tick();
  }

  void settle() {
    for (int i = 0; i < kSettleCycles && !top_->receiver_idle; ++i) tick();
    if (!top_->receiver_idle) throw std::logic_error("the RTL receiver did not settle after a transfer");
    read_counters();
    watching_ = false;
  }

  // Runs until the next strobe carries the first sample of a frame: line 480, column 0, where a waiting world is
  // swapped in. Frames are 800 x 525 strobes long, so once the first one is found the rest follow by counting.
  void to_frame_start() {
    if (!frame_origin_) {
      while (!(top_->beam_line == device::kVga640x480.v_visible && top_->beam_column == 0)) tick();
      frame_origin_ = true;
      strobes_ = 0;
      return;
    }
    while (strobes_ % kFrameSamples != 0) tick();
  }

  void read_counters() {
    stats_.worlds_accepted = top_->worlds_accepted;
    stats_.worlds_replaced = top_->worlds_replaced;
    stats_.frames_rejected = top_->frames_rejected;
    stats_.garbage_runs = top_->garbage_runs;
    stats_.bytes_dropped = top_->bytes_dropped;
    stats_.worlds_missing = top_->worlds_missing;
    stats_.worlds_replayed = top_->worlds_replayed;
    stats_.sessions = top_->sessions;
  }

  int half_bit_;
  std::uint64_t vcd_strobes_;  // samples of the first frame drawn the VCD goes on for
  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<Top> top_;
  std::unique_ptr<VerilatedVcdC> vcd_;
  // The VCD gets the clocks of transfers (chip select falling to the receiver settling) and of frames drawn, not those
  // that pass on the way to a frame's start; a gap shows as a jump in time.
  bool watching_ = true;
  std::uint64_t time_ns_ = 0;
  bool frame_origin_ = false;  // strobes_ counts from a frame's first sample
  std::uint64_t strobes_ = 0;
  device::ReceiverStats stats_;
};

}  // namespace tripsitter::rtl

// The frame memory part as a co-simulation's test bench sees it: the Arty A7-100T's DDR3L (dram::Controller, at
// its commands: access time, bus width, turnaround, refresh) behind the user interface of the Xilinx MIG 7 Series
// controller (UG586) in its 4:1 mode, one interface clock (ui_clk) to 4 memory clocks, a burst of 128 bits a
// command. The interface as modelled:
//   - a command is taken when app_en and app_rdy are high in a clock; app_rdy is low while kQueue commands taken are
//     not yet issued to the part (the controller's queue);
//   - a write's data comes with its command (app_wdf_wren, app_wdf_end); app_wdf_rdy is always high (the data
//     FIFO is never full at one burst a command);
//   - read data returns in order, a burst a clock, in the first interface clock after the memory clock its last
//     transfer ends in. The controller's own pipeline (PHY and interface registers, some clocks each way in the
//     real MIG) is not modelled: a fixed delay that the port's schedule does not depend on.
// The memory's content is kept, 128 bits a burst, so that what is read is what was written.
#pragma once

#include <cstdint>
#include <deque>
#include <unordered_map>
#include <vector>

#include "rtl_ports.h"

#include <tripsitter/device/frame_dram.h>

namespace tripsitter::rtl {

class MigModel {
 public:
  static constexpr int kQueue = 8;
  static constexpr int kMemoryClocksPerUi = 4;

  struct Taken {
    device::dram::Request request;
    std::int64_t ui = 0;    // the interface clock it was taken in
    std::int64_t done = 0;  // the memory clock after its last data transfer
  };

  explicit MigModel(const device::dram::Timing& timing = device::dram::arty_timing()) : part_(timing) {}

  // The interface's inputs for interface clock `ui`, before the port's outputs are evaluated.
  template <class Top>
  void drive(Top& top, std::int64_t ui) {
    while (!issued_.empty() && issued_.front() <= ui * kMemoryClocksPerUi) issued_.pop_front();
    top.app_rdy = issued_.size() < kQueue;
    top.app_wdf_rdy = 1;
    const bool data = !reads_.empty() && reads_.front().ready_ui <= ui;
    top.app_rd_data_valid = data;
    put(top.app_rd_data, data ? reads_.front().data : UInt128{0});
  }

  // What the port did in interface clock `ui`, its outputs evaluated: a command taken, a burst of read data taken.
  // Returns the command taken, if one was.
  template <class Top>
  const Taken* take(Top& top, std::int64_t ui) {
    if (top.app_rd_data_valid) reads_.pop_front();
    if (!(top.app_en && top.app_rdy)) return nullptr;
    const bool write = top.app_cmd == 0;
    if (write && !(top.app_wdf_wren && top.app_wdf_end && top.app_wdf_rdy)) {
      ++unpaired_writes_;
      return nullptr;
    }
    const auto op = write ? device::dram::Op::kWrite : device::dram::Op::kRead;
    const std::int64_t bytes = static_cast<std::int64_t>(top.app_addr) * 2;  // app_addr counts 16-bit words
    const std::int64_t done = part_.issue(op, bytes, ui * kMemoryClocksPerUi);
    const device::dram::Timing& t = part_.timing();
    issued_.push_back(done - (write ? t.cwl : t.cl) - t.burst);
    if (write) {
      content_[bytes] = get(top.app_wdf_data);
    } else {
      const auto it = content_.find(bytes);
      reads_.push_back({(done + kMemoryClocksPerUi - 1) / kMemoryClocksPerUi, it == content_.end() ? UInt128{0} : it->second});
    }
    last_ = {{op, bytes}, ui, done};
    return &last_;
  }

  // Puts `data` at byte `address` without a command: the memory's content before the simulation.
  void preload(std::int64_t address, UInt128 data) { content_[address] = data; }
  int unpaired_writes() const { return unpaired_writes_; }
  const device::dram::Counts& counts() const { return part_.counts(); }

 private:
  struct Read {
    std::int64_t ready_ui = 0;
    UInt128 data = 0;
  };
  device::dram::Controller part_;
  std::deque<std::int64_t> issued_;  // memory clocks the commands taken are issued at
  std::deque<Read> reads_;
  std::unordered_map<std::int64_t, UInt128> content_;
  Taken last_;
  int unpaired_writes_ = 0;
};

}  // namespace tripsitter::rtl

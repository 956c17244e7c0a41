#include <tripsitter/device/frame_dram.h>

#include <algorithm>
#include <stdexcept>

#include <tripsitter/core/screen.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/vga_signal.h>

namespace tripsitter::device::dram {

Timing arty_timing() { return {}; }

Controller::Controller(const Timing& timing, const Geometry& geometry) : t_(timing), g_(geometry) {
  if (g_.banks != static_cast<int>(banks_.size())) throw std::invalid_argument("dram::Controller: 8 banks");
  refresh_due_ = t_.refi;
}

std::int64_t Controller::command_at(std::int64_t t) {
  t = std::max(t, next_command_);
  next_command_ = t + 1;
  return t;
}

std::int64_t Controller::precharge(Bank& bank, std::int64_t t) {
  t = command_at(std::max(t, bank.pre_ready));
  bank.open_row = -1;
  bank.act_ready = std::max(bank.act_ready, t + t_.rp);
  ++counts_.precharges;
  return t;
}

std::int64_t Controller::activate(Bank& bank, int row, std::int64_t t) {
  t = std::max({t, bank.act_ready, acts_.back() + t_.rrd, acts_.front() + t_.faw});
  t = command_at(t);
  std::rotate(acts_.begin(), acts_.begin() + 1, acts_.end());
  acts_.back() = t;
  bank.open_row = row;
  bank.act = t;
  bank.pre_ready = t + t_.ras;
  bank.act_ready = t + t_.rc;
  ++counts_.activates;
  return t;
}

void Controller::refresh(std::int64_t t) {
  for (Bank& b : banks_)
    if (b.open_row >= 0) t = std::max(t, precharge(b, t) + t_.rp);
  for (const Bank& b : banks_) t = std::max(t, b.act_ready);
  t = command_at(t);
  for (Bank& b : banks_) b.act_ready = t + t_.rfc;
  ++counts_.refreshes;
}

std::int64_t Controller::issue(Op op, std::int64_t address, std::int64_t not_before) {
  if (address < 0 || address >= g_.bytes() || address % g_.burst_bytes() != 0)
    throw std::invalid_argument("dram::Controller: address " + std::to_string(address) +
                                " is not a burst's of the part");
  std::int64_t t = std::max(not_before, next_command_);
  // Refreshes fall due every tREFI; the controller takes each before the next request after it is due (the part
  // allows eight to be postponed, so a refresh never has to break into a burst).
  while (t >= refresh_due_) {
    refresh(refresh_due_);
    refresh_due_ += t_.refi;
    t = std::max(t, next_command_);
  }
  const std::int64_t word = address / g_.word_bytes;
  const auto bank_index = static_cast<std::size_t>((word / g_.columns) % g_.banks);
  const auto row = static_cast<int>(word / (std::int64_t{g_.columns} * g_.banks));
  Bank& bank = banks_[bank_index];
  if (bank.open_row != row) {
    if (bank.open_row >= 0) t = precharge(bank, t);
    t = activate(bank, row, t) + t_.rcd;
  }
  const bool write = op == Op::kWrite;
  if (any_ && write != last_was_write_) ++counts_.turnarounds;
  if (write) {
    // After a READ the bus must turn around: its data ends at CL + burst, the write's starts at CWL, two clocks
    // of gap (JEDEC's read-to-write command spacing CL + tCCD + 2 - CWL).
    t = std::max({t, last_write_ + t_.ccd, last_read_ + t_.cl + t_.ccd + 2 - t_.cwl});
    t = command_at(t);
    last_write_ = t;
    bank.pre_ready = std::max(bank.pre_ready, t + t_.cwl + t_.burst + t_.wr);
    ++counts_.writes;
  } else {
    t = std::max({t, last_read_ + t_.ccd, last_write_ + t_.cwl + t_.burst + t_.wtr});
    t = command_at(t);
    last_read_ = t;
    bank.pre_ready = std::max(bank.pre_ready, t + t_.rtp);
    ++counts_.reads;
  }
  last_was_write_ = write;
  any_ = true;
  return t + (write ? t_.cwl : t_.cl) + t_.burst;
}

namespace {

void check_traffic(int entry_bits, int run) {
  const Geometry g;
  if (entry_bits <= 0 || (8 * g.burst_bytes()) % entry_bits != 0)
    throw std::invalid_argument("dram: an entry must divide a burst's 128 bits");
  if (run < 1) throw std::invalid_argument("dram: runs of at least one burst");
}

std::int64_t line_bytes(int entry_bits) { return std::int64_t{core::kScreenWidth} * entry_bits / 8; }

constexpr int kLines = kVga640x480.v_total();  // a frame's line periods, 525

}  // namespace

std::vector<Request> line_requests(int line, int entry_bits, int run) {
  check_traffic(entry_bits, run);
  const Geometry g;
  const std::int64_t bytes = line_bytes(entry_bits), bursts = bytes / g.burst_bytes();
  const int read_line = (line + 2) % kLines, write_line = line - 1;
  const bool reads = read_line < core::kScreenHeight, writes = write_line >= 0 && write_line < core::kScreenHeight;
  std::vector<Request> out;
  std::int64_t r = 0, w = 0;
  while ((reads && r < bursts) || (writes && w < bursts)) {
    for (int k = 0; k < run && reads && r < bursts; ++k, ++r)
      out.push_back({Op::kRead, read_line * bytes + r * g.burst_bytes()});
    for (int k = 0; k < run && writes && w < bursts; ++k, ++w)
      out.push_back({Op::kWrite, write_line * bytes + w * g.burst_bytes()});
  }
  return out;
}

LineTraffic frame_traffic(int entry_bits, int run, int frames, const Timing& timing) {
  check_traffic(entry_bits, run);
  LineTraffic out;
  out.entry_bits = entry_bits;
  out.bytes_per_line = 2 * line_bytes(entry_bits);
  // A line period (800 pixel clocks at 25 MHz) in memory clocks: 32 us / 3.077 ns, whole clocks.
  const std::int64_t line_ps = std::int64_t{kLineCycles} * (1'000'000 / (kDeviceClockHz / 1'000'000));
  out.line_clocks = line_ps / timing.clock_ps;
  out.peak_bytes_per_line = out.line_clocks * timing.bytes_per_clock;
  Controller memory(timing, Geometry{});
  std::int64_t end = 0;
  for (int f = 0; f < frames; ++f) {
    for (int line = 0; line < kLines; ++line) {
      const std::int64_t start = (std::int64_t{f} * kLines + line) * out.line_clocks;
      const std::vector<Request> requests = line_requests(line, entry_bits, run);
      for (const Request& q : requests) end = std::max(end, memory.issue(q.op, q.address, start));
      if (!requests.empty() && end - start > out.worst_clocks) {
        out.worst_clocks = end - start;
        out.worst_line = line;
      }
    }
  }
  out.counts = memory.counts();
  return out;
}

}  // namespace tripsitter::device::dram

// The frame memory part (docs/device.md, "The frame memory part"): the DDR3L SDRAM of the Digilent Arty A7-100T, the
// development board of rtl/boards/arty_a7, a Micron MT41K128M16JT-125 (2 Gbit; 16 data pins; 8 banks of 16,384
// rows of 1,024 16-bit columns, a 2 KB page; burst length 8), behind the Xilinx MIG 7 Series controller at a
// 3,077 ps memory clock (325 MHz, 650 MT/s: the XC7A100T-1's ceiling for DDR3L through its 4:1 controller is
// 667 MT/s, DS181). Frame memory is far beyond the chip's block RAM (19.7 Mbit against 4.9), so it lives here.
//
// The model is at the memory's commands, one a clock: ACTIVATE, READ, WRITE, PRECHARGE and REFRESH, each issued at
// the first clock every timing rule of the part allows, in the order the requests come (an in-order controller
// with the page left open, as MIG's default; it reorders nothing, so the figures are what a line's traffic costs
// without a scheduler's help). A request is one burst: 16 bytes, two 64-bit frame-memory entries. Addresses map
// as MIG's ROW_BANK_COLUMN: the 16-bit word's low 10 bits are the column, the next 3 the bank, the rest the row.
// The same class is the co-simulation's memory behind the RTL's controller port (issue the RTL's requests, read the
// clock their data ends).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace tripsitter::device::dram {

// The part's timing in memory clocks (the datasheet's nanoseconds rounded up to whole clocks of clock_ps), at the
// DDR3-667 speed bin the controller runs it at.
struct Timing {
  int clock_ps = 3077;
  int cl = 5;      // READ to its first data
  int cwl = 5;     // WRITE to its first data
  int burst = 4;   // data clocks of a burst of 8 (two transfers a clock)
  int rcd = 5;     // ACTIVATE to READ or WRITE: 13.75 ns
  int rp = 5;      // PRECHARGE to ACTIVATE: 13.75 ns
  int ras = 12;    // ACTIVATE to PRECHARGE: 35 ns
  int rc = 17;     // ACTIVATE to ACTIVATE, one bank: tRAS + tRP
  int rrd = 4;     // ACTIVATE to ACTIVATE, two banks: max(4 clocks, 7.5 ns)
  int faw = 17;    // four ACTIVATEs in a window of 50 ns (2 KB page)
  int ccd = 4;     // READ to READ, WRITE to WRITE
  int wr = 5;      // write recovery: last data to PRECHARGE, 15 ns
  int wtr = 4;     // last write data to READ: max(4 clocks, 7.5 ns)
  int rtp = 4;     // READ to PRECHARGE: max(4 clocks, 7.5 ns)
  int rfc = 52;    // REFRESH to the next command: 160 ns (2 Gbit)
  int refi = 2535; // REFRESH every 7.8 us
  int bytes_per_clock = 4;  // 16 data pins, two transfers a clock
};

struct Geometry {
  int banks = 8;
  int rows = 16384;
  int columns = 1024;  // 16-bit words a row
  int word_bytes = 2;
  constexpr std::int64_t burst_bytes() const { return std::int64_t{8} * word_bytes; }
  std::int64_t bytes() const { return std::int64_t{banks} * rows * columns * word_bytes; }
};

// The part as the board carries it, and its name for the ledger and the summaries.
Timing arty_timing();
inline constexpr const char* kPartName = "MT41K128M16JT-125 DDR3L (Arty A7-100T), MIG at 325 MHz";
// FPGA pins the interface takes: DQ 16, DQS 2 pairs, DM 2, address 14, bank 3, RAS/CAS/WE 3, CK a pair, CKE, CS,
// ODT, RESET.
inline constexpr int kPins = 16 + 4 + 2 + 14 + 3 + 3 + 2 + 4;

enum class Op { kRead, kWrite };

// What the controller did so far.
struct Counts {
  std::int64_t reads = 0, writes = 0, activates = 0, precharges = 0, refreshes = 0, turnarounds = 0;
};

class Controller {
 public:
  explicit Controller(const Timing& timing = arty_timing(), const Geometry& geometry = {});

  // Issues the burst at byte `address` (a multiple of 16, below geometry.bytes()), no earlier than clock
  // `not_before`, after every request issued before it; refreshes first when one is due. Returns the clock after
  // its last data transfer. Throws std::invalid_argument on an address outside the part or not a burst's.
  std::int64_t issue(Op op, std::int64_t address, std::int64_t not_before = 0);

  const Counts& counts() const { return counts_; }
  const Timing& timing() const { return t_; }
  const Geometry& geometry() const { return g_; }

 private:
  struct Bank {
    int open_row = -1;
    std::int64_t act = -(1 << 20);       // last ACTIVATE
    std::int64_t pre_ready = 0;          // PRECHARGE allowed from
    std::int64_t act_ready = 0;          // ACTIVATE allowed from
  };
  std::int64_t command_at(std::int64_t t);  // the first free command slot at or after t, taken
  std::int64_t precharge(Bank& bank, std::int64_t t);
  std::int64_t activate(Bank& bank, int row, std::int64_t t);
  void refresh(std::int64_t t);

  Timing t_;
  Geometry g_;
  std::array<Bank, 8> banks_{};
  std::array<std::int64_t, 4> acts_{-(1 << 20), -(1 << 20), -(1 << 20), -(1 << 20)};  // the last four ACTIVATEs,
                                                                                  // oldest first (tFAW)
  std::int64_t next_command_ = 0;
  std::int64_t last_read_ = -(1 << 20), last_write_ = -(1 << 20);
  std::int64_t refresh_due_ = 0;
  bool last_was_write_ = false;
  bool any_ = false;
  Counts counts_;
};

// A line period's requests, in the order the device makes them: in display line i (0..524) it reads the entries of
// line i + 2 (modulo 525: the line it traces next, whose counts decide what it traces) and writes back those of line
// i - 1 (traced), in alternating runs of `run` bursts, reads first (a line of the 480 only; none in the others).
// The RTL's port (rtl/path/ts_path_frame_port.sv) makes the same.
struct Request {
  Op op = Op::kRead;
  std::int64_t address = 0;  // bytes
  bool operator==(const Request&) const = default;
};
std::vector<Request> line_requests(int line, int entry_bits = 64, int run = 32);

// A frame's traffic through the part, line period by line period: each period's requests (line_requests), none
// before the period's start (and, the controller being in order, none before the previous period's).
struct LineTraffic {
  int entry_bits = 64;
  std::int64_t bytes_per_line = 0;      // one line's reads and writes at most
  std::int64_t peak_bytes_per_line = 0; // what the pins could carry in a line period
  std::int64_t line_clocks = 0;         // memory clocks in a line period (32 us)
  std::int64_t worst_clocks = 0;        // the longest a line period's traffic took, from its start
  int worst_line = 0;
  Counts counts;                        // of the whole frame
  double demand() const { return static_cast<double>(bytes_per_line) / static_cast<double>(peak_bytes_per_line); }
  double busy() const { return static_cast<double>(worst_clocks) / static_cast<double>(line_clocks); }
};
// `frames` frames one after another (refresh drifts across them); the figures are the worst line of any.
LineTraffic frame_traffic(int entry_bits, int run = 32, int frames = 2, const Timing& timing = arty_timing());

}  // namespace tripsitter::device::dram

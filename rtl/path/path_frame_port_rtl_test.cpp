// Frame memory's port (ts_path_frame_port.sv) against its model, dram::line_requests, with the part's timing in the
// test bench (mig_model.h: the DDR3L's commands behind the MIG's user interface): two frames and more of display
// lines, each line's requests exactly the model's in order, every burst loaded the entries the device stored in
// that row a frame before (or the memory's first content), every line's traffic done inside its period, and the
// worst line's share of the period next to frame_traffic's. Then the same with line periods too short for the
// traffic: the late lines counted, a line late behind another replaced by the next, each line the port makes
// still whole and right.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include "mig_model.h"

#include <Vts_path_frame_port.h>

#include <tripsitter/core/screen.h>
#include <tripsitter/device/frame_memory.h>
#include <tripsitter/device/vga_signal.h>

namespace tripsitter::rtl {
namespace {

using device::dram::Op;
using device::dram::Request;

constexpr std::int64_t kRowBytes = std::int64_t{core::kScreenWidth} * device::kAccumEntryBits / 8;  // 5,120
constexpr int kBursts = static_cast<int>(kRowBytes / device::dram::Geometry{}.burst_bytes());   // a row's, 320
constexpr int kLines = device::kVga640x480.v_total();                                           // 525

struct Result {
  int skipped_lines = 0;  // lines whose requests the port never made (a late line replaced by the next)
  int bad_order = 0, bad_stores = 0, bad_loads = 0, loads = 0, late_lines = 0, unpaired = 0;
  double worst_busy = 0;  // the longest a line's traffic took from its period's start, a share of the period
};

// Runs `frames` frames (and two lines more, so the last frame's last writes are made) with a line period of
// `line_ui` interface clocks on average (the memory clocks of a 32 us period, 10,399, over 4).
Result run(double line_ui, int frames, std::mt19937_64& rng) {
  VerilatedContext context;
  context.randReset(2);
  auto top = std::make_unique<Vts_path_frame_port>(&context);
  MigModel mig;
  const auto random128 = [&] { return static_cast<UInt128>(rng()) << 64 | rng(); };
  // What each row holds (the memory's first content, then what the port stored into it), and the store buffer:
  // each row's entries as the device last traced them.
  std::vector<std::vector<UInt128>> held(core::kScreenHeight, std::vector<UInt128>(kBursts));
  std::vector<std::vector<UInt128>> traced(core::kScreenHeight, std::vector<UInt128>(kBursts));
  for (int row = 0; row < core::kScreenHeight; ++row) {
    for (int b = 0; b < kBursts; ++b) {
      held[static_cast<std::size_t>(row)][static_cast<std::size_t>(b)] = random128();
      mig.preload(row * kRowBytes + b * 16, held[static_cast<std::size_t>(row)][static_cast<std::size_t>(b)]);
    }
  }
  top->rst = 1;
  top->line_start = 0;
  for (int i = 0; i < 3; ++i) rising_edge(*top);
  top->rst = 0;

  Result out;
  std::vector<Request> got;  // every request, in the order the controller took them
  std::int64_t ui = 0;
  // One interface clock: the controller's inputs, the loads and the request taken checked, the store buffer's answer.
  const auto clock = [&](bool line_start, int line) {
    top->line_start = line_start;
    top->line = static_cast<SData>(line);
    mig.drive(*top, ui);
    top->eval();
    const std::size_t store_row = top->store_row, store_burst = top->store_burst;
    if (top->load_we) {
      ++out.loads;
      if (get(top->load_data) != held.at(top->load_row).at(top->load_burst) && ++out.bad_loads <= 3)
        ADD_FAILURE() << "line " << line << ": row " << int{top->load_row} << " burst " << int{top->load_burst}
                      << " loaded other data than the row holds";
    }
    const UInt128 written = get(top->app_wdf_data);
    const MigModel::Taken* t = mig.take(*top, ui);
    if (t) {
      got.push_back(t->request);
      if (t->request.op == Op::kWrite) {
        const auto row = static_cast<std::size_t>(t->request.address / kRowBytes);
        const auto burst = static_cast<std::size_t>(t->request.address % kRowBytes / 16);
        if (written != traced.at(row).at(burst) && ++out.bad_stores <= 3)
          ADD_FAILURE() << "line " << line << ": row " << row << " burst " << burst << " stored other data than traced";
        held[row][burst] = written;
      }
    }
    rising_edge(*top);
    ++ui;
    // The store buffer answers a clock after its address.
    put(top->store_data, store_row < traced.size() && store_burst < kBursts ? traced[store_row][store_burst] : UInt128{0});
    return t;
  };
  const int total = frames * kLines + 2;
  for (int n = 0; n < total; ++n) {
    const int line = n % kLines;
    // The device traced row line - 1 in the line before: the entries the port is to store in this line.
    if (line >= 1 && line <= core::kScreenHeight)
      for (auto& t : traced[static_cast<std::size_t>(line - 1)]) t = random128();
    const std::int64_t begin_ui = ui;
    std::int64_t end_mem = -1;
    const auto next_start = static_cast<std::int64_t>(static_cast<double>(n + 1) * line_ui + 0.999);
    for (bool first = true; ui < next_start; first = false)
      if (const MigModel::Taken* t = clock(first, line)) end_mem = std::max(end_mem, t->done);
    if (end_mem >= 0) {
      out.worst_busy = std::max(out.worst_busy, static_cast<double>(end_mem - begin_ui * MigModel::kMemoryClocksPerUi) /
                                                    (line_ui * MigModel::kMemoryClocksPerUi));
    }
  }
  // A late port finishes the line it is on.
  for (int drain = 0; top->busy && drain < 10000; ++drain) clock(false, 0);
  // The requests are the lines' in order, each line's whole or (late, replaced) not at all.
  std::size_t at = 0;
  for (int n = 0; n < total; ++n) {
    const std::vector<Request> want = device::dram::line_requests(n % kLines);
    if (want.empty()) continue;
    if (got.size() - at >= want.size() && std::equal(want.begin(), want.end(), got.begin() + static_cast<std::ptrdiff_t>(at)))
      at += want.size();
    else
      ++out.skipped_lines;
  }
  if (at != got.size()) {
    ADD_FAILURE() << got.size() - at << " requests after the last line's, or out of the lines' order (from request "
                  << at << ")";
    ++out.bad_order;
  }
  out.late_lines = static_cast<int>(top->late_lines);
  out.unpaired = mig.unpaired_writes();
  return out;
}

TEST(PathFramePortRtl, EachLinesReadModifyWriteIsTheModelsAndFitsItsPeriod) {
  std::mt19937_64 rng(121);
  const device::dram::LineTraffic model = device::dram::frame_traffic(64);
  const Result r = run(static_cast<double>(model.line_clocks) / MigModel::kMemoryClocksPerUi, 2, rng);
  EXPECT_EQ(r.bad_order, 0);
  EXPECT_EQ(r.skipped_lines, 0);
  EXPECT_EQ(r.bad_stores, 0);
  EXPECT_EQ(r.bad_loads, 0);
  EXPECT_EQ(r.loads, (2 * core::kScreenHeight + 2) * kBursts);  // and rows 2 and 3 again in the two lines more
  EXPECT_EQ(r.late_lines, 0);
  EXPECT_EQ(r.unpaired, 0);
  // The port cannot start before the line's first interface clock, nor make more than a request a clock; the queue
  // of 8 keeps it close behind the part.
  EXPECT_GE(r.worst_busy, model.busy() - 0.01);
  EXPECT_LT(r.worst_busy, 0.8);
  std::printf("worst line: %.1f%% of its period through the port, %.1f%% in frame_traffic\n", 100 * r.worst_busy,
              100 * model.busy());
}

// Line periods too short for a line's 640 bursts (600 interface clocks): lines start late, counted, some are
// replaced by the next before they begin, and each line the port makes is still the model's, whole, with the right
// data.
TEST(PathFramePortRtl, LinesTooShortForTheTrafficAreCountedLateAndStillRight) {
  std::mt19937_64 rng(122);
  const Result r = run(600.5, 1, rng);
  EXPECT_GT(r.late_lines, 100);
  EXPECT_GT(r.skipped_lines, 0);
  EXPECT_LE(r.skipped_lines, r.late_lines);
  EXPECT_EQ(r.bad_order, 0);
  EXPECT_EQ(r.bad_stores, 0);
  EXPECT_EQ(r.bad_loads, 0);
  EXPECT_EQ(r.unpaired, 0);
}

}  // namespace
}  // namespace tripsitter::rtl

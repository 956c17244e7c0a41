// ts_controller (through ts_scanout) line by line against device::schedule_line: workers emulated in C++ take
// each pixel's occupancy from a chosen bounce count (DevicePreset::pixel_occupancy), and every line the RTL shows
// must be the line schedule_line writes, colours and black (late) pixels alike, with the same late count. Lines
// vary in sphere count and in how their pixels reflect, so that some are on time, some late, some very late.
#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <set>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/device/controller.h>
#include <tripsitter/device/preset.h>

#include "Vrtl_scanout_n10_board.h"
#include "Vrtl_scanout_n10_wide.h"
#include "Vrtl_scanout_n10_wide_noflush.h"
#include "Vrtl_scanout_n1_board.h"
#include "Vrtl_scanout_n1_wide.h"
#include "Vrtl_scanout_n7_board.h"
#include "Vrtl_scanout_n7_wide.h"
#include "scanout_bench.h"

namespace tripsitter::rtl {
namespace {

using device::DevicePreset;
using testing::BenchConfig;
using testing::Job;
using testing::PlacedSample;
using testing::ScanoutBench;

// One row's work: its sphere count and each pixel's colour and reflections.
struct RowPlan {
  std::int64_t spheres = 1;
  std::array<core::PixelTrace, 640> pixels;
};

// Rows of many kinds: no reflections, a few at random, a run of reflecting columns (a metal sphere in view), every
// pixel reflecting; sphere counts from one to beyond what fits a line.
RowPlan random_row(std::mt19937& rng, const std::vector<std::int64_t>& sphere_counts, bool reflections) {
  RowPlan plan;
  plan.spheres = sphere_counts[std::uniform_int_distribution<std::size_t>(0, sphere_counts.size() - 1)(rng)];
  std::uniform_int_distribution<int> colour(1, 4095), bounce(1, 3), column(0, 639);
  const int kind = reflections ? std::uniform_int_distribution<int>(0, 3)(rng) : 0;
  const double share = std::uniform_int_distribution<int>(0, 1)(rng) ? 0.05 : 0.3;
  int from = column(rng), to = column(rng);
  if (from > to) std::swap(from, to);
  const int all = bounce(rng);
  std::bernoulli_distribution reflects(share);
  for (int col = 0; col < 640; ++col) {
    int bounces = 0;
    if (kind == 1 && reflects(rng)) bounces = bounce(rng);
    if (kind == 2 && col >= from && col < to) bounces = all;
    if (kind == 3) bounces = all;
    plan.pixels[static_cast<std::size_t>(col)] = {core::Rgb444(static_cast<std::uint16_t>(colour(rng))), bounces};
  }
  return plan;
}

struct Tally {
  int rows_compared = 0;
  int rows_late = 0;
  int rows_on_time = 0;
  int rows_skipped = 0;  // a worker was still busy when the row's window opened (no flush)
  std::int64_t cycles_ahead = 0;  // speculative workers: how far their starts came before the model's
};

// One frame of rows (0..479, from reset) with plans from `seed`; each row the RTL shows is compared with
// schedule_line on the same plan, and each window's late count with the model's.
template <class V>
Tally expect_lines_equal_schedule_line(DevicePreset preset, const BenchConfig& config, std::uint32_t seed,
                                       const std::vector<std::int64_t>& sphere_counts, bool reflections = true) {
  preset.workers = config.workers;
  preset.lead_cycles = config.lead_cycles;
  EXPECT_EQ(preset.drain_cycles(), config.drain);
  std::mt19937 rng(seed);
  std::vector<RowPlan> plans;
  for (int row = 0; row < 480; ++row) plans.push_back(random_row(rng, sphere_counts, reflections));

  ScanoutBench<V> bench(
      config,
      [&](int row, int col) {
        const RowPlan& plan = plans[static_cast<std::size_t>(row)];
        const core::PixelTrace& t = plan.pixels[static_cast<std::size_t>(col)];
        return Job{t.colour, preset.pixel_occupancy(plan.spheres, t.bounces)};
      },
      [&](int row) {
        return static_cast<std::uint16_t>(std::min<std::int64_t>(
            65535, preset.pixel_occupancy(plans[static_cast<std::size_t>(row)].spheres, 0)));
      });
  std::vector<std::array<core::Rgb444, 640>> shown(480);
  bench.on_sample = [&](const PlacedSample& s) {
    if (s.line < 480 && s.column < 640)
      shown[static_cast<std::size_t>(s.line)][static_cast<std::size_t>(s.column)] = s.sample.colour;
  };
  std::vector<int> late;
  bench.on_late = [&](int n) { late.push_back(n); };
  bench.run_samples(800 * 525);  // from line 480 to the end of line 479: rows 0..479 shown

  Tally tally;
  EXPECT_EQ(late.size(), 480u);
  for (int row = 0; row < 480 && row < static_cast<int>(late.size()); ++row) {
    const RowPlan& plan = plans[static_cast<std::size_t>(row)];
    std::array<core::Rgb444, 640> want;
    const device::LineResult r = device::schedule_line(
        preset, plan.spheres, std::span<core::Rgb444>(want),
        [&](int col) { return plan.pixels[static_cast<std::size_t>(col)]; });
    if (bench.busy_at_open().count(row) != 0) {
      ++tally.rows_skipped;
      continue;
    }
    ++tally.rows_compared;
    (r.late_pixels > 0 ? tally.rows_late : tally.rows_on_time) += 1;
    EXPECT_EQ(late[static_cast<std::size_t>(row)], r.late_pixels) << "row " << row << ", " << plan.spheres << " spheres";
    const auto& got = shown[static_cast<std::size_t>(row)];
    for (int col = 0; col < 640; ++col) {
      if (got[static_cast<std::size_t>(col)] != want[static_cast<std::size_t>(col)]) {
        ADD_FAILURE() << "row " << row << " (" << plan.spheres << " spheres), column " << col << " (worker "
                      << col % config.workers << "): RTL 0x" << std::hex << got[static_cast<std::size_t>(col)].packed
                      << ", schedule_line 0x" << want[static_cast<std::size_t>(col)].packed << std::dec;
        return tally;
      }
    }
  }
  EXPECT_FALSE(bench.protocol_error());
  EXPECT_EQ(bench.bad_starts(), 0);
  tally.cycles_ahead = bench.cycles_ahead();
  return tally;
}

// board-2023: 51 cycles a pixel with one sphere (45 more per sphere, 55 more per reflection at one sphere), no
// drain, a 3000-cycle lead. Here its workers do not flush (FLUSH = 0): a reflecting pixel can outlive its window,
// and the row after it is then not the model's (skipped, counted); the rows after that must be the model's again.
const std::vector<std::int64_t> kBoardSpheres = {1, 1, 1, 2, 3, 5, 12, 30};
// wide: a pixel issues a pass per sphere (41 cycles of stall per reflection), 35 cycles of drain, a 3200-cycle lead.
const std::vector<std::int64_t> kWideSpheres = {1, 2, 5, 12, 30, 45, 49, 50, 51, 64, 200};

BenchConfig board(int workers) {
  return {.workers = workers, .lead_cycles = 3000, .drain = 0, .flush = false, .speculative = false};
}
BenchConfig wide(int workers, bool flush = true) {
  return {.workers = workers, .lead_cycles = 3200, .drain = 35, .flush = flush, .speculative = false};
}
BenchConfig speculative(int workers) {
  return {.workers = workers, .lead_cycles = 3200, .drain = 35, .flush = true, .speculative = true};
}

// Rows both on time and late (wide), or all late (the board: 51 cycles a pixel never fit 64 pixels in 3000), and
// every row compared unless a worker without flush was still busy when the row's window opened.
void expect_rows(const Tally& t, bool board, bool may_skip) {
  EXPECT_GT(t.rows_late, 20);
  if (board) {
    EXPECT_EQ(t.rows_on_time, 0);
  } else {
    EXPECT_GT(t.rows_on_time, 20);
  }
  if (may_skip) {
    EXPECT_GT(t.rows_compared, 250);
  } else {
    EXPECT_EQ(t.rows_skipped, 0);
    EXPECT_EQ(t.rows_compared, 480);
  }
}

TEST(RtlController, TenWorkersOfTheBoardEqualScheduleLine) {
  expect_rows(expect_lines_equal_schedule_line<Vrtl_scanout_n10_board>(device::board_2023_preset(), board(10), 1,
                                                                        kBoardSpheres),
              true, true);
}
TEST(RtlController, SevenWorkersOfTheBoardEqualScheduleLine) {
  expect_rows(expect_lines_equal_schedule_line<Vrtl_scanout_n7_board>(device::board_2023_preset(), board(7), 2,
                                                                       {1, 1, 2, 3}),
              true, true);
}
TEST(RtlController, OneWorkerOfTheBoardEqualsScheduleLine) {
  expect_rows(expect_lines_equal_schedule_line<Vrtl_scanout_n1_board>(device::board_2023_preset(), board(1), 3,
                                                                       kBoardSpheres),
              true, true);
}
// The board's workers never reflect (max_bounces 0): then no pixel outlives its window, and every row is compared.
TEST(RtlController, TenWorkersOfTheBoardWithoutReflectionsAreNeverBusyAtTheWindow) {
  expect_rows(expect_lines_equal_schedule_line<Vrtl_scanout_n10_board>(device::board_2023_preset(), board(10), 8,
                                                                        kBoardSpheres, false),
              true, false);
}
TEST(RtlController, TenWideWorkersEqualScheduleLine) {
  expect_rows(expect_lines_equal_schedule_line<Vrtl_scanout_n10_wide>(device::wide_preset(), wide(10), 4, kWideSpheres),
              false, false);
}
TEST(RtlController, SevenWideWorkersEqualScheduleLine) {
  expect_rows(expect_lines_equal_schedule_line<Vrtl_scanout_n7_wide>(device::wide_preset(), wide(7), 5, kWideSpheres),
              false, false);
}
TEST(RtlController, OneWideWorkerEqualsScheduleLine) {
  expect_rows(expect_lines_equal_schedule_line<Vrtl_scanout_n1_wide>(device::wide_preset(), wide(1), 6, {1, 1, 1, 2, 3}),
              false, false);
}
// Workers that take the next pixel as if the last did not reflect (the pipelined ts_worker) and deliver colours on
// the model's schedule: many pixels in flight, started before the model starts them; the lines are the same.
TEST(RtlController, TenSpeculativeWideWorkersEqualScheduleLine) {
  const Tally t = expect_lines_equal_schedule_line<Vrtl_scanout_n10_wide>(device::wide_preset(), speculative(10), 9,
                                                                          kWideSpheres);
  expect_rows(t, false, false);
  EXPECT_GT(t.cycles_ahead, 100000);
}
TEST(RtlController, SevenSpeculativeWideWorkersEqualScheduleLine) {
  const Tally t = expect_lines_equal_schedule_line<Vrtl_scanout_n7_wide>(device::wide_preset(), speculative(7), 10,
                                                                         kWideSpheres);
  expect_rows(t, false, false);
  EXPECT_GT(t.cycles_ahead, 100000);
}
TEST(RtlController, OneSpeculativeWideWorkerEqualsScheduleLine) {
  const Tally t = expect_lines_equal_schedule_line<Vrtl_scanout_n1_wide>(device::wide_preset(), speculative(1), 11,
                                                                         {1, 1, 1, 2, 3});
  expect_rows(t, false, false);
  EXPECT_GT(t.cycles_ahead, 100000);
}

// Without flush a worker can still be busy when the next window opens: those rows are skipped, and the stale
// colours that arrive in the next window must be dropped, not written.
TEST(RtlController, TenWideWorkersWithoutFlushDropStaleColours) {
  const Tally t = expect_lines_equal_schedule_line<Vrtl_scanout_n10_wide_noflush>(device::wide_preset(),
                                                                                  wide(10, false), 7, kWideSpheres);
  expect_rows(t, false, true);
  EXPECT_GT(t.rows_skipped, 0);
}

}  // namespace
}  // namespace tripsitter::rtl

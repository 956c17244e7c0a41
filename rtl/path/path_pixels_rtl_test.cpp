// A path unit's pixels of a line (ts_path_pixels.sv) against the model, bit for bit and cycle for cycle: each
// column's entry loaded from frame memory (this world's epoch or another's, empty, partly and nearly full, so that
// some columns have converged and take no samples), its samples' ends at the unit's pixel port (lights out of the
// bounce stage, one a cycle at most, and cut paths, queued behind the lights: artix::serve_pixel_port), and each
// column's entry at the window's end: final exactly when the schedule puts it within the window (its last sample
// through the port by cycle 3198), and then path_pixel()'s entry. Lines back to back, as the banks change roles at
// each window's first cycle: the next line's entries loaded, this line's samples summed, the last line's read.
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include "path_line_model.h"
#include "path_rtl_util.h"

#include <Vts_path_pixels.h>

#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/artix_units.h>
#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/preset.h>

namespace tripsitter::rtl {
namespace {

using Light = std::array<std::int64_t, 3>;
constexpr int kUnits = 9;   // the block's N
constexpr int kUnit = 4;    // its columns: 4, 13, ..., 634
constexpr std::int64_t kLine = 3200;
constexpr int kLatency = 2;  // ts_artix_pkg::PixelLatency

struct End {
  std::int64_t cycle;  // at the pixel port: a light's cycle, a cut's
  int col;
  int sample;
  bool lit;
  Light light;
};

struct Line {
  device::PathFrame frame;
  std::vector<int> cols;                        // the unit's columns
  std::vector<device::AccumEntry> stored;       // a column's entry in frame memory
  std::vector<bool> takes;
  std::vector<End> ends;
  std::vector<std::vector<std::int64_t>> port;  // a column's samples' cycles through the port, in order
  std::vector<bool> final;                      // the model's: the entry final by the window's end
  std::vector<device::AccumEntry> entry;        // path_pixel's
};

// A line of the unit's columns: their samples end at random cycles (`span` of them: past 3,200 some are late), a
// light at most one a cycle and a cut at most one a cycle; a third of the columns' samples back to back. The first
// column that takes samples ends its from cycle `edge` on, if it is given (near the window's last cycles).
Line random_line(std::mt19937_64& rng, int spp, std::int64_t span, std::int64_t edge = -1) {
  Line l;
  l.frame.epoch = static_cast<std::uint8_t>(rng() % device::kEpochs);
  l.frame.spp = spp;
  l.frame.frame = static_cast<std::uint32_t>(rng() % 50);
  std::set<std::int64_t> lit_at, cut_at;
  const auto free_cycle = [&](std::set<std::int64_t>& used, std::int64_t want) {
    while (used.count(want) != 0) ++want;
    used.insert(want);
    return want;
  };
  for (int col = kUnit; col < device::kLineWidth; col += kUnits) {
    l.cols.push_back(col);
    const device::AccumEntry e = path::random_entry(rng, l.frame.epoch, 40);
    l.stored.push_back(e);
    const bool open = e.epoch == l.frame.epoch;
    const bool takes = (open ? e.count : 0) + spp <= device::kMaxSamples;
    l.takes.push_back(takes);
    if (!takes) continue;
    const bool at_edge = edge >= 0;
    const bool together = at_edge || rng() % 3 == 0;
    std::int64_t at = at_edge ? edge : static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(span));
    edge = -1;
    for (int s = 0; s < spp; ++s) {
      End end{0, col, s, rng() % 10 < 7, {}};
      if (end.lit)
        for (auto& c : end.light)
          c = rng() % 6 == 0 ? 65536 - static_cast<std::int64_t>(rng() % 64) : static_cast<std::int64_t>(rng() % 65537);
      if (!together) at = static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(span));
      end.cycle = free_cycle(end.lit ? lit_at : cut_at, at);
      at = end.cycle + 1;
      l.ends.push_back(end);
    }
  }
  std::sort(l.ends.begin(), l.ends.end(), [](const End& a, const End& b) { return a.cycle < b.cycle; });

  // The model: the port's cycles, then each column final or not, and its entry.
  std::vector<std::vector<std::int64_t>> ended(device::kLineWidth);
  std::vector<std::vector<bool>> lit(device::kLineWidth);
  for (const End& e : l.ends) {
    const auto c = static_cast<std::size_t>(e.col);
    ended[c].resize(static_cast<std::size_t>(spp), -1);
    lit[c].resize(static_cast<std::size_t>(spp), false);
    ended[c][static_cast<std::size_t>(e.sample)] = e.cycle;
    lit[c][static_cast<std::size_t>(e.sample)] = e.lit;
  }
  const std::vector<std::vector<std::int64_t>> port = path::port_cycles(ended, lit, kUnits);
  for (std::size_t k = 0; k < l.cols.size(); ++k) {
    std::vector<std::int64_t> at = port[static_cast<std::size_t>(l.cols[k])];
    std::sort(at.begin(), at.end());
    l.final.push_back(!l.takes[k] || at.back() + kLatency <= kLine);
    l.port.push_back(std::move(at));
    std::vector<Light> lights(static_cast<std::size_t>(spp));
    for (const End& e : l.ends)
      if (e.col == l.cols[k]) lights[static_cast<std::size_t>(e.sample)] = e.light;
    std::size_t next = 0;
    l.entry.push_back(device::path_pixel(device::artix::path_arith(), l.cols[k], 0, l.stored[k], l.frame,
                                         [&](device::PathRng&) {
                                           device::PathSample s;
                                           s.light = lights[next++];
                                           return s;
                                         })
                          .entry);
  }
  return l;
}

struct Stats {
  int columns = 0, final = 0, late = 0, converged = 0, cuts_waited = 0, back_to_back = 0;
};

// Lines through the block back to back: line l's entries loaded in window l - 1 (the first before its window),
// its samples in window l, its entries read in window l + 1.
void run(const std::vector<Line>& lines, Stats& stats, std::mt19937_64& rng) {
  VerilatedContext context;
  context.randReset(2);
  auto t = std::make_unique<Vts_path_pixels>(&context);
  t->rst = 1;
  t->start = 0;
  t->flush = 0;
  t->ld_we = 0;
  t->lit_valid = 0;
  t->cut_valid = 0;
  for (int i = 0; i < 3; ++i) rising_edge(*t);
  t->rst = 0;
  int bad = 0;
  const auto fail = [&](const std::string& what) {
    if (++bad <= 5) ADD_FAILURE() << what;
  };
  const auto load = [&](const Line& l, std::size_t k) {
    t->ld_we = 1;
    t->ld_col = static_cast<SData>(l.cols[k]);
    t->ld_entry = path::pack(l.stored[k]);
    t->epoch = l.frame.epoch;
    t->spp = static_cast<CData>(l.frame.spp);
  };
  const std::size_t per_line = lines[0].cols.size();
  std::vector<bool> takes_got(per_line);
  for (std::size_t k = 0; k < per_line; ++k) {
    load(lines[0], k);
    t->clk = 0;
    t->eval();
    takes_got[k] = t->ld_takes != 0;
    rising_edge(*t);
  }
  t->ld_we = 0;
  for (std::size_t k = 0; k < per_line; ++k)
    if (takes_got[k] != lines[0].takes[k]) fail("line 0 column " + std::to_string(lines[0].cols[k]) + ": takes");

  for (std::size_t w = 0; w <= lines.size(); ++w) {
    const Line* now = w < lines.size() ? &lines[w] : nullptr;
    const Line* next = w + 1 < lines.size() ? &lines[w + 1] : nullptr;
    const Line* before = w > 0 ? &lines[w - 1] : nullptr;
    std::size_t e = 0;
    std::int64_t read_k = -1;  // the column read last cycle
    for (std::int64_t cyc = 0; cyc < kLine; ++cyc) {
      t->start = cyc == 0;
      t->flush = cyc == kLine - 1;
      // The next line's entries, one every other cycle from the window's first; junk on the port otherwise.
      const std::int64_t load_k = cyc % 2 == 0 ? cyc / 2 : -1;
      t->ld_we = next != nullptr && load_k >= 0 && load_k < static_cast<std::int64_t>(per_line);
      if (t->ld_we != 0) {
        load(*next, static_cast<std::size_t>(load_k));
      } else {
        t->ld_col = static_cast<SData>(rng() & 1023);
        t->ld_entry = rng();
      }
      // This line's ends at the port.
      t->lit_valid = 0;
      t->cut_valid = 0;
      t->lit_col = static_cast<SData>(rng() & 1023);
      put(t->lit_light, (static_cast<UInt128>(rng()) << 64 | rng()) & ((UInt128{1} << 54) - 1));
      t->cut_col = static_cast<SData>(rng() & 1023);
      for (; now != nullptr && e < now->ends.size() && now->ends[e].cycle == cyc; ++e) {
        const End& end = now->ends[e];
        if (end.lit) {
          t->lit_valid = 1;
          t->lit_col = static_cast<SData>(end.col);
          UInt128 light = 0;
          for (int k = 0; k < 3; ++k) light |= static_cast<UInt128>(end.light[static_cast<std::size_t>(k)]) << (18 * k);
          put(t->lit_light, light);
        } else {
          t->cut_valid = 1;
          t->cut_col = static_cast<SData>(end.col);
        }
      }
      // The last line's entries, one a cycle from the window's first; each on the port the cycle after.
      const std::int64_t k_now = cyc < static_cast<std::int64_t>(per_line) ? cyc : -1;
      t->rd_col = static_cast<SData>(before != nullptr && k_now >= 0 ? before->cols[static_cast<std::size_t>(k_now)]
                                                                     : rng() & 1023);
      t->clk = 0;
      t->eval();
      if (t->ld_we != 0 && (t->ld_takes != 0) != next->takes[static_cast<std::size_t>(load_k)])
        fail("line " + std::to_string(w + 1) + " column " + std::to_string(next->cols[static_cast<std::size_t>(load_k)]) + ": takes");
      if (read_k >= 0 && before != nullptr) {
        const auto k = static_cast<std::size_t>(read_k);
        const std::string where = "line " + std::to_string(w - 1) + " column " + std::to_string(before->cols[k]);
        ++stats.columns;
        stats.converged += !before->takes[k];
        if ((t->rd_final != 0) != before->final[k]) {
          fail(where + ": final " + std::to_string(t->rd_final) + ", the model's " + std::to_string(before->final[k]));
        } else if (before->final[k]) {
          ++stats.final;
          const device::AccumEntry got = path::unpack_entry(t->rd_entry);
          if (!(got == before->entry[k]))
            fail(where + ": entry count " + std::to_string(got.count) + " sums " + std::to_string(got.sum[0]) + " " +
                 std::to_string(got.sum[1]) + " " + std::to_string(got.sum[2]) + ", the model's count " +
                 std::to_string(before->entry[k].count) + " sums " + std::to_string(before->entry[k].sum[0]));
        } else {
          ++stats.late;
        }
      }
      read_k = k_now;
      rising_edge(*t);
    }
  }
  EXPECT_EQ(t->overflow, 0);
  EXPECT_EQ(bad, 0);
}

TEST(PathPixelsRtl, EveryColumnsEntryIsFinalWhenTheScheduleSaysAndIsTheModels) {
  std::mt19937_64 rng(20261207);
  std::vector<Line> lines;
  Stats stats;
  for (int l = 0; l < 40; ++l) {
    const int spp = l % 5 == 4 ? 1 + static_cast<int>(rng() % 31) : 1 + l % 4;
    // Most lines' ends well within the window; a quarter's to 3,300 (some columns late).
    // A column's samples from the window's first cycle in a quarter of the lines, to its last cycles in another.
    const std::int64_t edge = l % 4 == 1 ? 0 : l % 4 == 2 ? kLine - 1 - spp - l / 4 % 3 : -1;
    lines.push_back(random_line(rng, spp, l % 4 == 3 ? 3300 : 3000, edge));
  }
  // What the lines hold: cuts that meet a light, samples of a column through the port in consecutive cycles (the
  // second takes the first's sum from the forwarding register), and the window's edges: a sample through the port in
  // its first cycle, and columns whose last went through in cycle 3198 (final) or 3199 (late).
  std::array<int, 2> edge{};
  int first_cycle = 0;
  for (const Line& l : lines) {
    std::vector<std::int64_t> lit_cycles;
    for (const End& e : l.ends) {
      if (e.lit) lit_cycles.push_back(e.cycle);
    }
    for (const End& e : l.ends)
      if (!e.lit && std::binary_search(lit_cycles.begin(), lit_cycles.end(), e.cycle)) ++stats.cuts_waited;
    bool at_first = false;
    for (const std::vector<std::int64_t>& at : l.port) {
      if (at.empty()) continue;
      for (std::size_t i = 1; i < at.size(); ++i) stats.back_to_back += at[i] == at[i - 1] + 1;
      at_first = at_first || at.front() == 0;
      if (at.back() == kLine - 2 || at.back() == kLine - 1) ++edge[static_cast<std::size_t>(at.back() - (kLine - 2))];
    }
    first_cycle += at_first;
  }
  run(lines, stats, rng);
  std::printf("%d columns: %d final, %d late, %d converged; %d cuts met a light, %d samples of a column through the port in consecutive cycles\n",
              stats.columns, stats.final, stats.late, stats.converged, stats.cuts_waited, stats.back_to_back);
  EXPECT_EQ(stats.columns, 40 * 71);
  EXPECT_GT(stats.late, 20);
  EXPECT_GT(stats.converged, 40);
  EXPECT_GT(stats.cuts_waited, 20);
  EXPECT_GT(stats.back_to_back, 100);
  std::printf("at the edges: %d lines with a sample through the port in the window's first cycle; %d columns final "
              "from cycle 3198, %d late from 3199\n", first_cycle, edge[0], edge[1]);
  EXPECT_GT(first_cycle, 5);
  EXPECT_GT(edge[0], 0);
  EXPECT_GT(edge[1], 0);
}

}  // namespace
}  // namespace tripsitter::rtl

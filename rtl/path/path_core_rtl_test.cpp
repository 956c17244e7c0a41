// The artix path preset's tracing core as RTL (ts_path_core.sv: path units and the bounce stage they share, joined
// by the turn, and each unit's pixels; nine units as the preset has them, seven, and one) held to the model line by
// line: every sample of every column ends where the model ends it (the stage's light, equal bit for bit to
// artix::trace_path_sample's, or 0 for a path absorbed; or its unit's cut at the path's last ray), every column's
// last sample goes through its unit's pixel port when artix::unit_finish_cycles says (or the column is one the
// model finds late), and every column read back in the next window is final exactly when the model has it on time,
// with path_pixel()'s entry. No ray's next ray or hit comes from the test bench: the units trace and the stage
// bounces. The test bench is the rest of the device: the camera's directions with each pixel's entry from frame
// memory (written in the line before; random entries, some of them converged), each unit's tile lists, scene and
// node memory, and the surfaces' memory, each a registered read. Lines run back to back, 3,200 cycles each with the
// window's flush at its end.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sphere_unit_draw.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_path_core.h>
#include <Vts_path_core_n1.h>
#include <Vts_path_core_n7.h>

#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/path_rng.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/test_util.h>

#include "path_line_model.h"
#include "path_rtl_util.h"

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;
using path::ModelLine;
using sphere_unit::kCoordW;
using sphere_unit::kDirW;

constexpr int kLine = 3200;
constexpr int kAW = 8, kTagW = 5 + 10 + 5, kSurfaceRead = 2;

struct Stats {
  int lines = 0, columns = 0, late = 0, samples = 0, lit = 0, dark = 0, cuts = 0;
  int read = 0, final = 0, converged = 0;  // columns read back after their window
  void print(const char* what) const {
    std::printf("%s: %d lines, %d columns (%d late), %d samples over: %d lit by the sky, %d absorbed, %d cut; %d "
                "columns read back, %d final (%d converged)\n",
                what, lines, columns, late, samples, lit, dark, cuts, read, final, converged);
  }
};

// `lines` of one world through a core of kUnits units (Top, Verilated with N = kUnits), back to back (the first
// one's pixels written before its window).
template <class Top, int kUnits>
void run_lines(const device::DevicePreset& p, const path::PathScene& scene, const std::vector<ModelLine>& lines,
               Stats& stats) {
  ASSERT_EQ(p.workers, kUnits);
  const artix::UnitWorld& world = scene.world;
  const device::PathFrame& frame = scene.frame;
  const int shade = p.units->shade_latency;
  VerilatedContext context;
  context.randReset(2);
  auto t = std::make_unique<Top>(&context);
  path::put_world(*t, world, frame);
  t->sample_base = frame.frame * static_cast<std::uint32_t>(frame.spp);
  t->px_epoch = frame.epoch;
  t->px_spp = static_cast<CData>(frame.spp);
  t->start = 0;
  t->flush = 0;
  t->px_we = 0;
  t->rst = 1;
  for (int i = 0; i < 3; ++i) rising_edge(*t);
  t->rst = 0;

  // Column c is unit c mod N's pixel c / N.
  const auto write_pixel = [&](const ModelLine& m, int col) {
    t->px_we = 1;
    t->px_unit = static_cast<CData>(col % kUnits);
    t->px_slot = static_cast<SData>(col / kUnits);
    t->px_col = static_cast<SData>(col);
    t->px_entry = path::pack(m.stored[static_cast<std::size_t>(col)]);
    put(t->px_d, sphere_unit::pack3(artix::camera_direction(col, m.row), kDirW));
  };
  for (int col = 0; col < device::kLineWidth; ++col) {
    write_pixel(lines[0], col);
    rising_edge(*t);
  }
  t->px_we = 0;

  // The last window's row read back, a column a cycle from cycle 100 (unit c mod N's column c): final exactly when
  // the model has it on time, and then the model's entry. Called after each cycle's evaluation: checks the column
  // asked the cycle before, and asks the next.
  int asked = -1;
  const auto read_back = [&](const ModelLine* before, std::int64_t cyc) {
    if (asked >= 0) {
      const auto c = static_cast<std::size_t>(asked);
      const bool on_time = before->finish[c] <= kLine;
      ++stats.read;
      stats.converged += !before->takes[c];
      EXPECT_EQ(t->rd_final != 0, on_time) << "row " << before->row << " column " << asked;
      if (on_time && t->rd_final != 0) {
        ++stats.final;
        const device::AccumEntry got = path::unpack_entry(t->rd_entry);
        EXPECT_TRUE(got == before->entry[c])
            << "row " << before->row << " column " << asked << ": count " << int{got.count} << " sums " << got.sum[0]
            << " " << got.sum[1] << " " << got.sum[2] << ", the model's " << int{before->entry[c].count} << " "
            << before->entry[c].sum[0] << " " << before->entry[c].sum[1] << " " << before->entry[c].sum[2];
      }
    }
    asked = before != nullptr && cyc >= 100 && cyc < 100 + device::kLineWidth ? static_cast<int>(cyc - 100) : -1;
    t->rd_col = static_cast<SData>(asked >= 0 ? asked : 0);
    t->rd_unit = static_cast<CData>(asked >= 0 ? asked % kUnits : 0);
  };

  // The memories' registered reads: what each unit asked last cycle; the surface asked two cycles ago.
  std::array<int, kUnits> tile_q{}, pos_q{}, mem_q{}, node_q{};
  std::array<bool, kUnits> bound_q{};
  std::array<int, kSurfaceRead> surf_q{};

  for (const ModelLine& m : lines) {
    t->row = static_cast<SData>(m.row);
    // The model's samples: each one's light (the plain reference's), and when each ended.
    std::vector<std::vector<device::PathSample>> want(device::kLineWidth);
    std::vector<std::vector<std::int64_t>> ends(device::kLineWidth);
    std::vector<std::vector<bool>> lit(device::kLineWidth);  // a sample's end: at the stage, or cut
    for (int c = 0; c < device::kLineWidth; ++c) {
      const auto n = m.paths[static_cast<std::size_t>(c)].size();
      ends[static_cast<std::size_t>(c)].assign(n, -1);
      lit[static_cast<std::size_t>(c)].assign(n, false);
      for (std::size_t s = 0; s < n; ++s) {
        const auto pixel = static_cast<std::uint32_t>(m.row * device::kLineWidth + c);
        device::PathRng rng = device::PathRng::for_sample(
            pixel, frame.frame * static_cast<std::uint32_t>(frame.spp) + static_cast<std::uint32_t>(s));
        device::PathCounters counters;
        want[static_cast<std::size_t>(c)].push_back(
            artix::trace_path_sample(c, m.row, world.spheres, scene.surfaces, frame.depth, rng, counters));
      }
    }
    const auto sample_ends = [&](int col, int sample, std::int64_t at, bool at_stage, const char* how) {
      ASSERT_TRUE(col < device::kLineWidth && sample < static_cast<int>(ends[static_cast<std::size_t>(col)].size()))
          << how << " of no sample: column " << col << " sample " << sample;
      std::int64_t& e = ends[static_cast<std::size_t>(col)][static_cast<std::size_t>(sample)];
      EXPECT_EQ(e, -1) << how << ": column " << col << " sample " << sample << " ended twice";
      e = at;
      lit[static_cast<std::size_t>(col)][static_cast<std::size_t>(sample)] = at_stage;
      ++stats.samples;
    };
    const std::size_t l = static_cast<std::size_t>(&m - lines.data());
    for (std::int64_t cyc = 0; cyc < kLine; ++cyc) {
      t->start = cyc == 0;
      t->flush = cyc == kLine - 1;
      // The next line's pixels, one a cycle from the window's second cycle.
      t->px_we = 0;
      if (l + 1 < lines.size() && cyc >= 1 && cyc <= device::kLineWidth)
        write_pixel(lines[l + 1], static_cast<int>(cyc - 1));
      // The memories.
      for (int u = 0; u < kUnits; ++u) {
        const auto k = static_cast<std::size_t>(u);
        const path::UnitReads r = path::unit_reads(m, world, tile_q[k], pos_q[k], mem_q[k], bound_q[k], node_q[k]);
        set_bits(t->tile_count, u * (kAW + 1), kAW + 1, r.tile_count);
        set_bits(t->tile_sphere, u * kAW, kAW, r.tile_sphere);
        for (int j = 0; j < 3; ++j)
          set_bits(t->mem_c, (3 * u + j) * kCoordW, kCoordW, r.sphere->c[static_cast<std::size_t>(j)]);
        set_bits(t->mem_e, u * 6, 6, r.sphere->e);
        set_bits(t->mem_r2s, u * 34, 34, r.sphere->r2s);
        if (r.node != nullptr) {
          set_bits(t->node_first_sphere, u * kAW, kAW, r.node->first_sphere);
          set_bits(t->node_spheres, u * 8, 8, r.node->spheres);
          set_bits(t->node_first_child, u * kAW, kAW, r.node->first_child);
          set_bits(t->node_children, u * 8, 8, r.node->children);
        }
      }
      path::put_surface(*t, world, scene.surfaces, surf_q[0]);
      t->clk = 0;
      t->eval();

      // A sample's end at the stage (with its light; the schedule's cycle is the next), or at its unit's cut.
      if (t->end_valid != 0) {
        const int col = t->end_col, sample = t->end_sample;
        EXPECT_EQ(static_cast<int>(t->end_unit), col % kUnits) << "column " << col;
        sample_ends(col, sample, cyc + 1, true, "an end");
        if (col < device::kLineWidth && sample < static_cast<int>(want[static_cast<std::size_t>(col)].size())) {
          const device::PathSample& w = want[static_cast<std::size_t>(col)][static_cast<std::size_t>(sample)];
          std::array<std::int64_t, 3> light{};
          for (std::size_t k = 0; k < 3; ++k)
            light[k] = static_cast<std::int64_t>((t->end_light >> (18 * k)) & 0x3FFFF);
          EXPECT_EQ(light, w.light) << "row " << m.row << " column " << col << " sample " << sample;
          (light == std::array<std::int64_t, 3>{} ? stats.dark : stats.lit) += 1;
        }
      }
      for (int u = 0; u < kUnits; ++u) {
        if (((t->cut_valid >> u) & 1) == 0) continue;
        const auto tag = static_cast<int>(bits_of(t->cut_tag, u * kTagW, kTagW));
        const int col = (tag >> 5) & 1023, sample = tag & 31;
        EXPECT_EQ(col % kUnits, u) << "a cut of another unit's column " << col;
        sample_ends(col, sample, cyc, false, "a cut");
        if (col < device::kLineWidth && sample < static_cast<int>(want[static_cast<std::size_t>(col)].size())) {
          const device::PathSample& w = want[static_cast<std::size_t>(col)][static_cast<std::size_t>(sample)];
          EXPECT_EQ(w.rays, frame.depth) << "row " << m.row << " column " << col << " cut early";
          EXPECT_EQ(w.light, (std::array<std::int64_t, 3>{})) << "row " << m.row << " column " << col;
        }
        ++stats.cuts;
      }
      for (int u = 0; u < kUnits; ++u) {
        const auto k = static_cast<std::size_t>(u);
        tile_q[k] = static_cast<int>(bits_of(t->tile, u * 5, 5));
        pos_q[k] = static_cast<int>(bits_of(t->tile_pos, u * kAW, kAW));
        mem_q[k] = static_cast<int>(bits_of(t->mem_addr, u * kAW, kAW));
        bound_q[k] = ((t->mem_bound >> u) & 1) != 0;
        node_q[k] = static_cast<int>(bits_of(t->node_addr, u * kAW, kAW));
      }
      surf_q[0] = surf_q[1];
      surf_q[1] = t->surf_addr;
      read_back(l > 0 ? &lines[l - 1] : nullptr, cyc);
      rising_edge(*t);
    }
    // Each column: all its samples over, its entry final when the model says; or late.
    const std::vector<std::vector<std::int64_t>> port = path::port_cycles(ends, lit, kUnits);
    for (int c = 0; c < device::kLineWidth; ++c) {
      if (!m.takes[static_cast<std::size_t>(c)]) continue;
      ++stats.columns;
      stats.late += path::column_late(port[static_cast<std::size_t>(c)], m.finish[static_cast<std::size_t>(c)], shade,
                                      kLine, m.row, c);
    }
    ++stats.lines;
  }
  // A window more, with nothing to trace, to read the last line back.
  for (std::int64_t cyc = 0; cyc < kLine; ++cyc) {
    t->start = cyc == 0;
    t->flush = cyc == kLine - 1;
    t->px_we = 0;
    t->clk = 0;
    t->eval();
    read_back(&lines.back(), cyc);
    rising_edge(*t);
  }
  EXPECT_EQ(t->overflow, 0);
}

template <class Top, int kUnits>
void run_world(const device::SceneMemory& scene, int spp, int depth, std::uint32_t frame_no,
               const std::vector<int>& rows, Stats& stats) {
  device::DevicePreset p = device::artix_path_preset();
  p.workers = kUnits;
  const path::PathScene s = path::path_scene(scene, spp, depth, frame_no);
  std::vector<ModelLine> lines;
  std::mt19937_64 rng(frame_no);
  for (const int row : rows) {
    // Frame memory's entries: of this world's epoch or another's, empty, partly or nearly full (some converged).
    std::vector<device::AccumEntry> memory(device::kLineWidth);
    for (device::AccumEntry& e : memory) e = path::random_entry(rng, s.frame.epoch, 8);
    lines.push_back(path::model_line(p, s.world, row, s.frame, memory));
  }
  run_lines<Top, kUnits>(p, s, lines, stats);
}

TEST(PathCoreRtl, NineUnitsAndTheirStageTraceLinesAsTheModel) {
  std::mt19937_64 rng(20261207);
  const device::DevicePreset p = device::artix_path_preset();
  Stats stats;
  for (int w = 0; w < 4; ++w) {
    device::SceneMemory scene = device::testing::random_path_world(p, rng, w < 2 ? 64 : 8);
    if (w < 2) scene = device::testing::with_hierarchy(p, scene);
    run_world<Vts_path_core, 9>(scene, 1 + w % 2, w == 3 ? 1 : 4, static_cast<std::uint32_t>(w), {140, 250, 390},
                                stats);
  }
  stats.print("9 units");
  EXPECT_EQ(stats.lines, 12);
  EXPECT_EQ(stats.read, 12 * device::kLineWidth);
  EXPECT_GT(stats.converged, 100);
  EXPECT_GT(stats.lit, 1000);
  EXPECT_GT(stats.dark, 10);
  EXPECT_GT(stats.cuts, 100);
}

// A prime count of units (their turns do not divide the line's cycles evenly), and one unit alone (its turn every
// cycle: the stage's ends and its cuts may meet in one cycle).
TEST(PathCoreRtl, SevenUnitsAndOneTraceLinesAsTheModel) {
  std::mt19937_64 rng(77);
  const device::DevicePreset p = device::artix_path_preset();
  Stats seven, one;
  for (int w = 0; w < 2; ++w) {
    device::SceneMemory scene = device::testing::random_path_world(p, rng, w == 0 ? 64 : 8);
    if (w == 0) scene = device::testing::with_hierarchy(p, scene);
    run_world<Vts_path_core_n7, 7>(scene, 1 + w, 4, static_cast<std::uint32_t>(w + 5), {100, 300}, seven);
    run_world<Vts_path_core_n1, 1>(scene, 1, 4 - 3 * w, static_cast<std::uint32_t>(w + 5), {200}, one);
  }
  seven.print("7 units");
  one.print("1 unit");
  EXPECT_EQ(seven.lines, 4);
  EXPECT_EQ(seven.read, 4 * device::kLineWidth);
  EXPECT_GT(seven.lit, 500);
  EXPECT_GT(seven.cuts, 50);
  EXPECT_EQ(one.lines, 2);
  EXPECT_EQ(one.read, 2 * device::kLineWidth);
  EXPECT_GT(one.samples, 300);
  EXPECT_GT(one.late, 100);  // 640 columns on one unit: most are late
}

}  // namespace
}  // namespace tripsitter::rtl

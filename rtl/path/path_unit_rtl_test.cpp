// A sphere unit of the artix path preset as RTL (ts_path_unit.sv: the issue port, the queues of bounced rays and of
// walks' next levels, the camera's samples, the walker and the sphere unit, each path's ray and best hit, the unit's
// turn at the shared bounce stage) held to the model line by line: every ray's closest hit the model's
// (artix::path_line_chains, which traces the line's samples), handed to the bounce stage in the unit's turn or cut
// at the path's last ray, and every column's samples over when artix::unit_finish_cycles says: the light of a
// sample that enters the stage in cycle c is out at c + reflect_latency, a cut one's at its hit, and the column's
// colour shade_latency after its last. The test bench is the rest of the device: the camera's directions and which
// pixels take samples (written in the line before), the tile lists, scene memory (spheres and the hierarchy's
// bounds), node memory, and the bounce stage, which gives back each path's next ray, as the model traced it, or
// its word that the path is over, in the cycle before reflect_latency after its hit entered (the unit's turn; its
// port shows the hit registered, in the next cycle). Lines run back to back, 3,200 cycles each with the window's
// flush at its end: a column whose samples are not all over by then must be one the model finds late.
#include <algorithm>
#include <cstdio>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "sphere_unit_draw.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_path_unit.h>

#include <tripsitter/device/artix_units.h>
#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/test_util.h>

#include "path_line_model.h"

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;
using path::ModelLine;
using sphere_unit::kDirW;
using sphere_unit::kOriginW;
using sphere_unit::kTdW;
using sphere_unit::pack3;

constexpr int kUnits = 9;  // the Verilated unit's N (PARAMS), the preset's
constexpr int kLine = 3200;
constexpr int kSampleBits = 5, kColBits = 10;  // the tag: {path number, column, sample}
constexpr int kPaths = 32;                         // the Verilated unit's IDS (PARAMS)

struct Stats {
  int lines = 0, columns = 0, late = 0, samples = 0, entries = 0, cuts = 0, walks = 0, far = 0, converged = 0;
  void print(const char* what) const {
    std::printf("%s: %d lines of a unit, %d columns (%d late, %d converged), %d samples, %d hits to the bounce stage "
                "(%d far sides), %d cuts\n", what, lines, columns, late, converged, samples, entries, far, cuts);
  }
};

// The unit `unit` running `lines` back to back (the first one's pixels written before its window).
void run_lines(const device::DevicePreset& p, const artix::UnitWorld& world, const device::PathFrame& frame,
               int unit, const std::vector<ModelLine>& lines, Stats& stats) {
  auto t = std::make_unique<Vts_path_unit>();
  const int reflect = p.units->reflect_latency, shade = p.units->shade_latency;
  t->unit_id = static_cast<SData>(unit);
  path::put_world(*t, world, frame);
  t->rst = 1;
  for (int i = 0; i < 3; ++i) rising_edge(*t);
  t->rst = 0;

  // The unit's columns, its pixel k column unit + k N, written one a cycle.
  std::vector<int> cols;
  for (int c = unit; c < device::kLineWidth; c += kUnits) cols.push_back(c);
  const auto write_pixel = [&](const ModelLine& m, int k) {
    const int col = unit + k * kUnits;
    t->px_we = 1;
    t->px_slot = static_cast<CData>(k);
    t->px_takes = m.takes[static_cast<std::size_t>(col)];
    put(t->px_d, pack3(artix::camera_direction(col, m.row), kDirW));
  };
  const int slots = static_cast<int>(cols.size());
  for (int k = 0; k < slots; ++k) {
    write_pixel(lines[0], k);
    rising_edge(*t);
  }
  t->px_we = 0;

  // The memories' registered reads: what was asked last cycle.
  int tile_q = 0, pos_q = 0, mem_q = 0, node_q = 0;
  bool bound_q = false;

  for (std::size_t l = 0; l < lines.size(); ++l) {
    const ModelLine& m = lines[l];
    struct Return {
      int col, sample, ray;  // ray < 0: the path is over
      int tag;
    };
    std::multimap<std::int64_t, Return> returns;  // the bounce stage's next rays, by the cycle they come back
    std::vector<std::vector<std::int64_t>> ends(device::kLineWidth);  // each sample's light out (or its cut's)
    std::vector<std::vector<bool>> lit(device::kLineWidth);            // ... at the stage (else cut)
    std::vector<std::vector<int>> seen(device::kLineWidth);            // rays of each sample handed on
    std::array<int, kPaths> numbers;                                   // the live path of each number (col 32 + sample)
    numbers.fill(-1);
    for (const int c : cols) {
      const auto n = m.paths[static_cast<std::size_t>(c)].size();
      ends[static_cast<std::size_t>(c)].assign(n, -1);
      lit[static_cast<std::size_t>(c)].assign(n, false);
      seen[static_cast<std::size_t>(c)].assign(n, 0);
    }
    for (std::int64_t cyc = 0; cyc < kLine; ++cyc) {
      t->start = cyc == 0;
      t->flush = cyc == kLine - 1;
      // The next line's pixels, one a cycle from the window's second cycle.
      t->px_we = 0;
      if (l + 1 < lines.size() && cyc >= 1 && cyc <= slots) write_pixel(lines[l + 1], static_cast<int>(cyc - 1));
      // The memories.
      const path::UnitReads r = path::unit_reads(m, world, tile_q, pos_q, mem_q, bound_q, node_q);
      t->tile_count = static_cast<SData>(r.tile_count);
      t->tile_sphere = static_cast<CData>(r.tile_sphere);
      put(t->mem_c, pack3(r.sphere->c, sphere_unit::kCoordW));
      put(t->mem_e, static_cast<UInt128>(r.sphere->e) & 0x3f);
      put(t->mem_r2s, static_cast<UInt128>(r.sphere->r2s));
      if (r.node != nullptr) {
        t->node_first_sphere = static_cast<CData>(r.node->first_sphere);
        t->node_spheres = static_cast<CData>(r.node->spheres);
        t->node_first_child = static_cast<CData>(r.node->first_child);
        t->node_children = static_cast<CData>(r.node->children);
      }
      // The bounce stage's next ray, or its word that a path is over, in the cycle before it is known.
      t->ray_valid = 0;
      t->end_valid = 0;
      if (auto it = returns.find(cyc); it != returns.end()) {
        const Return r = it->second;
        returns.erase(it);
        ASSERT_EQ(returns.count(cyc), 0u) << "two words back in one cycle";
        if (r.ray < 0) {
          t->end_valid = 1;
          t->end_path = static_cast<CData>(r.tag >> (kColBits + kSampleBits));
          numbers[static_cast<std::size_t>(r.tag >> (kColBits + kSampleBits))] = -1;
        } else {
          const auto& next = m.paths[static_cast<std::size_t>(r.col)][static_cast<std::size_t>(r.sample)][static_cast<std::size_t>(r.ray)].first;
          t->ray_valid = 1;
          put(t->ray_o, pack3(next.ray.o, kOriginW));
          put(t->ray_d, pack3(next.ray.d, kDirW));
          t->ray_from = static_cast<CData>(next.from);
          t->ray_into = next.into;
          t->ray_rays = static_cast<CData>(r.ray + 1);
          t->ray_tag = static_cast<IData>(r.tag);
        }
      }
      t->clk = 0;
      t->eval();

      // A path's names from its tag; its number the same at every ray, and no other path's while it lives.
      const auto path_of = [&](int tag, int& col, int& sample) {
        col = (tag >> kSampleBits) & ((1 << kColBits) - 1);
        sample = tag & ((1 << kSampleBits) - 1);
        const int number = tag >> (kColBits + kSampleBits);
        if (col >= device::kLineWidth || (col - unit) % kUnits != 0 ||
            sample >= static_cast<int>(m.paths[static_cast<std::size_t>(col)].size()) || number >= kPaths)
          return false;
        const int key = col * 32 + sample;
        auto& holder = numbers[static_cast<std::size_t>(number)];
        if (holder < 0) holder = key;
        EXPECT_EQ(holder, key) << "path number " << number << " of two live paths";
        return true;
      };
      if (t->stage_valid != 0) {
        int col = 0, sample = 0;
        ASSERT_TRUE(path_of(t->stage_tag, col, sample)) << "a hit of no path, tag " << t->stage_tag;
        const auto& rays = m.paths[static_cast<std::size_t>(col)][static_cast<std::size_t>(sample)];
        const int ray = static_cast<int>(t->stage_rays) - 1;
        ASSERT_TRUE(ray >= 0 && ray < static_cast<int>(rays.size())) << "column " << col << " sample " << sample;
        EXPECT_EQ(seen[static_cast<std::size_t>(col)][static_cast<std::size_t>(sample)], ray) << "column " << col;
        seen[static_cast<std::size_t>(col)][static_cast<std::size_t>(sample)] = ray + 1;
        EXPECT_EQ((cyc - 1) % kUnits, unit) << "not the cycle after the unit's turn";
        const auto& [want_ray, want] = rays[static_cast<std::size_t>(ray)];
        const std::string where = "row " + std::to_string(m.row) + " column " + std::to_string(col) + " sample " +
                                  std::to_string(sample) + " ray " + std::to_string(ray);
        EXPECT_EQ(get(t->stage_o), pack3(want_ray.ray.o, kOriginW)) << where;
        EXPECT_EQ(get(t->stage_d), pack3(want_ray.ray.d, kDirW)) << where;
        EXPECT_EQ(t->stage_hit != 0, want.index >= 0) << where;
        if (want.index >= 0 && t->stage_hit != 0) {
          EXPECT_EQ(static_cast<int>(t->stage_index), want.index) << where;
          EXPECT_EQ(static_cast<std::int64_t>(sign_extend(get(t->stage_td), kTdW)), want.td) << where;
          EXPECT_EQ(t->stage_far != 0, want.inside) << where;
          stats.far += want.inside;
        }
        ++stats.entries;
        if (ray + 1 < static_cast<int>(rays.size())) {
          returns.insert({cyc + reflect - 2, {col, sample, ray + 1, static_cast<int>(t->stage_tag)}});
        } else {
          returns.insert({cyc + reflect - 2, {col, sample, -1, static_cast<int>(t->stage_tag)}});
          ends[static_cast<std::size_t>(col)][static_cast<std::size_t>(sample)] = cyc - 1 + reflect;
          lit[static_cast<std::size_t>(col)][static_cast<std::size_t>(sample)] = true;
        }
      }
      if (t->cut_valid != 0) {
        int col = 0, sample = 0;
        ASSERT_TRUE(path_of(t->cut_tag, col, sample)) << "a cut of no path, tag " << t->cut_tag;
        const auto& rays = m.paths[static_cast<std::size_t>(col)][static_cast<std::size_t>(sample)];
        EXPECT_EQ(static_cast<int>(rays.size()), frame.depth) << "column " << col << " cut early";
        EXPECT_GE(rays.back().second.index, 0) << "column " << col << " cut on a miss";
        EXPECT_EQ(seen[static_cast<std::size_t>(col)][static_cast<std::size_t>(sample)], frame.depth - 1);
        seen[static_cast<std::size_t>(col)][static_cast<std::size_t>(sample)] = frame.depth;
        ends[static_cast<std::size_t>(col)][static_cast<std::size_t>(sample)] = cyc;
        numbers[static_cast<std::size_t>(t->cut_tag >> (kColBits + kSampleBits))] = -1;
        ++stats.cuts;
      }
      tile_q = t->tile;
      pos_q = t->tile_pos;
      mem_q = t->mem_addr;
      bound_q = t->mem_bound != 0;
      node_q = t->node_addr;
      rising_edge(*t);
    }
    // Each column of the unit: all its samples over, its entry final when the model says; or late.
    const std::vector<std::vector<std::int64_t>> port = path::port_cycles(ends, lit, kUnits);
    for (const int c : cols) {
      const auto& e = port[static_cast<std::size_t>(c)];
      const std::int64_t want = m.finish[static_cast<std::size_t>(c)];
      if (!m.takes[static_cast<std::size_t>(c)]) {
        ++stats.converged;
        continue;
      }
      ++stats.columns;
      stats.samples += static_cast<int>(e.size());
      stats.late += path::column_late(e, want, shade, kLine, m.row, c);
    }
    ++stats.lines;
  }
  EXPECT_EQ(t->overflow, 0);
}

// A world as the device holds it, its frame (spp, depth), and rows of it, run through units 0, 4 and 8.
void run_world(const device::SceneMemory& scene, int spp, int depth, std::uint32_t frame_no,
               const std::vector<int>& rows, Stats& stats, bool converge_some = false) {
  const device::DevicePreset p = device::artix_path_preset();
  const path::PathScene s = path::path_scene(scene, spp, depth, frame_no);
  stats.walks += !s.world.nodes.empty();
  std::vector<ModelLine> lines;
  for (const int row : rows) {
    std::vector<device::AccumEntry> memory(device::kLineWidth);
    if (converge_some)
      for (std::size_t c = 0; c < memory.size(); c += 3) memory[c] = {{0, 0, 0}, 255, 1};  // converged
    lines.push_back(path::model_line(p, s.world, row, s.frame, memory));
  }
  for (const int unit : {0, 4, 8}) run_lines(p, s.world, s.frame, unit, lines, stats);
}

TEST(PathUnitRtl, WorldsWithAHierarchyWalkItLineByLineAsTheModel) {
  std::mt19937_64 rng(20261207);
  const device::DevicePreset p = device::artix_path_preset();
  Stats stats;
  for (int w = 0; w < 4; ++w) {
    const device::SceneMemory scene = device::testing::with_hierarchy(p, device::testing::random_path_world(p, rng, 64));
    run_world(scene, 1 + w % 2, w < 2 ? 4 : 1, static_cast<std::uint32_t>(w), {150, 240, 330}, stats);
  }
  stats.print("hierarchies");
  EXPECT_GE(stats.walks, 3);
  EXPECT_EQ(stats.lines, 4 * 3 * 3);
  EXPECT_GT(stats.entries, 1000);
  EXPECT_GT(stats.cuts, 10);
  EXPECT_GT(stats.far, 0);
}

TEST(PathUnitRtl, WorldsWithoutAHierarchyTestEverySphereLineByLineAsTheModel) {
  std::mt19937_64 rng(7);
  const device::DevicePreset p = device::artix_path_preset();
  Stats stats;
  for (int w = 0; w < 4; ++w) {
    const device::SceneMemory scene = device::testing::random_path_world(p, rng, 8);
    run_world(scene, 1 + w % 2, w % 2 == 0 ? 4 : 1, 3, {100, 240, 400}, stats, w == 3);
  }
  stats.print("every sphere");
  EXPECT_EQ(stats.walks, 0);
  EXPECT_GT(stats.entries, 1000);
  EXPECT_GT(stats.converged, 50);
}

// Each sphere twice: the originals at the hierarchy's root, their copies in its one leaf. A ray meets a sphere and
// its copy at the same t d, one in each level of its walk: the lower index, the root's, must win across the levels
// as within a pass (the model's keep_closest).
TEST(PathUnitRtl, ATieAcrossAWalksLevelsGoesToTheLowerIndex) {
  std::mt19937_64 rng(99);
  const device::DevicePreset p = device::artix_path_preset();
  Stats stats;
  for (int w = 0; w < 3; ++w) {
    device::SceneMemory scene = device::testing::random_path_world(p, rng, 8);
    const auto n = static_cast<int>(scene.geometry.size());
    for (int i = 0; i < n; ++i) {
      scene.geometry.push_back(scene.geometry[static_cast<std::size_t>(i)]);
      scene.surfaces.push_back(scene.surfaces[static_cast<std::size_t>(i)]);
    }
    // The leaf's bound: the box's centre, and its farthest sphere's reach from it with 1 to spare.
    std::array<std::int64_t, 3> lo{}, hi{};
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = hi[k] = scene.geometry[0].center[k];
      for (const auto& g : scene.geometry) {
        lo[k] = std::min(lo[k], g.center[k] - g.radius);
        hi[k] = std::max(hi[k], g.center[k] + g.radius);
      }
    }
    core::KernelSphere<std::int64_t> bound;
    bound.center = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
    double reach = 0;
    for (const auto& g : scene.geometry) {
      double d2 = 0;
      for (std::size_t k = 0; k < 3; ++k) d2 += std::pow(static_cast<double>(g.center[k] - bound.center[k]), 2);
      reach = std::max(reach, std::sqrt(d2) + static_cast<double>(g.radius));
    }
    bound.radius = std::min<std::int64_t>(static_cast<std::int64_t>(reach) + 2, (std::int64_t{1} << 21) - 1);
    scene.hierarchy = {{{}, 1, 1, 0, n}, {bound, 0, 0, n, n}};
    run_world(scene, 2, 4, static_cast<std::uint32_t>(w), {200, 260}, stats);
  }
  stats.print("copies");
  EXPECT_EQ(stats.walks, 3);
  EXPECT_GT(stats.entries, 500);
}

}  // namespace
}  // namespace tripsitter::rtl

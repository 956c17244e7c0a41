// What the tests of the path units and the bounce stage share (path_unit_rtl_test, path_bounce_rtl_test,
// path_core_rtl_test): a world as the device holds it with its frame, and on a block's ports; one line of the model
// with every sample's rays and hits; the memories a unit reads (the row's tile lists, scene memory, node memory) as
// the test bench serves them, each a registered read, and the stage's surfaces; a column's end against the model's.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"

#include <tripsitter/device/artix_units.h>
#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/preset.h>

namespace tripsitter::rtl::path {

namespace artix = device::artix;

// A world as the device holds it, and its frame (whose surfaces are a view of `surfaces`: moved, never copied).
struct PathScene {
  PathScene() = default;
  PathScene(const PathScene&) = delete;
  PathScene& operator=(const PathScene&) = delete;
  PathScene(PathScene&&) = default;
  PathScene& operator=(PathScene&&) = default;
  artix::UnitWorld world;
  std::vector<device::PathSurface> surfaces;
  device::PathFrame frame;
};
inline PathScene path_scene(const device::SceneMemory& scene, int spp, int depth, std::uint32_t frame_no) {
  PathScene s;
  s.world = artix::prepare_world(scene);
  for (const auto& w : scene.surfaces) s.surfaces.push_back(device::path_surface(w));
  s.frame.surfaces = s.surfaces;
  s.frame.frame = frame_no;
  s.frame.epoch = 1;
  s.frame.spp = spp;
  s.frame.depth = depth;
  return s;
}

// The world and the frame's path rules on the ports of a unit or of the core.
template <class Top>
void put_world(Top& t, const artix::UnitWorld& world, const device::PathFrame& frame) {
  t.spheres = static_cast<SData>(world.spheres.size());
  t.walks = !world.nodes.empty();
  if (!world.nodes.empty()) {
    t.root_first_sphere = static_cast<CData>(world.nodes[0].first_sphere);
    t.root_spheres = static_cast<CData>(world.nodes[0].spheres);
    t.root_first_child = static_cast<CData>(world.nodes[0].first_child);
    t.root_children = static_cast<CData>(world.nodes[0].children);
  }
  t.depth = static_cast<CData>(frame.depth);
  t.spp = static_cast<CData>(frame.spp);
}

// Sphere `s`'s surface and 1 / r on the surface port of the bounce stage or of the core.
template <class Top>
void put_surface(Top& t, const artix::UnitWorld& world, std::span<const device::PathSurface> surfaces, int s) {
  const auto i = static_cast<std::size_t>(std::clamp(s, 0, static_cast<int>(world.spheres.size()) - 1));
  const device::PathSurface& f = surfaces[i];
  t.surf_material = f.material;
  put(t.surf_albedo, static_cast<UInt128>(f.albedo[0]) | static_cast<UInt128>(f.albedo[1]) << 17 |
                         static_cast<UInt128>(f.albedo[2]) << 34);
  t.surf_fuzz = f.fuzz;
  t.surf_eta_enter = static_cast<IData>(f.eta_enter);
  t.surf_eta_leave = static_cast<IData>(f.eta_leave);
  t.surf_r0 = static_cast<SData>(f.r0);
  t.surf_straight = f.passes_straight;
  t.surf_rinv = static_cast<IData>(world.spheres[i].rinv);
}

// The cycles the samples' ends go through their units' pixel ports (artix::serve_pixel_port; column c is unit
// c mod `units`'s), from the cycles they ended in (`ends[col][sample]`, -1: not over) and whether each was a light
// out of the bounce stage (`lit`, else a cut).
inline std::vector<std::vector<std::int64_t>> port_cycles(const std::vector<std::vector<std::int64_t>>& ends,
                                                          const std::vector<std::vector<bool>>& lit, int units) {
  std::vector<std::vector<std::int64_t>> at = ends;
  for (int u = 0; u < units; ++u) {
    // Each kind's ends in the order of their cycles, with the sample each is.
    std::array<std::vector<std::pair<device::artix::PortEnd, std::size_t>>, 2> kinds;
    for (int c = u; c < static_cast<int>(ends.size()); c += units)
      for (std::size_t s = 0; s < ends[static_cast<std::size_t>(c)].size(); ++s)
        if (ends[static_cast<std::size_t>(c)][s] >= 0)
          kinds[lit[static_cast<std::size_t>(c)][s] ? 0 : 1].push_back({{ends[static_cast<std::size_t>(c)][s], c}, s});
    std::array<std::vector<device::artix::PortEnd>, 2> port;
    for (std::size_t k = 0; k < 2; ++k) {
      std::sort(kinds[k].begin(), kinds[k].end(),
                [](const auto& a, const auto& b) { return a.first.cycle < b.first.cycle; });
      for (const auto& e : kinds[k]) port[k].push_back(e.first);
    }
    device::artix::serve_pixel_port(port[0], port[1]);
    for (std::size_t k = 0; k < 2; ++k)
      for (std::size_t i = 0; i < port[k].size(); ++i)
        at[static_cast<std::size_t>(port[k][i].col)][kinds[k][i].second] = port[k][i].cycle;
  }
  return at;
}

// A column whose samples went through its unit's pixel port in the cycles `ends` (port_cycles; -1: not over when the
// line's window of `line` cycles closed): final exactly when the model says (`finish`, shade_latency after its last
// there), or late in the model too (a sample not over by the window's last cycle would end after it at the
// earliest). Returns whether it is late.
inline bool column_late(const std::vector<std::int64_t>& ends, std::int64_t finish, int shade, int line, int row,
                        int col) {
  if (std::all_of(ends.begin(), ends.end(), [](std::int64_t x) { return x >= 0; })) {
    EXPECT_EQ(*std::max_element(ends.begin(), ends.end()) + shade, finish) << "row " << row << " column " << col;
    return false;
  }
  EXPECT_GT(finish, line - 1 + shade) << "row " << row << " column " << col;
  return true;
}

// One line of the model: its tile lists, its columns' finish cycles, which columns take samples, their entries in
// frame memory before and after the line, and each sample's rays with their hits, in the order traced.
struct ModelLine {
  int row = 0;
  artix::RowTiles tiles;
  std::vector<std::int64_t> finish;
  std::vector<bool> takes;                                                          // a column
  std::vector<device::AccumEntry> stored, entry;                                    // a column's
  std::vector<std::vector<std::vector<std::pair<artix::PathUnitRay, artix::PathUnitHit>>>> paths;  // [col][sample]
};

inline ModelLine model_line(const device::DevicePreset& p, const artix::UnitWorld& world, int row,
                            const device::PathFrame& frame, const std::vector<device::AccumEntry>& memory) {
  ModelLine m;
  m.row = row;
  m.tiles = artix::row_tiles(world, row, p.units->tile_columns);
  m.paths.resize(device::kLineWidth);
  artix::LineChains work;
  std::vector<device::PathPixel> pixels(device::kLineWidth);
  device::PathCounters counters;
  const artix::RayObserver observe = [&](int col, const artix::PathUnitRay& ray, const artix::PathUnitHit& hit) {
    // The sample being traced: the column's chains so far.
    const std::size_t sample = work.chain_start.size() - 1 - static_cast<std::size_t>(work.start.back());
    auto& samples = m.paths[static_cast<std::size_t>(col)];
    if (samples.size() <= sample) samples.resize(sample + 1);
    samples[sample].push_back({ray, hit});
  };
  artix::path_line_chains(p, world, row, frame, memory, pixels, counters, artix::Search::kAll, work, &observe);
  m.finish = artix::unit_finish_cycles(p, work);
  m.stored = memory;
  for (int c = 0; c < device::kLineWidth; ++c) {
    m.takes.push_back(work.start[static_cast<std::size_t>(c) + 1] > work.start[static_cast<std::size_t>(c)]);
    m.entry.push_back(pixels[static_cast<std::size_t>(c)].entry);
  }
  return m;
}

// What a unit's memories give for the addresses it asked last cycle: the tile list's length and entry, the sphere
// or bound, the node (none in a world without a hierarchy).
struct UnitReads {
  int tile_count = 0, tile_sphere = 0;
  const artix::UnitSphere* sphere = nullptr;
  const artix::UnitNode* node = nullptr;
};
inline UnitReads unit_reads(const ModelLine& m, const artix::UnitWorld& world, int tile, int pos, int mem,
                            bool bound, int node) {
  const auto clamp = [](int i, std::size_t n) {
    return static_cast<std::size_t>(std::clamp(i, 0, std::max(0, static_cast<int>(n) - 1)));
  };
  UnitReads r;
  // A tile beyond the row's (a register's value before the unit first asks) reads as an empty list.
  const int tiles = static_cast<int>(m.tiles.start.size()) - 1;
  const std::span<const int> list = tile < tiles ? m.tiles.list(tile) : std::span<const int>();
  r.tile_count = static_cast<int>(list.size());
  r.tile_sphere = pos < r.tile_count ? list[static_cast<std::size_t>(pos)] : 0;
  r.sphere = bound && !world.nodes.empty() ? &world.nodes[clamp(mem, world.nodes.size())].bound
                                           : &world.spheres[clamp(mem, world.spheres.size())];
  if (!world.nodes.empty()) r.node = &world.nodes[clamp(node, world.nodes.size())];
  return r;
}

}  // namespace tripsitter::rtl::path

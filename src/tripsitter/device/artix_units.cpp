#include <tripsitter/device/artix_units.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <new>
#include <optional>

#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/worker.h>

namespace tripsitter::device::artix {

core::ScreenBounds cull_bounds(const UnitSphere& s) {
  const std::int64_t grown = s.r + (s.r >> 10) + 4;
  if (s.c[2] + grown <= 0) return {};  // wholly behind the camera plane
  const core::Vec3<std::int64_t> c{s.c[0], s.c[1], s.c[2]};
  // |c_k| < 2^21 and grown < 2^21.1: the plane tests' sums stay below 2^32 and their products below 2^110.
  core::ScreenBounds b =
      core::screen_bounds<core::Int128>(c, grown * grown, core::kScreenWidth, core::kScreenHeight, core::kScreenWidth);
  if (b.col_lo > b.col_hi || b.row_lo > b.row_hi) return {};
  b.col_lo = std::max(0, b.col_lo - 1);
  b.col_hi = std::min(core::kScreenWidth - 1, b.col_hi + 1);
  b.row_lo = std::max(0, b.row_lo - 1);
  b.row_hi = std::min(core::kScreenHeight - 1, b.row_hi + 1);
  return b;
}

UnitWorld prepare_world(const SceneMemory& scene) {
  UnitWorld w;
  w.spheres.reserve(scene.geometry.size());
  w.bounds.reserve(scene.geometry.size());
  for (std::size_t i = 0; i < scene.geometry.size(); ++i) {
    w.spheres.push_back(prepare_sphere(scene.geometry[i], kernel_surface(scene, static_cast<int>(i))));
    w.bounds.push_back(cull_bounds(w.spheres.back()));
  }
  w.nodes.reserve(scene.hierarchy.size());
  for (std::size_t i = 0; i < scene.hierarchy.size(); ++i) {
    const HierarchyNode& v = scene.hierarchy[i];
    // The root carries no bound and is never tested.
    w.nodes.push_back({i == 0 ? UnitSphere{} : prepare_sphere(v.bound, core::KernelSurface{}), v.first_child,
                       v.children, v.first_sphere, v.spheres});
  }
  return w;
}

void add_fast_search(UnitWorld& world) {
  if (world.nodes.empty()) {
    world.balls = build_balls(world.spheres);
    return;
  }
  world.sphere_block = SphereBlock(world.spheres);
  world.bound_block = SphereBlock();
  for (const UnitNode& v : world.nodes) world.bound_block.push_back(v.bound);
}

namespace {

// The fast model's search for a row's camera rays: its tiles' lists (the schedule's), their spheres as one block
// for the filter. (Lists for narrower tiles, 8 columns, were tried: rendering 20 frames of random-64 on one core
// took 2.05 s with them, 1.40 s without.)
struct RowSearch {
  const RowTiles& tiles;
  int columns;
  SphereBlock block;  // tile t's spheres from tiles.start[t]

  RowSearch(const UnitWorld& world, const RowTiles& row_tiles, int tile_columns)
      : tiles(row_tiles), columns(tile_columns) {
    std::vector<UnitSphere> listed;
    listed.reserve(tiles.spheres.size());
    for (const int i : tiles.spheres) listed.push_back(world.spheres[static_cast<std::size_t>(i)]);
    block = SphereBlock(listed);
  }
  Hit closest(const UnitRay& ray, std::span<const UnitSphere> spheres, int col, int excluded) const {
    const int tile = col / columns;
    return closest_hit(ray, spheres, tiles.list(tile), block, tiles.start[static_cast<std::size_t>(tile)], excluded);
  }
};

// Keeps the sphere `i` hit at `q` if it is closer than `best`, or as close and sent first.
void keep_closest(Hit& best, int i, const Quadratic& q) {
  if (q.hit() && (best.index < 0 || q.td < best.td || (q.td == best.td && i < best.index))) best = {i, q.td};
}

// Calls f(j) for each j < n whose block entry first + j the ray's line meets, as the filter says.
template <class F>
void for_each_meeting(const UnitRay& ray, const SphereBlock& block, int first, int n, const F& f) {
  if (n == 0) return;
  thread_local std::vector<std::uint8_t> meets;
  if (meets.size() < meets_room(static_cast<std::size_t>(n))) meets.resize(meets_room(static_cast<std::size_t>(n)));
  meets_line(ray, block, static_cast<std::size_t>(first), static_cast<std::size_t>(n), meets.data());
  for (int j = 0; j < n; ++j)
    if (meets[static_cast<std::size_t>(j)] != 0) f(j);
}

}  // namespace

Hit walk_closest_hit(const UnitRay& ray, const UnitWorld& world, int excluded, std::vector<int>& passes) {
  assert(!world.nodes.empty());
  const bool filter = world.bound_block.size() == world.nodes.size();
  thread_local std::vector<int> level;
  thread_local std::vector<int> next;
  level.assign(1, 0);
  Hit best;
  const auto test_sphere = [&](int i) {
    if (i != excluded) keep_closest(best, i, quadratic(ray, world.spheres[static_cast<std::size_t>(i)]));
  };
  const auto test_bound = [&](int c) {
    if (enters(ray, world.nodes[static_cast<std::size_t>(c)].bound)) next.push_back(c);
  };
  do {
    next.clear();
    int tests = 0;
    for (const int v : level) {
      const UnitNode& node = world.nodes[static_cast<std::size_t>(v)];
      tests += node.spheres + node.children;
      if (filter) {
        for_each_meeting(ray, world.sphere_block, node.first_sphere, node.spheres,
                         [&](int j) { test_sphere(node.first_sphere + j); });
        for_each_meeting(ray, world.bound_block, node.first_child, node.children,
                         [&](int j) { test_bound(node.first_child + j); });
      } else {
        for (int i = node.first_sphere; i < node.first_sphere + node.spheres; ++i) test_sphere(i);
        for (int c = node.first_child; c < node.first_child + node.children; ++c) test_bound(c);
      }
    }
    passes.push_back(tests);
    std::swap(level, next);
  } while (!level.empty());
  return best;
}

Hit closest_hit(const UnitRay& ray, std::span<const UnitSphere> spheres, std::span<const int> list,
                const SphereBlock& block, int first, int excluded) {
  Hit best;
  for_each_meeting(ray, block, first, static_cast<int>(list.size()), [&](int j) {
    const int i = list[static_cast<std::size_t>(j)];
    if (i != excluded) keep_closest(best, i, quadratic(ray, spheres[static_cast<std::size_t>(i)]));
  });
  return best;
}

BallTree build_balls(std::span<const UnitSphere> spheres) {
  return build_ball_tree(
      spheres.size(), [&](int i) { return spheres[static_cast<std::size_t>(i)].c; },
      [&](int i) {
        const UnitSphere& s = spheres[static_cast<std::size_t>(i)];
        return s.r + (std::int64_t{2} << std::max(s.e, 0)) + 1;
      });
}

Hit closest_hit(const UnitRay& ray, std::span<const UnitSphere> spheres, const BallTree& balls, int excluded) {
  Hit best;
  const std::int64_t a = ray.d[0] * ray.d[0] + ray.d[1] * ray.d[1] + ray.d[2] * ray.d[2];
  for_each_ball_member(balls, ray.o, ray.d, a, [&](int i) {
    if (i == excluded) return;
    const Quadratic q = quadratic(ray, spheres[static_cast<std::size_t>(i)]);
    if (!q.hit()) return;
    // The least t, and on a tie the sphere sent first, whatever order the balls are visited in.
    if (best.index < 0 || q.td < best.td || (q.td == best.td && i < best.index)) best = {i, q.td};
  });
  return best;
}

RowTiles row_tiles(const UnitWorld& world, int row, int tile_columns) {
  const int tiles = core::kScreenWidth / tile_columns;
  RowTiles t;
  t.start.assign(static_cast<std::size_t>(tiles) + 1, 0);
  const auto meets = [&](const core::ScreenBounds& b) { return b.col_lo <= b.col_hi && b.row_lo <= row && row <= b.row_hi; };
  for (const auto& b : world.bounds)
    if (meets(b))
      for (int k = b.col_lo / tile_columns; k <= b.col_hi / tile_columns; ++k) ++t.start[static_cast<std::size_t>(k) + 1];
  for (int k = 0; k < tiles; ++k) t.start[static_cast<std::size_t>(k) + 1] += t.start[static_cast<std::size_t>(k)];
  t.spheres.resize(static_cast<std::size_t>(t.start.back()));
  std::vector<int> fill(t.start.begin(), t.start.end() - 1);
  for (std::size_t i = 0; i < world.bounds.size(); ++i) {
    const auto& b = world.bounds[i];
    if (!meets(b)) continue;
    for (int k = b.col_lo / tile_columns; k <= b.col_hi / tile_columns; ++k)
      t.spheres[static_cast<std::size_t>(fill[static_cast<std::size_t>(k)]++)] = static_cast<int>(i);
  }
  return t;
}

void serve_pixel_port(std::span<PortEnd> lit, std::span<PortEnd> cut) {
  assert(std::is_sorted(lit.begin(), lit.end(), [](const PortEnd& a, const PortEnd& b) { return a.cycle < b.cycle; }));
  std::size_t next_lit = 0;
  std::int64_t free_from = 0;  // the cycle after the last cut's
  for (PortEnd& e : cut) {
    std::int64_t at = std::max(e.cycle, free_from);
    // The lights in order: skip those before `at`, and move past each that takes it.
    for (; next_lit < lit.size() && lit[next_lit].cycle <= at; ++next_lit)
      if (lit[next_lit].cycle == at) ++at;
    e.cycle = at;
    free_from = at + 1;
  }
}

std::vector<std::int64_t> unit_finish_cycles(const DevicePreset& preset, const LineChains& work) {
  assert(preset.units && work.start.size() == kLineWidth + 1);
  const DeviceUnits& u = *preset.units;
  std::vector<std::int64_t> finish(kLineWidth, 0);
  const auto last_end = [&](int col, std::int64_t cycle) {  // the column's colour (or entry) after an end at `cycle`
    std::int64_t& f = finish[static_cast<std::size_t>(col)];
    f = std::max(f, cycle + u.shade_latency);
  };
  struct Waiting {
    std::int64_t known;  // the cycle the pass is in the queue
    std::int64_t order;  // the order queued, for ties
    int col;
    int chain;
    int pass;            // index into work.passes
    bool before(const Waiting& o) const { return known != o.known ? known < o.known : order < o.order; }
  };
  // The queue as two FIFOs, passes after the bounce stage and a walk's next levels: passes end in the order they
  // issue and enter the stage in that order, so each FIFO is in the order known, and the pass known first is at
  // the front of one of them.
  struct Fifo {
    std::vector<Waiting> passes;  // passes[head ..] wait; the ones before have issued
    std::size_t head = 0;
    bool empty() const { return head == passes.size(); }
    const Waiting& front() const { return passes[head]; }
  };
  thread_local std::array<Fifo, 2> fifos;  // kept from line to line for their buffers
  thread_local std::array<std::vector<std::int64_t>, 2> frees;
  thread_local std::vector<PortEnd> lit, cut;  // a unit's samples' ends at its pixel port (pixel_port)
  const std::int64_t period = u.shared_bounce ? preset.workers : 1;  // a unit's cycles at the bounce stage
  for (int unit = 0; unit < preset.workers; ++unit) {
    lit.clear();
    cut.clear();
    for (Fifo& f : fifos) {
      f.passes.clear();
      f.head = 0;
    }
    std::int64_t queued = 0;
    const auto first = [&]() -> Fifo* {
      Fifo* best = nullptr;
      for (Fifo& f : fifos)
        if (!f.empty() && (best == nullptr || f.front().before(best->front()))) best = &f;
      return best;
    };
    // The unit's first cycle at the bounce stage from `known` on that no earlier hit took.
    std::int64_t stage_free = 0;
    const auto enter_stage = [&](std::int64_t known) {
      std::int64_t c = std::max(known, stage_free);
      c += ((unit - c) % period + period) % period;
      stage_free = c + 1;
      return c;
    };
    // The paths the unit holds (DeviceUnits::paths): those taken, less those over by `cycle`; the cycles from which
    // each path over is no longer held, in two runs each in order (paths ended by the bounce stage, and cut ones).
    std::int64_t taken = 0;
    std::array<std::vector<std::int64_t>, 2>& free_from = frees;
    std::array<std::size_t, 2> freed{};
    for (auto& f : free_from) f.clear();
    const auto held = [&](std::int64_t at) {
      for (std::size_t k = 0; k < 2; ++k)
        while (freed[k] < free_from[k].size() && free_from[k][freed[k]] <= at) ++freed[k];
      return taken - static_cast<std::int64_t>(freed[0] + freed[1]);
    };
    const auto next_free = [&]() {  // the first cycle from which a path held now is not, -1 if none is known
      std::int64_t t = -1;
      for (std::size_t k = 0; k < 2; ++k)
        if (freed[k] < free_from[k].size() && (t < 0 || free_from[k][freed[k]] < t)) t = free_from[k][freed[k]];
      return t;
    };
    std::int64_t cycle = 0;  // the issue port is free from this cycle
    int next_col = unit;
    int next_chain = work.start[static_cast<std::size_t>(unit)];
    while (true) {
      // A column with no chains (a converged path pixel) takes no issue slot: its colour is shown from frame memory.
      while (next_col < kLineWidth && work.start[static_cast<std::size_t>(next_col) + 1] == next_chain) {
        finish[static_cast<std::size_t>(next_col)] = u.pixel_port ? 0 : cycle + u.shade_latency;
        next_col += preset.workers;
        if (next_col < kLineWidth) next_chain = work.start[static_cast<std::size_t>(next_col)];
      }
      Waiting job{};
      Fifo* const queue = first();
      const bool camera = next_col < kLineWidth && (u.paths == 0 || held(cycle) < u.paths);
      if (queue != nullptr && queue->front().known <= cycle) {
        job = queue->front();
        ++queue->head;
      } else if (camera) {
        job = {cycle, 0, next_col, next_chain, work.chain_start[static_cast<std::size_t>(next_chain)]};
        ++taken;
        if (++next_chain == work.start[static_cast<std::size_t>(next_col) + 1]) {
          next_col += preset.workers;
          if (next_col < kLineWidth) next_chain = work.start[static_cast<std::size_t>(next_col)];
        }
      } else if (queue != nullptr || next_col < kLineWidth) {
        // Wait for the queue's first pass, or for a path to be over (a camera ray waits for one).
        std::int64_t t = queue != nullptr ? queue->front().known : -1;
        if (next_col < kLineWidth) {
          const std::int64_t f = next_free();  // -1 when no path's end is known yet (its passes are queued)
          if (f >= 0 && (t < 0 || f < t)) t = f;
        }
        assert(t > cycle);
        cycle = t;
        continue;
      } else {
        break;
      }
      const LineChains::Pass& pass = work.passes[static_cast<std::size_t>(job.pass)];
      cycle += pass.lead + std::max<std::int64_t>(u.min_pass, pass.tests);
      std::int64_t known = cycle + u.hit_latency;
      if (pass.bounce) known = enter_stage(known) + u.reflect_latency;
      if (job.pass + 1 < work.chain_start[static_cast<std::size_t>(job.chain) + 1]) {
        fifos[pass.bounce ? 0 : 1].passes.push_back(
            {pass.bounce ? known : known + u.walk_wait, queued++, job.col, job.chain, job.pass + 1});
      } else {
        // The path is over: its light is out of the bounce stage at `known`, or its cut hit known then.
        if (u.pixel_port)
          (pass.bounce ? lit : cut).push_back({known, job.col});
        else
          last_end(job.col, known);
        free_from[pass.bounce ? 0 : 1].push_back(pass.bounce ? known : known + 1);
      }
    }
    if (u.pixel_port) {
      serve_pixel_port(lit, cut);
      for (const auto* ends : {&lit, &cut})
        for (const PortEnd& e : *ends) last_end(e.col, e.cycle);
    }
  }
  return finish;
}

std::vector<std::int64_t> unit_finish_cycles(const DevicePreset& preset, std::int64_t spheres,
                                             std::span<const core::PixelTrace> pixels,
                                             std::span<const int> camera_tests) {
  assert(pixels.size() == kLineWidth && camera_tests.size() == kLineWidth);
  LineChains work;
  work.start.resize(kLineWidth + 1);
  work.chain_start.reserve(kLineWidth + 1);
  for (std::size_t c = 0; c < kLineWidth; ++c) {
    work.start[c] = static_cast<int>(c);
    work.chain_start.push_back(static_cast<int>(work.passes.size()));
    work.passes.push_back({camera_tests[c], 0, pixels[c].bounces > 0});
    for (int k = 0; k < pixels[c].bounces; ++k)
      work.passes.push_back({static_cast<int>(spheres), 0, k + 1 < pixels[c].bounces});
  }
  work.start[kLineWidth] = kLineWidth;
  work.chain_start.push_back(static_cast<int>(work.passes.size()));
  return unit_finish_cycles(preset, work);
}

namespace {

// The schedule applied to a line: a column whose colour is not in the line buffer by the lead time is black and
// late; every other shows on_time(c, result), which also counts what the column did. The demand is the latest
// finish, on time or not.
template <class OnTime>
LineResult apply_schedule(const DevicePreset& preset, std::span<const std::int64_t> finish,
                          std::span<core::Rgb444> line, const OnTime& on_time) {
  LineResult result;
  for (std::size_t c = 0; c < kLineWidth; ++c) {
    result.demand_cycles = std::max(result.demand_cycles, finish[c]);
    if (finish[c] > preset.lead_cycles) {
      line[c] = core::kBlack;
      ++result.late_pixels;
      continue;
    }
    line[c] = on_time(c, result);
  }
  return result;
}

}  // namespace

LineResult schedule_units(const DevicePreset& preset, std::int64_t spheres, std::span<const core::PixelTrace> pixels,
                          std::span<const int> camera_tests, std::span<core::Rgb444> line) {
  const std::vector<std::int64_t> finish = unit_finish_cycles(preset, spheres, pixels, camera_tests);
  return apply_schedule(preset, finish, line, [&](std::size_t c, LineResult& result) {
    result.reflections += pixels[c].bounces;
    return pixels[c].colour;
  });
}

LineResult render_line(const DevicePreset& preset, const UnitWorld& world, int row, std::span<core::Rgb444> line,
                       Search search) {
  const int tile_columns = preset.units->tile_columns;
  const RowTiles tiles = row_tiles(world, row, tile_columns);
  std::array<int, kLineWidth> tests{};
  std::array<core::PixelTrace, kLineWidth> pixels{};
  const std::span<const UnitSphere> spheres(world.spheres);
  const std::optional<RowSearch> fine =
      search == Search::kTiles ? std::optional<RowSearch>(std::in_place, world, tiles, tile_columns) : std::nullopt;
  for (int col = 0; col < kLineWidth; ++col) {
    tests[static_cast<std::size_t>(col)] = static_cast<int>(tiles.list(col / tile_columns).size());
    pixels[static_cast<std::size_t>(col)] =
        trace_pixel_with(col, row, spheres, preset.max_bounces, [&](const UnitRay& ray, int excluded, int pass) {
          return pass == 0 && fine ? fine->closest(ray, spheres, col, excluded) : closest_hit(ray, spheres, excluded);
        });
  }
  return schedule_units(preset, static_cast<std::int64_t>(spheres.size()), pixels, tests, line);
}

void path_line_chains(const DevicePreset& preset, const UnitWorld& world, int row, const PathFrame& frame,
                      std::span<const AccumEntry> memory, std::span<PathPixel> pixels, PathCounters& counters,
                      Search search, LineChains& work, const RayObserver* observe) {
  assert(memory.size() == kLineWidth && pixels.size() == kLineWidth);
  const int tile_columns = preset.units->tile_columns;
  const RowTiles tiles = row_tiles(world, row, tile_columns);
  const std::span<const UnitSphere> spheres(world.spheres);
  const std::optional<RowSearch> fine =
      search == Search::kTiles ? std::optional<RowSearch>(std::in_place, world, tiles, tile_columns) : std::nullopt;
  const bool walk = !world.nodes.empty();
  const auto all_spheres = static_cast<int>(spheres.size());
  const int walk_lead = preset.units->walk_lead;
  work.start.clear();
  work.chain_start.clear();
  work.passes.clear();
  assert(walk || search == Search::kAll || world.balls.order.size() == world.spheres.size());
  thread_local std::vector<int> levels;
  for (int col = 0; col < kLineWidth; ++col) {
    const std::span<const int> list = tiles.list(col / tile_columns);
    work.start.push_back(static_cast<int>(work.chain_start.size()));
    const auto search_hit = [&](const PathUnitRay& path) {
      // A ray's last pass enters the bounce stage (its bounce, or its escape to the sky) unless the path is cut
      // there: the sample's trace says so after it (below).
      if (path.from < 0) {  // the camera's ray: its tile's list is what the units test
        work.passes.push_back({static_cast<int>(list.size()), 0, true});
        const Hit near = fine ? fine->closest(path.ray, spheres, col, path.from)
                              : closest_hit(path.ray, spheres, path.from);
        return with_far_side(path, near, spheres);
      }
      if (!walk) {
        work.passes.push_back({all_spheres, 0, true});
        const Hit near = search == Search::kAll ? closest_hit(path.ray, spheres, path.from)
                                                : closest_hit(path.ray, spheres, world.balls, path.from);
        return with_far_side(path, near, spheres);
      }
      // A walk: its first pass tests the root's spheres and children, with a slot more for the far side of the
      // sphere the ray went into (the walk may not reach that sphere's node: with_far_side tests it anyway); each
      // later level first reads its first node's record (walk_lead).
      levels.clear();
      const Hit near = walk_closest_hit(path.ray, world, path.from, levels);
      work.passes.push_back({levels[0] + (path.into ? 1 : 0), 0, false});
      for (std::size_t k = 1; k < levels.size(); ++k) work.passes.push_back({levels[k], walk_lead, false});
      work.passes.back().bounce = true;
      return with_far_side(path, near, spheres);
    };
    const auto closest = [&](const PathUnitRay& path) {
      const PathUnitHit hit = search_hit(path);
      if (observe != nullptr) (*observe)(col, path, hit);
      return hit;
    };
    // Made in its place in the line's array (a new-expression from the returned value elides the copy, which would
    // load the pixel just stored field by field and wait for those stores).
    ::new (static_cast<void*>(&pixels[static_cast<std::size_t>(col)]))
        PathPixel(path_pixel(path_arith(), col, row, memory[static_cast<std::size_t>(col)], frame, [&](PathRng& rng) {
          work.chain_start.push_back(static_cast<int>(work.passes.size()));
          const auto cut = counters.cut;
          const PathSample sample =
              trace_path_sample(col, row, spheres, frame.surfaces, frame.depth, rng, counters, closest);
          if (counters.cut != cut) work.passes.back().bounce = false;  // the cut's hit ends the path
          return sample;
        }));
  }
  work.start.push_back(static_cast<int>(work.chain_start.size()));
  work.chain_start.push_back(static_cast<int>(work.passes.size()));
}

LineResult render_path_line(const DevicePreset& preset, const UnitWorld& world, int row, const PathFrame& frame,
                            std::span<AccumEntry> memory, std::span<core::Rgb444> line, PathCounters& counters,
                            Search search) {
  std::array<PathPixel, kLineWidth> pixels{};
  thread_local LineChains work;  // its buffers kept from line to line
  path_line_chains(preset, world, row, frame, memory, pixels, counters, search, work, nullptr);
  const std::vector<std::int64_t> finish = unit_finish_cycles(preset, work);
  return apply_schedule(preset, finish, line, [&](std::size_t c, LineResult& result) {
    memory[c] = pixels[c].entry;
    result.rays += pixels[c].rays;
    return pixels[c].colour;
  });
}

}  // namespace tripsitter::device::artix

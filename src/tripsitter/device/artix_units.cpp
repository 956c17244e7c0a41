#include <tripsitter/device/artix_units.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <deque>

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
  return w;
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

std::vector<std::int64_t> unit_finish_cycles(const DevicePreset& preset, std::int64_t spheres, const LineChains& work,
                                             std::span<const int> camera_tests) {
  assert(preset.units && work.start.size() == kLineWidth + 1 && camera_tests.size() == kLineWidth);
  const DeviceUnits& u = *preset.units;
  const std::int64_t reflected_pass = std::max<std::int64_t>(u.min_pass, spheres);
  std::vector<std::int64_t> finish(kLineWidth, 0);
  struct Waiting {
    std::int64_t known;  // the cycle the bounced ray is in the queue
    int col;
    int chain;           // index into work.passes
    int pass;
  };
  for (int unit = 0; unit < preset.workers; ++unit) {
    std::deque<Waiting> queue;  // in the order known, as passes end in the order they issued
    std::int64_t cycle = 0;     // the issue port is free from this cycle
    int next_col = unit;
    int next_chain = work.start[static_cast<std::size_t>(unit)];
    while (true) {
      // A column with no chains (a converged path pixel) takes no issue slot: its colour is shown from frame memory.
      while (next_col < kLineWidth && work.start[static_cast<std::size_t>(next_col) + 1] == next_chain) {
        finish[static_cast<std::size_t>(next_col)] = cycle + u.shade_latency;
        next_col += preset.workers;
        if (next_col < kLineWidth) next_chain = work.start[static_cast<std::size_t>(next_col)];
      }
      Waiting job{};
      if (!queue.empty() && queue.front().known <= cycle) {
        job = queue.front();
        queue.pop_front();
      } else if (next_col < kLineWidth) {
        job = {cycle, next_col, next_chain, 0};
        if (++next_chain == work.start[static_cast<std::size_t>(next_col) + 1]) {
          next_col += preset.workers;
          if (next_col < kLineWidth) next_chain = work.start[static_cast<std::size_t>(next_col)];
        }
      } else if (!queue.empty()) {
        job = queue.front();
        queue.pop_front();
        cycle = job.known;
      } else {
        break;
      }
      const auto c = static_cast<std::size_t>(job.col);
      cycle += job.pass == 0 ? std::max<std::int64_t>(u.min_pass, camera_tests[c]) : reflected_pass;
      const std::int64_t known = cycle + u.hit_latency;
      if (job.pass + 1 < work.passes[static_cast<std::size_t>(job.chain)])
        queue.push_back({known + u.reflect_latency, job.col, job.chain, job.pass + 1});
      else
        finish[c] = std::max(finish[c], known + u.shade_latency);
    }
  }
  return finish;
}

std::vector<std::int64_t> unit_finish_cycles(const DevicePreset& preset, std::int64_t spheres,
                                             std::span<const core::PixelTrace> pixels,
                                             std::span<const int> camera_tests) {
  assert(pixels.size() == kLineWidth);
  LineChains work;
  work.start.resize(kLineWidth + 1);
  work.passes.resize(kLineWidth);
  for (std::size_t c = 0; c < kLineWidth; ++c) {
    work.start[c] = static_cast<int>(c);
    work.passes[c] = 1 + pixels[c].bounces;
  }
  work.start[kLineWidth] = kLineWidth;
  return unit_finish_cycles(preset, spheres, work, camera_tests);
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
  for (int col = 0; col < kLineWidth; ++col) {
    const std::span<const int> list = tiles.list(col / tile_columns);
    tests[static_cast<std::size_t>(col)] = static_cast<int>(list.size());
    pixels[static_cast<std::size_t>(col)] =
        trace_pixel_with(col, row, spheres, preset.max_bounces, [&](const UnitRay& ray, int excluded, int pass) {
          return pass == 0 && search == Search::kTiles ? closest_hit(ray, spheres, list, excluded)
                                                       : closest_hit(ray, spheres, excluded);
        });
  }
  return schedule_units(preset, static_cast<std::int64_t>(spheres.size()), pixels, tests, line);
}

LineResult render_path_line(const DevicePreset& preset, const UnitWorld& world, int row, const PathFrame& frame,
                            std::span<AccumEntry> memory, std::span<core::Rgb444> line, PathCounters& counters,
                            Search search) {
  const int tile_columns = preset.units->tile_columns;
  const RowTiles tiles = row_tiles(world, row, tile_columns);
  const std::span<const UnitSphere> spheres(world.spheres);
  std::array<int, kLineWidth> tests{};
  std::array<PathPixel, kLineWidth> pixels{};
  LineChains work;
  work.start.reserve(kLineWidth + 1);
  work.passes.reserve(static_cast<std::size_t>(kLineWidth) * static_cast<std::size_t>(frame.spp));
  assert(search == Search::kAll || world.balls.order.size() == world.spheres.size());
  for (int col = 0; col < kLineWidth; ++col) {
    const auto c = static_cast<std::size_t>(col);
    const std::span<const int> list = tiles.list(col / tile_columns);
    tests[c] = static_cast<int>(list.size());
    work.start.push_back(static_cast<int>(work.passes.size()));
    const auto closest = [&](const PathUnitRay& path) {
      const Hit near = search == Search::kAll ? closest_hit(path.ray, spheres, path.from)
                       : path.from < 0         ? closest_hit(path.ray, spheres, list, path.from)
                                               : closest_hit(path.ray, spheres, world.balls, path.from);
      return with_far_side(path, near, spheres);
    };
    pixels[c] = path_pixel(path_arith(), col, row, memory[c], frame, [&](PathRng& rng) {
      const PathSample s = trace_path_sample(col, row, spheres, frame.surfaces, frame.depth, rng, counters, closest);
      work.passes.push_back(s.rays);
      return s;
    });
  }
  work.start.push_back(static_cast<int>(work.passes.size()));
  const std::vector<std::int64_t> finish =
      unit_finish_cycles(preset, static_cast<std::int64_t>(spheres.size()), work, tests);
  return apply_schedule(preset, finish, line, [&](std::size_t c, LineResult& result) {
    memory[c] = pixels[c].entry;
    result.rays += pixels[c].rays;
    return pixels[c].colour;
  });
}

}  // namespace tripsitter::device::artix

// The bounce stage the artix path preset's units share, as RTL (ts_path_bounce.sv), held to its C++ twin
// (artix::bounce_stage) in a loop with the model's closest-hit search: each path's camera ray goes in with its hit,
// the stage's next ray comes back, the test bench finds that ray's closest hit over every sphere and sends it in
// again (a cut at the path's last ray stays with the bench, as it stays in the unit), until the stage says the path
// is over. Every output the twin's, bit for bit and Latency cycles after its input: the next ray (hit point,
// direction, the sphere it leaves, whether it went in, the rays), or the sky's light, or nothing for a path
// absorbed; and the stage's own state between a path's rays, its random stream and its throughput, is what the
// twin's copy holds, so that every path's light is the one artix::trace_path_sample gives its sample. Paths of nine
// units, up to 32 each, interleaved in a random order with gaps, with the surfaces from a memory read two cycles late;
// then the line window's flush, after which nothing of the rays in the stage comes out.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sphere_unit_draw.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_path_bounce.h>

#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/test_util.h>

#include "path_line_model.h"

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;
using sphere_unit::kDirW;
using sphere_unit::kOriginW;
using sphere_unit::pack3;

constexpr int kLatency = 49;    // ts_path_bounce's Latency
constexpr int kSurfaceRead = 2;  // its surface port's
constexpr int kUnits = 9, kPaths = 32;
constexpr int kHitFW = 39;     // ts_artix_pkg::HitFW: a hit's f_k fits it
// Junk for a port has the port's width: Verilator keeps the bits above it of a port's word zero, and a wider value
// there would spill into the fields a concatenation puts above the port's.
constexpr std::uint64_t kTdMask = (std::uint64_t{1} << sphere_unit::kTdW) - 1;

artix::Vec3i unpack3(UInt128 v, int bits) {
  artix::Vec3i out{};
  for (std::size_t k = 0; k < 3; ++k)
    out[k] = static_cast<std::int64_t>(sign_extend(v >> (bits * static_cast<int>(k)), bits));
  return out;
}

// One path: a sample of a pixel, its ray at the stage, and the twin's state.
struct Path {
  int unit = 0, id = 0, col = 0, sample = 0, rays = 1;
  artix::PathUnitRay ray;
  artix::PathUnitHit hit;
  std::array<std::int64_t, 3> throughput{65536, 65536, 65536};
  device::PathRng rng{1};
  device::PathSample want;  // trace_path_sample's
  std::array<std::int64_t, 3> light{};
};

struct Sent {
  std::int64_t cycle;
  int path;
  artix::PathStep step;
  artix::PathUnitRay next;               // the twin's next ray (kRay)
  std::array<std::int64_t, 3> light{};  // the twin's light (kLight)
};

struct Stats {
  int entries = 0, rays = 0, sky = 0, absorbed = 0, cuts = 0, far = 0, samples = 0;
  device::PathCounters counters;
};

// The paths of `rows` (every column, `spp` samples) of one world through the stage.
void run_world(const device::SceneMemory& scene, int spp, int depth, std::uint32_t frame_no,
               const std::vector<int>& rows, std::mt19937_64& rng, Stats& stats) {
  const path::PathScene held = path::path_scene(scene, spp, depth, frame_no);
  const artix::UnitWorld& world = held.world;
  const std::vector<device::PathSurface>& surfaces = held.surfaces;
  const auto closest = [&](const artix::PathUnitRay& r) {
    return artix::with_far_side(r, artix::closest_hit(r.ray, world.spheres, r.from), world.spheres);
  };

  VerilatedContext context;
  context.randReset(2);
  auto t = std::make_unique<Vts_path_bounce>(&context);
  t->rst = 1;
  t->flush = 0;
  t->in_valid = 0;
  for (int i = 0; i < 3; ++i) rising_edge(*t);
  t->rst = 0;
  t->sample_base = frame_no * static_cast<std::uint32_t>(spp);

  for (const int row : rows) {
    t->row = static_cast<SData>(row);
    std::vector<Path> paths;
    std::array<std::deque<int>, kUnits> waiting;  // each unit's samples not started, in order
    for (int col = 0; col < device::kLineWidth; ++col) {
      for (int s = 0; s < spp; ++s) {
        Path p;
        p.unit = col % kUnits;
        p.col = col;
        p.sample = s;
        const auto pixel = static_cast<std::uint32_t>(row * device::kLineWidth + col);
        const std::uint32_t index = frame_no * static_cast<std::uint32_t>(spp) + static_cast<std::uint32_t>(s);
        p.rng = device::PathRng::for_sample(pixel, index);
        device::PathRng twin = device::PathRng::for_sample(pixel, index);
        p.want = artix::trace_path_sample(col, row, world.spheres, surfaces, depth, twin, stats.counters);
        p.ray = {{{}, artix::camera_direction(col, row)}, -1, false};
        p.hit = closest(p.ray);
        waiting[static_cast<std::size_t>(p.unit)].push_back(static_cast<int>(paths.size()));
        paths.push_back(p);
      }
    }
    std::array<std::vector<int>, kUnits> free_ids;
    for (auto& f : free_ids)
      for (int i = kPaths - 1; i >= 0; --i) f.push_back(i);
    std::multimap<std::int64_t, int> ready;  // paths whose ray waits to go in, by the first cycle it may
    std::deque<Sent> in_flight;
    std::deque<std::pair<std::int64_t, int>> surface_asked;  // (cycle, sphere)
    int over = 0;
    const auto end_path = [&](int i) {
      Path& p = paths[static_cast<std::size_t>(i)];
      EXPECT_EQ(p.light, p.want.light) << "row " << row << " column " << p.col << " sample " << p.sample;
      EXPECT_EQ(p.rays, p.want.rays) << "row " << row << " column " << p.col << " sample " << p.sample;
      free_ids[static_cast<std::size_t>(p.unit)].push_back(p.id);
      ++over;
      ++stats.samples;
    };
    // A path's ray at its hit: to the stage, or a cut at the path's last ray.
    const auto arrive = [&](int i, std::int64_t at) {
      Path& p = paths[static_cast<std::size_t>(i)];
      if (p.hit.index >= 0 && p.rays == depth) {
        ++stats.cuts;
        end_path(i);
      } else {
        ready.insert({at, i});
      }
    };
    const auto start_paths = [&](std::int64_t now) {
      for (int u = 0; u < kUnits; ++u) {
        auto& w = waiting[static_cast<std::size_t>(u)];
        auto& f = free_ids[static_cast<std::size_t>(u)];
        while (!w.empty() && !f.empty()) {
          paths[static_cast<std::size_t>(w.front())].id = f.back();
          f.pop_back();
          arrive(w.front(), now + static_cast<std::int64_t>(rng() % 4));
          w.pop_front();
        }
      }
    };
    start_paths(0);
    const std::int64_t limit = 200 * static_cast<std::int64_t>(paths.size()) + 1000;
    for (std::int64_t cyc = 0; over < static_cast<int>(paths.size()) && cyc < limit; ++cyc) {
      // The surface memory: the sphere asked for kSurfaceRead cycles ago.
      if (!surface_asked.empty() && surface_asked.front().first == cyc - kSurfaceRead) {
        path::put_surface(*t, world, surfaces, surface_asked.front().second);
        surface_asked.pop_front();
      }
      // A ray in: one of those ready, at random, in three cycles of four.
      t->in_valid = 0;
      std::vector<std::multimap<std::int64_t, int>::iterator> can;
      for (auto it = ready.begin(); it != ready.end() && it->first <= cyc && can.size() < 16; ++it) can.push_back(it);
      if (!can.empty() && rng() % 4 != 0) {
        const auto it = can[rng() % can.size()];
        const int i = it->second;
        ready.erase(it);
        Path& p = paths[static_cast<std::size_t>(i)];
        t->in_valid = 1;
        t->in_unit = static_cast<CData>(p.unit);
        t->in_path = static_cast<CData>(p.id);
        t->in_col = static_cast<SData>(p.col);
        t->in_sample = static_cast<CData>(p.sample);
        t->in_rays = static_cast<CData>(p.rays);
        put(t->in_o, pack3(p.ray.ray.o, kOriginW));
        put(t->in_d, pack3(p.ray.ray.d, kDirW));
        t->in_hit = p.hit.index >= 0;
        t->in_index = static_cast<CData>(std::max(p.hit.index, 0));
        t->in_far = p.hit.inside;
        if (p.hit.index >= 0) {
          const artix::UnitSphere& s = world.spheres[static_cast<std::size_t>(p.hit.index)];
          const artix::Quadratic q = artix::quadratic(p.ray.ray, s);
          put(t->in_td, static_cast<UInt128>(p.hit.td));
          put(t->in_beta, static_cast<UInt128>(q.bd) & 0x1FFFF);  // b d's fraction
          for (int k = 0; k < 3; ++k) set_bits(t->in_f, k * kHitFW, kHitFW, q.f[static_cast<std::size_t>(k)]);
          put(t->in_s, static_cast<UInt128>(q.s));
          put(t->in_e, static_cast<UInt128>(s.e) & 0x3f);
          stats.far += p.hit.inside;
        } else {
          put(t->in_td, static_cast<UInt128>(rng() & kTdMask));  // a miss's hit fields are junk
        }
        const auto draw = [&] { return p.rng.next(); };
        device::PathBounces bounces;
        device::PathCounters counters;
        artix::PathUnitRay next = p.ray;  // the twin writes the next ray over it
        std::array<std::int64_t, 3> light{};
        const artix::PathStep step =
            artix::bounce_stage(next, p.hit, world.spheres, surfaces, p.throughput, light, draw, counters, bounces);
        in_flight.push_back({cyc + kLatency, i, step, next, light});
        ++stats.entries;
      } else {
        put(t->in_td, static_cast<UInt128>(rng() & kTdMask));
        t->in_index = static_cast<CData>(rng());
      }
      t->clk = 0;
      t->eval();
      if (t->in_valid) surface_asked.push_back({cyc, static_cast<int>(t->surf_addr)});
      rising_edge(*t);
      const std::int64_t now = cyc + 1;  // the outputs after the edge are the cycle after's
      if (t->ray_valid == 0 && t->end_valid == 0) {
        ASSERT_TRUE(in_flight.empty() || in_flight.front().cycle > now) << "no output at cycle " << now;
        continue;
      }
      ASSERT_TRUE(t->ray_valid == 0 || t->end_valid == 0) << "a ray and an end at once, cycle " << now;
      ASSERT_FALSE(in_flight.empty()) << "an output with nothing in flight, cycle " << now;
      const Sent s = in_flight.front();
      in_flight.pop_front();
      ASSERT_EQ(s.cycle, now) << "an output at the wrong cycle";
      Path& p = paths[static_cast<std::size_t>(s.path)];
      const std::string where = "row " + std::to_string(row) + " column " + std::to_string(p.col) + " sample " +
                                std::to_string(p.sample) + " ray " + std::to_string(p.rays);
      EXPECT_EQ(static_cast<int>(t->out_unit), p.unit) << where;
      EXPECT_EQ(static_cast<int>(t->out_path), p.id) << where;
      EXPECT_EQ(static_cast<int>(t->out_col), p.col) << where;
      EXPECT_EQ(static_cast<int>(t->out_sample), p.sample) << where;
      const bool ray = s.step == artix::PathStep::kRay;
      ASSERT_EQ(t->ray_valid != 0, ray) << where;
      if (ray) {
        EXPECT_EQ(static_cast<int>(t->out_rays), p.rays + 1) << where;
        EXPECT_EQ(unpack3(get(t->out_o), kOriginW), s.next.ray.o) << where;
        EXPECT_EQ(unpack3(get(t->out_d), kDirW), s.next.ray.d) << where;
        EXPECT_EQ(static_cast<int>(t->out_from), s.next.from) << where;
        EXPECT_EQ(t->out_into != 0, s.next.into) << where;
        ++stats.rays;
        p.ray = s.next;
        p.rays += 1;
        p.hit = closest(p.ray);
        arrive(s.path, now + 1 + static_cast<std::int64_t>(rng() % 8));
      } else {
        const std::uint64_t light = t->out_light;
        for (std::size_t k = 0; k < 3; ++k) p.light[k] = static_cast<std::int64_t>((light >> (18 * k)) & 0x3FFFF);
        EXPECT_EQ(p.light, s.light) << where;
        if (s.step == artix::PathStep::kLight) ++stats.sky;
        else ++stats.absorbed;
        end_path(s.path);
      }
      start_paths(now);
    }
    ASSERT_EQ(over, static_cast<int>(paths.size())) << "row " << row << ": paths never over";
  }
  // The window's flush: of rays going in every cycle up to it, those out by its cycle come out, the others never.
  constexpr int kFlushAt = 60;
  int out = 0;
  for (int cyc = 0; cyc < kFlushAt + 2 * kLatency; ++cyc) {
    t->in_valid = cyc <= kFlushAt;
    t->in_hit = (cyc & 1) != 0;
    t->flush = cyc == kFlushAt;
    rising_edge(*t);
    out += t->ray_valid + t->end_valid;
  }
  t->flush = 0;
  EXPECT_EQ(out, kFlushAt + 1 - kLatency) << "rays out around the flush";
}

TEST(PathBounceRtl, PathsThroughTheStageEqualTheModelsBounceByBounce) {
  std::mt19937_64 rng(20261207);
  const device::DevicePreset p = device::artix_path_preset();
  Stats stats;
  for (int w = 0; w < 4; ++w) {
    const device::SceneMemory scene = device::testing::random_path_world(p, rng, 16);
    run_world(scene, 1 + w % 2, w == 3 ? 1 : 4 + w, static_cast<std::uint32_t>(w * 7), {120 + 90 * w, 300}, rng,
              stats);
  }
  std::printf("%d samples: %d entries, %d next rays (%d from far sides), %d to the sky, %d absorbed, %d cuts; "
              "bounces %llu lambertian, %llu metal, %llu dielectric (%llu refracted)\n",
              stats.samples, stats.entries, stats.rays, stats.far, stats.sky, stats.absorbed, stats.cuts,
              static_cast<unsigned long long>(stats.counters.lambertian),
              static_cast<unsigned long long>(stats.counters.metal),
              static_cast<unsigned long long>(stats.counters.dielectric),
              static_cast<unsigned long long>(stats.counters.refracted));
  EXPECT_GT(stats.rays, 5000);
  EXPECT_GT(stats.sky, 1000);
  EXPECT_GT(stats.absorbed, 10);
  EXPECT_GT(stats.cuts, 100);
  EXPECT_GT(stats.far, 100);
  EXPECT_GT(stats.counters.lambertian, 100u);
  EXPECT_GT(stats.counters.metal, 100u);
  EXPECT_GT(stats.counters.refracted, 100u);
}

}  // namespace
}  // namespace tripsitter::rtl

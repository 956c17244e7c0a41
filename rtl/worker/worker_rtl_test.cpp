// The worker's RTL (ts_worker.sv) against the C++ model: device::Worker::trace for every pixel's colour and
// reflection count, and DevicePreset::pixel_occupancy and drain_cycles for the cycle each pixel makes the worker
// ready again and the cycle of its done pulse. Scene memory is a device::SceneMemory served through the
// worker's read port (a registered read: the fields the cycle after the address). Random worlds (spheres in view,
// behind the camera, around it, huge, tiny, at the formats' limits, metals), ties, and mirrors that make every
// pixel reflect up to the cut-off, in both presets; the pipelined worker takes its pixels back to back (and with
// gaps). The board's worker with the planted square-root fault must fail.
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_worker_board.h>
#include <Vts_worker_board_bug.h>
#include <Vts_worker_wide.h>

#include <tripsitter/device/preset.h>
#include <tripsitter/device/scene_memory.h>
#include <tripsitter/device/test_util.h>
#include <tripsitter/device/worker.h>
#include <tripsitter/link/frame.h>

namespace tripsitter::rtl {
namespace {

using device::DevicePreset;
using device::SceneMemory;

struct Pixel {
  int col = 0;
  int row = 0;
  int gap = 0;  // the earliest start, in cycles after the previous pixel's start (0: as soon as ready)
};

// What the RTL did with one pixel.
struct Traced {
  std::int64_t start = -1;  // the cycle of its start pulse
  std::int64_t done = -1;   // the cycle of its done pulse
  int done_col = -1;
  core::Rgb444 colour;
  int bounces = -1;
};

// What the RTL did with a run of pixels: each pixel's trace, and every cycle's ready.
struct RunResult {
  std::vector<Traced> pixels;
  std::vector<bool> ready;  // by cycle, from ready_from
  std::int64_t ready_from = 0;
  bool ready_at(std::int64_t c) const {
    const std::int64_t i = c - ready_from;
    return i >= 0 && i < static_cast<std::int64_t>(ready.size()) && ready[static_cast<std::size_t>(i)];
  }
  bool recorded(std::int64_t c) const { return c >= ready_from && c - ready_from < static_cast<std::int64_t>(ready.size()); }
  std::string error;        // a protocol problem (a done pulse with nothing in flight, a pixel never done)
};

// One Verilated worker with scene memory beside it, clocked by hand: inputs are set and the model settled with
// the clock low (ready, the read port and the done pulse are read then), then the rising edge; scene memory
// answers a read in the next cycle, as block RAM does.
template <class V>
class WorkerRtl {
 public:
  WorkerRtl(const DevicePreset& preset, const SceneMemory& scene) : preset_(preset), scene_(scene) {
    context_.randReset(2);  // random initial values: the reset must make them irrelevant
    top_ = std::make_unique<V>(&context_);
    top_->rst = 1;
    top_->flush = 0;
    top_->start = 0;
    put(top_->sphere_count, static_cast<UInt128>(scene.geometry.size()));
    for (int i = 0; i < 3; ++i) tick();
    top_->rst = 0;
  }

  // Starts `pixels` in order, each in the first cycle the worker is ready, `gap` cycles or more after the
  // previous start, and runs until every pixel is done (or a time limit). flush_at >= 0 pulses flush in that
  // cycle (counted from the first start).
  RunResult run(const std::vector<Pixel>& pixels, std::int64_t flush_at = -1) {
    RunResult out;
    out.ready_from = cycle_;
    out.pixels.resize(pixels.size());
    std::size_t next = 0, done = 0;
    std::int64_t first = -1, last_start = -1000000;
    const std::int64_t limit = cycle_ + 200000 + static_cast<std::int64_t>(pixels.size()) * 20000;
    while ((next < pixels.size() || done < next) && cycle_ < limit) {
      top_->start = 0;
      top_->flush = flush_at >= 0 && first >= 0 && cycle_ - first == flush_at;
      settle();
      const bool ready = top_->ready != 0;
      out.ready.push_back(ready);
      if (next < pixels.size() && ready && cycle_ - last_start >= pixels[next].gap && !top_->flush) {
        top_->start = 1;
        top_->col = static_cast<SData>(pixels[next].col);
        top_->row = static_cast<SData>(pixels[next].row);
        settle();
        out.pixels[next].start = cycle_;
        if (first < 0) first = cycle_;
        last_start = cycle_;
        ++next;
      }
      if (top_->done) {
        if (done >= next) {
          out.error = "a done pulse with no pixel in flight at cycle " + std::to_string(cycle_);
          break;
        }
        Traced& t = out.pixels[done++];
        t.done = cycle_;
        t.done_col = top_->done_col;
        t.colour = core::Rgb444(static_cast<std::uint16_t>(top_->colour));
        t.bounces = top_->bounces;
      }
      if (top_->flush) done = next;  // the pixels in flight are dropped
      const bool read = top_->sphere_rd != 0;
      const auto address = static_cast<std::size_t>(top_->sphere_addr);
      tick();
      if (read) serve(address);
    }
    if (out.error.empty() && done < next) out.error = "pixels never done";
    return out;
  }

  std::int64_t cycle() const { return cycle_; }

 private:
  void settle() {
    top_->clk = 0;
    top_->eval();
  }
  void tick() {
    rising_edge(*top_);
    ++cycle_;
  }
  // Scene memory's registered read: sphere `i`'s fields (zeros past the last sphere).
  void serve(std::size_t i) {
    core::KernelSphere<std::int64_t> g{};
    device::SurfaceWord s{};
    if (i < scene_.geometry.size()) g = scene_.geometry[i];
    if (i < scene_.surfaces.size()) s = scene_.surfaces[i];
    put(top_->sphere_x, static_cast<UInt128>(g.center.x & mask(preset_.x.total_bits)));
    put(top_->sphere_y, static_cast<UInt128>(g.center.y & mask(preset_.y.total_bits)));
    put(top_->sphere_z, static_cast<UInt128>(g.center.z & mask(preset_.z.total_bits)));
    put(top_->sphere_r, static_cast<UInt128>(g.radius & mask(preset_.radius.total_bits)));
    top_->sphere_metal = s.material == link::kMaterialMetal;
    top_->sphere_albedo = static_cast<IData>(s.albedo[0]) << 16 | static_cast<IData>(s.albedo[1]) << 8 | s.albedo[2];
  }

  DevicePreset preset_;
  const SceneMemory& scene_;
  VerilatedContext context_;
  std::unique_ptr<V> top_;
  std::int64_t cycle_ = 0;
};

// The model's schedule of a run: pixel i starts when it was started or when the worker is free of pixel i - 1,
// whichever is later (the speculative worker starts pixels early and replays them), is free again occupancy
// cycles later, and is done drain - 1 cycles after that.
struct Schedule {
  std::vector<std::int64_t> start, free, done;
};
Schedule model_schedule(const DevicePreset& p, std::int64_t spheres, const std::vector<Traced>& rtl,
                        const std::vector<int>& bounces) {
  Schedule s;
  std::int64_t free = -1;
  for (std::size_t i = 0; i < rtl.size(); ++i) {
    const std::int64_t start = std::max(rtl[i].start, free);
    free = start + p.pixel_occupancy(spheres, bounces[i]);
    s.start.push_back(start);
    s.free.push_back(free);
    s.done.push_back(free + p.drain_cycles() - 1);
  }
  return s;
}

// Runs `pixels` through the RTL and compares everything with the model; returns the number of pixels whose
// colour or bounce count differ (the first is reported with both values when `report`). Timing differences
// are test failures.
template <class V>
int compare(const DevicePreset& p, const SceneMemory& scene, const std::vector<Pixel>& pixels, const std::string& what,
            bool report = true) {
  WorkerRtl<V> rtl(p, scene);
  const RunResult run = rtl.run(pixels);
  EXPECT_EQ(run.error, "") << what;
  if (!run.error.empty()) return static_cast<int>(pixels.size());
  const device::Worker worker(p);
  std::vector<int> bounces;
  std::vector<core::PixelTrace> expected;
  for (const Pixel& px : pixels) {
    expected.push_back(worker.trace(px.col, px.row, scene));
    bounces.push_back(expected.back().bounces);
  }
  const auto spheres = static_cast<std::int64_t>(scene.geometry.size());
  const Schedule s = model_schedule(p, spheres, run.pixels, bounces);
  int bad = 0;
  bool timing_reported = false;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const Traced& t = run.pixels[i];
    std::ostringstream where;
    where << what << ", pixel " << i << " (col " << pixels[i].col << ", row " << pixels[i].row << ", " << spheres
          << " spheres)";
    if (t.colour != expected[i].colour || t.bounces != expected[i].bounces) {
      if (bad++ == 0 && report) {
        ADD_FAILURE() << where.str() << ": the RTL gives colour 0x" << std::hex << t.colour.packed << std::dec
                      << " after " << t.bounces << " reflections, the model 0x" << std::hex
                      << expected[i].colour.packed << std::dec << " after " << expected[i].bounces;
      }
    }
    const bool timing_ok = t.done_col == pixels[i].col && t.done == s.done[i];
    if (!timing_ok && !timing_reported) {
      timing_reported = true;
      ADD_FAILURE() << where.str() << ": started in cycle " << t.start << " (the model's start " << s.start[i]
                    << "), done in cycle " << t.done << " with column " << t.done_col << "; the model's done "
                    << s.done[i] << " (occupancy " << p.pixel_occupancy(spheres, bounces[i]) << ", drain "
                    << p.drain_cycles() << ")";
    }
  }
  // Ready. The speculative worker: a pixel started as soon as the worker was ready starts no later than the model
  // frees the worker of the pixel before (earlier only when that pixel then reflects: it is replayed).
  if (p.costs.pipelined) {
    for (std::size_t i = 1; i < pixels.size(); ++i) {
      if (pixels[i].gap == 0 && run.pixels[i].start > s.free[i - 1]) {
        ADD_FAILURE() << what << ", pixel " << i << ": started in cycle " << run.pixels[i].start
                      << ", but the model frees the worker in cycle " << s.free[i - 1];
        break;
      }
    }
  }
  // One pixel at a time: ready exactly from the cycle the model frees the worker until the next start.
  if (!p.costs.pipelined) {
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      const std::int64_t until = i + 1 < pixels.size() ? run.pixels[i + 1].start : s.free[i] + 1;
      for (std::int64_t c = run.pixels[i].start + 1; c <= until && run.recorded(c); ++c) {
        if (run.ready_at(c) != (c >= s.free[i])) {
          ADD_FAILURE() << what << ", pixel " << i << ": ready is " << run.ready_at(c)
                        << " in cycle " << c << ", the model frees the worker in cycle " << s.free[i];
          break;
        }
      }
    }
  }
  return bad;
}

// The worker's pixels of one row, as the controller hands them (columns w, w + workers, ...), then random pixels.
std::vector<Pixel> pixels_of(std::mt19937_64& rng, int row, int worker, int workers, int random_count, int max_gap) {
  std::vector<Pixel> v;
  for (int col = worker; col < device::kLineWidth; col += workers) v.push_back({col, row, 0});
  for (int i = 0; i < random_count; ++i) {
    const int gap = max_gap > 0 && rng() % 4 == 0 ? static_cast<int>(rng() % static_cast<std::uint64_t>(max_gap)) : 0;
    v.push_back({static_cast<int>(rng() % device::kLineWidth), static_cast<int>(rng() % 480), gap});
  }
  return v;
}

SceneMemory with_ties(SceneMemory m, std::mt19937_64& rng) {
  // Copies of spheres later in memory, with other surfaces: the first in memory must win every tie.
  const std::size_t n = m.geometry.size();
  m.surfaces.resize(n);
  for (std::size_t i = 0; i < n && i < 6; ++i) {
    m.geometry.push_back(m.geometry[i]);
    device::SurfaceWord s;
    s.material = m.surfaces[i].material == link::kMaterialMetal ? link::kMaterialLambertian : link::kMaterialMetal;
    s.albedo = {static_cast<std::uint8_t>(rng()), 255, static_cast<std::uint8_t>(rng())};
    m.surfaces.push_back(s);
  }
  return m;
}

void add_sphere(SceneMemory& m, const DevicePreset& p, double x, double y, double z, double r, bool metal,
                std::array<std::uint8_t, 3> albedo) {
  m.valid = true;
  m.geometry.push_back({{p.x.quantize(x).raw, p.y.quantize(y).raw, p.z.quantize(z).raw}, p.radius.quantize(r).raw});
  device::SurfaceWord s;
  s.material = metal ? link::kMaterialMetal : link::kMaterialLambertian;
  s.albedo = albedo;
  m.surfaces.push_back(s);
}

// ---- board-2023: one pixel at a time, no reflections (metals are normal-shaded) ---------------------------

TEST(WorkerRtl, BoardDemoSphere) {
  const DevicePreset p = device::board_2023_preset();
  SceneMemory m;
  add_sphere(m, p, 0, 0, 400, 64, false, {128, 128, 128});
  std::mt19937_64 rng(1);
  std::vector<Pixel> pixels;
  for (int col = 260; col < 380; col += 3) pixels.push_back({col, 240, 0});
  for (int row = 180; row < 300; row += 7) pixels.push_back({320, row, 0});
  auto more = pixels_of(rng, 200, 3, 10, 20, 0);
  pixels.insert(pixels.end(), more.begin(), more.end());
  EXPECT_EQ(compare<Vts_worker_board>(p, m, pixels, "demo sphere"), 0);
}

TEST(WorkerRtl, BoardRandomWorlds) {
  const DevicePreset p = device::board_2023_preset();
  std::mt19937_64 rng(2);
  int hits = 0, metals = 0;
  for (int world = 0; world < 48; ++world) {
    SceneMemory m = device::testing::random_world(p, rng);
    if (world % 4 == 3) m = with_ties(m, rng);
    std::vector<Pixel> pixels = pixels_of(rng, static_cast<int>(rng() % 480), static_cast<int>(rng() % 10), 10, 16, 3);
    if (m.geometry.size() > 24) pixels.resize(40);  // keep the run short: 45 cycles per sphere and pixel
    EXPECT_EQ(compare<Vts_worker_board>(p, m, pixels, "board world " + std::to_string(world)), 0);
    const device::Worker w(p);
    for (const Pixel& px : pixels) {
      hits += w.shade(px.col, px.row, m) != core::kBackground;
      metals += std::any_of(m.surfaces.begin(), m.surfaces.end(),
                            [](const device::SurfaceWord& s) { return s.material == link::kMaterialMetal; });
    }
  }
  EXPECT_GT(hits, 200) << "the random worlds hardly hit anything";
  EXPECT_GT(metals, 200) << "no metal surfaces to normal-shade";
}

TEST(WorkerRtl, BoardEmptyAndFullMemory) {
  const DevicePreset p = device::board_2023_preset();
  SceneMemory empty;
  empty.valid = true;
  EXPECT_EQ(compare<Vts_worker_board>(p, empty, {{0, 0, 0}, {320, 240, 0}, {639, 479, 0}}, "no spheres"), 0);
  std::mt19937_64 rng(3);
  SceneMemory full;
  for (int i = 0; i < 64; ++i) {
    add_sphere(full, p, (static_cast<double>(rng() % 2000) - 1000), static_cast<double>(rng() % 1000) - 500,
               static_cast<double>(rng() % 4000) - 500, 1 + static_cast<double>(rng() % 300), rng() % 3 == 0,
               {255, 0, 17});
  }
  EXPECT_EQ(compare<Vts_worker_board>(p, full, pixels_of(rng, 100, 7, 10, 0, 0), "64 spheres"), 0);
}

// The planted square-root fault (the recurrence's comparison flipped): the board's worker built with it must
// get colours wrong, and the comparison above must see it.
TEST(WorkerRtl, ThePlantedSquareRootFaultIsCaught) {
  const DevicePreset p = device::board_2023_preset();
  SceneMemory m;
  add_sphere(m, p, 0, 0, 400, 64, false, {128, 128, 128});
  add_sphere(m, p, 150, -60, 700, 200, true, {128, 128, 128});
  std::vector<Pixel> pixels;
  for (int col = 200; col < 440; col += 4) pixels.push_back({col, 240, 0});
  const int bad = compare<Vts_worker_board_bug>(p, m, pixels, "planted fault", false);
  EXPECT_GT(bad, static_cast<int>(pixels.size()) / 2) << "the planted fault changed only " << bad << " of "
                                                      << pixels.size() << " pixels";
  EXPECT_EQ(compare<Vts_worker_board>(p, m, pixels, "the same pixels without the fault"), 0);
}

// flush on the one-pixel worker in every cycle around a pixel's end: the pass's end, the cycle its shading borrows
// the sphere test's multipliers, the shading, the done pulse. A done pulse due in the flush cycle is given, nothing
// of the dropped pixel after it, and the pixels started at once after it are traced and timed as ever.
TEST(WorkerRtl, BoardFlushAroundAPixelsEnd) {
  const DevicePreset p = device::board_2023_preset();
  SceneMemory m;
  add_sphere(m, p, 0, 0, 400, 64, false, {128, 128, 128});
  add_sphere(m, p, 40, -30, 500, 120, true, {255, 0, 0});
  const device::Worker w(p);
  const std::vector<Pixel> pixels = {{318, 236, 0}, {330, 250, 0}, {300, 230, 0}};
  for (const Pixel& px : pixels) ASSERT_NE(w.shade(px.col, px.row, m), core::kBackground);
  const std::int64_t occupancy = p.pixel_occupancy(2, 0);  // 96: the last pair at 45, its pass ends at 45 + 43
  for (std::int64_t at = 80; at < occupancy; ++at) {
    WorkerRtl<Vts_worker_board> rtl(p, m);
    const RunResult run = rtl.run(pixels, at);
    ASSERT_EQ(run.error, "") << "flush at " << at;
    const Traced& first = run.pixels[0];
    if (at == occupancy - 1) {  // the done pulse is in the flush cycle
      EXPECT_EQ(first.done, first.start + at) << "flush at " << at;
      EXPECT_EQ(first.colour, w.shade(pixels[0].col, pixels[0].row, m)) << "flush at " << at;
    } else {
      EXPECT_EQ(first.done, -1) << "flush at " << at;
    }
    EXPECT_EQ(run.pixels[1].start, first.start + at + 1) << "not ready after the flush at " << at;
    for (std::size_t i = 1; i < pixels.size(); ++i) {
      const Traced& t = run.pixels[i];
      EXPECT_EQ(t.colour, w.shade(pixels[i].col, pixels[i].row, m)) << "pixel " << i << ", flush at " << at;
      EXPECT_EQ(t.done, t.start + occupancy - 1) << "pixel " << i << ", flush at " << at;
    }
  }
}

// ---- wide: pipelined, up to 3 reflections ---------------------------------------------------------------

TEST(WorkerRtl, WideRandomWorldsBackToBack) {
  const DevicePreset p = device::wide_preset();
  std::mt19937_64 rng(4);
  const device::Worker w(p);
  std::array<int, 4> by_bounces{};
  for (int world = 0; world < 120; ++world) {
    SceneMemory m = device::testing::random_world(p, rng);
    if (world % 5 == 4) m = with_ties(m, rng);
    const std::vector<Pixel> pixels =
        pixels_of(rng, static_cast<int>(rng() % 480), static_cast<int>(rng() % 10), 10, 64, 0);
    EXPECT_EQ(compare<Vts_worker_wide>(p, m, pixels, "wide world " + std::to_string(world)), 0);
    for (const Pixel& px : pixels) ++by_bounces[static_cast<std::size_t>(w.trace(px.col, px.row, m).bounces)];
  }
  EXPECT_GT(by_bounces[1], 50) << "too few reflecting pixels";
  EXPECT_GT(by_bounces[2], 0) << "no pixel reflected twice";
}

TEST(WorkerRtl, WideRandomWorldsWithGaps) {
  const DevicePreset p = device::wide_preset();
  std::mt19937_64 rng(5);
  for (int world = 0; world < 40; ++world) {
    const SceneMemory m = device::testing::random_world(p, rng);
    const std::vector<Pixel> pixels = pixels_of(rng, static_cast<int>(rng() % 480), 0, 40, 64, 60);
    EXPECT_EQ(compare<Vts_worker_wide>(p, m, pixels, "wide world with gaps " + std::to_string(world)), 0);
  }
}

// Two nearly flat mirrors around the camera (Mirror.LatePixelsGrowWithTheBounceCutOff): every pixel reflects
// three times, the cut-off, and each costs 131 cycles.
TEST(WorkerRtl, WideMirrorsEveryPixelAtTheCutOff) {
  const DevicePreset p = device::wide_preset();
  SceneMemory m;
  add_sphere(m, p, 0, 0, 100000, 99000, true, {255, 255, 255});
  add_sphere(m, p, 0, 0, -100000, 99000, true, {200, 100, 255});
  std::mt19937_64 rng(6);
  const auto pixels = pixels_of(rng, 17, 3, 10, 32, 0);
  const device::Worker w(p);
  for (const Pixel& px : pixels) ASSERT_EQ(w.trace(px.col, px.row, m).bounces, 3);
  EXPECT_EQ(p.pixel_occupancy(2, 3), 131);
  EXPECT_EQ(compare<Vts_worker_wide>(p, m, pixels, "mirrors"), 0);
}

TEST(WorkerRtl, WideMetalsAndLimits) {
  const DevicePreset p = device::wide_preset();
  std::mt19937_64 rng(7);
  // A metal sphere in front, coloured spheres around it, one behind the camera, tiny and huge ones, and
  // coordinates at the formats' ends.
  SceneMemory m;
  add_sphere(m, p, 0, 0, 600, 250, true, {255, 200, 100});
  add_sphere(m, p, -400, 0, 300, 150, false, {1, 2, 3});
  add_sphere(m, p, 400, 100, 350, 150, true, {90, 255, 10});
  add_sphere(m, p, 0, -300, 200, 120, false, {0, 0, 0});
  add_sphere(m, p, 0, 0, -500, 400, true, {255, 255, 255});
  add_sphere(m, p, 10, 10, 100, 0.0625, false, {7, 7, 7});
  add_sphere(m, p, p.x.max_value(), p.y.min_value(), p.z.max_value(), p.radius.max_value(), true, {255, 0, 255});
  add_sphere(m, p, p.x.min_value(), 0, 1000, p.radius.max_value() / 3, false, {9, 9, 9});
  std::vector<Pixel> pixels;
  for (int col = 0; col < device::kLineWidth; col += 5) pixels.push_back({col, 240, 0});
  for (int row = 0; row < 480; row += 9) pixels.push_back({330, row, 0});
  const device::Worker w(p);
  int reflecting = 0;
  for (const Pixel& px : pixels) reflecting += w.trace(px.col, px.row, m).bounces > 0;
  EXPECT_GT(reflecting, 40);
  EXPECT_EQ(compare<Vts_worker_wide>(p, m, pixels, "metals and limits"), 0);
}

TEST(WorkerRtl, WideEmptyMemoryAndOneSphere) {
  const DevicePreset p = device::wide_preset();
  SceneMemory empty;
  empty.valid = true;
  std::mt19937_64 rng(8);
  EXPECT_EQ(compare<Vts_worker_wide>(p, empty, pixels_of(rng, 5, 0, 10, 10, 0), "no spheres"), 0);
  SceneMemory one;
  add_sphere(one, p, 0, 0, 400, 64, true, {255, 128, 0});
  EXPECT_EQ(compare<Vts_worker_wide>(p, one, pixels_of(rng, 240, 0, 1, 0, 0), "one metal sphere, a whole row"), 0);
}

// Hundreds of spheres (sphere indices of 9 bits and more), metals among them.
TEST(WorkerRtl, WideManySpheres) {
  const DevicePreset p = device::wide_preset();
  std::mt19937_64 rng(9);
  SceneMemory m;
  for (int i = 0; i < 700; ++i) {
    const double z = 200 + static_cast<double>(rng() % 3000);
    add_sphere(m, p, (static_cast<double>(rng() % 2001) - 1000) * z / 1000, (static_cast<double>(rng() % 1501) - 750) * z / 1000,
               z, 5 + static_cast<double>(rng() % 60), rng() % 3 == 0,
               {static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng()), 255});
  }
  const auto pixels = pixels_of(rng, 300, 5, 10, 16, 0);
  EXPECT_EQ(compare<Vts_worker_wide>(p, m, pixels, "700 spheres"), 0);
}

// flush: a done pulse due in the flush cycle is given, nothing after it, and the worker is ready at once.
TEST(WorkerRtl, FlushDropsThePixelsInFlight) {
  const DevicePreset p = device::wide_preset();
  SceneMemory m;
  add_sphere(m, p, 0, 0, 400, 64, true, {255, 128, 0});
  add_sphere(m, p, 0, 0, -400, 300, false, {255, 128, 0});
  WorkerRtl<Vts_worker_wide> rtl(p, m);
  std::vector<Pixel> pixels;
  for (int col = 300; col < 340; ++col) pixels.push_back({col, 240, 0});
  const RunResult run = rtl.run(pixels, 150);
  EXPECT_EQ(run.error, "");
  const std::int64_t flush_cycle = run.pixels.front().start + 150;
  const device::Worker w(p);
  int before = 0, after = 0;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const Traced& t = run.pixels[i];
    if (t.start < flush_cycle) {  // dropped, unless done by the flush cycle
      if (t.done >= 0) {
        ++before;
        EXPECT_LE(t.done, flush_cycle) << i;
      }
    } else {  // started afresh after it: traced as ever
      ++after;
      EXPECT_EQ(t.colour, w.shade(pixels[i].col, pixels[i].row, m)) << i;
      EXPECT_GE(t.done, 0) << i;
    }
  }
  EXPECT_GT(before, 0);
  EXPECT_GT(after, 0);
  EXPECT_TRUE(run.ready_at(flush_cycle + 1)) << "not ready after the flush";
}

}  // namespace
}  // namespace tripsitter::rtl

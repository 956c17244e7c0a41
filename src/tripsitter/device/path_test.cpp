// The path preset's device: its random streams, its arithmetic and its frames.
#include <tripsitter/device/path_kernel.h>

#include <array>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/core/sanitizers.h>
#include <tripsitter/device/controller.h>
#include <tripsitter/device/device.h>
#include <tripsitter/device/fast_tracer.h>
#include <tripsitter/device/test_util.h>
#include <tripsitter/link/wire_v1.h>

namespace tripsitter::device {
namespace {

using testing::kDielectric;
using testing::kLambertian;
using testing::kMetal;
using testing::PathBall;
using testing::path_frame_of;

// Fewer worlds under the sanitizers, which run the whole suite many times slower.
using core::kSanitized;

// What one frame of a device came to: the visible pixels, the statistics and frame memory after it.
struct Shot {
  std::vector<core::Rgb444> pixels;
  FrameStats stats;
  std::vector<AccumEntry> entries;
};

Shot shoot(Device& dev) {
  Shot s;
  s.pixels = testing::visible_pixels(dev, &s.stats);
  const auto e = dev.frame_memory()->entries();
  s.entries.assign(e.begin(), e.end());
  return s;
}

DevicePreset path_with(int spp, int depth, int workers = 64) {
  DevicePreset p = path_preset();
  p.path->spp = spp;
  p.path->depth = depth;
  p.workers = workers;
  return p;
}

std::string counters_text(const PathCounters& c) {
  return "samples " + std::to_string(c.samples) + " rays " + std::to_string(c.rays) + " lambertian " +
         std::to_string(c.lambertian) + " metal " + std::to_string(c.metal) + " dielectric " +
         std::to_string(c.dielectric) + " refracted " + std::to_string(c.refracted) + " absorbed " +
         std::to_string(c.absorbed) + " sky " + std::to_string(c.sky) + " cut " + std::to_string(c.cut) + " draws " +
         std::to_string(c.draws);
}

std::string stats_text(const FrameStats& s) {
  return "sequence " + std::to_string(s.sequence) + " world " + std::to_string(s.has_world) + " late " +
         std::to_string(s.late_pixels) + "/" + std::to_string(s.late_lines) + " spp " +
         std::to_string(s.samples_per_pixel) + " rays " + std::to_string(s.rays) + " worst line " +
         std::to_string(s.worst_line_cycles) + " reflections " + std::to_string(s.reflections) + " " +
         counters_text(s.path);
}

// The mixed world of the worker-count test: lambertian, fuzzed and sharp metal, glass, a large lambertian floor.
std::vector<PathBall> mixed_world() {
  return {{{-150, 20, 600, 100}, kLambertian, {200, 80, 80}},
          {{120, 30, 500, 90}, kMetal, {220, 220, 220}, 20000},
          {{0, -60, 420, 60}, kDielectric, {255, 255, 255}, 0, 6144},
          {{0, 1300, 900, 1100}, kLambertian, {128, 160, 90}},
          {{250, -150, 800, 80}, kMetal, {255, 200, 120}, 0}};
}

TEST(PathRng, NeighbouringPixelsStartUnrelatedStreams) {
  // The seed hash spreads consecutive keys: the first draws of 4096 neighbouring pixels are all different, and
  // about half of their bits differ from the previous pixel's.
  std::set<std::uint32_t> first;
  std::uint64_t flipped = 0;
  std::uint32_t previous = 0;
  for (std::uint32_t pixel = 0; pixel < 4096; ++pixel) {
    const std::uint32_t d = PathRng::for_sample(pixel, 0).next();
    first.insert(d);
    if (pixel > 0) flipped += static_cast<std::uint64_t>(std::popcount(d ^ previous));
    previous = d;
  }
  EXPECT_EQ(first.size(), 4096u);
  EXPECT_NEAR(static_cast<double>(flipped) / 4095.0, 16.0, 0.5);
}

TEST(PathDevice, AnEmptyWorldShowsTheSkyFixedToTheView) {
  // No sphere: every sample is the sky of the pixel's direction, the same at every sample, so the frame memory
  // holds it exactly once per sample; the top of the screen is bluer (less red) than the bottom.
  Device dev(path_preset(), link::WireVersion::kV2, 1);
  dev.transfer(testing::frame_of(path_preset(), 1, {}));
  testing::visible_pixels(dev);
  const auto entries = dev.frame_memory()->entries();
  const auto top = entry_mean(entries[320]);
  const auto bottom = entry_mean(entries[479 * 640 + 320]);
  EXPECT_LT(top[0], bottom[0]);
  EXPECT_NEAR(bottom[0], 1.0, 0.25);
  EXPECT_EQ(entries[320].count, 1);
}

// A pixel's samples do not depend on which worker traced it: with 1, 10, 37 and 640 workers the same world gives
// the same colour and the same frame-memory entry at every pixel on time in both frames compared. Fewer workers
// make more pixels late, and a late pixel is black and leaves frame memory alone (its entry stays empty here: the
// first world's epoch never held anything). On time is read from frame memory, not from the colour: an on-time
// pixel may be legitimately black (a path absorbed or cut at every sample).
TEST(PathDevice, WorkerCountChangesOnlyWhichPixelsAreLate) {
  const std::vector<int> counts{1, 10, 37, 640};
  std::vector<std::array<Shot, 2>> shots;
  for (const int workers : counts) {
    const DevicePreset p = path_with(1, 4, workers);
    Device dev(p, link::WireVersion::kV2, 1);
    dev.transfer(path_frame_of(p, 1, mixed_world()));
    std::array<Shot, 2> s{shoot(dev), shoot(dev)};
    for (int f = 0; f < 2; ++f) {
      const Shot& shot = s[static_cast<std::size_t>(f)];
      int late = 0;
      for (std::size_t i = 0; i < shot.entries.size(); ++i) {
        // After frame f an entry holds 0..f+1 samples; a pixel late in frame f shows black.
        ASSERT_LE(shot.entries[i].count, f + 1) << workers << " workers, pixel " << i;
        if (f == 0 && shot.entries[i].count == 0) {
          ++late;
          ASSERT_EQ(shot.pixels[i], core::kBlack) << workers << " workers, pixel " << i;
        }
      }
      if (f == 0) {
        EXPECT_EQ(late, shot.stats.late_pixels) << workers << " workers";
      }
    }
    shots.push_back(s);
  }
  // One worker is late on every line; 640 workers, one pixel each, never are.
  EXPECT_GT(shots.front()[0].stats.late_pixels, 100000);
  EXPECT_EQ(shots.back()[0].stats.late_pixels, 0);
  EXPECT_EQ(shots.back()[1].stats.late_pixels, 0);
  // The world exercises every material.
  const PathCounters& c = shots.back()[0].stats.path;
  EXPECT_GT(c.lambertian, 10000u);
  EXPECT_GT(c.metal, 10000u);
  EXPECT_GT(c.refracted, 1000u);
  EXPECT_GT(c.dielectric, c.refracted);  // some reflect
  EXPECT_GT(c.absorbed, 0u);             // fuzz pushes some below the metal
  for (std::size_t a = 0; a < counts.size(); ++a) {
    for (std::size_t b = a + 1; b < counts.size(); ++b) {
      int compared[2] = {0, 0};
      for (std::size_t f = 0; f < 2; ++f) {
        const Shot& x = shots[a][f];
        const Shot& y = shots[b][f];
        for (std::size_t i = 0; i < x.entries.size(); ++i) {
          // On time in frame 0 in both: count 1. After frame 1, count 2 is on time in both frames in both.
          if (x.entries[i].count != f + 1 || y.entries[i].count != f + 1) continue;
          ++compared[f];
          ASSERT_EQ(x.entries[i], y.entries[i]) << counts[a] << " vs " << counts[b] << " workers, frame " << f
                                                << ", pixel " << i;
          ASSERT_EQ(x.pixels[i], y.pixels[i]) << counts[a] << " vs " << counts[b] << " workers, frame " << f
                                              << ", pixel " << i;
        }
      }
      EXPECT_GT(compared[0], 10000) << counts[a] << " vs " << counts[b];
      EXPECT_GT(compared[1], 10000) << counts[a] << " vs " << counts[b];
    }
  }
}

// The fast model (FastTracer, lines ahead of the beam on 1 and 2 threads) shows exactly the plain model's frames on
// random worlds of every material: pixels, statistics (late pixels and lines, samples, rays, the workers' counts)
// and frame memory, frame after frame as the world accumulates, at several depths and sample counts.
TEST(PathDevice, FastFramesEqualThePlainModel) {
  std::mt19937_64 rng(77);
  constexpr int kFrames = kSanitized ? 2 : 3;
  struct Config {
    int depth, spp, workers;
  };
  // Every depth, 1 and 3 samples a frame, some on 16 workers (more pixels late). The plain model takes up to a
  // second a frame here, so few worlds (FastRowsEqualThePlainModelOnRandomWorlds covers many more, row by row); under
  // the sanitizers only the last, the deepest (every world is drawn all the same, so it is the same world).
  const std::vector<Config> configs{{1, 3, 16}, {2, 1, 64}, {4, 3, 64}, {16, 1, 16}};
  std::uint64_t late = 0, cut = 0, absorbed = 0, refracted = 0;
  for (std::size_t world = 0; world < configs.size(); ++world) {
    const Config& c = configs[world];
    const DevicePreset p = path_with(c.spp, c.depth, c.workers);
    const SceneMemory scene = testing::random_path_world(p, rng, 6);
    if (kSanitized && world + 1 < configs.size()) continue;
    Device plain(p, link::WireVersion::kV2, 1, DeviceModel::kPlain);
    Device fast1(p, link::WireVersion::kV2, 1, DeviceModel::kFast);
    Device fast2(p, link::WireVersion::kV2, 2, DeviceModel::kFast);
    for (int frame = 0; frame < kFrames; ++frame) {
      // The world again with a new sequence number for the last frame: the same content keeps accumulating.
      if (frame == 0 || frame == kFrames - 1) {
        const auto bytes = testing::frame_of_scene(p, static_cast<std::uint32_t>(1 + frame), scene);
        for (Device* d : {&plain, &fast1, &fast2}) d->transfer(bytes);
      }
      const Shot want = shoot(plain);
      for (Device* d : {&fast1, &fast2}) {
        const Shot got = shoot(*d);
        const std::string where = "world " + std::to_string(world) + " (" + std::to_string(scene.geometry.size()) +
                                  " spheres, spp " + std::to_string(p.path->spp) + ", depth " +
                                  std::to_string(p.path->depth) + ") frame " + std::to_string(frame) +
                                  (d == &fast1 ? ", 1 thread" : ", 2 threads");
        ASSERT_EQ(stats_text(got.stats), stats_text(want.stats)) << where;
        for (std::size_t i = 0; i < want.pixels.size(); ++i) {
          ASSERT_EQ(got.pixels[i], want.pixels[i]) << where << " pixel " << i;
          ASSERT_EQ(got.entries[i], want.entries[i]) << where << " pixel " << i;
        }
      }
      EXPECT_EQ(want.stats.samples_per_pixel, (frame + 1) * p.path->spp);
      late += static_cast<std::uint64_t>(want.stats.late_pixels);
      cut += want.stats.path.cut;
      absorbed += want.stats.path.absorbed;
      refracted += want.stats.path.refracted;
    }
  }
  // The worlds exercise what they are meant to.
  EXPECT_GT(late, 0u);
  EXPECT_GT(cut, 0u);
  EXPECT_GT(absorbed, 0u);
  EXPECT_GT(refracted, 0u);
}

// The same row by row on many more worlds, from frame memory of every kind (empty, of another epoch, partly and
// fully accumulated), under the path preset's schedule and a tighter one, and the artix path preset's with its 9
// units and with 2 (the plain model tests every sphere on a camera ray, the fast one its tile's): the row, its late
// pixels and rays, its new frame memory and the workers' counts.
TEST(PathDevice, FastRowsEqualThePlainModelOnRandomWorlds) {
  std::mt19937_64 rng(2027);
  DevicePreset tight = path_preset();
  tight.workers = 7;
  tight.lead_cycles = 2000;
  DevicePreset two_units = artix_path_preset();
  two_units.name = "artix-path, 2 units";
  two_units.workers = 2;
  const int worlds = kSanitized ? 40 : 150;
  for (const DevicePreset& p : {path_preset(), tight, artix_path_preset(), two_units}) {
    const Controller plain(p);
    FastTracer fast(p);
    std::uint64_t late = 0, converged = 0, traced = 0;
    for (int world = 0; world < worlds; ++world) {
      SceneMemory scene = testing::random_path_world(p, rng, 24);
      // Half the worlds with the hierarchy the host sends, which the artix path preset's bounced rays walk.
      if (p.walks_hierarchy() && world % 2 == 0) scene = testing::with_hierarchy(p, scene);
      std::vector<PathSurface> surfaces;
      for (const SurfaceWord& w : scene.surfaces) surfaces.push_back(path_surface(w));
      PathFrame frame;
      frame.surfaces = surfaces;
      frame.frame = static_cast<std::uint32_t>(rng() % 40);
      frame.epoch = 5;
      frame.spp = 1 + static_cast<int>(rng() % 3);
      frame.depth = 1 + static_cast<int>(rng() % kMaxPathDepth);
      frame.dither = rng() % 4 != 0;
      fast.load(scene);
      for (int k = 0; k < 3; ++k) {
        const int row = k == 0 ? 240 : static_cast<int>(rng() % 480);
        std::vector<AccumEntry> memory(kLineWidth);
        for (AccumEntry& e : memory) {
          const auto kind = rng() % 4;
          if (kind == 0) continue;  // never written
          e.epoch = kind == 1 ? 4 : 5;
          e.count = static_cast<std::uint8_t>(kind == 3 ? kMaxSamples - rng() % 4 : rng() % 200);
          for (auto& s : e.sum) s = static_cast<std::uint32_t>(rng() % (511u * e.count + 1));
        }
        std::vector<AccumEntry> want_memory = memory, got_memory = memory;
        std::array<core::Rgb444, kLineWidth> want, got;
        want.fill(core::Rgb444(0xABC));
        got.fill(core::Rgb444(0xDEF));
        PathCounters want_counters, got_counters;
        const LineResult a = plain.render_path_line(row, scene, frame, want_memory, want, want_counters);
        const LineResult b = fast.render_path_line(row, frame, got_memory, got, got_counters);
        const std::string where = p.name + " world " + std::to_string(world) + " row " + std::to_string(row);
        ASSERT_EQ(a.late_pixels, b.late_pixels) << where;
        ASSERT_EQ(a.rays, b.rays) << where;
        ASSERT_EQ(a.reflections, b.reflections) << where;
        ASSERT_EQ(a.demand_cycles, b.demand_cycles) << where;
        ASSERT_EQ(counters_text(want_counters), counters_text(got_counters)) << where;
        for (std::size_t col = 0; col < kLineWidth; ++col) {
          ASSERT_EQ(want[col], got[col]) << where << " col " << col;
          ASSERT_EQ(want_memory[col], got_memory[col]) << where << " col " << col;
          const bool full = memory[col].epoch == 5 && memory[col].count + frame.spp > kMaxSamples;
          if (full && want[col] != core::kBlack) ++converged;
        }
        late += static_cast<std::uint64_t>(a.late_pixels);
        traced += want_counters.samples;
      }
    }
    if (p.name != "artix-path") {
      EXPECT_GT(late, 1000u) << p.name;
    }
    EXPECT_GT(converged, 1000u) << p.name;
    EXPECT_GT(traced, 400u * static_cast<unsigned>(worlds)) << p.name;
  }
}

// A pixel accumulates spp samples a frame while the world's content is unchanged, and sample k of a pixel is the
// same whichever frame draws it: 4 frames of 1 sample, 2 of 2 and 1 of 4 leave the same frame memory (2 of 1 and
// 1 of 2 under the sanitizers).
TEST(PathDevice, AStillWorldAccumulatesTheSameSamplesWhateverTheSplit) {
  const int total = kSanitized ? 2 : 4;  // samples of each pixel
  std::vector<std::vector<AccumEntry>> last;
  for (int spp = 1; spp <= total; spp *= 2) {
    const DevicePreset p = path_with(spp, 4, 640);  // a pixel a worker: none is late
    Device dev(p, link::WireVersion::kV2, 2);
    dev.transfer(path_frame_of(p, 1, mixed_world()));
    const int frames = total / spp;
    Shot previous;
    for (int f = 0; f < frames; ++f) {
      const Shot s = shoot(dev);
      ASSERT_EQ(s.stats.late_pixels, 0) << spp;
      ASSERT_EQ(s.stats.samples_per_pixel, (f + 1) * spp) << spp;
      ASSERT_EQ(s.stats.path.samples, 640u * 480u * static_cast<unsigned>(spp)) << spp;
      for (std::size_t i = 0; i < s.entries.size(); ++i) {
        ASSERT_EQ(s.entries[i].count, (f + 1) * spp) << "spp " << spp << " frame " << f << " pixel " << i;
        ASSERT_EQ(s.entries[i].epoch, s.entries[0].epoch) << "spp " << spp << " frame " << f << " pixel " << i;
        if (f > 0) {
          ASSERT_EQ(s.entries[i].epoch, previous.entries[i].epoch);
          for (std::size_t k = 0; k < 3; ++k) {
            ASSERT_GE(s.entries[i].sum[k], previous.entries[i].sum[k]);
            ASSERT_LE(s.entries[i].sum[k], previous.entries[i].sum[k] + 511u * static_cast<unsigned>(spp));
          }
        }
      }
      previous = s;
    }
    last.push_back(previous.entries);
  }
  for (std::size_t i = 1; i < last.size(); ++i) EXPECT_TRUE(last[i] == last[0]) << i;
}

// A pixel stops at kMaxSamples: with 128 samples a frame, the second frame would pass 255, so a pixel on time in
// the first traces nothing in the second (FrameStats.rays counts the rays of pixels on time: none), keeps its
// entry and shows the same colour. The pixels of the sphere cost their worker more than a line (128 samples of two
// rays and a bounce each), so they and the rest of their worker's line are late in every frame: their workers
// still trace the ones they start, the same ones each frame (a path off a lone lambertian sphere always has two
// rays), so the second frame's samples are the first's less those of the converged pixels.
TEST(PathDevice, AConvergedPixelTracesNothing) {
  const DevicePreset p = path_with(128, 2);
  Device dev(p, link::WireVersion::kV2, 2);
  dev.transfer(path_frame_of(p, 1, {{{0, 0, 900, 60}, kLambertian, {200, 200, 200}}}));
  const Shot first = shoot(dev);
  EXPECT_EQ(first.stats.samples_per_pixel, 128);
  std::uint64_t on_time = 0;
  for (std::size_t i = 0; i < first.entries.size(); ++i) {
    ASSERT_TRUE(first.entries[i].count == 0 || first.entries[i].count == 128) << i;
    on_time += first.entries[i].count == 128 ? 1 : 0;
  }
  EXPECT_EQ(on_time, 640u * 480u - static_cast<std::uint64_t>(first.stats.late_pixels));
  EXPECT_GT(first.stats.late_pixels, 1000);
  EXPECT_GT(on_time, 250000u);
  EXPECT_GE(first.stats.rays, 128u * on_time);
  const Shot second = shoot(dev);
  EXPECT_EQ(second.stats.samples_per_pixel, 128);
  EXPECT_EQ(second.stats.late_pixels, first.stats.late_pixels);
  EXPECT_EQ(second.stats.rays, 0u);
  EXPECT_EQ(second.stats.path.samples, first.stats.path.samples - 128u * on_time);
  EXPECT_TRUE(second.entries == first.entries);
  EXPECT_TRUE(second.pixels == first.pixels);
}

// The boundary pixel by pixel: an entry takes spp more samples only while it stays within 255.
TEST(PathDevice, APixelTakesSamplesUpTo255) {
  const FixedArith arith{SqrtUnit(16)};
  const std::vector<core::KernelSphere<std::int64_t>> spheres;
  const std::span<const core::KernelSphere<std::int64_t>> none(spheres);
  const auto closest = [](const PathRay&) { return PathHit{}; };
  for (const auto& [count, spp, traced] : std::vector<std::array<int, 3>>{
           {254, 1, 1}, {255, 1, 0}, {252, 3, 1}, {253, 3, 0}, {0, 255, 1}, {1, 255, 0}}) {
    PathFrame frame;
    frame.epoch = 2;
    frame.spp = spp;
    frame.depth = 4;
    AccumEntry stored{{count * 300u, count * 400u, count * 511u}, static_cast<std::uint8_t>(count), 2};
    PathCounters counters;
    const PathPixel px = trace_path_pixel(arith, 100, 100, stored, none, frame, counters, closest);
    EXPECT_EQ(px.entry.count, count + traced * spp) << count << " + " << spp;
    EXPECT_EQ(px.rays, traced * spp) << count << " + " << spp;  // the sky: one ray a sample
    EXPECT_EQ(counters.samples, static_cast<std::uint64_t>(traced * spp)) << count << " + " << spp;
    if (!traced) {
      EXPECT_EQ(px.entry, stored);
    }
    // The same entry of another epoch is empty: it starts again.
    stored.epoch = 1;
    const PathPixel fresh = trace_path_pixel(arith, 100, 100, stored, none, frame, counters, closest);
    EXPECT_EQ(fresh.entry.count, spp);
    EXPECT_EQ(fresh.entry.epoch, 2);
  }
}

// The same content with a new sequence number keeps accumulating; other content starts a new epoch, back to spp
// samples; the content compared is the one shown, so the first world coming back starts again too.
TEST(PathDevice, NewContentStartsAgainAndTheSameContentAccumulates) {
  const DevicePreset p = path_with(2, 4);
  Device dev(p, link::WireVersion::kV2, 2);
  const std::vector<PathBall> a = mixed_world();
  std::vector<PathBall> b = a;
  b[1].fuzz = 20001;  // one field of one sphere
  const auto check = [&](const Shot& s, int count, std::uint32_t sequence, const std::string& what) {
    EXPECT_EQ(s.stats.sequence, sequence) << what;
    EXPECT_EQ(s.stats.late_pixels, 0) << what;
    EXPECT_EQ(s.stats.samples_per_pixel, count) << what;
    for (const AccumEntry& e : s.entries) {
      ASSERT_EQ(e.count, count) << what;
      ASSERT_EQ(e.epoch, s.entries[0].epoch) << what;
    }
  };
  dev.transfer(path_frame_of(p, 1, a));
  const Shot s1 = shoot(dev);
  check(s1, 2, 1, "first world");
  dev.transfer(path_frame_of(p, 2, a));
  const Shot s2 = shoot(dev);
  check(s2, 4, 2, "the same content again");
  EXPECT_EQ(s2.entries[0].epoch, s1.entries[0].epoch);
  dev.transfer(path_frame_of(p, 3, b));
  const Shot s3 = shoot(dev);
  check(s3, 2, 3, "other content");
  EXPECT_EQ(s3.entries[0].epoch, (s1.entries[0].epoch + 1) % kEpochs);
  dev.transfer(path_frame_of(p, 4, a));
  const Shot s4 = shoot(dev);
  check(s4, 2, 4, "the first content back");
  EXPECT_EQ(s4.entries[0].epoch, (s1.entries[0].epoch + 2) % kEpochs);
  // Starting again, the first world's first samples: the same entries as its first frame.
  EXPECT_EQ(s4.pixels, s1.pixels);
  for (std::size_t i = 0; i < s1.entries.size(); ++i) {
    ASSERT_EQ(s4.entries[i].sum, s1.entries[i].sum) << i;
  }
  // A frame with nothing new: the same world goes on.
  const Shot s5 = shoot(dev);
  check(s5, 4, 4, "no new world");
}

// A pixel late in a frame leaves its frame-memory entry as it was: one worker traces an empty world on time
// (a pixel costs one cycle), then a world of a sphere filling the screen makes most of each line late. Late
// pixels keep the first world's entries (and show black); the others start the new epoch.
TEST(PathDevice, ALatePixelKeepsItsOldEntry) {
  const DevicePreset p = path_with(1, 4, 1);
  Device dev(p, link::WireVersion::kV2, 1);
  dev.transfer(path_frame_of(p, 1, {}));
  const Shot empty = shoot(dev);
  ASSERT_EQ(empty.stats.late_pixels, 0);
  const std::uint8_t old_epoch = empty.entries[0].epoch;
  dev.transfer(path_frame_of(p, 2, {{{0, 0, 3000, 2900}, kLambertian, {100, 150, 200}}}));
  for (int f = 0; f < 2; ++f) {
    const Shot s = shoot(dev);
    EXPECT_GT(s.stats.late_pixels, 200000) << f;
    int late = 0;
    for (std::size_t i = 0; i < s.entries.size(); ++i) {
      if (s.pixels[i] == core::kBlack && s.entries[i].epoch == old_epoch) {
        ++late;
        ASSERT_EQ(s.entries[i], empty.entries[i]) << "frame " << f << " pixel " << i;
      } else {
        ASSERT_EQ(s.entries[i].epoch, (old_epoch + 1) % kEpochs) << "frame " << f << " pixel " << i;
        ASSERT_GE(s.entries[i].count, 1) << "frame " << f << " pixel " << i;
        ASSERT_LE(s.entries[i].count, f + 1) << "frame " << f << " pixel " << i;
      }
    }
    // Every pixel late in the second world's first frame is one of these; later, a pixel late again after an
    // on-time frame keeps its new entry (black, but of the new epoch).
    if (f == 0) {
      EXPECT_EQ(late, s.stats.late_pixels);
    }
    EXPECT_GT(late, 200000) << f;
  }
}

// trace_late_pixels on the path preset: the late pixels are traced (the workers' counts grow by their work) but
// their samples never reach frame memory or the screen: pixels, late pixels and lines, rays and frame memory are
// the same with it as without, frame after frame, in both models; the demand is the same in both models, and
// traced at least the untraced lower bound.
TEST(PathDevice, TracingLatePixelsChangesNothingShown) {
  const DevicePreset off = path_with(1, 2, 16);
  DevicePreset on = off;
  on.trace_late_pixels = true;
  constexpr int kFrames = kSanitized ? 1 : 2;
  std::vector<std::vector<Shot>> shots;  // plain off, plain on, fast off, fast on; a shot a frame
  for (const DeviceModel model : {DeviceModel::kPlain, DeviceModel::kFast}) {
    for (const DevicePreset* p : std::array<const DevicePreset*, 2>{&off, &on}) {
      Device dev(*p, link::WireVersion::kV2, 2, model);
      dev.transfer(path_frame_of(*p, 1, mixed_world()));
      shots.emplace_back();
      for (int f = 0; f < kFrames; ++f) shots.back().push_back(shoot(dev));
    }
  }
  for (int f = 0; f < kFrames; ++f) {
    const Shot& want = shots[0][static_cast<std::size_t>(f)];
    EXPECT_GT(want.stats.late_lines, 0) << f;
    for (std::size_t i = 1; i < shots.size(); ++i) {
      const Shot& got = shots[i][static_cast<std::size_t>(f)];
      ASSERT_EQ(got.pixels, want.pixels) << "run " << i << " frame " << f;
      ASSERT_EQ(got.entries, want.entries) << "run " << i << " frame " << f;
      EXPECT_EQ(got.stats.late_pixels, want.stats.late_pixels) << "run " << i << " frame " << f;
      EXPECT_EQ(got.stats.late_lines, want.stats.late_lines) << "run " << i << " frame " << f;
      EXPECT_EQ(got.stats.rays, want.stats.rays) << "run " << i << " frame " << f;
      EXPECT_EQ(got.stats.samples_per_pixel, want.stats.samples_per_pixel) << "run " << i << " frame " << f;
    }
    const auto stats = [&](std::size_t run) { return shots[run][static_cast<std::size_t>(f)].stats; };
    EXPECT_EQ(stats_text(stats(0)), stats_text(stats(2))) << f;
    EXPECT_EQ(stats_text(stats(1)), stats_text(stats(3))) << f;
    EXPECT_GT(stats(0).worst_line_cycles, off.lead_cycles) << f;
    EXPECT_LT(stats(0).worst_line_cycles, stats(1).worst_line_cycles) << f;
    EXPECT_GT(stats(1).path.samples, stats(0).path.samples) << f;  // the late pixels' work counts
    EXPECT_EQ(stats(1).path.samples, 640u * 480u) << f;
  }
}

// The receiver refuses a dielectric whose index of refraction the path preset cannot take (outside 0.25..8: its
// eta tables and Schlick's r0 are computed for that range); the world on screen stays, and keeps accumulating
// as on a device that never saw the refused frames. The bounds themselves are accepted, and other materials carry
// any index (they do not use it).
TEST(PathDevice, TheReceiverRefusesAnIndexOfRefractionOutOfRange) {
  const DevicePreset p = path_with(1, 4);
  Device dev(p, link::WireVersion::kV2, 2);
  Device reference(p, link::WireVersion::kV2, 2);
  dev.transfer(path_frame_of(p, 1, mixed_world()));
  reference.transfer(path_frame_of(p, 1, mixed_world()));
  shoot(dev);
  shoot(reference);
  std::uint64_t rejected = 0;
  for (const std::uint16_t ior : {std::uint16_t(kPathIorMin - 1), std::uint16_t(kPathIorMax + 1), std::uint16_t(1),
                                  std::uint16_t(65535)}) {
    std::vector<PathBall> bad = mixed_world();
    bad[2].ior = ior;  // the glass ball
    dev.transfer(path_frame_of(p, 2, bad));
    ++rejected;
    EXPECT_EQ(dev.receiver_stats().frames_rejected, rejected) << ior;
    EXPECT_NE(dev.receiver_stats().last_error.find("index of refraction"), std::string::npos)
        << dev.receiver_stats().last_error;
    EXPECT_NE(dev.receiver_stats().last_error.find("sphere 2"), std::string::npos) << dev.receiver_stats().last_error;
  }
  EXPECT_TRUE(dev.ready());  // nothing waits for the swap
  const Shot got = shoot(dev), want = shoot(reference);
  EXPECT_EQ(got.stats.sequence, 1u);
  EXPECT_EQ(got.stats.samples_per_pixel, 2);
  EXPECT_EQ(stats_text(got.stats), stats_text(want.stats));
  EXPECT_TRUE(got.pixels == want.pixels);
  EXPECT_TRUE(got.entries == want.entries);
  EXPECT_EQ(dev.receiver_stats().worlds_accepted, 1u);
  // Both ends of the range, and indices no dielectric may have on a lambertian and a metal sphere: accepted and
  // traced.
  std::vector<PathBall> edge = mixed_world();
  edge[2].ior = kPathIorMin;
  edge.push_back({{-420, -150, 700, 90}, kDielectric, {255, 255, 255}, 0, kPathIorMax});
  edge[0].ior = 1;
  edge[1].ior = 65535;
  dev.transfer(path_frame_of(p, 3, edge));
  EXPECT_EQ(dev.receiver_stats().frames_rejected, rejected) << dev.receiver_stats().last_error;
  EXPECT_EQ(dev.receiver_stats().worlds_accepted, 2u);
  const Shot s = shoot(dev);
  EXPECT_EQ(s.stats.sequence, 3u);
  EXPECT_EQ(s.stats.samples_per_pixel, 1);
  EXPECT_GT(s.stats.path.refracted, 0u);
}

// The board's v1 words carry no material: the path preset normal-shades them exactly as the wide preset does (one
// lambertian sphere; wide's mirrors never come into it), and leaves frame memory and the path counts alone.
TEST(PathDevice, V1WordsAreNormalShadedAsOnTheWidePreset) {
  std::vector<std::uint8_t> bytes;
  link::append_v1_bytes(0x0320032025804000u, bytes);  // centre (100, 50, 300), radius 16
  Device path(path_preset(), link::WireVersion::kV1, 2);
  Device wide(wide_preset(), link::WireVersion::kV1, 2);
  for (int round = 0; round < 2; ++round) {
    path.transfer(bytes);
    wide.transfer(bytes);
    FrameStats ps, ws;
    const auto got = testing::visible_pixels(path, &ps);
    const auto want = testing::visible_pixels(wide, &ws);
    EXPECT_TRUE(got == want) << round;
    EXPECT_EQ(ps.late_pixels, 0);
    EXPECT_EQ(ps.rays, 0u);
    EXPECT_EQ(ps.samples_per_pixel, 0);
    EXPECT_EQ(ps.path.samples, 0u);
    if (round == 0) {
      EXPECT_EQ(got[240 * 640 + 320], core::kBackground);
    }
    for (const AccumEntry& e : path.frame_memory()->entries()) ASSERT_EQ(e.count, 0);
    // The second round: the board's example of a sphere straight ahead, its point facing the camera 0x770.
    bytes.clear();
    link::append_v1_bytes(link::encode_v1_word({0, 0, 400 * 8, 6, 0xFFF}), bytes);
  }
  const auto again = testing::visible_pixels(path);
  EXPECT_EQ(again[240 * 640 + 320], core::Rgb444(0x770));
}

// With the fixed-point checks compiled in (TRIPSITTER_CHECK_FIXED), no check fires on valid worlds of the path
// preset: random ones with every material and the deepest paths, and worlds at the formats' limits of glass and
// mirrors around and in front of the camera. Without them nothing could fire, and the test could not fail.
TEST(PathDevice, NoFixedPointCheckFiresOnValidWorlds) {
  if (!kCheckFixed) GTEST_SKIP() << "built without TRIPSITTER_CHECK_FIXED";
  const DevicePreset p = path_preset();
  const Controller plain(p);
  FastTracer fast(p);
  std::mt19937_64 rng(99);
  std::uniform_int_distribution<std::int64_t> x(p.x.min_raw(), p.x.max_raw()), y(p.y.min_raw(), p.y.max_raw()),
      z(p.z.min_raw(), p.z.max_raw()), radius(1, p.radius.max_raw());
  std::uint64_t samples = 0;
  for (int world = 0; world < (kSanitized ? 16 : 40); ++world) {
    SceneMemory scene;
    if (world % 2 == 0) {
      scene = testing::random_path_world(p, rng, 24);
    } else {  // at the limits: a giant around the camera, the largest and farthest spheres the formats hold
      scene.valid = true;
      scene.geometry.push_back({{0, 0, p.z.max_raw() / 2}, p.radius.max_raw()});
      scene.geometry.push_back({{0, 0, 0}, p.radius.max_raw() / (1 + static_cast<std::int64_t>(rng() % 1000))});
      for (int i = 0; i < 10; ++i) scene.geometry.push_back({{x(rng), y(rng), z(rng)}, radius(rng)});
      for (std::size_t i = 0; i < scene.geometry.size(); ++i) {
        SurfaceWord s = testing::random_path_surface(rng);
        s.material = i % 2 == 0 ? kDielectric : kMetal;
        scene.surfaces.push_back(s);
      }
    }
    std::vector<PathSurface> surfaces;
    for (const SurfaceWord& w : scene.surfaces) surfaces.push_back(path_surface(w));
    PathFrame frame;
    frame.surfaces = surfaces;
    frame.epoch = 1;
    frame.spp = 2;
    frame.depth = kMaxPathDepth;
    ASSERT_NO_THROW(fast.load(scene)) << world;
    for (int k = 0; k < 3; ++k) {
      const int row = static_cast<int>(rng() % 480);
      std::vector<AccumEntry> memory(kLineWidth);
      std::array<core::Rgb444, kLineWidth> line;
      PathCounters counters;
      ASSERT_NO_THROW(plain.render_path_line(row, scene, frame, memory, line, counters)) << world << " row " << row;
      ASSERT_NO_THROW(fast.render_path_line(row, frame, memory, line, counters)) << world << " row " << row;
      samples += counters.samples;
    }
  }
  EXPECT_GT(samples, 10000u);
  // And a whole frame through the device, its lines ahead of the beam on two threads.
  std::mt19937_64 world_rng(5);
  Device dev(p, link::WireVersion::kV2, 2);
  dev.transfer(testing::frame_of_scene(p, 1, testing::random_path_world(p, world_rng, 24)));
  ASSERT_NO_THROW(shoot(dev));
}

}  // namespace
}  // namespace tripsitter::device

// ts_scanout (VGA timing, line buffers, controller) against the C++ model, sample by sample over whole frames:
// first with line contents the test chooses, against device::VgaTimingGenerator; then with workers that compute
// the device model's own pixels, against device::Device itself (every sample of two frames, late pixels included).
#include <array>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/device/device.h>
#include <tripsitter/device/vga.h>
#include <tripsitter/device/worker.h>
#include <tripsitter/link/frame.h>

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
using device::VgaSample;
using testing::BenchConfig;
using testing::Job;
using testing::PlacedSample;
using testing::ScanoutBench;

constexpr std::int64_t kFrameSamples = 800 * 525;

std::string describe(const VgaSample& s) {
  char text[64];
  std::snprintf(text, sizeof text, "hsync_n %d vsync_n %d colour 0x%03X", s.hsync_n ? 1 : 0, s.vsync_n ? 1 : 0,
                static_cast<unsigned>(s.colour.packed));
  return text;
}

BenchConfig board(int workers) {
  return {.workers = workers, .lead_cycles = 3000, .drain = 0, .flush = false, .speculative = false};
}
BenchConfig wide(int workers, bool flush = true, bool speculative = false) {
  return {.workers = workers, .lead_cycles = 3200, .drain = 35, .flush = flush, .speculative = speculative};
}

// The colour a test image has at (frame, row, col): never black, so a black pixel on screen is one not written.
core::Rgb444 image_colour(int frame, int row, int col) {
  std::uint32_t h = static_cast<std::uint32_t>(frame * 1000003 + row * 7919 + col * 104729) * 2654435761u;
  h ^= h >> 15;
  return core::Rgb444(static_cast<std::uint16_t>(1 + h % 4095));
}

// Two frames of samples from reset, one image per frame, workers taking one cycle a pixel (the wide preset with
// one sphere: every pixel on time), against the timing generator as the model's Device starts it (line 480).
template <class V>
void expect_frames_equal_the_timing_generator(const BenchConfig& config) {
  int job_frame = 0;
  ScanoutBench<V> bench(
      config,
      [&](int row, int col) {
        if (row == 0 && col == 0) ++job_frame;
        return Job{image_colour(job_frame, row, col), 1};
      },
      [](int) { return std::uint16_t{1}; });
  device::VgaTimingGenerator timing;
  while (timing.line() != timing.mode().v_visible) timing.tick();
  int sample_frame = 0;
  std::int64_t samples = 0, visible = 0, hsync_low = 0, vsync_low = 0;
  bool failed = false;
  bench.on_sample = [&](const PlacedSample& s) {
    if (s.line == 0 && s.column == 0) ++sample_frame;
    const VgaSample want = timing.sample(image_colour(sample_frame, timing.line(), timing.column()));
    if (!failed && (s.line != timing.line() || s.column != timing.column() || !(s.sample == want))) {
      failed = true;
      ADD_FAILURE() << "sample " << samples << ": RTL at line " << s.line << " column " << s.column << ": "
                    << describe(s.sample) << "; model at line " << timing.line() << " column " << timing.column()
                    << ": " << describe(want);
    }
    visible += timing.visible() ? 1 : 0;
    hsync_low += want.hsync_n ? 0 : 1;
    vsync_low += want.vsync_n ? 0 : 1;
    ++samples;
    timing.tick();
  };
  bench.run_samples(2 * kFrameSamples);
  EXPECT_EQ(samples, 2 * kFrameSamples);
  EXPECT_EQ(visible, 2 * 640 * 480);
  EXPECT_EQ(hsync_low, 2 * 96 * 525);
  EXPECT_EQ(vsync_low, 2 * 2 * 800);
  EXPECT_EQ(sample_frame, 2);
  EXPECT_FALSE(bench.protocol_error());
  EXPECT_EQ(bench.bad_starts(), 0);
  EXPECT_TRUE(bench.busy_at_open().empty());
}

TEST(RtlScanout, TwoFramesEqualTheTimingGeneratorWithTenWorkers) {
  expect_frames_equal_the_timing_generator<Vrtl_scanout_n10_wide>(wide(10));
}
TEST(RtlScanout, TwoFramesEqualTheTimingGeneratorWithSevenWorkers) {
  expect_frames_equal_the_timing_generator<Vrtl_scanout_n7_wide>(wide(7));
}
TEST(RtlScanout, TwoFramesEqualTheTimingGeneratorWithOneWorker) {
  expect_frames_equal_the_timing_generator<Vrtl_scanout_n1_wide>(wide(1));
}

// --- Against device::Device ---

// A world's frame on the v2 wire: spheres in pixel units, metals where `metal` says, albedo as given.
struct Sphere {
  double x, y, z, r;
  bool metal = false;
  std::array<std::uint8_t, 3> albedo{200, 200, 200};
};

std::vector<std::uint8_t> world_frame(const DevicePreset& p, const std::vector<Sphere>& spheres) {
  link::World w;
  w.sequence = 1;
  w.frac_bits = static_cast<std::uint8_t>(p.frac_bits());
  for (const Sphere& s : spheres) {
    link::WireSphere ws;
    ws.x = static_cast<std::int32_t>(p.x.quantize(s.x).raw);
    ws.y = static_cast<std::int32_t>(p.y.quantize(s.y).raw);
    ws.z = static_cast<std::int32_t>(p.z.quantize(s.z).raw);
    ws.radius = static_cast<std::uint32_t>(p.radius.quantize(s.r).raw);
    ws.material = s.metal ? link::kMaterialMetal : link::kMaterialLambertian;
    ws.albedo = s.albedo;
    ws.ior = 6144;
    w.spheres.push_back(ws);
  }
  return link::encode_frame(link::WireVersion::kV2, w);
}

std::vector<Sphere> random_world(std::uint32_t seed, int count, double metal_share) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> xy(-300, 300), z(200, 1200), r(10, 90), u(0, 1);
  std::uniform_int_distribution<int> albedo(60, 255);
  std::vector<Sphere> spheres;
  for (int i = 0; i < count; ++i) {
    Sphere s{xy(rng), xy(rng), z(rng), r(rng)};
    s.metal = u(rng) < metal_share;
    s.albedo = {static_cast<std::uint8_t>(albedo(rng)), static_cast<std::uint8_t>(albedo(rng)),
                static_cast<std::uint8_t>(albedo(rng))};
    spheres.push_back(s);
  }
  return spheres;
}

struct CoSimResult {
  int late_pixels[2] = {0, 0};  // the RTL's, per frame
  int late_lines[2] = {0, 0};
  device::FrameStats model[2];
  std::int64_t reflections = 0;  // in the pixels the workers were given
};

// Two frames of the device model with `world`, and two frames of the RTL from reset whose workers return the
// model worker's pixels (device::Worker::trace on the device's scene memory) on the model's schedule: every sample
// must be the same. preset.workers is the RTL's N.
template <class V>
CoSimResult expect_frames_equal_the_device(const DevicePreset& preset, const BenchConfig& config,
                                           const std::vector<Sphere>& world) {
  EXPECT_EQ(preset.workers, config.workers);
  device::Device model(preset, link::WireVersion::kV2, 1);
  model.transfer(world_frame(preset, world));
  std::vector<VgaSample> expected;
  expected.reserve(2 * kFrameSamples);
  CoSimResult result;
  for (int f = 0; f < 2; ++f) result.model[f] = model.run_frame([&](const VgaSample& s) { expected.push_back(s); });
  EXPECT_TRUE(result.model[0].has_world);

  const device::SceneMemory& scene = model.scene();
  const std::int64_t spheres = static_cast<std::int64_t>(scene.geometry.size());
  EXPECT_EQ(spheres, static_cast<std::int64_t>(world.size()));
  const device::Worker worker(preset);
  std::vector<core::PixelTrace> traces(640 * 480);
  for (int row = 0; row < 480; ++row)
    for (int col = 0; col < 640; ++col) traces[static_cast<std::size_t>(row * 640 + col)] = worker.trace(col, row, scene);

  ScanoutBench<V> bench(
      config,
      [&](int row, int col) {
        const core::PixelTrace& t = traces[static_cast<std::size_t>(row * 640 + col)];
        result.reflections += t.bounces;
        return Job{t.colour, preset.pixel_occupancy(spheres, t.bounces)};
      },
      [&](int) { return static_cast<std::uint16_t>(preset.pixel_occupancy(spheres, 0)); });
  std::size_t k = 0;
  bool failed = false;
  bench.on_sample = [&](const PlacedSample& s) {
    if (!failed && k < expected.size() && !(s.sample == expected[k])) {
      failed = true;
      ADD_FAILURE() << "sample " << k << " (line " << s.line << ", column " << s.column << "): RTL "
                    << describe(s.sample) << ", model " << describe(expected[k]);
    }
    ++k;
  };
  int window = 0;
  bench.on_late = [&](int late) {
    const int frame = window++ / 480;
    if (frame > 1) return;
    result.late_pixels[frame] += late;
    result.late_lines[frame] += late > 0 ? 1 : 0;
  };
  bench.run_samples(2 * kFrameSamples);
  EXPECT_EQ(k, expected.size());
  for (int f = 0; f < 2; ++f) {
    EXPECT_EQ(result.late_pixels[f], result.model[f].late_pixels) << "frame " << f;
    EXPECT_EQ(result.late_lines[f], result.model[f].late_lines) << "frame " << f;
  }
  EXPECT_FALSE(bench.protocol_error());
  EXPECT_EQ(bench.bad_starts(), 0);
  return result;
}

DevicePreset with_workers(DevicePreset p, int workers) {
  p.workers = workers;
  return p;
}

const std::vector<Sphere> kDemo = {{0, 0, 400, 64}};

// The board's demo: 51 cycles a pixel, a 3000-cycle lead, 58 pixels per worker: columns 580..639 black.
TEST(RtlScanout, EqualsTheDeviceOnTheBoardsDemo) {
  const CoSimResult r = expect_frames_equal_the_device<Vrtl_scanout_n10_board>(device::board_2023_preset(), board(10), kDemo);
  EXPECT_EQ(r.late_pixels[0], 60 * 480);
}

TEST(RtlScanout, EqualsTheDeviceOnTheBoardWithSevenWorkers) {
  const CoSimResult r = expect_frames_equal_the_device<Vrtl_scanout_n7_board>(
      with_workers(device::board_2023_preset(), 7), board(7), random_world(5, 3, 0.0));
  EXPECT_GT(r.late_pixels[0], 0);
}

TEST(RtlScanout, EqualsTheDeviceOnTheBoardWithOneWorker) {
  const CoSimResult r =
      expect_frames_equal_the_device<Vrtl_scanout_n1_board>(with_workers(device::board_2023_preset(), 1), board(1), kDemo);
  EXPECT_EQ(r.late_pixels[0], (640 - 58) * 480);
}

// Two nearly flat mirrors around the camera: every pixel reflects 3 times (131 cycles), 24 pixels per worker on
// time, and the 25th, started in time, runs past the line's end: the workers are flushed.
TEST(RtlScanout, EqualsTheDeviceWithMirrorsOnEveryPixel) {
  const std::vector<Sphere> mirrors = {{0, 0, 100000, 99000, true, {255, 255, 255}},
                                       {0, 0, -100000, 99000, true, {200, 200, 200}}};
  const CoSimResult r = expect_frames_equal_the_device<Vrtl_scanout_n10_wide>(device::wide_preset(), wide(10), mirrors);
  EXPECT_EQ(r.late_pixels[0], 400 * 480);
}

// The same with workers that start pixels ahead of the model's schedule (as ts_worker does) and keep to it.
TEST(RtlScanout, EqualsTheDeviceWithMirrorsAndSpeculativeWorkers) {
  const std::vector<Sphere> mirrors = {{0, 0, 100000, 99000, true, {255, 255, 255}},
                                       {0, 0, -100000, 99000, true, {200, 200, 200}}};
  const CoSimResult r =
      expect_frames_equal_the_device<Vrtl_scanout_n10_wide>(device::wide_preset(), wide(10, true, true), mirrors);
  EXPECT_EQ(r.late_pixels[0], 400 * 480);
}

TEST(RtlScanout, EqualsTheDeviceWithMetalsAndSevenWorkers) {
  const CoSimResult r = expect_frames_equal_the_device<Vrtl_scanout_n7_wide>(with_workers(device::wide_preset(), 7),
                                                                             wide(7), random_world(11, 14, 0.5));
  EXPECT_GT(r.reflections, 1000);
  EXPECT_GT(r.late_lines[0], 0);
  EXPECT_LT(r.late_lines[0], 480);
}

TEST(RtlScanout, EqualsTheDeviceWithAMetalSphereAndOneSpeculativeWorker) {
  const CoSimResult r = expect_frames_equal_the_device<Vrtl_scanout_n1_wide>(
      with_workers(device::wide_preset(), 1), wide(1, true, true), {{0, 0, 400, 64, true, {255, 170, 128}}});
  EXPECT_GT(r.reflections, 1000);
  EXPECT_GT(r.late_lines[0], 0);
  EXPECT_LT(r.late_lines[0], 480);
}

// 60 spheres without metal: 64 x 60 + 35 > 3200, so every line is late, and no worker outlives its window even
// without flush (no pixel is started that cannot be on time).
TEST(RtlScanout, EqualsTheDeviceWithSixtySpheresWithoutFlush) {
  const CoSimResult r = expect_frames_equal_the_device<Vrtl_scanout_n10_wide_noflush>(
      device::wide_preset(), wide(10, false), random_world(3, 60, 0.0));
  EXPECT_EQ(r.late_lines[0], 480);
}

}  // namespace
}  // namespace tripsitter::rtl

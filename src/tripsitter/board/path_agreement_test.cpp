// The path presets' devices (`path`, and `artix-path` on the sphere units, its bounced rays walking the hierarchy
// the host sends) against the float path tracer of the device's own rays (render::render_device_view): the same
// world gives the same picture in distribution, material by material (fixed seeds: nothing flakes); and the
// device's white furnace, exactly.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/core/parallel.h>
#include <tripsitter/core/sanitizers.h>
#include <tripsitter/core/screen.h>
#include <tripsitter/device/device.h>
#include <tripsitter/device/test_util.h>
#include <tripsitter/host/hierarchy.h>
#include <tripsitter/link/frame.h>
#include <tripsitter/render/device_view.h>
#include <tripsitter/render/path_tracer.h>
#include <tripsitter/render/rng.h>

namespace tripsitter {
namespace {

using device::testing::PathBall;

using core::kSanitized;

constexpr int kWidth = core::kScreenWidth, kHeight = core::kScreenHeight;
constexpr std::size_t kPixels = std::size_t{kWidth} * kHeight;
constexpr std::uint8_t kLambertian = link::kMaterialLambertian, kMetal = link::kMaterialMetal,
                       kDielectric = link::kMaterialDielectric;

using Channels = std::array<double, 3>;

// Per pixel and channel: the mean of its samples, and the variance of that mean (estimated from the samples).
struct Estimate {
  std::vector<Channels> mean = std::vector<Channels>(kPixels);
  std::vector<Channels> var_of_mean = std::vector<Channels>(kPixels);
};

device::DevicePreset agreement_preset(const device::DevicePreset& base, int spp, int depth) {
  device::DevicePreset p = base;
  p.path->spp = spp;
  p.path->depth = depth;
  p.workers = 640;  // a pixel a worker (a unit a column): none late (the count changes nothing else; path_test.cpp)
  // and a bounce stage each (640 units sharing one would each have a cycle of it in 640).
  if (p.units) p.units->shared_bounce = false;
  return p;
}

// The world's frame as the host sends it to the preset: v2 for `path`; v3 with the hierarchy for `artix-path`.
std::vector<std::uint8_t> world_frame(const device::DevicePreset& p, const std::vector<PathBall>& balls) {
  const std::vector<std::uint8_t> v2 = device::testing::path_frame_of(p, 1, balls);
  if (!p.walks_hierarchy()) return v2;
  link::World w = link::decode_frame(link::WireVersion::kV2, v2, p.max_spheres).value();
  w.session = 1;
  link::SceneFormats formats{p.x, p.y, p.z, p.radius, p.max_spheres};
  formats.hierarchy = true;
  host::attach_hierarchy(w, host::build_hierarchy(w.spheres, formats));
  return link::encode_frame(link::WireVersion::kV3, w);
}

// The device's picture: `frames` frames of `spp` samples, accumulated in frame memory. The variance of each
// pixel's mean comes from its frames: each frame's samples (the difference of the entry's sums) are one batch
// mean, and frames are independent (their samples draw from streams of their own), so var(mean) = var(batch) /
// frames. Also returns the world as scene memory holds it.
Estimate run_device(const device::DevicePreset& base, const std::vector<PathBall>& balls, int spp, int frames,
                    int depth, device::SceneMemory& scene, device::PathCounters* counters = nullptr) {
  const device::DevicePreset p = agreement_preset(base, spp, depth);
  device::Device dev(p, p.walks_hierarchy() ? link::WireVersion::kV3 : link::WireVersion::kV2, 0);
  dev.transfer(world_frame(p, balls));
  std::vector<Channels> sum(kPixels), sum2(kPixels);
  std::vector<device::AccumEntry> previous(kPixels);
  for (int f = 0; f < frames; ++f) {
    const device::FrameStats stats = dev.run_frame([](const device::VgaSample&) {});
    // Every pixel on time, so every pixel has every sample (a pixel always late would have none).
    EXPECT_EQ(stats.late_pixels, 0) << "frame " << f;
    if (counters) *counters += stats.path;
    const auto entries = dev.frame_memory()->entries();
    for (std::size_t i = 0; i < kPixels; ++i) {
      if (entries[i].count != (f + 1) * spp) {
        ADD_FAILURE() << "frame " << f << " pixel " << i << " has " << int{entries[i].count} << " samples";
        return {};
      }
      for (std::size_t k = 0; k < 3; ++k) {
        const double batch = (entries[i].sum[k] - (f > 0 ? previous[i].sum[k] : 0u)) / (512.0 * spp);
        sum[i][k] += batch;
        sum2[i][k] += batch * batch;
      }
      previous[i] = entries[i];
    }
  }
  scene = dev.scene();
  Estimate e;
  for (std::size_t i = 0; i < kPixels; ++i) {
    const Channels whole = device::entry_mean(previous[i]);
    for (std::size_t k = 0; k < 3; ++k) {
      e.mean[i][k] = sum[i][k] / frames;
      if (std::abs(e.mean[i][k] - whole[k]) > 1e-12) {
        ADD_FAILURE() << "pixel " << i << ": the frames add up to another mean than the entry's";
        return {};
      }
      const double var_batch = std::max(0.0, (sum2[i][k] - frames * e.mean[i][k] * e.mean[i][k]) / (frames - 1));
      e.var_of_mean[i][k] = var_batch / frames;
    }
  }
  return e;
}

// Scene memory as the float path tracer takes it (modes::scene_memory_spheres' reading), in pixel units:
// albedo byte / 255 (the device multiplies by it within 2^-16, path_kernel.h), fuzz / 65535, ior / 4096. (An albedo
// off by 1/256 of itself, as the device's once was, (a + a/128) / 256, fails this test: mean square z-scores of 3
// to 7, blocks off by 0.002.)
std::vector<scene::Sphere> float_world(const device::SceneMemory& memory, int frac_bits) {
  const double unit = std::ldexp(1.0, -frac_bits);
  std::vector<scene::Sphere> out;
  for (std::size_t i = 0; i < memory.geometry.size(); ++i) {
    const auto& g = memory.geometry[i];
    const device::SurfaceWord& w = memory.surfaces[i];
    scene::Sphere s;
    s.center = {static_cast<double>(g.center.x) * unit, static_cast<double>(g.center.y) * unit,
                static_cast<double>(g.center.z) * unit};
    s.radius = static_cast<double>(g.radius) * unit;
    s.material.type = w.material == kMetal        ? scene::MaterialType::kMetal
                      : w.material == kDielectric ? scene::MaterialType::kDielectric
                                                  : scene::MaterialType::kLambertian;
    s.material.albedo = {w.albedo[0] / 255.0, w.albedo[1] / 255.0, w.albedo[2] / 255.0};
    s.material.fuzz = w.fuzz / link::kFuzzScale;
    s.material.ior = w.ior / link::kIorScale;
    out.push_back(s);
  }
  return out;
}

// A float sample's channel as the device stores a sample (device::sample_channel): light times 512, rounded, at
// most 511. The device's known quantisation bias: a stored sample is off by -1/1024..+1/1024 from rounding, and
// down to -1/512 where the light is 511.5/512 or more, clamped to 511 (the sky's blue is exactly 1 everywhere and is
// stored as 511/512). On means that is a bias of up to 1/1024, 1/512 on the sky's blue: as large as the differences
// this test is after. So the float side stores its samples alike, and the comparison is of the paths' light
// distributions alone (the bias itself is exact and deterministic, not something to estimate).
double quantised(float light) { return std::min(511.0, std::floor(static_cast<double>(light) * 512.0 + 0.5)) / 512.0; }

// The float path tracer's picture of the device's rays, sample by sample exactly as render_device_view draws them
// (the same streams, the same mirroring of view space; DeviceViewIsThisLoop checks it): `raw` the mean as
// render_device_view gives it; the returned estimate of each sample stored as the device stores one (quantised).
Estimate run_float(const std::vector<scene::Sphere>& view, int spp, int depth, std::uint64_t seed,
                   core::ImageRgbF* raw = nullptr) {
  std::vector<scene::Sphere> mirrored = view;  // mirrored in y and scaled down, as render_device_view does
  const double scale = 1.0 / render::kDeviceViewPixelsPerUnit;
  for (auto& s : mirrored) {
    s.center = {s.center.x * scale, -s.center.y * scale, s.center.z * scale};
    s.radius *= scale;
  }
  const render::PathScene scene(mirrored);
  const render::RngStreams streams(seed);
  const render::Sky sky;
  Estimate e;
  if (raw) *raw = {kWidth, kHeight, std::vector<render::Vec3f>(kPixels)};
  const float inv_spp = 1.0f / static_cast<float>(spp);
  core::parallel_for(0, kHeight, 0, [&](int row) {
    for (int col = 0; col < kWidth; ++col) {
      const auto pixel = static_cast<std::size_t>(row) * kWidth + static_cast<std::size_t>(col);
      render::Rng rng = streams.stream(pixel);
      const render::Vec3f d = core::device_ray<float>(col, row);
      const render::Ray ray{{0, 0, 0}, {d.x, -d.y, d.z}};
      render::Vec3f sum{0, 0, 0};
      Channels q{}, q2{};
      for (int s = 0; s < spp; ++s) {
        const render::Vec3f light = render::trace_path(scene, ray, depth, sky, rng);
        sum += light;
        for (int k = 0; k < 3; ++k) {
          const double v = quantised(light[k]);
          q[static_cast<std::size_t>(k)] += v;
          q2[static_cast<std::size_t>(k)] += v * v;
        }
      }
      if (raw) raw->pixels[pixel] = sum * inv_spp;
      for (std::size_t k = 0; k < 3; ++k) {
        const double mean = q[k] / spp;
        e.mean[pixel][k] = mean;
        e.var_of_mean[pixel][k] = std::max(0.0, (q2[k] - spp * mean * mean) / (spp - 1)) / spp;
      }
    }
  });
  return e;
}

// How far the device's arithmetic may move a mean beyond sampling noise, once both sides' samples are stored alike:
// its unit vectors, cosines and reflectances are rounded to 2^-14, the sky's blend to 2^-14 of its direction, the
// throughput to 2^-16 a bounce, hit points to the position grid (1/16 pixel). Each moves a sample's light by
// about 10^-4, so a stored sample crosses a rounding boundary of 1/512 with probability about 10^-4 * 512 = 5%:
// about 10^-4 on a mean. 2^-10 leaves a margin of ten; a real difference in distribution (a wrong reflectance,
// fuzz or albedo) moves means of whole blocks by 10^-2.
constexpr double kArithmetic = 1.0 / 1024.0;
constexpr double kSigmas = 5.0;

struct Agreement {
  double worst_excess = -1;  // max over blocks and channels of |diff| - tolerance (<= 0: all within)
  double max_z = 0;          // max |diff| / se over blocks with noise
  double mean_z2 = 0;        // mean of (diff / se)^2 over blocks with noise: about 1 when they agree
  double whole[3] = {0, 0, 0};
  std::string worst;
};

// Block means of the two estimates, per channel, block x block pixels at a time (and the whole image as one block):
// each must be within kSigmas standard errors of the difference (from both sides' variances) plus kArithmetic.
Agreement compare_blocks(const Estimate& dev, const Estimate& flt, int block, const std::string& name) {
  Agreement a;
  int noisy = 0;
  const auto check = [&](int x0, int y0, int w, int h, const std::string& where) {
    Channels dm{}, dv{}, fm{}, fv{};
    for (int y = y0; y < y0 + h; ++y)
      for (int x = x0; x < x0 + w; ++x) {
        const auto i = static_cast<std::size_t>(y) * kWidth + static_cast<std::size_t>(x);
        for (std::size_t k = 0; k < 3; ++k) {
          dm[k] += dev.mean[i][k];
          dv[k] += dev.var_of_mean[i][k];
          fm[k] += flt.mean[i][k];
          fv[k] += flt.var_of_mean[i][k];
        }
      }
    const double n = static_cast<double>(w) * h;
    for (std::size_t k = 0; k < 3; ++k) {
      const double diff = (dm[k] - fm[k]) / n, se = std::sqrt((dv[k] + fv[k]) / (n * n));
      const double excess = std::abs(diff) - (kSigmas * se + kArithmetic);
      EXPECT_LE(excess, 0) << name << " " << where << " channel " << k << ": device " << dm[k] / n << ", float "
                           << fm[k] / n << ", standard error " << se;
      if (excess > a.worst_excess || a.worst.empty()) {
        a.worst_excess = excess;
        a.worst =
            where + " channel " + std::to_string(k) + " diff " + std::to_string(diff) + " se " + std::to_string(se);
      }
      if (w == kWidth && h == kHeight) a.whole[k] = diff;
      if (se > 1e-4) {
        ++noisy;
        a.max_z = std::max(a.max_z, std::abs(diff) / se);
        a.mean_z2 += diff * diff / (se * se);
      }
    }
  };
  for (int y = 0; y < kHeight; y += block)
    for (int x = 0; x < kWidth; x += block)
      check(x, y, block, block, "block (" + std::to_string(x) + ", " + std::to_string(y) + ")");
  check(0, 0, kWidth, kHeight, "whole image");
  if (noisy > 0) a.mean_z2 /= noisy;
  return a;
}

// Device and float at the same depth and sample count, compared in 32 x 32 blocks. The device's samples come 2 a
// frame: with 640 workers each pixel then has a whole line's time, so none is late even at depth 6 (and the frames
// are batches enough for a good estimate of the device's variance).
void expect_agreement(const std::string& name, const std::vector<PathBall>& balls, int depth,
                      const device::DevicePreset& base = device::path_preset()) {
  const int frames = kSanitized ? 4 : 16, spp = 2;
  device::SceneMemory memory;
  device::PathCounters counters;
  const Estimate dev = run_device(base, balls, spp, frames, depth, memory, &counters);
  if (::testing::Test::HasFailure()) return;
  if (base.walks_hierarchy() && balls.size() > host::kFlatWorldSpheres) {
    EXPECT_FALSE(memory.hierarchy.empty()) << name << ": the host sent no hierarchy";
  }
  const Estimate flt = run_float(float_world(memory, base.frac_bits()), spp * frames, depth, 1);
  const Agreement a = compare_blocks(dev, flt, 32, name);
  // The figures, for whoever tunes the device (the z-scores of noisy blocks should look standard normal).
  std::printf("%s: worst %s (excess %.5f); max |z| %.2f, mean z^2 %.2f; whole image diff %.5f %.5f %.5f\n",
              name.c_str(), a.worst.c_str(), a.worst_excess, a.max_z, a.mean_z2, a.whole[0], a.whole[1], a.whole[2]);
  std::printf("%s: device samples %llu, rays %llu, lambertian %llu, metal %llu, dielectric %llu (refracted %llu), "
              "absorbed %llu, cut %llu\n",
              name.c_str(), static_cast<unsigned long long>(counters.samples),
              static_cast<unsigned long long>(counters.rays), static_cast<unsigned long long>(counters.lambertian),
              static_cast<unsigned long long>(counters.metal), static_cast<unsigned long long>(counters.dielectric),
              static_cast<unsigned long long>(counters.refracted), static_cast<unsigned long long>(counters.absorbed),
              static_cast<unsigned long long>(counters.cut));
  // A device whose picture differed from the float one by a bias below the tolerance everywhere would still stand
  // out here: the mean square z-score of hundreds of noisy blocks is near 1 when the two agree.
  EXPECT_LT(a.mean_z2, 2.0) << name;
}

// A floor (a large sphere under the view: y grows downwards) and balls on it.
std::vector<PathBall> lambertian_world() {
  return {{{0, 10300, 1500, 10000}, kLambertian, {150, 150, 150}},
          {{-250, 150, 900, 150}, kLambertian, {230, 60, 60}},
          {{100, 100, 700, 200}, kLambertian, {60, 200, 90}},
          {{380, 200, 600, 100}, kLambertian, {255, 255, 255}}};
}

std::vector<PathBall> metal_world() {
  return {{{0, 10300, 1500, 10000}, kMetal, {200, 200, 200}, 19661},  // fuzz 0.3
          {{-250, 150, 900, 150}, kMetal, {255, 220, 180}, 0},
          {{100, 100, 700, 200}, kMetal, {180, 180, 255}, 39321},        // 0.6
          {{380, 200, 600, 100}, kMetal, {220, 220, 220}, 65535}};       // 1
}

std::vector<PathBall> dielectric_world() {
  return {{{0, 10300, 1500, 10000}, kDielectric, {255, 255, 255}, 0, 6144},  // glass, 1.5
          {{-250, 150, 900, 150}, kDielectric, {255, 255, 255}, 0, 9830},   // diamond, 2.4
          {{100, 100, 700, 200}, kDielectric, {200, 255, 220}, 0, 5448},    // water, 1.33
          {{380, 200, 600, 100}, kDielectric, {255, 255, 255}, 0, 2867},    // 0.7: total reflection from outside
          {{-40, -120, 500, 50}, kDielectric, {255, 255, 255}, 0, 4096}};   // 1: straight through
}

std::vector<PathBall> mixed_world() {
  return {{{0, 10300, 1500, 10000}, kLambertian, {128, 140, 110}},
          {{-250, 150, 900, 150}, kDielectric, {255, 255, 255}, 0, 6144},
          {{100, 100, 700, 200}, kMetal, {230, 200, 160}, 13107},  // fuzz 0.2
          {{380, 200, 600, 100}, kLambertian, {40, 90, 230}},
          {{-300, -100, 1200, 120}, kMetal, {255, 255, 255}, 0}};
}

// A floor and 24 balls of every material in rows on it: more than 8 spheres, so artix-path's bounced rays walk the
// hierarchy the host sends (the floor at its root, the balls in leaves).
std::vector<PathBall> crowd_world() {
  std::vector<PathBall> out = {{{0, 10300, 1500, 10000}, kLambertian, {150, 150, 150}}};
  for (int i = 0; i < 24; ++i) {
    const int row = i / 6, col = i % 6;
    const double r = 40 + 10 * (i % 3);
    PathBall b{{-300.0 + 120 * col, 300 - r, 700.0 + 150 * row, r}, kLambertian,
               {static_cast<std::uint8_t>(60 + 8 * i), 200, static_cast<std::uint8_t>(250 - 8 * i)}};
    if (i % 3 == 1) b.material = kMetal, b.fuzz = static_cast<std::uint16_t>(2000 * i);
    if (i % 3 == 2) b.material = kDielectric, b.albedo = {255, 255, 255}, b.ior = static_cast<std::uint16_t>(5000 + 200 * i);
    out.push_back(b);
  }
  return out;
}

TEST(PathAgreement, LambertianWorld) { expect_agreement("lambertian", lambertian_world(), 4); }
TEST(PathAgreement, MetalWorld) { expect_agreement("metal", metal_world(), 4); }
TEST(PathAgreement, DielectricWorld) { expect_agreement("dielectric", dielectric_world(), 6); }
TEST(PathAgreement, MixedWorld) { expect_agreement("mixed", mixed_world(), 4); }
TEST(PathAgreement, ArtixPathLambertianWorld) {
  expect_agreement("artix-path lambertian", lambertian_world(), 4, device::artix_path_preset());
}
TEST(PathAgreement, ArtixPathMetalWorld) {
  expect_agreement("artix-path metal", metal_world(), 4, device::artix_path_preset());
}
TEST(PathAgreement, ArtixPathDielectricWorld) {
  expect_agreement("artix-path dielectric", dielectric_world(), 6, device::artix_path_preset());
}
TEST(PathAgreement, ArtixPathMixedWorld) {
  expect_agreement("artix-path mixed", mixed_world(), 4, device::artix_path_preset());
}
TEST(PathAgreement, ArtixPathCrowdWalkingTheHierarchy) {
  expect_agreement("artix-path crowd", crowd_world(), 4, device::artix_path_preset());
}

// The white furnace, in the device's fixed point. An albedo byte of 255 is exactly 1 on the device (path_kernel.h),
// and a throughput times it, rounded, is exactly the throughput: a path off such spheres carries 1.0 until it
// escapes, and its light is then exactly the sky of its escape direction, or it is cut (black) after `depth` rays;
// a lambertian bounce never absorbs. The device's sky has blue 1.0 everywhere (white at the bottom, (0.5, 0.7, 1)
// at the top), stored as a sample of 512/512, clamped to 511; red and green are at least 0.5 and 0.7 (stored 256 and
// 358). So, exactly, with no tolerance:
//  - every sample's blue is 511 or 0, so a pixel's blue sum is 511 times its escaped samples, and the frame's
//    missing blue, the sum over pixels of 511 count - blue, is 511 times the cut paths (PathCounters::cut);
//  - no sample is absorbed, and every sample ends in the sky or is cut;
//  - red <= green <= blue in every sample (the blend is monotone in each channel), and red and green lie between
//    256 and 511, 358 and 511 per escaped sample.
// Shallow paths (3 rays) cut often; deep ones (16) rarely, in a cluster of touching-close balls on a white floor.
TEST(PathFurnace, WhiteSpheresReturnTheSkyExactly) {
  const std::vector<PathBall> balls{{{0, 10300, 1500, 10000}, kLambertian, {255, 255, 255}},
                                    {{0, 100, 700, 200}, kLambertian, {255, 255, 255}},
                                    {{-330, 150, 720, 130}, kLambertian, {255, 255, 255}},
                                    {{320, 170, 690, 125}, kLambertian, {255, 255, 255}},
                                    {{0, -240, 760, 100}, kLambertian, {255, 255, 255}}};
  for (const int depth : {3, 16}) {
    const device::DevicePreset p = agreement_preset(device::path_preset(), 2, depth);
    device::Device dev(p, link::WireVersion::kV2, 0);
    dev.transfer(device::testing::path_frame_of(p, 1, balls));
    std::uint64_t samples = 0, cut = 0, sky = 0, bounces = 0;
    for (int f = 0; f < 2; ++f) {
      const device::FrameStats stats = dev.run_frame([](const device::VgaSample&) {});
      ASSERT_EQ(stats.late_pixels, 0) << depth;
      EXPECT_EQ(stats.path.absorbed, 0u) << depth;
      EXPECT_EQ(stats.path.metal + stats.path.dielectric, 0u) << depth;
      samples += stats.path.samples;
      cut += stats.path.cut;
      sky += stats.path.sky;
      bounces += stats.path.lambertian;
    }
    EXPECT_EQ(samples, 2u * 2u * kPixels) << depth;
    EXPECT_EQ(sky + cut, samples) << depth;
    std::uint64_t missing_blue = 0;
    const auto entries = dev.frame_memory()->entries();
    for (std::size_t i = 0; i < kPixels; ++i) {
      const device::AccumEntry& e = entries[i];
      ASSERT_EQ(e.count, 4) << depth << " pixel " << i;
      const std::uint32_t r = e.sum[0], g = e.sum[1], b = e.sum[2];
      ASSERT_EQ(b % 511, 0u) << depth << " pixel " << i << ": blue " << b;
      const std::uint32_t escaped = b / 511;
      ASSERT_LE(r, g) << depth << " pixel " << i;
      ASSERT_LE(g, b) << depth << " pixel " << i;
      ASSERT_GE(r, 256 * escaped) << depth << " pixel " << i;
      ASSERT_GE(g, 358 * escaped) << depth << " pixel " << i;
      missing_blue += 511u * e.count - b;
    }
    EXPECT_EQ(missing_blue, 511u * cut) << depth;
    // The world does what it is for: paths bounce many times, and some are cut even at depth 16.
    EXPECT_GT(bounces, samples / 2) << depth;
    EXPECT_GT(cut, depth == 3 ? 50000u : 10u) << depth;
  }
}

// The float side above is render_device_view, sample for sample.
TEST(PathAgreement, DeviceViewIsThisLoop) {
  device::SceneMemory memory;
  run_device(device::path_preset(), mixed_world(), 1, 2, 1, memory);
  const std::vector<scene::Sphere> view = float_world(memory, device::path_preset().frac_bits());
  core::ImageRgbF raw;
  run_float(view, 2, 4, 7, &raw);
  render::DeviceViewSettings settings;
  settings.spp = 2;
  settings.max_depth = 4;
  settings.seed = 7;
  const core::ImageRgbF want = render::render_device_view(view, settings);
  ASSERT_EQ(raw.pixels.size(), want.pixels.size());
  for (std::size_t i = 0; i < kPixels; ++i) ASSERT_EQ(raw.pixels[i], want.pixels[i]) << i;
}

}  // namespace
}  // namespace tripsitter

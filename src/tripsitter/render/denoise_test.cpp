// The denoiser against what it promises: same bytes on any thread count, flat colour and hard edges left
// sharp, region means kept, an exact image left alone, and noise actually removed (synthetic and path-traced).
#include <tripsitter/render/denoise.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/core/colour.h>
#include <tripsitter/core/sanitizers.h>
#include <tripsitter/render/path_tracer.h>
#include <tripsitter/render/test_util.h>
#include <tripsitter/scene/builtin.h>

namespace tripsitter::render {
namespace {

// Uniform noise in [-1, 1) from a counter (splitmix64), reproducible everywhere.
float noise(std::uint64_t i) {
  std::uint64_t z = i * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<float>(z >> 40) * 0x1.0p-23f - 1.0f;
}

// A synthetic frame: the clean picture, a noisy one and the noisy one's luminance variance (of the mean).
struct Frame {
  int width = 0, height = 0;
  std::vector<Vec3f> clean, color;
  std::vector<float> variance;
  Aovs aovs;

  Frame(int w, int h) : width(w), height(h), clean(Aovs::pixels(w, h)), color(Aovs::pixels(w, h)),
                        variance(Aovs::pixels(w, h)), aovs(w, h) {}
  std::size_t at(int x, int y) const { return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x); }
  DenoiseInput input() const { return {width, height, color, variance, &aovs}; }

  // Sets a pixel: radiance `light` under albedo `albedo` (colour = albedo * light), with a surface at `depth`
  // facing `normal` (infinite depth: sky).
  void set(int x, int y, Vec3f albedo, Vec3f light, Vec3f normal, float depth) {
    const std::size_t i = at(x, y);
    clean[i] = {albedo.x * light.x, albedo.y * light.y, albedo.z * light.z};
    aovs.albedo[i] = albedo;
    aovs.normal[i] = normal;
    aovs.depth[i] = depth;
  }
  // Adds noise to every channel: the same uniform deviate in [-amplitude, amplitude) times the clean colour
  // (multiplicative, like a path tracer's), and sets the variance of the mean to what that noise has.
  void add_noise(float amplitude, std::uint64_t seed) {
    for (std::size_t i = 0; i < clean.size(); ++i) {
      const float n = amplitude * noise(seed * 1000003u + i);
      color[i] = clean[i] * (1.0f + n);
      const float l = core::luminance(clean[i]);
      variance[i] = l * l * amplitude * amplitude / 3.0f;
    }
  }
};

const Vec3f kFacing{0.0f, 0.0f, -1.0f};
const Vec3f kWhite{1.0f, 1.0f, 1.0f};
using testing::kInf;

std::vector<Vec3f> run(const DenoiseInput& in, const DenoiseSettings& settings) {
  std::vector<Vec3f> out(in.color.size());
  denoise(in, settings, out);
  return out;
}

double mse(std::span<const Vec3f> a, std::span<const Vec3f> b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec3f d = a[i] - b[i];
    sum += static_cast<double>(core::dot(d, d)) / 3.0;
  }
  return sum / static_cast<double>(a.size());
}

// Mean luminance over the pixels x in [x0, x1), y in [y0, y1).
double region_mean(std::span<const Vec3f> img, int width, int x0, int x1, int y0, int y1) {
  double sum = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      sum += core::luminance(img[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)]);
  return sum / (static_cast<double>(x1 - x0) * static_cast<double>(y1 - y0));
}

// A busy scene: a lit gradient, two "spheres" of other albedo, normal and depth, a sky band, noise.
Frame busy_frame(int w, int h, float amplitude, std::uint64_t seed) {
  Frame f(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float u = static_cast<float>(x) / static_cast<float>(w), v = static_cast<float>(y) / static_cast<float>(h);
      const float dx1 = u - 0.3f, dy1 = v - 0.5f, dx2 = u - 0.7f, dy2 = v - 0.6f;
      if (v < 0.2f) {
        f.set(x, y, kWhite, {0.6f + 0.4f * v, 0.7f, 1.0f}, {}, kInf);
      } else if (dx1 * dx1 + dy1 * dy1 < 0.04f) {
        const float nz = std::sqrt(std::max(0.0f, 1.0f - (dx1 * dx1 + dy1 * dy1) / 0.04f));
        f.set(x, y, {0.8f, 0.2f, 0.2f}, kWhite * (0.3f + 0.6f * nz), core::normalize(Vec3f{dx1, -dy1, -nz - 1e-3f}), 4.0f - nz);
      } else if (dx2 * dx2 + dy2 * dy2 < 0.02f) {
        f.set(x, y, {0.2f, 0.3f, 0.9f}, kWhite * 0.9f, {0.0f, 0.6f, -0.8f}, 3.0f);
      } else {
        f.set(x, y, {0.5f, 0.5f, 0.5f}, kWhite * (0.2f + 0.6f * u), {0.0f, 1.0f, 0.0f}, 5.0f + 10.0f * (1.0f - v));
      }
    }
  }
  f.add_noise(amplitude, seed);
  return f;
}

TEST(Denoise, SameBytesOnAnyThreadCountAndWhenReused) {
  const Frame f = busy_frame(77, 45, 0.8f, 1);
  const Frame other = busy_frame(40, 30, 0.5f, 9);
  for (const int iterations : {3, 5}) {
    for (const bool spatial : {false, true}) {
      SCOPED_TRACE(::testing::Message() << iterations << " iterations, " << (spatial ? "estimated" : "given") << " variance");
      DenoiseInput in = f.input();
      if (spatial) in.variance = {};
      DenoiseSettings s;
      s.iterations = iterations;
      s.threads = 1;
      const std::vector<Vec3f> one = run(in, s);
      s.threads = 2;
      const std::vector<Vec3f> two = run(in, s);
      s.threads = 3;
      // A Denoiser that has filtered another size with other settings first, then this image twice.
      Denoiser reused;
      std::vector<Vec3f> scratch(other.color.size());
      DenoiseSettings wide = s;
      wide.iterations = Denoiser::kMaxIterations;
      reused.denoise(other.input(), wide, scratch);
      std::vector<Vec3f> three(one.size());
      for (int k = 0; k < 2; ++k) reused.denoise(in, s, three);
      EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(Vec3f)), 0);
      EXPECT_EQ(std::memcmp(one.data(), three.data(), one.size() * sizeof(Vec3f)), 0);
      EXPECT_GT(mse(one, f.color), 0.0);  // it did something
    }
  }
}

TEST(Denoise, OutputMayBeTheInput) {
  const Frame f = busy_frame(33, 20, 0.8f, 2);
  const std::vector<Vec3f> apart = run(f.input(), {});
  std::vector<Vec3f> in_place = f.color;
  DenoiseInput in = f.input();
  in.color = in_place;
  denoise(in, {}, in_place);
  EXPECT_EQ(std::memcmp(apart.data(), in_place.data(), apart.size() * sizeof(Vec3f)), 0);
}

// A pixel that should come out as it went in is divided by its albedo, averaged with equal values and multiplied
// back: a few roundings of half an ulp (2^-24) each.
constexpr float kRoundingRelative = 4e-7f;  // measured: 2.1e-7 (flat colour), 1.0e-7 (without AOVs), 9.7e-8 (zero variance)

float worst_relative_change(std::span<const Vec3f> out, std::span<const Vec3f> in) {
  float worst = 0;
  for (std::size_t i = 0; i < out.size(); ++i)
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::fabs(out[i][c] - in[i][c]) / std::max(in[i][c], 1e-6f));
  return worst;
}

TEST(Denoise, FlatColourWithNoisyVariancePassesThrough) {
  Frame f(50, 40);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) f.set(x, y, {0.8f, 0.6f, 0.4f}, {0.3f, 0.5f, 0.7f}, kFacing, 3.0f);
  f.add_noise(0.5f, 2);
  f.color = f.clean;  // the variance says noisy, the picture is flat
  EXPECT_LE(worst_relative_change(run(f.input(), {}), f.color), kRoundingRelative);
  // Without feature buffers too.
  DenoiseInput in = f.input();
  in.aovs = nullptr;
  EXPECT_LE(worst_relative_change(run(in, {}), f.color), kRoundingRelative);
}

TEST(Denoise, ZeroVarianceLeavesTheImageAlone) {
  Frame f = busy_frame(64, 48, 0.8f, 3);
  std::fill(f.variance.begin(), f.variance.end(), 0.0f);
  EXPECT_LE(worst_relative_change(run(f.input(), {}), f.color), kRoundingRelative);
}

// Two halves that differ in one guide (or only in brightness), noisy on both sides.
enum class EdgeKind { kAlbedo, kNormal, kDepth, kSky, kLuminance };

Frame edge_frame(EdgeKind kind, std::uint64_t seed) {
  Frame f(64, 32);
  for (int y = 0; y < f.height; ++y) {
    for (int x = 0; x < f.width; ++x) {
      const bool right = x >= f.width / 2;
      switch (kind) {
        case EdgeKind::kAlbedo:  // same light, other paint: the light may mix, the colours must not
          f.set(x, y, right ? Vec3f{0.1f, 0.2f, 0.9f} : Vec3f{0.9f, 0.3f, 0.1f}, kWhite * 0.7f, kFacing, 3.0f);
          break;
        case EdgeKind::kNormal:
          f.set(x, y, kWhite * 0.5f, kWhite * (right ? 0.2f : 0.9f), right ? Vec3f{0.0f, 1.0f, 0.0f} : kFacing, 3.0f);
          break;
        case EdgeKind::kDepth:
          f.set(x, y, kWhite * 0.5f, kWhite * (right ? 0.2f : 0.9f), kFacing, right ? 6.0f : 3.0f);
          break;
        case EdgeKind::kSky:
          f.set(x, y, right ? kWhite : kWhite * 0.5f, kWhite * (right ? 0.9f : 0.2f), right ? Vec3f{} : kFacing,
                right ? kInf : 3.0f);
          break;
        case EdgeKind::kLuminance:  // nothing but brightness tells the sides apart
          f.set(x, y, kWhite * 0.5f, kWhite * (right ? 0.2f : 0.9f), kFacing, 3.0f);
          break;
      }
    }
  }
  f.add_noise(0.3f, seed);
  return f;
}

// The bounds of the edge tests, each over 3 seeds, every kind of edge and 3 and 5 iterations, with the worst seen
// in the comment. The noise is uniform within +-30% of the clean colour (standard deviation 17%).
constexpr double kEdgeLeak = 0.05;           // guided edges: 0.030 (sky), 0.024 (normal, depth), 0.025 (albedo)
constexpr double kLuminanceEdgeLeak = 0.2;   // brightness alone, a step of 4 noise deviations: 0.116
constexpr double kRegionDrift = 0.01;        // each half's mean and the whole image's: 0.0047 (luminance edge)
constexpr double kEdgeNoiseRatio = 0.05;     // MSE after / before: 0.029

TEST(Denoise, HardEdgesStaySharpAndRegionMeansStay) {
  for (const int iterations : {3, 5}) {
    for (const EdgeKind kind : {EdgeKind::kAlbedo, EdgeKind::kNormal, EdgeKind::kDepth, EdgeKind::kSky, EdgeKind::kLuminance}) {
      for (std::uint64_t seed = 1; seed <= 3; ++seed) {
        SCOPED_TRACE(::testing::Message() << iterations << " iterations, edge kind " << static_cast<int>(kind) << ", seed " << seed);
        const Frame f = edge_frame(kind, seed);
        DenoiseSettings settings;
        settings.iterations = iterations;
        const std::vector<Vec3f> out = run(f.input(), settings);
        const int w = f.width, h = f.height, mid = w / 2;
        // The columns either side of the edge, averaged down the image (which cancels most of the remaining
        // noise), against their side's clean colour, channel by channel.
        for (const int x : {mid - 1, mid}) {
          for (int c = 0; c < 3; ++c) {
            double sum = 0;
            for (int y = 0; y < h; ++y) sum += out[f.at(x, y)][c];
            const double expected = f.clean[f.at(x, 0)][c];
            EXPECT_LE(std::fabs(sum / h - expected) / expected, kind == EdgeKind::kLuminance ? kLuminanceEdgeLeak : kEdgeLeak)
                << "column " << x << ", channel " << c;
          }
        }
        for (const auto& [x0, x1] : {std::pair{0, mid}, std::pair{mid, w}, std::pair{0, w}}) {
          const double before = region_mean(f.color, w, x0, x1, 0, h);
          EXPECT_LE(std::fabs(region_mean(out, w, x0, x1, 0, h) / before - 1), kRegionDrift) << "columns " << x0 << " to " << x1;
        }
        EXPECT_LE(mse(out, f.clean) / mse(f.color, f.clean), kEdgeNoiseRatio);
      }
    }
  }
}

// Sky pixels take weight only from sky pixels: with a surface far brighter than anything in the sky, every sky
// pixel stays within the range of the sky's inputs.
TEST(Denoise, SkyMixesOnlyWithSky) {
  Frame f = edge_frame(EdgeKind::kSky, 4);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width / 2; ++x) f.color[f.at(x, y)] = f.color[f.at(x, y)] * 1000.0f;
  float sky_max = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = f.width / 2; x < f.width; ++x) sky_max = std::max(sky_max, f.color[f.at(x, y)].x);
  const std::vector<Vec3f> out = run(f.input(), {});
  for (int y = 0; y < f.height; ++y)
    for (int x = f.width / 2; x < f.width; ++x) ASSERT_LE(out[f.at(x, y)].x, sky_max) << x << ", " << y;
}

// The spatial estimate of a noisy flat region's variance, against the variance the noise has.
TEST(Denoise, EstimatesTheVarianceOfAFlatRegion) {
  Frame f(48, 40);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) f.set(x, y, {0.6f, 0.5f, 0.3f}, kWhite * 0.8f, kFacing, 4.0f);
  f.add_noise(0.4f, 5);
  std::vector<float> estimate(f.color.size());
  Denoiser d;
  d.estimate_variance(f.input(), 3, 2, estimate);
  double sum = 0;
  for (const float v : estimate) sum += v;
  // Measured: 0.976 (the estimates are sample variances of 16 to 49 pixels each, of one noise field).
  EXPECT_NEAR(sum / static_cast<double>(estimate.size()) / f.variance[0], 1.0, 0.1);
}

TEST(Denoise, ReducesNoiseOnASyntheticImage) {
  const Frame f = busy_frame(96, 64, 0.8f, 4);
  for (const int iterations : {3, 5}) {
    for (const bool spatial : {false, true}) {
      SCOPED_TRACE(::testing::Message() << iterations << " iterations, " << (spatial ? "estimated" : "given") << " variance");
      DenoiseInput in = f.input();
      if (spatial) in.variance = {};
      DenoiseSettings settings;
      settings.iterations = iterations;
      const std::vector<Vec3f> out = run(in, settings);
      // Measured: 0.030 and 0.032 with 3 iterations, 0.015 and 0.014 with 5; drifts below 0.1%.
      EXPECT_LE(mse(out, f.clean) / mse(f.color, f.clean), 0.1);
      EXPECT_LE(std::fabs(region_mean(out, f.width, 0, f.width, 0, f.height) /
                          region_mean(f.color, f.width, 0, f.width, 0, f.height) - 1), kRegionDrift);
    }
  }
}

// One path per pixel of `field` (defocus, 400 small spheres, glass and metal) against many, with the feature
// buffers render_path writes.
TEST(Denoise, ReducesNoiseOnAPathTracedField) {
  const scene::Scene field = *scene::builtin("field");
  const PathScene scene(field.spheres);
  PathSettings settings;
  settings.width = 96;
  settings.height = 54;
  settings.max_depth = 8;
  settings.threads = 2;
  const ThinLensCamera camera(field.camera, settings.width, settings.height);
  settings.spp = core::kSanitized ? 64 : 256;
  const core::ImageRgbF reference = render_path(scene, camera, settings);
  settings.spp = 1;
  Aovs aovs;
  const core::ImageRgbF noisy = render_path(scene, camera, settings, {}, &aovs);
  const std::vector<Vec3f> out = run({noisy.width, noisy.height, noisy.pixels, {}, &aovs}, {});
  // The whole image, where silhouettes keep the aliasing of one sample per pixel, which no filter undoes ...
  // Measured: 0.538 with a 256-sample reference, 0.541 with 64.
  EXPECT_LE(mse(out, reference.pixels) / mse(noisy.pixels, reference.pixels), 0.65);
  // ... and the interior of surfaces: pixels whose eight neighbours show the same surface (depth within 5%,
  // normals within 25 degrees). Measured: 0.214 and 0.216.
  std::vector<Vec3f> a, b, r;
  const int w = noisy.width, h = noisy.height;
  for (int y = 1; y + 1 < h; ++y) {
    for (int x = 1; x + 1 < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
      bool interior = std::isfinite(aovs.depth[i]);
      for (int dy = -1; dy <= 1 && interior; ++dy) {
        for (int dx = -1; dx <= 1 && interior; ++dx) {
          const std::size_t j = static_cast<std::size_t>(y + dy) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x + dx);
          interior = std::isfinite(aovs.depth[j]) && std::fabs(aovs.depth[j] - aovs.depth[i]) <= 0.05f * aovs.depth[i] &&
                     core::dot(aovs.normal[i], aovs.normal[j]) >= 0.9f;
        }
      }
      if (!interior) continue;
      a.push_back(out[i]);
      b.push_back(noisy.pixels[i]);
      r.push_back(reference.pixels[i]);
    }
  }
  ASSERT_GE(a.size(), noisy.pixels.size() / 4);
  EXPECT_LE(mse(a, r) / mse(b, r), 0.3);
  // Measured: +0.57%.
  const double drift = region_mean(out, w, 0, w, 0, h) / region_mean(noisy.pixels, w, 0, w, 0, h) - 1;
  EXPECT_LE(std::fabs(drift), 0.02);
}

TEST(Denoise, RejectsBadArguments) {
  const Frame f = busy_frame(16, 8, 0.5f, 5);
  std::vector<Vec3f> out(f.color.size());
  DenoiseSettings s;
  s.iterations = Denoiser::kMaxIterations + 1;
  EXPECT_THROW(denoise(f.input(), s, out), std::invalid_argument);
  s = {};
  s.sigma_luminance = 0;
  EXPECT_THROW(denoise(f.input(), s, out), std::invalid_argument);
  std::vector<Vec3f> short_out(out.size() - 1);
  EXPECT_THROW(denoise(f.input(), {}, short_out), std::invalid_argument);
  DenoiseInput in = f.input();
  in.variance = in.variance.first(3);
  EXPECT_THROW(denoise(in, {}, out), std::invalid_argument);
  Aovs small(8, 8);
  in = f.input();
  in.aovs = &small;
  EXPECT_THROW(denoise(in, {}, out), std::invalid_argument);
  std::vector<float> short_variance(out.size() - 1);
  Denoiser d;
  EXPECT_THROW(d.estimate_variance(f.input(), 3, 1, short_variance), std::invalid_argument);
}

// Two halves of a pixel's samples merged: the mean of all of them, a luminance variance of (a - b)^2 / 4, and
// feature buffers averaged alike, except a depth only one half found, which is kept.
TEST(Denoise, MergedHalvesAreTheMeanWithTheirOwnVariance) {
  const core::ImageRgbF a{2, 1, {{1, 1, 1}, {0, 0, 0}}}, b{2, 1, {{0, 0, 0}, {0.5f, 0.5f, 0.5f}}};
  Aovs aovs_a(2, 1), aovs_b(2, 1);
  aovs_a.albedo = {{1, 0, 0}, {0, 0, 0}};
  aovs_b.albedo = {{0, 0, 1}, {1, 1, 1}};
  aovs_a.depth = {2.0f, kInf};
  aovs_b.depth = {4.0f, 3.0f};
  std::vector<float> variance(2);
  const core::ImageRgbF merged = merge_halves(a, aovs_a, b, aovs_b, 0.25f, variance);
  EXPECT_EQ(merged.width, 2);
  EXPECT_EQ(merged.pixels[0].x, 0.25f);
  EXPECT_EQ(merged.pixels[1].y, 0.375f);
  EXPECT_FLOAT_EQ(variance[0], 0.25f);  // luminance 1 against 0
  EXPECT_FLOAT_EQ(variance[1], 0.0625f);
  EXPECT_EQ(aovs_a.albedo[0].x, 0.25f);
  EXPECT_EQ(aovs_a.albedo[0].z, 0.75f);
  EXPECT_EQ(aovs_a.depth[0], 3.5f);
  EXPECT_EQ(aovs_a.depth[1], 3.0f);
}

// A denoised still is the denoiser over its two halves' merged picture and variance; one sample per pixel takes
// its variance from the neighbours instead. Either way the feature buffers are the whole picture's.
TEST(Denoise, DenoisedStillFiltersTheMergedHalves) {
  const scene::Scene scene = *scene::builtin("cluster");
  const PathScene world(scene.spheres);
  const ThinLensCamera lens(scene.camera, 24, 16);
  PathSettings s{.width = 24, .height = 16, .spp = 4, .max_depth = 4, .seed = 3, .threads = 2, .sky = {}};
  const TraceStill trace = [&](const PathSettings& part, Aovs* aovs) { return render_path(world, lens, part, {}, aovs); };
  Denoiser denoiser;
  Aovs aovs;
  const core::ImageRgbF still = denoised_still(s, trace, denoiser, aovs);
  PathSettings first = s, second = s;
  first.spp = second.spp = 2;
  second.first_sample = 2;
  Aovs first_aovs, second_aovs;
  const core::ImageRgbF a = trace(first, &first_aovs), b = trace(second, &second_aovs);
  std::vector<float> variance(a.pixels.size());
  core::ImageRgbF expected = merge_halves(a, first_aovs, b, second_aovs, 0.5f, variance);
  DenoiseSettings filter;
  filter.threads = 2;
  denoise({.width = 24, .height = 16, .color = expected.pixels, .variance = variance, .aovs = &first_aovs}, filter,
          expected.pixels);
  EXPECT_EQ(still.pixels, expected.pixels);
  EXPECT_EQ(aovs.depth, first_aovs.depth);
  s.spp = 1;
  const core::ImageRgbF one = denoised_still(s, trace, denoiser, aovs);
  EXPECT_EQ(one.pixels.size(), 24u * 16u);
  EXPECT_NE(one.pixels, trace(s, nullptr).pixels);  // filtered
}

}  // namespace
}  // namespace tripsitter::render

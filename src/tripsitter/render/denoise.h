// A denoiser for path-traced images: an edge-avoiding à-trous wavelet filter (Dammertz et al. 2010) guided by
// the feature buffers (aov.h) and by each pixel's variance, which it filters along, as SVGF does (Schied et al.
// 2017). It smooths what the samples' noise allows and stops at changes of normal, depth and luminance; colour
// is filtered divided by the albedo and multiplied back, so that neighbouring surfaces' colours do not bleed.
// Deterministic: every pixel sums its taps in a fixed order, so any thread count gives the same bytes (and the
// AVX2 and SSE2 builds the same bytes too: eight pixels at a time on render/simd8.h, each lane the IEEE operation).
// docs/denoiser.md describes the filter, its parameters, its cost and what it blurs.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include <tripsitter/render/aov.h>
#include <tripsitter/render/path_tracer.h>

namespace tripsitter::render {

struct DenoiseInput {
  int width = 0;
  int height = 0;
  // Linear radiance per pixel, row-major: the mean of the pixel's samples.
  std::span<const Vec3f> color;
  // Per pixel: the variance of that mean's luminance (Rec. 709, core/colour.h), i.e. the samples' variance
  // divided by their number. Empty: estimated from the neighbours (Denoiser::estimate_variance with
  // DenoiseSettings::variance_radius). 0 for exact pixels: a pixel whose 3x3 neighbourhood is all exact keeps its
  // value (up to rounding).
  std::span<const float> variance;
  // Albedo, normal and depth of the same pixels (width x height). Null: no feature buffers, so only luminance
  // stops the filter (every pixel counts as one surface of albedo 1).
  const Aovs* aovs = nullptr;
};

struct DenoiseSettings {
  // À-trous passes; pass i (from 0) takes its taps 2^i pixels apart, so 3 passes reach 7 pixels each way and 5
  // reach 31. 0 returns the input. At most kMaxIterations. A pass costs about 2.8 ms of one core at 640x480,
  // the set-up about 1 ms (docs/denoiser.md).
  int iterations = 3;
  // How many standard deviations of a pixel's (filtered) luminance noise a neighbour's luminance may differ by
  // before its weight drops to exp(-1); the first pass compares luminances prefiltered over 3x3 pixels, whose
  // differences are smaller than the noise. Larger: smoother, and more detail lost.
  float sigma_luminance = 2.0f;
  // Normal weight exp(-sigma_normal (1 - n_p . n_q)) (to first order SVGF's (n_p . n_q)^sigma_normal): 32
  // gives a neighbour whose normal is 10 degrees off 0.6 of the weight, 30 degrees off 0.014, 45 degrees off 1e-4.
  float sigma_normal = 32.0f;
  // Depth weight exp(-|z_p - z_q| / (sigma_depth s g_p + 0.001 z_p)), s the pass's tap spacing and g_p the depth's
  // change per pixel at p along the tap's direction (x, y, or the sum of both for a diagonal tap): how many times
  // the change a plane through p would show is tolerated. The sky (infinite depth) and the surfaces never mix.
  float sigma_depth = 2.0f;
  // Half-width of the window (2r + 1 pixels square) over which a missing variance is estimated.
  int variance_radius = 3;
  int threads = 0;  // 0: all hardware threads
};

// Holds the scratch planes, so that a window calling it every frame allocates only when the size (or the
// number of iterations) grows.
class Denoiser {
 public:
  static constexpr int kMaxIterations = 8;

  // Writes the filtered image to `out` (width x height), which may be input.color itself.
  // Throws std::invalid_argument unless width, height >= 1; color, out, and variance unless empty, are sized
  // width x height; aovs, unless null, is of that size too; 0 <= iterations <= kMaxIterations; the sigmas are
  // positive and variance_radius >= 1. REQUIRES colour and variance finite, variance >= 0.
  void denoise(const DenoiseInput& input, const DenoiseSettings& settings, std::span<Vec3f> out);

  // The variance of each pixel's luminance estimated from its neighbours: the sample variance of the luminance
  // of colour / albedo over the (2 radius + 1)^2 window, counting only pixels of the same kind (sky or surface),
  // times the pixel's albedo luminance squared. What DenoiseInput::variance expects when every pixel is the mean
  // of equally many samples, overestimated where the picture itself varies within the window. input.variance is
  // ignored. Throws std::invalid_argument as denoise does, and unless radius >= 1 and `out` is width x height.
  void estimate_variance(const DenoiseInput& input, int radius, int threads, std::span<float> out);

 private:
  // Sizes the planes for an image of width x height and taps up to `reach` pixels away.
  void layout(int width, int height, int reach);
  // The first plane's first float, on a cache line.
  float* planes_base();
  // estimate_variance on checked arguments, in the planes as laid out.
  void estimate(const DenoiseInput& input, int radius, int threads, float* out);

  // Structure-of-arrays planes of stride_ floats a row (the image plus at least `pad_` columns of blank pixels on
  // each side, which every weight rejects), rows interleaved (denoise.cpp: Planes).
  int width_ = 0, height_ = 0, pad_ = 0, stride_ = 0;
  std::vector<float> storage_;
  std::vector<float> variance_;  // the spatial estimate, when the input has none
};

// One-shot form of Denoiser::denoise (allocates its scratch each call).
void denoise(const DenoiseInput& input, const DenoiseSettings& settings, std::span<Vec3f> out);

// Two estimates of one picture, `a` the mean of a share weight_a of every pixel's samples and `b` of the rest,
// merged into the mean of them all, which it returns. Their difference gives each pixel's own variance, written
// to `variance`: two estimates of the mean, each of about half the samples, put the variance of their mean at
// about (a - b)^2 / 4 in luminance (a noisy estimate of it, which the denoiser smooths before use). `aovs_a`,
// the first estimate's feature buffers, becomes the merged buffers (depth: the finite one where the other is
// infinite). REQUIRES a, b, aovs_a, aovs_b and variance all of a's pixels.
core::ImageRgbF merge_halves(const core::ImageRgbF& a, Aovs& aovs_a, const core::ImageRgbF& b, const Aovs& aovs_b,
                             float weight_a, std::span<float> variance);

// How a still's samples are traced: render_path of the picture for `settings`, filling `aovs` (MPI shares the
// rows among ranks, cmd/render_mpi.cpp).
using TraceStill = std::function<core::ImageRgbF(const PathSettings& settings, Aovs* aovs)>;

// A path-traced still filtered with its own feature buffers (`render --mode path --denoise`), into `aovs`. With
// two or more samples per pixel they are traced in two halves (the first and the second half of each pixel's
// sequence) and merged (merge_halves), so that each pixel's variance is its own and what its samples agree on (a
// sharp reflection, say) is kept, where a variance from the neighbours would count it as noise. One sample per
// pixel says nothing of its own spread: the variance then comes from the neighbours (estimate_variance). The
// picture is the same bytes whichever Denoiser is given; keeping one keeps its scratch planes.
core::ImageRgbF denoised_still(const PathSettings& settings, const TraceStill& trace, Denoiser& denoiser, Aovs& aovs);

}  // namespace tripsitter::render

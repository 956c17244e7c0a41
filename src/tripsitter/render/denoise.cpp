// The denoiser in stages, each over rows of structure-of-arrays planes, eight pixels at a time (simd::F8):
//   estimate_variance  (when the input has none) estimate_inputs_row, horizontal_sums_row, estimate_chunk;
//   set-up             clear_blank_row, prepare_row (demodulation and guides), prefilter_luminance;
//   passes             filter_pass: per row filter_row, per eight pixels centre_at, tap_weight, sum_taps,
//                      then store_pass (the next pass's planes) or, in the last pass, store_output (remodulated).
// docs/denoiser.md follows the same steps.
#include <tripsitter/render/denoise.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>

#include <tripsitter/core/colour.h>
#include <tripsitter/core/parallel.h>
#include <tripsitter/render/simd8.h>

namespace tripsitter::render {
namespace {

using simd::F8;
constexpr int kLanes = F8::kLanes;

constexpr float kLog2e = 1.44269504f;
// Albedo channels at or below this are not divided out (black surfaces keep their colour as it is).
constexpr float kAlbedoEpsilon = 1e-3f;
// Depth keys: surfaces keep their depth, the sky (infinite depth) gets kSkyDepth and the blank padding around the
// image kBlankDepth, so that the depth weight between any two of the three kinds is exactly 0.
constexpr float kSkyDepth = 1e30f;
constexpr float kBlankDepth = -1e30f;
// Depth differences below this fraction of the centre's depth count as the same surface.
constexpr float kDepthRelative = 1e-3f;
// One side's depth change more than this many times the other's (plus 1% of the depth) marks an edge.
constexpr float kSlopeJump = 8.0f;
// Keeps the luminance scale positive where the variance is 0: only neighbours of exactly equal luminance mix.
constexpr float kLuminanceEpsilon = 1e-10f;
// The luminance the first pass compares is prefiltered over the 3x3 neighbours whose depth key is within this
// fraction of the centre's (the same surface, or both sky).
constexpr float kPrefilterDepth = 0.05f;
// Weights 2^-a are exactly 0 from a = kCutoff on.
constexpr float kCutoff = 60.0f;
// The plain loops below (the variance estimate) go in blocks of this many pixels of a row, which the compiler
// vectorises; the rows of the planes are padded to a whole number of blocks.
constexpr int kBlock = 64;
// Rows a thread takes at a time in the filter's passes and the variance estimate's vertical sums.
constexpr int kChunk = 8;
// Floats in a cache line.
constexpr int kAlign = 16;

// The weights are 2^-a, a >= 0 the sum of the edge-stopping terms in units of log2 e (so that exp(-x) is 2^-(x log2 e))
// plus the kernel's exponent. They come to within 6.1 per cent from the float whose bits are (kCutoff - a) 2^23:
// exponent field kCutoff - 1 - floor(a), the mantissa linear in the fraction of a (Schraudolph 1999), times
// 2^(127 - kCutoff). So the filter computes a's terms already multiplied by 2^23 (kBits), subtracts them from
// kCutoff 2^23 and has its weight in four operations; continuous and decreasing in a, which is all a weight needs,
// 1 for a <= 0, exactly 0 from a = kCutoff on (and for NaN). Nonzero weights stay above 2^-60, so that their
// squares (which weigh the variance) are normal floats.
constexpr float kBits = 8388608.0f;                         // 2^23
constexpr float kWeightScale = 147573952589676412928.0f;  // 2^67 = 2^(127 - kCutoff)
static_assert(kCutoff == 60.0f, "kWeightScale is 2^(127 - kCutoff)");
F8 weight_from_bits(F8 bits) {
  const F8 clamped = min(max(bits, F8::set1(0.0f)), F8::set1(kCutoff * kBits));
  return float_with_bits(clamped) * F8::set1(kWeightScale);
}

// core::luminance of eight colours: the same products, summed in the same order, so the same bits.
F8 luminance(F8 r, F8 g, F8 b) {
  const Vec3f& weight = core::kRec709Luminance;
  return F8::set1(weight.x) * r + F8::set1(weight.y) * g + F8::set1(weight.z) * b;
}

// Depth keys of a surface (not the sky nor the blank padding).
F8 is_surface(F8 key) { return (key >= F8::set1(0.0f)) & (key < F8::set1(kSkyDepth)); }

// A depth as a key: itself for a surface, kSkyDepth for infinity (and NaN or a negative depth).
F8 depth_key(F8 d) { return select(is_surface(d), d, F8::set1(kSkyDepth)); }

// The depth's change per pixel at pixels of key z, from their neighbours of keys a and b on either side: the mean
// of the two changes, unless one side is not a surface (sky or blank) or changes more than kSlopeJump times the
// other, which marks an edge: then the smaller change (0 when neither side is a surface, or z is the sky). Each
// depth is that of one jittered sample or a mean over a few, so one side alone can show almost no change.
F8 depth_slope(F8 z, F8 a, F8 b) {
  const F8 sky = F8::set1(kSkyDepth), zero = F8::set1(0.0f);
  const F8 da = select(is_surface(a), abs(z - a), sky), db = select(is_surface(b), abs(z - b), sky);
  const F8 lo = min(da, db), hi = max(da, db);
  const F8 smooth = (hi < sky) & (hi < F8::set1(kSlopeJump) * lo + F8::set1(kDepthRelative * 10.0f) * z);
  const F8 g = select(smooth, (lo + hi) * F8::set1(0.5f), lo);
  return select((g < sky) & is_surface(z), g, zero);
}

// Planes of the scratch storage.
enum Plane : int {
  kZ,   // depth key
  kNx,  // normal (the sky's is (0, 0, 1): the depth key alone keeps it apart)
  kNy,
  kNz,
  kGx,  // the depth's change per pixel along x and y (0 where unknown)
  kGy,
  kAlbedo,  // the albedo divisor (3 planes)
  kColorA = kAlbedo + 3,  // ping-pong A: colour / albedo (3 planes), its variance, its luminance
  kVarianceA = kColorA + 3,
  kLuminanceA,
  kColorB,  // ping-pong B, the same
  kVarianceB = kColorB + 3,
  kLuminanceB,
  kPlaneCount
};
constexpr int kVariance = 3, kLuminance = 4;  // offsets from kColorA or kColorB
static_assert(sizeof(Vec3f) == 3 * sizeof(float), "colours, albedos and normals are read as arrays of floats");

// The same storage while the variance is estimated: per pixel the luminance l of colour / albedo, its kind (1 in
// the surface plane or in the sky plane; the blank padding is neither) and the albedo's luminance squared; then
// horizontal sums over 2 radius + 1 columns of each kind's count, l and l^2 (six planes from kSums: surface count,
// l, l^2, sky count, l, l^2).
enum EstimatePlane : int { kL, kSurface, kSky, kAlbedoSquare, kSums };

// The scratch storage: kPlaneCount planes of `stride` floats by the image's rows, row y of every plane before
// row y + 1 (so that a tap's loads come from a few pages). A row holds the image's pixels from column `pad` on,
// with blank pixels (which every weight rejects) before and after; row `height` is a blank row.
struct Planes {
  float* base;
  int width, height, stride, pad;

  // Pixel (0, y) of plane k; columns -pad to stride - pad - 1 may be addressed from there.
  float* row(int k, int y) const {
    const std::size_t plane_row = static_cast<std::size_t>(y) * kPlaneCount + static_cast<std::size_t>(k);
    return base + plane_row * static_cast<std::size_t>(stride) + pad;
  }
  // Row y, or the blank row where y is outside the image.
  const float* row_or_blank(int k, int y) const { return row(k, y >= 0 && y < height ? y : height); }
  // The padding of row y of plane k set to `blank`.
  void blank_margins(int k, int y, float blank) const {
    std::fill(row(k, y) - pad, row(k, y), blank);
    std::fill(row(k, y) + width, row(k, y) + (stride - pad), blank);
  }
  // The index of pixel (x, y) in the caller's row-major arrays.
  std::size_t pixel(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
  }
};

// The blank row below the image, which the taps above and below the image read.
void clear_blank_row(const Planes& p) {
  for (int k = 0; k < kPlaneCount; ++k) {
    float* row = p.row(k, p.height);
    std::fill(row - p.pad, row + (p.stride - p.pad), k == kZ ? kBlankDepth : 0.0f);
  }
}

// The 3x3 blurs read one pixel beyond the row's ends: the end's own.
void extend_ends(float* row, int width) {
  row[-1] = row[0];
  row[width] = row[width - 1];
}

// Row y of the input as arrays of floats: colour, its variance (given or estimated; null while it is being
// estimated), and the feature buffers, null without them (the depth rows above and below also at the image's edges).
struct InputRow {
  const float *colour, *variance, *albedo, *normal, *depth, *depth_up, *depth_down;
};

InputRow input_row(const DenoiseInput& in, const float* variance, int y) {
  const std::size_t first = static_cast<std::size_t>(y) * static_cast<std::size_t>(in.width);
  InputRow row{&in.color[first].x, variance != nullptr ? variance + first : nullptr, nullptr, nullptr, nullptr, nullptr,
               nullptr};
  if (const Aovs* aovs = in.aovs) {
    row.albedo = &aovs->albedo[first].x;
    row.normal = &aovs->normal[first].x;
    row.depth = aovs->depth.data() + first;
    if (y > 0) row.depth_up = row.depth - in.width;
    if (y + 1 < in.height) row.depth_down = row.depth + in.width;
  }
  return row;
}

// The colour and the albedo divisor of the `count` pixels (at most eight used) from column x: the albedo where a
// channel exceeds kAlbedoEpsilon, 1 elsewhere and without feature buffers.
[[gnu::always_inline]] inline void load_colour_and_divisor(const InputRow& in, int x, int count, F8 (&c)[3],
                                                           F8 (&a)[3]) {
  const F8 one = F8::set1(1.0f);
  const std::size_t x3 = 3 * static_cast<std::size_t>(x);
  F8::load3_first(in.colour + x3, count, c[0], c[1], c[2]);
  if (in.albedo == nullptr) {
    a[0] = a[1] = a[2] = one;
    return;
  }
  F8::load3_first(in.albedo + x3, count, a[0], a[1], a[2]);
  for (F8& channel : a) channel = select(channel > F8::set1(kAlbedoEpsilon), channel, one);
}

// ---- The variance estimate ----

// Row y's per-pixel planes of the estimate (EstimatePlane), with blank padding.
void estimate_inputs_row(const Planes& p, const DenoiseInput& input, int y) {
  float* rows[kSums];
  for (int k = 0; k < kSums; ++k) {
    p.blank_margins(k, y, 0.0f);
    rows[k] = p.row(k, y);
  }
  const InputRow in = input_row(input, nullptr, y);
  const F8 one = F8::set1(1.0f), zero = F8::set1(0.0f);
  for (int x = 0, width = p.width; x < width; x += kLanes) {
    const int count = width - x;
    F8 c[3], a[3], surface = one;
    load_colour_and_divisor(in, x, count, c, a);
    if (in.depth != nullptr)
      surface = select(depth_key(F8::load_first(in.depth + x, count)) < F8::set1(kSkyDepth), one, zero);
    const F8 la = luminance(a[0], a[1], a[2]);
    luminance(c[0] / a[0], c[1] / a[1], c[2] / a[2]).store_first(rows[kL] + x, count);
    surface.store_first(rows[kSurface] + x, count);
    (one - surface).store_first(rows[kSky] + x, count);
    (la * la).store_first(rows[kAlbedoSquare] + x, count);
  }
}

// Row y's sums over 2 radius + 1 columns of each kind's count, l and l^2, in plain loops the compiler vectorises.
void horizontal_sums_row(const Planes& p, int radius, int y) {
  const float *l = p.row(kL, y), *surface = p.row(kSurface, y), *sky = p.row(kSky, y);
  for (int x0 = 0; x0 < p.width; x0 += kBlock) {
    float acc[6][kBlock] = {};
    for (int dx = -radius; dx <= radius; ++dx) {
      const float *lq = l + x0 + dx, *sq = surface + x0 + dx, *kq = sky + x0 + dx;
      for (int i = 0; i < kBlock; ++i) {
        acc[0][i] += sq[i];
        acc[1][i] += sq[i] * lq[i];
        acc[2][i] += sq[i] * lq[i] * lq[i];
        acc[3][i] += kq[i];
        acc[4][i] += kq[i] * lq[i];
        acc[5][i] += kq[i] * lq[i] * lq[i];
      }
    }
    for (int k = 0; k < 6; ++k) std::copy(acc[k], acc[k] + kBlock, p.row(kSums + k, y) + x0);
  }
}

// The six horizontal sums of the rows of y's window (2 radius + 1 rows, within the image), columns x to x + 7.
void sum_window(const Planes& p, int radius, int y, int x, F8 (&acc)[6]) {
  const int y0 = std::max(y - radius, 0), y1 = std::min(y + radius, p.height - 1);
  for (int k = 0; k < 6; ++k) {
    acc[k] = F8::loadu(p.row(kSums + k, y0) + x);
    for (int yq = y0 + 1; yq <= y1; ++yq) acc[k] = acc[k] + F8::loadu(p.row(kSums + k, yq) + x);
  }
}

// The window of row y - 1 moved to row y: the row that enters it added, the one that leaves it subtracted.
void slide_window(const Planes& p, int radius, int y, int x, F8 (&acc)[6]) {
  const int enters = y + radius, leaves = y - radius - 1;
  for (int k = 0; k < 6; ++k) {
    if (enters < p.height) acc[k] = acc[k] + F8::loadu(p.row(kSums + k, enters) + x);
    if (leaves >= 0) acc[k] = acc[k] - F8::loadu(p.row(kSums + k, leaves) + x);
  }
}

// The sample variance of the window's pixels of the centre's kind (0 for fewer than two), times the centre's
// albedo luminance squared.
F8 window_variance(const Planes& p, int y, int x, const F8 (&acc)[6]) {
  const F8 one = F8::set1(1.0f), zero = F8::set1(0.0f);
  const F8 surface = F8::loadu(p.row(kSurface, y) + x) > F8::set1(0.5f);
  const F8 n = select(surface, acc[0], acc[3]), sum = select(surface, acc[1], acc[4]),
           sum_square = select(surface, acc[2], acc[5]);
  const F8 v = max((sum_square - sum * sum / n) / (n - one), zero);
  return select(n > F8::set1(1.5f), v, zero) * F8::loadu(p.row(kAlbedoSquare, y) + x);
}

// The variance of the rows of `chunk` (kChunk rows) into out: the first row sums its window, each next one slides
// it (a fixed order for every pixel, whatever the thread count).
void estimate_chunk(const Planes& p, int radius, int chunk, float* out) {
  const int first_row = chunk * kChunk, end_row = std::min(first_row + kChunk, p.height);
  for (int x = 0; x < p.width; x += kLanes) {
    F8 acc[6];
    for (int y = first_row; y < end_row; ++y) {
      if (y == first_row) sum_window(p, radius, y, x, acc);
      else slide_window(p, radius, y, x, acc);
      window_variance(p, y, x, acc).store_first(out + p.pixel(x, y), p.width - x);
    }
  }
}

// ---- The set-up: demodulation and guides ----

// Eight pixels of a row from column x into the row's planes: colour / albedo with its variance and luminance into
// ping-pong A, the albedo divisor, the depth key, the normal (the sky's (0, 0, 1)) and the depth's slope along y.
[[gnu::always_inline]] inline void prepare_lanes(float* const (&rows)[kPlaneCount], const InputRow& in, int x,
                                                 int count) {
  const F8 one = F8::set1(1.0f), zero = F8::set1(0.0f), sky = F8::set1(kSkyDepth);
  F8 c[3], a[3], n[3] = {zero, zero, one}, z = one, z_up = sky, z_down = sky;
  load_colour_and_divisor(in, x, count, c, a);
  if (in.normal != nullptr) F8::load3_first(in.normal + 3 * static_cast<std::size_t>(x), count, n[0], n[1], n[2]);
  if (in.depth != nullptr) z = depth_key(F8::load_first(in.depth + x, count));
  if (in.depth_up != nullptr) z_up = depth_key(F8::load_first(in.depth_up + x, count));
  if (in.depth_down != nullptr) z_down = depth_key(F8::load_first(in.depth_down + x, count));
  for (int k = 0; k < 3; ++k) {
    a[k].store_first(rows[kAlbedo + k] + x, count);
    c[k] = c[k] / a[k];
    c[k].store_first(rows[kColorA + k] + x, count);
  }
  const F8 la = luminance(a[0], a[1], a[2]);
  (F8::load_first(in.variance + x, count) / (la * la)).store_first(rows[kVarianceA] + x, count);
  luminance(c[0], c[1], c[2]).store_first(rows[kLuminanceA] + x, count);
  z.store_first(rows[kZ] + x, count);
  const F8 surface = z < sky;
  select(surface, n[0], zero).store_first(rows[kNx] + x, count);
  select(surface, n[1], zero).store_first(rows[kNy] + x, count);
  select(surface, n[2], one).store_first(rows[kNz] + x, count);
  depth_slope(z, z_up, z_down).store_first(rows[kGy] + x, count);
}

// Row y of every plane from the input (`variance`: the variance of each pixel's luminance), with blank padding.
void prepare_row(const Planes& p, const DenoiseInput& input, const float* variance, int y) {
  float* rows[kPlaneCount];
  for (int k = 0; k < kPlaneCount; ++k) {
    p.blank_margins(k, y, k == kZ ? kBlankDepth : 0.0f);
    rows[k] = p.row(k, y);
  }
  const InputRow in = input_row(input, variance, y);
  const int width = p.width;
  for (int x = 0; x < width; x += kLanes) prepare_lanes(rows, in, x, width - x);
  // The slope along the row, from the keys (the blank padding counts as no surface, like the sky).
  for (int x = 0; x < width; x += kLanes) {
    const float* z = rows[kZ] + x;
    depth_slope(F8::loadu(z), F8::loadu(z - 1), F8::loadu(z + 1)).store_first(rows[kGx] + x, width - x);
  }
  extend_ends(rows[kVarianceA], width);
}

// Row y's prefiltered luminance into B's luminance plane: each pixel's mean over its 3x3 neighbours (1 2 1 by
// 1 2 1) of the same surface.
void prefilter_row(const Planes& p, int y) {
  const float *l_rows[3], *z_rows[3];
  for (int k = 0; k < 3; ++k) {
    l_rows[k] = p.row_or_blank(kLuminanceA, y + k - 1);
    z_rows[k] = p.row_or_blank(kZ, y + k - 1);
  }
  const float* zc_row = p.row(kZ, y);
  float* out_row = p.row(kLuminanceB, y);
  const F8 zero = F8::set1(0.0f);
  for (int x = 0, width = p.width; x < width; x += kLanes) {
    const F8 zc = F8::loadu(zc_row + x);
    const F8 near = F8::set1(kPrefilterDepth) * abs(zc);
    F8 sum = zero, weight = zero;
    for (int dy = 0; dy < 3; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const F8 kernel = F8::set1((dy == 1 ? 2.0f : 1.0f) * (dx == 0 ? 2.0f : 1.0f));
        // The centre always counts (its difference is 0); the blank padding never does.
        const F8 k = select(abs(F8::loadu(z_rows[dy] + x + dx) - zc) < near, kernel, zero);
        sum = sum + k * F8::loadu(l_rows[dy] + x + dx);
        weight = weight + k;
      }
    }
    (sum / weight).store_first(out_row + x, width - x);
  }
}

// The luminance the first pass compares, so that single samples are not sorted into bright and dark ones
// (docs/denoiser.md, step 3): written into B's luminance plane, which the first pass overwrites, and copied back
// once every row is done.
void prefilter_luminance(const Planes& p, int threads) {
  core::parallel_for(0, p.height, threads, [&](int y) { prefilter_row(p, y); });
  core::parallel_for(0, p.height, threads,
                     [&](int y) { std::copy_n(p.row(kLuminanceB, y), p.width, p.row(kLuminanceA, y)); });
}

// ---- The passes ----

// The eight taps around the centre of the 3x3 kernel (1 2 1 by 1 2 1, centre weight 1 here, so edges 1/2 and
// corners 1/4: the exponents 1 and 2 below), in a fixed order.
struct Tap {
  int dx, dy;
  int axis;        // which depth scale: 0 along x, 1 along y, 2 diagonal
  float exponent;  // the kernel weight is 2^-exponent
};
constexpr Tap kTaps[8] = {{-1, -1, 2, 2.0f}, {0, -1, 1, 1.0f}, {1, -1, 2, 2.0f}, {-1, 0, 0, 1.0f},
                          {1, 0, 0, 1.0f},   {-1, 1, 2, 2.0f}, {0, 1, 1, 1.0f},  {1, 1, 2, 2.0f}};

// One pass: its tap spacing and the ping-pong planes it reads and writes.
struct Pass {
  int step;
  int from, to;  // kColorA or kColorB
  bool last;     // writes the output instead of `to`
};

// What a pass's weights are made of, in the units of weight_from_bits. The normal term sigma (1 - n_c . n_q)
// log2 e is sigma log2 e less a dot product whose centre normal carries the scale; the constant part goes together
// with the kernel's exponent into the bits a weight starts from, for the taps along an axis and the diagonal ones.
struct PassWeights {
  F8 start_edge, start_corner;
  F8 normal_scale;  // sigma_normal log2 e 2^23
  F8 sigma_luminance, log2e_bits;
  F8 depth_step;  // sigma_depth times the pass's tap spacing
};

PassWeights pass_weights(const DenoiseSettings& settings, int step) {
  const float normal_scale = settings.sigma_normal * kLog2e * kBits;
  return {F8::set1((kCutoff - 1.0f) * kBits - normal_scale), F8::set1((kCutoff - 2.0f) * kBits - normal_scale),
          F8::set1(normal_scale), F8::set1(settings.sigma_luminance), F8::set1(kLog2e * kBits),
          F8::set1(settings.sigma_depth * static_cast<float>(step))};
}

// Where the taps of row y find the planes: each tap's depth-key row shifted by its column offset (rows outside
// the image read the blank row, whose every weight is 0), and the other planes at fixed distances from it (the
// planes of a row lie `stride` floats apart).
struct TapRows {
  const float* z[8];
  std::ptrdiff_t nx, ny, nz, r, g, b, variance, luminance;
};

TapRows tap_rows(const Planes& p, const Pass& pass, int y) {
  const auto offset = [&p](int plane) { return static_cast<std::ptrdiff_t>(plane - kZ) * p.stride; };
  TapRows t{{},
            offset(kNx),
            offset(kNy),
            offset(kNz),
            offset(pass.from),
            offset(pass.from + 1),
            offset(pass.from + 2),
            offset(pass.from + kVariance),
            offset(pass.from + kLuminance)};
  for (int k = 0; k < 8; ++k) t.z[k] = p.row_or_blank(kZ, y + kTaps[k].dy * pass.step) + kTaps[k].dx * pass.step;
  return t;
}

// The centre pixels' rows in a pass: the variance of the rows above, at and below (the image's edge rows repeated).
struct CentreRows {
  const float *variance_up, *variance, *variance_down;
  const float *luminance, *z, *normal[3], *slope_x, *slope_y, *colour[3];
};

CentreRows centre_rows(const Planes& p, const Pass& pass, int y) {
  const int v = pass.from + kVariance;
  return {p.row(v, std::max(y - 1, 0)), p.row(v, y), p.row(v, std::min(y + 1, p.height - 1)),
          p.row(pass.from + kLuminance, y), p.row(kZ, y), {p.row(kNx, y), p.row(kNy, y), p.row(kNz, y)},
          p.row(kGx, y), p.row(kGy, y), {p.row(pass.from, y), p.row(pass.from + 1, y), p.row(pass.from + 2, y)}};
}

// Eight centre pixels as the weights need them: their luminance and its scale (from the variance blurred over
// 3x3 pixels, 1 2 1 by 1 2 1 over 16), depth key and its scales along x, y and the diagonal (from the depth's
// slope), both with log2 e 2^23 folded in, the normal times the normal scale; and the values the pass averages.
struct Centre {
  F8 luminance, inv_luminance, z, inv_z[3], normal[3];
  F8 colour[3], variance;
};

F8 blur121(const float* row, int x) {
  return F8::loadu(row + x - 1) + F8::set1(2.0f) * F8::loadu(row + x) + F8::loadu(row + x + 1);
}

[[gnu::always_inline]] inline Centre centre_at(const CentreRows& rows, const PassWeights& w, int x) {
  Centre c;
  const F8 guide = (blur121(rows.variance_up, x) + F8::set1(2.0f) * blur121(rows.variance, x) +
                    blur121(rows.variance_down, x)) * F8::set1(1.0f / 16.0f);
  c.inv_luminance = w.log2e_bits / (w.sigma_luminance * sqrt(guide) + F8::set1(kLuminanceEpsilon));
  c.luminance = F8::loadu(rows.luminance + x);
  c.z = F8::loadu(rows.z + x);
  const F8 base = F8::set1(kDepthRelative) * c.z + F8::set1(1e-30f);
  const F8 gx = F8::loadu(rows.slope_x + x), gy = F8::loadu(rows.slope_y + x);
  c.inv_z[0] = w.log2e_bits / (w.depth_step * gx + base);
  c.inv_z[1] = w.log2e_bits / (w.depth_step * gy + base);
  c.inv_z[2] = w.log2e_bits / (w.depth_step * (gx + gy) + base);
  for (int k = 0; k < 3; ++k) {
    c.normal[k] = w.normal_scale * F8::loadu(rows.normal[k] + x);
    c.colour[k] = F8::loadu(rows.colour[k] + x);
  }
  c.variance = F8::loadu(rows.variance + x);
  return c;
}

// Tap k's weight for the centre pixels c at column x: the kernel's and the normal, luminance and depth terms.
[[gnu::always_inline]] inline F8 tap_weight(const TapRows& t, int k, const Centre& c, const PassWeights& w, int x) {
  const float* q = t.z[k] + x;
  const F8 dot =
      c.normal[0] * F8::loadu(q + t.nx) + c.normal[1] * F8::loadu(q + t.ny) + c.normal[2] * F8::loadu(q + t.nz);
  const F8 bits = ((kTaps[k].exponent == 1.0f ? w.start_edge : w.start_corner) + dot) -
                  abs(c.luminance - F8::loadu(q + t.luminance)) * c.inv_luminance -
                  abs(c.z - F8::loadu(q)) * c.inv_z[kTaps[k].axis];
  return weight_from_bits(bits);
}

// The weighted sums over the centre (weight 1) and its taps; the variance's with the squared weights, unless
// kLast (whose variance nothing reads).
struct Sums {
  F8 r, g, b, variance, weight;
};

template <bool kLast>
[[gnu::always_inline]] inline Sums sum_taps(const TapRows& t, const Centre& c, const PassWeights& w, int x) {
  // All eight weights first, then the sums: eight independent chains for the processor to overlap.
  F8 weights[8];
#pragma GCC unroll 8
  for (int k = 0; k < 8; ++k) weights[k] = tap_weight(t, k, c, w, x);
  Sums s{c.colour[0], c.colour[1], c.colour[2], c.variance, F8::set1(1.0f)};
#pragma GCC unroll 8
  for (int k = 0; k < 8; ++k) {
    const float* q = t.z[k] + x;
    s.r = s.r + weights[k] * F8::loadu(q + t.r);
    s.g = s.g + weights[k] * F8::loadu(q + t.g);
    s.b = s.b + weights[k] * F8::loadu(q + t.b);
    if constexpr (!kLast) s.variance = s.variance + weights[k] * weights[k] * F8::loadu(q + t.variance);
    s.weight = s.weight + weights[k];
  }
  return s;
}

// The means into the next pass's planes at row y, columns x on: colour, variance (sum w^2 v / (sum w)^2) and
// luminance.
[[gnu::always_inline]] inline void store_pass(const Planes& p, const Pass& pass, int y, int x, const Sums& s) {
  const int count = p.width - x;
  const F8 inv_w = F8::set1(1.0f) / s.weight;
  const F8 r = s.r * inv_w, g = s.g * inv_w, b = s.b * inv_w;
  r.store_first(p.row(pass.to, y) + x, count);
  g.store_first(p.row(pass.to + 1, y) + x, count);
  b.store_first(p.row(pass.to + 2, y) + x, count);
  (s.variance * (inv_w * inv_w)).store_first(p.row(pass.to + kVariance, y) + x, count);
  luminance(r, g, b).store_first(p.row(pass.to + kLuminance, y) + x, count);
}

// The means multiplied back by the albedo, into the output at row y, columns x on.
[[gnu::always_inline]] inline void store_output(const Planes& p, int y, int x, const Sums& s, std::span<Vec3f> out) {
  const F8 inv_w = F8::set1(1.0f) / s.weight;
  const F8 r = s.r * inv_w * F8::loadu(p.row(kAlbedo, y) + x), g = s.g * inv_w * F8::loadu(p.row(kAlbedo + 1, y) + x),
           b = s.b * inv_w * F8::loadu(p.row(kAlbedo + 2, y) + x);
  F8::store3_first(&out[p.pixel(x, y)].x, p.width - x, r, g, b);
}

// One row of a pass.
template <bool kLast>
void filter_row(const Planes& p, const PassWeights& weights, const Pass& pass, int y, std::span<Vec3f> out) {
  // A local copy of the weights: the stores to the planes could alias anything outside (an F8 may alias a
  // float), which would then be loaded again for every eight pixels.
  const PassWeights w = weights;
  const TapRows taps = tap_rows(p, pass, y);
  const CentreRows rows = centre_rows(p, pass, y);
  for (int x = 0; x < p.width; x += kLanes) {
    const Sums s = sum_taps<kLast>(taps, centre_at(rows, w, x), w, x);
    if constexpr (kLast) store_output(p, y, x, s, out);
    else store_pass(p, pass, y, x, s);
  }
  if constexpr (!kLast) extend_ends(p.row(pass.to + kVariance, y), p.width);
}

// row(y) for every row, in the order y = c, c + step, c + 2 step, ... for c = 0 .. step - 1, so that the rows a
// row's taps read were mostly read by the row before (and are still in the cache); threads take kChunk at a time.
template <class Row>
void for_rows_by_step(int height, int step, int threads, const Row& row) {
  const int chunks = (height + kChunk - 1) / kChunk;
  core::parallel_for(0, chunks, threads, [&](int chunk) {
    int first = chunk * kChunk;
    const int end = std::min(first + kChunk, height);
    int c = 0;
    while (first >= (height - c + step - 1) / step) first -= (height - c++ + step - 1) / step;
    for (int i = chunk * kChunk, y = c + first * step; i < end; ++i) {
      row(y);
      y += step;
      if (y >= height) y = ++c;
    }
  });
}

// Pass t (from 0) of `iterations`; the last writes the output.
void filter_pass(const Planes& p, const DenoiseSettings& settings, int t, std::span<Vec3f> out) {
  const Pass pass{1 << t, t % 2 == 0 ? kColorA : kColorB, t % 2 == 0 ? kColorB : kColorA, t + 1 == settings.iterations};
  const PassWeights weights = pass_weights(settings, pass.step);
  for_rows_by_step(p.height, pass.step, settings.threads, [&](int y) {
    if (pass.last) filter_row<true>(p, weights, pass, y, out);
    else filter_row<false>(p, weights, pass, y, out);
  });
}

// The number of pixels, after checking the input's sizes.
std::size_t validate(const DenoiseInput& in) {
  if (in.width < 1 || in.height < 1) throw std::invalid_argument("denoise: the image is empty");
  const std::size_t n = Aovs::pixels(in.width, in.height);
  if (in.color.size() != n) throw std::invalid_argument("denoise: colour is not width x height");
  if (in.aovs != nullptr &&
      (in.aovs->width != in.width || in.aovs->height != in.height || in.aovs->albedo.size() != n ||
       in.aovs->normal.size() != n || in.aovs->depth.size() != n))
    throw std::invalid_argument("denoise: the feature buffers are not width x height");
  return n;
}

void check_settings(const DenoiseSettings& s) {
  if (s.iterations < 0 || s.iterations > Denoiser::kMaxIterations)
    throw std::invalid_argument("denoise: iterations out of range");
  if (!(s.sigma_luminance > 0) || !(s.sigma_normal > 0) || !(s.sigma_depth > 0))
    throw std::invalid_argument("denoise: the sigmas must be positive");
  if (s.variance_radius < 1) throw std::invalid_argument("denoise: variance_radius must be at least 1");
}

int round_up(int v, int m) { return (v + m - 1) / m * m; }

}  // namespace

void Denoiser::layout(int width, int height, int reach) {
  const int pad = round_up(std::max(reach, 1), kAlign);
  if (width_ == width && height_ == height && pad_ >= pad) return;
  width_ = width;
  height_ = height;
  pad_ = pad;
  stride_ = pad_ + round_up(width, kBlock) + pad_;
  // One more row than the image: a blank row, which the taps above and below the image read.
  const std::size_t size = static_cast<std::size_t>(stride_) * static_cast<std::size_t>(height + 1) * kPlaneCount;
  if (storage_.size() < size + kAlign) storage_.resize(size + kAlign);
}

float* Denoiser::planes_base() {
  // Rows start on cache lines (stride and pad are multiples of 16 floats), so loads at the pixels' own columns do
  // not straddle two.
  const std::uintptr_t address = reinterpret_cast<std::uintptr_t>(storage_.data());
  return storage_.data() + (kAlign - address / sizeof(float) % kAlign) % kAlign;
}

void Denoiser::estimate_variance(const DenoiseInput& input, int radius, int threads, std::span<float> out) {
  validate(input);
  if (out.size() != Aovs::pixels(input.width, input.height))
    throw std::invalid_argument("estimate_variance: out is not width x height");
  if (radius < 1) throw std::invalid_argument("estimate_variance: radius must be at least 1");
  layout(input.width, input.height, radius);
  estimate(input, radius, threads, out.data());
}

void Denoiser::estimate(const DenoiseInput& input, int radius, int threads, float* out) {
  const Planes p{planes_base(), width_, height_, stride_, pad_};
  core::parallel_for(0, p.height, threads, [&](int y) {
    estimate_inputs_row(p, input, y);
    horizontal_sums_row(p, radius, y);
  });
  const int chunks = (p.height + kChunk - 1) / kChunk;
  core::parallel_for(0, chunks, threads, [&](int chunk) { estimate_chunk(p, radius, chunk, out); });
}

void Denoiser::denoise(const DenoiseInput& input, const DenoiseSettings& settings, std::span<Vec3f> out) {
  check_settings(settings);
  const std::size_t n = validate(input);
  if (out.size() != n) throw std::invalid_argument("denoise: out is not width x height");
  if (!input.variance.empty() && input.variance.size() != n)
    throw std::invalid_argument("denoise: variance is neither empty nor width x height");
  if (settings.iterations == 0) {
    if (out.data() != input.color.data()) std::copy(input.color.begin(), input.color.end(), out.begin());
    return;
  }
  layout(input.width, input.height, std::max(1 << (settings.iterations - 1), settings.variance_radius));
  const float* variance = input.variance.data();
  if (input.variance.empty()) {
    if (variance_.size() < n) variance_.resize(n);
    estimate(input, settings.variance_radius, settings.threads, variance_.data());
    variance = variance_.data();
  }
  const Planes p{planes_base(), width_, height_, stride_, pad_};
  clear_blank_row(p);
  core::parallel_for(0, p.height, settings.threads, [&](int y) { prepare_row(p, input, variance, y); });
  prefilter_luminance(p, settings.threads);
  for (int t = 0; t < settings.iterations; ++t) filter_pass(p, settings, t, out);
}

void denoise(const DenoiseInput& input, const DenoiseSettings& settings, std::span<Vec3f> out) {
  Denoiser d;
  d.denoise(input, settings, out);
}

}  // namespace tripsitter::render

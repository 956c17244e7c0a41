#include <tripsitter/render/denoise.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <type_traits>

#if defined(__AVX2__)
#include <immintrin.h>
#else
#include <emmintrin.h>
#endif

#include <tripsitter/core/parallel.h>

namespace tripsitter::render {
namespace {

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
// Rows a thread takes at a time in the filter's passes.
constexpr int kChunk = 8;
// Floats in a cache line.
constexpr int kAlign = 16;

// The filter's arithmetic on several pixels at once: eight lanes where the library is built for AVX2, four
// (SSE2) otherwise. Each lane performs its pixel's IEEE operations in the same order either way (no fused
// multiply-add), so both give the same bits. Internal to this file, so no other translation unit can mix up the
// two layouts (isa.h).
#if defined(__AVX2__)
struct Lanes {
  static constexpr int kWidth = 8;
  __m256 v;
  static Lanes load(const float* p) { return {_mm256_loadu_ps(p)}; }
  static Lanes set1(float x) { return {_mm256_set1_ps(x)}; }
  void store(float* p) const { _mm256_storeu_ps(p, v); }
  friend Lanes operator+(Lanes a, Lanes b) { return {_mm256_add_ps(a.v, b.v)}; }
  friend Lanes operator-(Lanes a, Lanes b) { return {_mm256_sub_ps(a.v, b.v)}; }
  friend Lanes operator*(Lanes a, Lanes b) { return {_mm256_mul_ps(a.v, b.v)}; }
  friend Lanes operator/(Lanes a, Lanes b) { return {_mm256_div_ps(a.v, b.v)}; }
  friend Lanes abs(Lanes a) { return {_mm256_andnot_ps(_mm256_set1_ps(-0.0f), a.v)}; }
  friend Lanes sqrt(Lanes a) { return {_mm256_sqrt_ps(a.v)}; }
  // Lane by lane; b where either is NaN.
  friend Lanes min(Lanes a, Lanes b) { return {_mm256_min_ps(a.v, b.v)}; }
  friend Lanes max(Lanes a, Lanes b) { return {_mm256_max_ps(a.v, b.v)}; }
  // The float whose bits are the whole part of a (a in [0, 2^31)).
  friend Lanes float_with_bits(Lanes a) { return {_mm256_castsi256_ps(_mm256_cvttps_epi32(a.v))}; }
  // Masks: all ones in a lane where the comparison holds (false where either side is NaN).
  friend Lanes operator<(Lanes a, Lanes b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)}; }
  friend Lanes operator>(Lanes a, Lanes b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)}; }
  friend Lanes operator>=(Lanes a, Lanes b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GE_OQ)}; }
  friend Lanes operator&(Lanes a, Lanes b) { return {_mm256_and_ps(a.v, b.v)}; }
  // mask ? a : b, lane by lane.
  friend Lanes select(Lanes mask, Lanes a, Lanes b) { return {_mm256_blendv_ps(b.v, a.v, mask.v)}; }

  // Eight 3-vectors (24 floats: x0 y0 z0 x1 ...) to three planes and back. Each plane's lanes are blended from the
  // three registers where they lie (x at 0 3 6 of the first, 1 4 7 of the second, 2 5 of the third, ...), then
  // put in order by one permutation.
  static void load3(const float* p, Lanes& x, Lanes& y, Lanes& z) {
    const __m256 a = _mm256_loadu_ps(p), b = _mm256_loadu_ps(p + 8), c = _mm256_loadu_ps(p + 16);
    const __m256 bx = _mm256_blend_ps(_mm256_blend_ps(a, b, 0b10010010), c, 0b00100100);
    const __m256 by = _mm256_blend_ps(_mm256_blend_ps(a, b, 0b00100100), c, 0b01001001);
    const __m256 bz = _mm256_blend_ps(_mm256_blend_ps(a, b, 0b01001001), c, 0b10010010);
    x.v = _mm256_permutevar8x32_ps(bx, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    y.v = _mm256_permutevar8x32_ps(by, _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
    z.v = _mm256_permutevar8x32_ps(bz, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
  }
  static void store3(float* p, Lanes x, Lanes y, Lanes z) {
    const __m256 bx = _mm256_permutevar8x32_ps(x.v, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    const __m256 by = _mm256_permutevar8x32_ps(y.v, _mm256_setr_epi32(5, 0, 3, 6, 1, 4, 7, 2));
    const __m256 bz = _mm256_permutevar8x32_ps(z.v, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
    _mm256_storeu_ps(p, _mm256_blend_ps(_mm256_blend_ps(bx, by, 0b10010010), bz, 0b00100100));
    _mm256_storeu_ps(p + 8, _mm256_blend_ps(_mm256_blend_ps(bz, bx, 0b10010010), by, 0b00100100));
    _mm256_storeu_ps(p + 16, _mm256_blend_ps(_mm256_blend_ps(by, bz, 0b10010010), bx, 0b00100100));
  }
};
#else
struct Lanes {
  static constexpr int kWidth = 4;
  __m128 v;
  static Lanes load(const float* p) { return {_mm_loadu_ps(p)}; }
  static Lanes set1(float x) { return {_mm_set1_ps(x)}; }
  void store(float* p) const { _mm_storeu_ps(p, v); }
  friend Lanes operator+(Lanes a, Lanes b) { return {_mm_add_ps(a.v, b.v)}; }
  friend Lanes operator-(Lanes a, Lanes b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend Lanes operator*(Lanes a, Lanes b) { return {_mm_mul_ps(a.v, b.v)}; }
  friend Lanes operator/(Lanes a, Lanes b) { return {_mm_div_ps(a.v, b.v)}; }
  friend Lanes abs(Lanes a) { return {_mm_andnot_ps(_mm_set1_ps(-0.0f), a.v)}; }
  friend Lanes sqrt(Lanes a) { return {_mm_sqrt_ps(a.v)}; }
  friend Lanes min(Lanes a, Lanes b) { return {_mm_min_ps(a.v, b.v)}; }
  friend Lanes max(Lanes a, Lanes b) { return {_mm_max_ps(a.v, b.v)}; }
  friend Lanes float_with_bits(Lanes a) { return {_mm_castsi128_ps(_mm_cvttps_epi32(a.v))}; }
  friend Lanes operator<(Lanes a, Lanes b) { return {_mm_cmplt_ps(a.v, b.v)}; }
  friend Lanes operator>(Lanes a, Lanes b) { return {_mm_cmpgt_ps(a.v, b.v)}; }
  friend Lanes operator>=(Lanes a, Lanes b) { return {_mm_cmpge_ps(a.v, b.v)}; }
  friend Lanes operator&(Lanes a, Lanes b) { return {_mm_and_ps(a.v, b.v)}; }
  friend Lanes select(Lanes mask, Lanes a, Lanes b) {
    return {_mm_or_ps(_mm_and_ps(mask.v, a.v), _mm_andnot_ps(mask.v, b.v))};
  }

  // Four 3-vectors (12 floats: x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3) to three planes and back.
  static void load3(const float* p, Lanes& x, Lanes& y, Lanes& z) {
    const __m128 a = _mm_loadu_ps(p), b = _mm_loadu_ps(p + 4), c = _mm_loadu_ps(p + 8);
    const __m128 x01 = _mm_shuffle_ps(a, a, _MM_SHUFFLE(0, 3, 0, 0));  // x0 . x1 .
    const __m128 x23 = _mm_shuffle_ps(b, c, _MM_SHUFFLE(0, 1, 0, 2));  // x2 . x3 .
    const __m128 y01 = _mm_shuffle_ps(a, b, _MM_SHUFFLE(0, 0, 0, 1));  // y0 . y1 .
    const __m128 y23 = _mm_shuffle_ps(b, c, _MM_SHUFFLE(0, 2, 0, 3));  // y2 . y3 .
    const __m128 z01 = _mm_shuffle_ps(a, b, _MM_SHUFFLE(0, 1, 0, 2));  // z0 . z1 .
    const __m128 z23 = _mm_shuffle_ps(c, c, _MM_SHUFFLE(0, 3, 0, 0));  // z2 . z3 .
    x.v = _mm_shuffle_ps(x01, x23, _MM_SHUFFLE(2, 0, 2, 0));
    y.v = _mm_shuffle_ps(y01, y23, _MM_SHUFFLE(2, 0, 2, 0));
    z.v = _mm_shuffle_ps(z01, z23, _MM_SHUFFLE(2, 0, 2, 0));
  }
  static void store3(float* p, Lanes x, Lanes y, Lanes z) {
    const __m128 xy01 = _mm_unpacklo_ps(x.v, y.v);                            // x0 y0 x1 y1
    const __m128 xy23 = _mm_unpackhi_ps(x.v, y.v);                            // x2 y2 x3 y3
    const __m128 t = _mm_shuffle_ps(z.v, xy01, _MM_SHUFFLE(3, 2, 1, 0));      // z0 z1 x1 y1
    const __m128 u = _mm_shuffle_ps(z.v, xy23, _MM_SHUFFLE(3, 2, 3, 2));      // z2 z3 x3 y3
    _mm_storeu_ps(p, _mm_shuffle_ps(xy01, t, _MM_SHUFFLE(2, 0, 1, 0)));       // x0 y0 z0 x1
    _mm_storeu_ps(p + 4, _mm_shuffle_ps(t, xy23, _MM_SHUFFLE(1, 0, 1, 3)));   // y1 z1 x2 y2
    _mm_storeu_ps(p + 8, _mm_shuffle_ps(u, u, _MM_SHUFFLE(1, 3, 2, 0)));      // z2 x3 y3 z3
  }
};
#endif

// The first `count` lanes of a to p (all of them when count >= the width): the planes' padding stays blank.
void store(Lanes a, float* p, int count) {
  if (count >= Lanes::kWidth) {
    a.store(p);
  } else {
    float lanes[Lanes::kWidth];
    a.store(lanes);
    std::copy(lanes, lanes + count, p);
  }
}

// Lanes from p[0 .. count) (all of them when count >= the width), 0 beyond: never reads past an input array.
[[gnu::noinline]] Lanes load_tail(const float* p, int count) {
  float lanes[Lanes::kWidth] = {};
  std::copy(p, p + count, lanes);
  return Lanes::load(lanes);
}
inline Lanes load(const float* p, int count) { return count >= Lanes::kWidth ? Lanes::load(p) : load_tail(p, count); }

// The same for `count` 3-vectors at p (3 count floats), as three planes.
[[gnu::noinline]] void load3_tail(const float* p, int count, Lanes& x, Lanes& y, Lanes& z) {
  float lanes[3 * Lanes::kWidth] = {};
  std::copy(p, p + 3 * count, lanes);
  Lanes::load3(lanes, x, y, z);
}
inline void load3(const float* p, int count, Lanes& x, Lanes& y, Lanes& z) {
  if (count >= Lanes::kWidth) {
    Lanes::load3(p, x, y, z);
  } else {
    load3_tail(p, count, x, y, z);
  }
}

Lanes luminance709(Lanes r, Lanes g, Lanes b) {
  return Lanes::set1(0.2126f) * r + Lanes::set1(0.7152f) * g + Lanes::set1(0.0722f) * b;
}

// A depth as a key: itself for a surface, kSkyDepth for infinity (and NaN or a negative depth).
Lanes depth_key(Lanes d) {
  return select((d >= Lanes::set1(0.0f)) & (d < Lanes::set1(kSkyDepth)), d, Lanes::set1(kSkyDepth));
}

// The depth's change per pixel at pixels of key z, from their neighbours of keys a and b on either side: the mean
// of the two changes, unless one side is not a surface (sky or blank) or changes more than kSlopeJump times the
// other, which marks an edge: then the smaller change (0 when neither side is a surface, or z is the sky). Each
// depth is that of one jittered sample or a mean over a few, so one side alone can show almost no change.
Lanes depth_slope(Lanes z, Lanes a, Lanes b) {
  const Lanes sky = Lanes::set1(kSkyDepth), zero = Lanes::set1(0.0f);
  const auto is_surface = [zero, sky](Lanes key) { return (key >= zero) & (key < sky); };  // not sky nor blank
  const Lanes da = select(is_surface(a), abs(z - a), sky), db = select(is_surface(b), abs(z - b), sky);
  const Lanes lo = min(da, db), hi = max(da, db);
  const Lanes smooth = (hi < sky) & (hi < Lanes::set1(kSlopeJump) * lo + Lanes::set1(kDepthRelative * 10.0f) * z);
  const Lanes g = select(smooth, (lo + hi) * Lanes::set1(0.5f), lo);
  return select((g < sky) & is_surface(z), g, zero);
}

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
Lanes weight_from_bits(Lanes bits) {
  const Lanes clamped = min(max(bits, Lanes::set1(0.0f)), Lanes::set1(kCutoff * kBits));
  return float_with_bits(clamped) * Lanes::set1(kWeightScale);
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

// The scratch storage: kPlaneCount planes of `stride` floats by the image's rows, row y of every plane before
// row y + 1 (so that a tap's loads come from a few pages). A row holds the image's pixels from column `pad` on,
// with blank pixels (which every weight rejects) before and after.
struct Denoiser::Planes {
  float* base;
  int stride, pad;
  // Pixel (0, y) of plane k; columns -pad to stride - pad - 1 may be addressed from there.
  float* row(int k, int y) const {
    return base + (static_cast<std::size_t>(y) * kPlaneCount + static_cast<std::size_t>(k)) * static_cast<std::size_t>(stride) + pad;
  }
};

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
  const Planes p{planes_base(), stride_, pad_};
  const int w = width_, h = height_;
  const Aovs* aovs = input.aovs;
  const std::size_t row_pixels = static_cast<std::size_t>(w);
  // Per pixel the luminance l of colour / albedo, its kind (1 in the surface plane or in the sky plane; the
  // blank padding is neither) and the albedo's luminance squared; then horizontal sums over 2 radius + 1 columns
  // of each kind's count, l and l^2.
  constexpr int kL = 0, kSurface = 1, kSky = 2, kAlbedoSquare = 3, kSums = 4;  // kSums .. kSums + 5: surface
                                                                               // count, l, l^2, sky count, ...
  core::parallel_for(0, h, threads, [&](int y) {
    float* rows[kSums];
    for (int k = 0; k < kSums; ++k) {
      rows[k] = p.row(k, y);
      std::fill(rows[k] - p.pad, rows[k], 0.0f);
      std::fill(rows[k] + w, rows[k] + (p.stride - p.pad), 0.0f);
    }
    const std::size_t first = static_cast<std::size_t>(y) * row_pixels;
    const Lanes one = Lanes::set1(1.0f), zero = Lanes::set1(0.0f), epsilon = Lanes::set1(kAlbedoEpsilon);
    for (int x = 0; x < w; x += Lanes::kWidth) {
      const int count = w - x;
      const std::size_t at = first + static_cast<std::size_t>(x);
      Lanes c[3], a[3] = {one, one, one}, surface = one;
      load3(&input.color[at].x, count, c[0], c[1], c[2]);
      if (aovs != nullptr) {
        load3(&aovs->albedo[at].x, count, a[0], a[1], a[2]);
        for (Lanes& channel : a) channel = select(channel > epsilon, channel, one);
        surface = select(depth_key(load(aovs->depth.data() + at, count)) < Lanes::set1(kSkyDepth), one, zero);
      }
      const Lanes la = luminance709(a[0], a[1], a[2]);
      store(luminance709(c[0] / a[0], c[1] / a[1], c[2] / a[2]), rows[kL] + x, count);
      store(surface, rows[kSurface] + x, count);
      store(one - surface, rows[kSky] + x, count);
      store(la * la, rows[kAlbedoSquare] + x, count);
    }
    for (int x0 = 0; x0 < w; x0 += kBlock) {
      float acc[6][kBlock] = {};
      for (int dx = -radius; dx <= radius; ++dx) {
        const float* lq = rows[kL] + x0 + dx;
        const float* sq = rows[kSurface] + x0 + dx;
        const float* kq = rows[kSky] + x0 + dx;
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
  });
  // Vertical sums of the horizontal ones over 2 radius + 1 rows, of the centre's kind: the sample variance of
  // its window, times the albedo's luminance squared. Threads take kChunk rows at a time; the first row of a chunk
  // sums its window, each next one adds the row that enters it and subtracts the one that leaves (a fixed order
  // for every pixel, whatever the thread count).
  const int chunks = (h + kChunk - 1) / kChunk;
  core::parallel_for(0, chunks, threads, [&](int chunk) {
    const int first_row = chunk * kChunk, end_row = std::min(first_row + kChunk, h);
    for (int x = 0; x < w; x += Lanes::kWidth) {
      Lanes acc[6];
      for (int y = first_row; y < end_row; ++y) {
        if (y == first_row) {
          const int y0 = std::max(y - radius, 0), y1 = std::min(y + radius, h - 1);
          for (int k = 0; k < 6; ++k) {
            acc[k] = Lanes::load(p.row(kSums + k, y0) + x);
            for (int yq = y0 + 1; yq <= y1; ++yq) acc[k] = acc[k] + Lanes::load(p.row(kSums + k, yq) + x);
          }
        } else {
          const int enters = y + radius, leaves = y - radius - 1;
          for (int k = 0; k < 6; ++k) {
            if (enters < h) acc[k] = acc[k] + Lanes::load(p.row(kSums + k, enters) + x);
            if (leaves >= 0) acc[k] = acc[k] - Lanes::load(p.row(kSums + k, leaves) + x);
          }
        }
        const Lanes is_surface = Lanes::load(p.row(kSurface, y) + x) > Lanes::set1(0.5f);
        const Lanes n = select(is_surface, acc[0], acc[3]), sum = select(is_surface, acc[1], acc[4]),
                    sum_square = select(is_surface, acc[2], acc[5]);
        const Lanes one = Lanes::set1(1.0f), zero = Lanes::set1(0.0f);
        const Lanes v = max((sum_square - sum * sum / n) / (n - one), zero);
        store(select(n > Lanes::set1(1.5f), v, zero) * Lanes::load(p.row(kAlbedoSquare, y) + x),
              out + static_cast<std::size_t>(y) * row_pixels + static_cast<std::size_t>(x), w - x);
      }
    }
  });
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
  const int w = input.width, h = input.height;
  const int threads = settings.threads;
  layout(w, h, std::max(1 << (settings.iterations - 1), settings.variance_radius));
  const float* variance = input.variance.data();
  if (input.variance.empty()) {
    if (variance_.size() < n) variance_.resize(n);
    estimate(input, settings.variance_radius, threads, variance_.data());
    variance = variance_.data();
  }

  const Planes p{planes_base(), stride_, pad_};
  const Aovs* aovs = input.aovs;
  const std::size_t row_pixels = static_cast<std::size_t>(w);

  // The blank row below the image.
  for (int k = 0; k < kPlaneCount; ++k)
    std::fill(p.row(k, h) - p.pad, p.row(k, h) + (p.stride - p.pad), k == kZ ? kBlankDepth : 0.0f);
  // Colour / albedo and its variance and luminance into ping-pong A, the guides into theirs; blank padding.
  constexpr int kWidth = Lanes::kWidth;
  core::parallel_for(0, h, threads, [&](int y) {
    float* rows[kPlaneCount];
    for (int k = 0; k < kPlaneCount; ++k) {
      rows[k] = p.row(k, y);
      const float blank = k == kZ ? kBlankDepth : 0.0f;
      std::fill(rows[k] - p.pad, rows[k], blank);
      std::fill(rows[k] + w, rows[k] + (p.stride - p.pad), blank);
    }
    const std::size_t first = static_cast<std::size_t>(y) * row_pixels;
    const float* color = &input.color[first].x;
    const float* row_variance = variance + first;
    const float* albedo = aovs != nullptr ? &aovs->albedo[first].x : nullptr;
    const float* normal = aovs != nullptr ? &aovs->normal[first].x : nullptr;
    const float* depth = aovs != nullptr ? aovs->depth.data() + first : nullptr;
    const float* up = aovs != nullptr && y > 0 ? depth - row_pixels : nullptr;
    const float* down = aovs != nullptr && y + 1 < h ? depth + row_pixels : nullptr;
    const Lanes one = Lanes::set1(1.0f), zero = Lanes::set1(0.0f), epsilon = Lanes::set1(kAlbedoEpsilon),
                sky = Lanes::set1(kSkyDepth);
    // The inputs, kWidth pixels at a time (the last few through a buffer, so as not to read past the arrays):
    // colour / albedo, its variance and luminance, the albedo divisor, the depth keys and normals.
    for (int x = 0; x < w; x += kWidth) {
      const int count = w - x;
      const std::size_t x3 = static_cast<std::size_t>(x) * 3;
      const auto vectors = [count, x3](const float* from, Lanes& a, Lanes& b, Lanes& c) {
        load3(from + x3, count, a, b, c);
      };
      const auto floats = [count, x](const float* from) { return load(from + x, count); };
      Lanes c[3], a[3] = {one, one, one}, n[3] = {zero, zero, one}, z = one;
      vectors(color, c[0], c[1], c[2]);
      if (aovs != nullptr) {
        vectors(albedo, a[0], a[1], a[2]);
        vectors(normal, n[0], n[1], n[2]);
        z = depth_key(floats(depth));
      }
      const Lanes surface = z < sky;
      for (int k = 0; k < 3; ++k) {
        a[k] = select(a[k] > epsilon, a[k], one);
        c[k] = c[k] / a[k];
        store(a[k], rows[kAlbedo + k] + x, count);
        store(c[k], rows[kColorA + k] + x, count);
      }
      const Lanes la = luminance709(a[0], a[1], a[2]);
      store(floats(row_variance) / (la * la), rows[kVarianceA] + x, count);
      store(luminance709(c[0], c[1], c[2]), rows[kLuminanceA] + x, count);
      store(z, rows[kZ] + x, count);
      store(select(surface, n[0], zero), rows[kNx] + x, count);
      store(select(surface, n[1], zero), rows[kNy] + x, count);
      store(select(surface, n[2], one), rows[kNz] + x, count);
      const Lanes z_up = up != nullptr ? depth_key(floats(up)) : sky;
      const Lanes z_down = down != nullptr ? depth_key(floats(down)) : sky;
      store(depth_slope(z, z_up, z_down), rows[kGy] + x, count);
    }
    // The slope along the row, from the keys (the blank padding counts as no surface, like the sky).
    for (int x = 0; x < w; x += kWidth) {
      const Lanes z = Lanes::load(rows[kZ] + x);
      store(depth_slope(z, Lanes::load(rows[kZ] + x - 1), Lanes::load(rows[kZ] + x + 1)), rows[kGx] + x, w - x);
    }
    // The variance prefilter reads one pixel beyond the edges: the edge's own.
    rows[kVarianceA][-1] = rows[kVarianceA][0];
    rows[kVarianceA][w] = rows[kVarianceA][w - 1];
  });

  // The luminance the first pass compares: each pixel's mean over its 3x3 neighbours (1 2 1 by 1 2 1) of the same
  // surface, so that single samples are not sorted into bright and dark ones (docs/denoiser.md, step 3).
  // Written into B's luminance plane, which the first pass overwrites, and copied back once every row is done.
  core::parallel_for(0, h, threads, [&](int y) {
    const float *l_rows[3], *z_rows[3];
    for (int k = 0; k < 3; ++k) {
      const int yq = y + k - 1;
      l_rows[k] = p.row(kLuminanceA, yq >= 0 && yq < h ? yq : h);  // outside the image: the blank row
      z_rows[k] = p.row(kZ, yq >= 0 && yq < h ? yq : h);
    }
    const float* zc_row = p.row(kZ, y);
    float* out_row = p.row(kLuminanceB, y);
    const Lanes zero = Lanes::set1(0.0f), tolerance = Lanes::set1(kPrefilterDepth);
    for (int x = 0; x < w; x += kWidth) {
      const Lanes zc = Lanes::load(zc_row + x);
      const Lanes near = tolerance * abs(zc);
      Lanes sum = zero, weight = zero;
      for (int dy = 0; dy < 3; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const Lanes kernel = Lanes::set1((dy == 1 ? 2.0f : 1.0f) * (dx == 0 ? 2.0f : 1.0f));
          // The centre always counts (its difference is 0); the blank padding never does.
          const Lanes k = select(abs(Lanes::load(z_rows[dy] + x + dx) - zc) < near, kernel, zero);
          sum = sum + k * Lanes::load(l_rows[dy] + x + dx);
          weight = weight + k;
        }
      }
      store(sum / weight, out_row + x, w - x);
    }
  });
  core::parallel_for(0, h, threads, [&](int y) { std::copy_n(p.row(kLuminanceB, y), w, p.row(kLuminanceA, y)); });

  // The eight taps around the centre of the 3x3 kernel (1 2 1 by 1 2 1, centre weight 1 here, so edges 1/2 and
  // corners 1/4: the exponents 1 and 2 below), in a fixed order.
  struct Tap {
    int dx, dy;
    int axis;        // which depth scale: 0 along x, 1 along y, 2 diagonal
    float exponent;  // the kernel weight is 2^-exponent
  };
  static constexpr Tap kTaps[8] = {{-1, -1, 2, 2.0f}, {0, -1, 1, 1.0f}, {1, -1, 2, 2.0f}, {-1, 0, 0, 1.0f},
                                   {1, 0, 0, 1.0f},   {-1, 1, 2, 2.0f}, {0, 1, 1, 1.0f},  {1, 1, 2, 2.0f}};
  // The normal term sigma (1 - n_c . n_q) log2 e is sigma log2 e less a dot product whose centre normal carries
  // the scale; the constant part goes together with the kernel's exponent into the bits a weight starts from, for
  // the taps along an axis and the diagonal ones.
  const float normal_scale = settings.sigma_normal * kLog2e * kBits;
  const Lanes start_edge = Lanes::set1((kCutoff - 1.0f) * kBits - normal_scale);
  const Lanes start_corner = Lanes::set1((kCutoff - 2.0f) * kBits - normal_scale);
  const Lanes sigma_luminance = Lanes::set1(settings.sigma_luminance);
  const Lanes log2e_bits = Lanes::set1(kLog2e * kBits);
  for (int t = 0; t < settings.iterations; ++t) {
    const int step = 1 << t;
    const bool last = t + 1 == settings.iterations;
    const int from = t % 2 == 0 ? kColorA : kColorB;
    const int to = t % 2 == 0 ? kColorB : kColorA;
    const Lanes depth_step = Lanes::set1(settings.sigma_depth * static_cast<float>(step));
    // Where a tap finds each plane, from its row's depth key (the planes of a row lie `stride` floats apart).
    const std::ptrdiff_t stride = p.stride;
    const auto offset = [stride](int plane) { return static_cast<std::ptrdiff_t>(plane - kZ) * stride; };
    const std::ptrdiff_t at_nx = offset(kNx), at_ny = offset(kNy), at_nz = offset(kNz), at_r = offset(from),
                         at_g = offset(from + 1), at_b = offset(from + 2), at_v = offset(from + kVariance),
                         at_l = offset(from + kLuminance);
    // One row; the last pass (kLast) needs no variance and writes the output.
    const auto filter_row = [&](int y, auto last_pass) {
      constexpr bool kLast = decltype(last_pass)::value;
      // Local copies of what the loop reads: the stores to the planes could alias anything outside (__m256 may
      // alias a float), which would then be loaded again for every group of pixels.
      const Lanes start_e = start_edge, start_c = start_corner, sigma_l = sigma_luminance, log2e_b = log2e_bits,
                  depth_s = depth_step, scale = Lanes::set1(normal_scale);
      // The depth-key row each tap reads, shifted by its column offset; rows outside the image read the blank
      // row below the image, whose every weight is 0.
      const float* taps[8];
      for (int k = 0; k < 8; ++k) {
        const int yq = y + kTaps[k].dy * step;
        taps[k] = p.row(kZ, yq >= 0 && yq < h ? yq : h) + kTaps[k].dx * step;
      }
      const float* v_up = p.row(from + kVariance, std::max(y - 1, 0));
      const float* v_mid = p.row(from + kVariance, y);
      const float* v_down = p.row(from + kVariance, std::min(y + 1, h - 1));
      const float *l_row = p.row(from + kLuminance, y), *z_row = p.row(kZ, y);
      const float *nx_row = p.row(kNx, y), *ny_row = p.row(kNy, y), *nz_row = p.row(kNz, y);
      const float *gx_row = p.row(kGx, y), *gy_row = p.row(kGy, y);
      const float *r_row = p.row(from, y), *g_row = p.row(from + 1, y), *b_row = p.row(from + 2, y);
      for (int x = 0; x < w; x += kWidth) {
        // The centre: its luminance scale from the variance blurred over 3x3 pixels (1 2 1 by 1 2 1, over 16), its
        // depth scales along x, y and the diagonal from the depth's slope, with log2 e 2^23 folded in.
        const auto blur = [x](const float* row) {
          return Lanes::load(row + x - 1) + Lanes::set1(2.0f) * Lanes::load(row + x) + Lanes::load(row + x + 1);
        };
        const Lanes guide = (blur(v_up) + Lanes::set1(2.0f) * blur(v_mid) + blur(v_down)) * Lanes::set1(1.0f / 16.0f);
        const Lanes inv_l = log2e_b / (sigma_l * sqrt(guide) + Lanes::set1(kLuminanceEpsilon));
        const Lanes lc = Lanes::load(l_row + x), zc = Lanes::load(z_row + x);
        const Lanes base = Lanes::set1(kDepthRelative) * zc + Lanes::set1(1e-30f);
        const Lanes gx = Lanes::load(gx_row + x), gy = Lanes::load(gy_row + x);
        const Lanes inv_z[3] = {log2e_b / (depth_s * gx + base), log2e_b / (depth_s * gy + base),
                                log2e_b / (depth_s * (gx + gy) + base)};
        const Lanes nx = scale * Lanes::load(nx_row + x), ny = scale * Lanes::load(ny_row + x),
                    nz = scale * Lanes::load(nz_row + x);
        // The centre's own tap, weight 1.
        Lanes r = Lanes::load(r_row + x), g = Lanes::load(g_row + x), b = Lanes::load(b_row + x);
        Lanes v = Lanes::load(v_mid + x), sum_w = Lanes::set1(1.0f);
        // All eight weights first, then the sums: eight independent chains for the processor to overlap.
        Lanes weights[8];
#pragma GCC unroll 8
        for (int k = 0; k < 8; ++k) {
          const float* q = taps[k] + x;
          const Lanes dot = nx * Lanes::load(q + at_nx) + ny * Lanes::load(q + at_ny) + nz * Lanes::load(q + at_nz);
          const Lanes bits = ((kTaps[k].exponent == 1.0f ? start_e : start_c) + dot) -
                             abs(lc - Lanes::load(q + at_l)) * inv_l - abs(zc - Lanes::load(q)) * inv_z[kTaps[k].axis];
          weights[k] = weight_from_bits(bits);
        }
#pragma GCC unroll 8
        for (int k = 0; k < 8; ++k) {
          const float* q = taps[k] + x;
          const Lanes weight = weights[k];
          r = r + weight * Lanes::load(q + at_r);
          g = g + weight * Lanes::load(q + at_g);
          b = b + weight * Lanes::load(q + at_b);
          if constexpr (!kLast) v = v + weight * weight * Lanes::load(q + at_v);
          sum_w = sum_w + weight;
        }
        const Lanes inv_w = Lanes::set1(1.0f) / sum_w;
        r = r * inv_w;
        g = g * inv_w;
        b = b * inv_w;
        const int count = w - x;
        if constexpr (kLast) {
          // Multiplied back by the albedo, into the output.
          r = r * Lanes::load(p.row(kAlbedo, y) + x);
          g = g * Lanes::load(p.row(kAlbedo + 1, y) + x);
          b = b * Lanes::load(p.row(kAlbedo + 2, y) + x);
          float* o = &out[static_cast<std::size_t>(y) * row_pixels + static_cast<std::size_t>(x)].x;
          if (count >= kWidth) {
            Lanes::store3(o, r, g, b);
          } else {
            float buffer[3 * kWidth];
            Lanes::store3(buffer, r, g, b);
            std::copy(buffer, buffer + 3 * count, o);
          }
        } else {
          store(r, p.row(to, y) + x, count);
          store(g, p.row(to + 1, y) + x, count);
          store(b, p.row(to + 2, y) + x, count);
          store(v * (inv_w * inv_w), p.row(to + kVariance, y) + x, count);
          store(luminance709(r, g, b), p.row(to + kLuminance, y) + x, count);
        }
      }
      if constexpr (!kLast) {
        float* v = p.row(to + kVariance, y);
        v[-1] = v[0];
        v[w] = v[w - 1];
      }
    };
    // Rows in the order y = c, c + step, c + 2 step, ... for c = 0 .. step - 1, so that the rows a row's taps
    // read were mostly read by the row before (and are still in the cache); threads take kChunk at a time.
    const int chunks = (h + kChunk - 1) / kChunk;
    core::parallel_for(0, chunks, threads, [&](int chunk) {
      int first = chunk * kChunk;
      const int end = std::min(first + kChunk, h);
      int c = 0;
      while (first >= (h - c + step - 1) / step) first -= (h - c++ + step - 1) / step;
      for (int i = chunk * kChunk, y = c + first * step; i < end; ++i) {
        if (last) {
          filter_row(y, std::true_type{});
        } else {
          filter_row(y, std::false_type{});
        }
        y += step;
        if (y >= h) y = ++c;
      }
    });
  }
}

void denoise(const DenoiseInput& input, const DenoiseSettings& settings, std::span<Vec3f> out) {
  Denoiser d;
  d.denoise(input, settings, out);
}

}  // namespace tripsitter::render

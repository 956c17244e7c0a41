// Eight floats at a time: one AVX register where the translation unit is compiled for AVX, two SSE registers
// otherwise. Every operation is the IEEE operation of each lane, so a lane computes bit for bit what the same scalar
// expression computes, provided no multiply and add are fused: GCC, by default and where FMA is available, fuses
// these intrinsics as it fuses plain float arithmetic, so code that must give the scalar kernel's bits
// (sphere_lanes.h) is compiled with -ffp-contract=off, as the whole render library is (render/CMakeLists.txt).
// Besides arithmetic: masks, 3-vectors read from and written to arrays of x y z triples (load3, store3), and the
// tails of rows that do not fill eight lanes (load_first, store_first), as the denoiser needs (denoise.cpp).
//
// Safe to include anywhere: F8 lives in tripsitter::render::simd, in an inline namespace named after the instruction
// set the including translation unit is compiled for (isa.h: simd::avx2::F8 in the render library, built for
// x86-64-v3; simd::sse2::F8 in a baseline build or a test), so code compiled for different instruction sets never
// shares an inline function, or a layout, that the linker could mix up. Callers write simd::F8.
#pragma once

#include <cstdint>

#if defined(__AVX__)
#include <immintrin.h>
#else
#include <emmintrin.h>
#endif

#include <tripsitter/render/isa.h>

namespace tripsitter::render::simd {
inline namespace TRIPSITTER_RENDER_ISA {

struct F8 {
#if defined(__AVX__)
  __m256 v;
  static F8 load(const float* p) { return {_mm256_load_ps(p)}; }  // REQUIRES p 32-byte aligned
  static F8 loadu(const float* p) { return {_mm256_loadu_ps(p)}; }
  static F8 set1(float x) { return {_mm256_set1_ps(x)}; }
  void store(float* p) const { _mm256_store_ps(p, v); }
  void storeu(float* p) const { _mm256_storeu_ps(p, v); }
  friend F8 operator+(F8 a, F8 b) { return {_mm256_add_ps(a.v, b.v)}; }
  friend F8 operator-(F8 a, F8 b) { return {_mm256_sub_ps(a.v, b.v)}; }
  friend F8 operator*(F8 a, F8 b) { return {_mm256_mul_ps(a.v, b.v)}; }
  friend F8 operator/(F8 a, F8 b) { return {_mm256_div_ps(a.v, b.v)}; }
  friend F8 operator&(F8 a, F8 b) { return {_mm256_and_ps(a.v, b.v)}; }
  friend F8 operator|(F8 a, F8 b) { return {_mm256_or_ps(a.v, b.v)}; }
  friend F8 operator^(F8 a, F8 b) { return {_mm256_xor_ps(a.v, b.v)}; }
  friend F8 andnot(F8 mask, F8 a) { return {_mm256_andnot_ps(mask.v, a.v)}; }  // a where mask is clear
  friend F8 sqrt(F8 a) { return {_mm256_sqrt_ps(a.v)}; }
  // Lane by lane; b where either is NaN.
  friend F8 min(F8 a, F8 b) { return {_mm256_min_ps(a.v, b.v)}; }
  friend F8 max(F8 a, F8 b) { return {_mm256_max_ps(a.v, b.v)}; }
  // Masks: all ones in a lane where the comparison holds (false where either side is NaN).
  friend F8 operator>=(F8 a, F8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GE_OQ)}; }
  friend F8 operator>(F8 a, F8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)}; }
  friend F8 operator<(F8 a, F8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)}; }
  friend F8 operator<=(F8 a, F8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)}; }
  friend F8 operator==(F8 a, F8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ)}; }
  friend F8 operator!=(F8 a, F8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_NEQ_UQ)}; }
  // mask ? a : b, lane by lane.
  friend F8 select(F8 mask, F8 a, F8 b) { return {_mm256_blendv_ps(b.v, a.v, mask.v)}; }
  // The float whose bits are the whole part of a, truncated (REQUIRES a in [0, 2^31)).
  friend F8 float_with_bits(F8 a) { return {_mm256_castsi256_ps(_mm256_cvttps_epi32(a.v))}; }
#if defined(__AVX2__)
  // Eight 3-vectors (24 floats: x0 y0 z0 x1 ...) to three planes and back. Each plane's lanes are blended from the
  // three registers where they lie (x at 0 3 6 of the first, 1 4 7 of the second, 2 5 of the third, ...), then
  // put in order by one permutation.
  static void load3(const float* p, F8& x, F8& y, F8& z) {
    const __m256 a = _mm256_loadu_ps(p), b = _mm256_loadu_ps(p + 8), c = _mm256_loadu_ps(p + 16);
    const __m256 bx = _mm256_blend_ps(_mm256_blend_ps(a, b, 0b10010010), c, 0b00100100);
    const __m256 by = _mm256_blend_ps(_mm256_blend_ps(a, b, 0b00100100), c, 0b01001001);
    const __m256 bz = _mm256_blend_ps(_mm256_blend_ps(a, b, 0b01001001), c, 0b10010010);
    x.v = _mm256_permutevar8x32_ps(bx, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    y.v = _mm256_permutevar8x32_ps(by, _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
    z.v = _mm256_permutevar8x32_ps(bz, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
  }
  static void store3(float* p, F8 x, F8 y, F8 z) {
    const __m256 bx = _mm256_permutevar8x32_ps(x.v, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    const __m256 by = _mm256_permutevar8x32_ps(y.v, _mm256_setr_epi32(5, 0, 3, 6, 1, 4, 7, 2));
    const __m256 bz = _mm256_permutevar8x32_ps(z.v, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
    _mm256_storeu_ps(p, _mm256_blend_ps(_mm256_blend_ps(bx, by, 0b10010010), bz, 0b00100100));
    _mm256_storeu_ps(p + 8, _mm256_blend_ps(_mm256_blend_ps(bz, bx, 0b10010010), by, 0b00100100));
    _mm256_storeu_ps(p + 16, _mm256_blend_ps(_mm256_blend_ps(by, bz, 0b10010010), bx, 0b00100100));
  }
#else
  // AVX without AVX2 has no lane permutation across halves: each half as four 3-vectors.
  static void load3(const float* p, F8& x, F8& y, F8& z) {
    __m128 x0, y0, z0, x1, y1, z1;
    load3_4(p, x0, y0, z0);
    load3_4(p + 12, x1, y1, z1);
    x.v = _mm256_set_m128(x1, x0);
    y.v = _mm256_set_m128(y1, y0);
    z.v = _mm256_set_m128(z1, z0);
  }
  static void store3(float* p, F8 x, F8 y, F8 z) {
    store3_4(p, _mm256_castps256_ps128(x.v), _mm256_castps256_ps128(y.v), _mm256_castps256_ps128(z.v));
    store3_4(p + 12, _mm256_extractf128_ps(x.v, 1), _mm256_extractf128_ps(y.v, 1), _mm256_extractf128_ps(z.v, 1));
  }
#endif
  // One bit per lane of a mask.
  int bits() const { return _mm256_movemask_ps(v); }
  // The smallest lane (REQUIRES no NaN lane).
  float min_lane() const { return min4(_mm_min_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1))); }
#else
  __m128 lo, hi;
  static F8 load(const float* p) { return {_mm_load_ps(p), _mm_load_ps(p + 4)}; }  // REQUIRES p 16-byte aligned
  static F8 loadu(const float* p) { return {_mm_loadu_ps(p), _mm_loadu_ps(p + 4)}; }
  static F8 set1(float x) { return {_mm_set1_ps(x), _mm_set1_ps(x)}; }
  void store(float* p) const {
    _mm_store_ps(p, lo);
    _mm_store_ps(p + 4, hi);
  }
  void storeu(float* p) const {
    _mm_storeu_ps(p, lo);
    _mm_storeu_ps(p + 4, hi);
  }
  friend F8 operator+(F8 a, F8 b) { return {_mm_add_ps(a.lo, b.lo), _mm_add_ps(a.hi, b.hi)}; }
  friend F8 operator-(F8 a, F8 b) { return {_mm_sub_ps(a.lo, b.lo), _mm_sub_ps(a.hi, b.hi)}; }
  friend F8 operator*(F8 a, F8 b) { return {_mm_mul_ps(a.lo, b.lo), _mm_mul_ps(a.hi, b.hi)}; }
  friend F8 operator/(F8 a, F8 b) { return {_mm_div_ps(a.lo, b.lo), _mm_div_ps(a.hi, b.hi)}; }
  friend F8 operator&(F8 a, F8 b) { return {_mm_and_ps(a.lo, b.lo), _mm_and_ps(a.hi, b.hi)}; }
  friend F8 operator|(F8 a, F8 b) { return {_mm_or_ps(a.lo, b.lo), _mm_or_ps(a.hi, b.hi)}; }
  friend F8 operator^(F8 a, F8 b) { return {_mm_xor_ps(a.lo, b.lo), _mm_xor_ps(a.hi, b.hi)}; }
  friend F8 andnot(F8 mask, F8 a) { return {_mm_andnot_ps(mask.lo, a.lo), _mm_andnot_ps(mask.hi, a.hi)}; }
  friend F8 sqrt(F8 a) { return {_mm_sqrt_ps(a.lo), _mm_sqrt_ps(a.hi)}; }
  friend F8 min(F8 a, F8 b) { return {_mm_min_ps(a.lo, b.lo), _mm_min_ps(a.hi, b.hi)}; }
  friend F8 max(F8 a, F8 b) { return {_mm_max_ps(a.lo, b.lo), _mm_max_ps(a.hi, b.hi)}; }
  friend F8 operator>=(F8 a, F8 b) { return {_mm_cmpge_ps(a.lo, b.lo), _mm_cmpge_ps(a.hi, b.hi)}; }
  friend F8 operator>(F8 a, F8 b) { return {_mm_cmpgt_ps(a.lo, b.lo), _mm_cmpgt_ps(a.hi, b.hi)}; }
  friend F8 operator<(F8 a, F8 b) { return {_mm_cmplt_ps(a.lo, b.lo), _mm_cmplt_ps(a.hi, b.hi)}; }
  friend F8 operator<=(F8 a, F8 b) { return {_mm_cmple_ps(a.lo, b.lo), _mm_cmple_ps(a.hi, b.hi)}; }
  friend F8 operator==(F8 a, F8 b) { return {_mm_cmpeq_ps(a.lo, b.lo), _mm_cmpeq_ps(a.hi, b.hi)}; }
  friend F8 operator!=(F8 a, F8 b) { return {_mm_cmpneq_ps(a.lo, b.lo), _mm_cmpneq_ps(a.hi, b.hi)}; }
  friend F8 select(F8 mask, F8 a, F8 b) {
    return {_mm_or_ps(_mm_and_ps(mask.lo, a.lo), _mm_andnot_ps(mask.lo, b.lo)),
            _mm_or_ps(_mm_and_ps(mask.hi, a.hi), _mm_andnot_ps(mask.hi, b.hi))};
  }
  friend F8 float_with_bits(F8 a) {
    return {_mm_castsi128_ps(_mm_cvttps_epi32(a.lo)), _mm_castsi128_ps(_mm_cvttps_epi32(a.hi))};
  }
  // Eight 3-vectors (24 floats) to three planes and back, four at a time.
  static void load3(const float* p, F8& x, F8& y, F8& z) {
    load3_4(p, x.lo, y.lo, z.lo);
    load3_4(p + 12, x.hi, y.hi, z.hi);
  }
  static void store3(float* p, F8 x, F8 y, F8 z) {
    store3_4(p, x.lo, y.lo, z.lo);
    store3_4(p + 12, x.hi, y.hi, z.hi);
  }
  int bits() const { return _mm_movemask_ps(lo) | (_mm_movemask_ps(hi) << 4); }
  float min_lane() const { return min4(_mm_min_ps(lo, hi)); }
#endif
  static constexpr int kLanes = 8;

  // |a|, lane by lane (the sign bit cleared).
  friend F8 abs(F8 a) { return andnot(set1(-0.0f), a); }

  // Tails: the first `count` lanes of a row that ends within eight floats. Nothing is read or written past
  // p + count (3 count floats for the 3-vector forms); lanes beyond count load as 0. A count of 8 or more is the
  // whole F8. The partial forms are kept out of line, so that the loops calling these stay small.
  static F8 load_first(const float* p, int count) { return count >= kLanes ? loadu(p) : load_partial(p, count); }
  void store_first(float* p, int count) const {
    if (count >= kLanes) storeu(p);
    else store_partial(p, count);
  }
  static void load3_first(const float* p, int count, F8& x, F8& y, F8& z) {
    if (count >= kLanes) load3(p, x, y, z);
    else load3_partial(p, count, x, y, z);
  }
  static void store3_first(float* p, int count, F8 x, F8 y, F8 z) {
    if (count >= kLanes) store3(p, x, y, z);
    else store3_partial(p, count, x, y, z);
  }
  // The smallest of four floats.
  static float min4(__m128 m) {
    m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_min_ss(m, _mm_shuffle_ps(m, m, 1)));
  }

  // The magnitude of a with the sign of b, lane by lane (std::copysign).
  friend F8 copysign(F8 a, F8 b) {
    const F8 sign = set1(-0.0f);
    return andnot(sign, a) | (b & sign);
  }

 private:
  [[gnu::noinline]] static F8 load_partial(const float* p, int count) {
    float lanes[kLanes] = {};
    for (int i = 0; i < count; ++i) lanes[i] = p[i];
    return loadu(lanes);
  }
  [[gnu::noinline]] void store_partial(float* p, int count) const {
    float lanes[kLanes];
    storeu(lanes);
    for (int i = 0; i < count; ++i) p[i] = lanes[i];
  }
  [[gnu::noinline]] static void load3_partial(const float* p, int count, F8& x, F8& y, F8& z) {
    float lanes[3 * kLanes] = {};
    for (int i = 0; i < 3 * count; ++i) lanes[i] = p[i];
    load3(lanes, x, y, z);
  }
  [[gnu::noinline]] static void store3_partial(float* p, int count, F8 x, F8 y, F8 z) {
    float lanes[3 * kLanes];
    store3(lanes, x, y, z);
    for (int i = 0; i < 3 * count; ++i) p[i] = lanes[i];
  }

  // Four 3-vectors (12 floats: x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3) to three SSE registers and back.
  static void load3_4(const float* p, __m128& x, __m128& y, __m128& z) {
    const __m128 a = _mm_loadu_ps(p), b = _mm_loadu_ps(p + 4), c = _mm_loadu_ps(p + 8);
    const __m128 x01 = _mm_shuffle_ps(a, a, _MM_SHUFFLE(0, 3, 0, 0));  // x0 . x1 .
    const __m128 x23 = _mm_shuffle_ps(b, c, _MM_SHUFFLE(0, 1, 0, 2));  // x2 . x3 .
    const __m128 y01 = _mm_shuffle_ps(a, b, _MM_SHUFFLE(0, 0, 0, 1));  // y0 . y1 .
    const __m128 y23 = _mm_shuffle_ps(b, c, _MM_SHUFFLE(0, 2, 0, 3));  // y2 . y3 .
    const __m128 z01 = _mm_shuffle_ps(a, b, _MM_SHUFFLE(0, 1, 0, 2));  // z0 . z1 .
    const __m128 z23 = _mm_shuffle_ps(c, c, _MM_SHUFFLE(0, 3, 0, 0));  // z2 . z3 .
    x = _mm_shuffle_ps(x01, x23, _MM_SHUFFLE(2, 0, 2, 0));
    y = _mm_shuffle_ps(y01, y23, _MM_SHUFFLE(2, 0, 2, 0));
    z = _mm_shuffle_ps(z01, z23, _MM_SHUFFLE(2, 0, 2, 0));
  }
  static void store3_4(float* p, __m128 x, __m128 y, __m128 z) {
    const __m128 xy01 = _mm_unpacklo_ps(x, y);                            // x0 y0 x1 y1
    const __m128 xy23 = _mm_unpackhi_ps(x, y);                            // x2 y2 x3 y3
    const __m128 t = _mm_shuffle_ps(z, xy01, _MM_SHUFFLE(3, 2, 1, 0));    // z0 z1 x1 y1
    const __m128 u = _mm_shuffle_ps(z, xy23, _MM_SHUFFLE(3, 2, 3, 2));    // z2 z3 x3 y3
    _mm_storeu_ps(p, _mm_shuffle_ps(xy01, t, _MM_SHUFFLE(2, 0, 1, 0)));      // x0 y0 z0 x1
    _mm_storeu_ps(p + 4, _mm_shuffle_ps(t, xy23, _MM_SHUFFLE(1, 0, 1, 3)));  // y1 z1 x2 y2
    _mm_storeu_ps(p + 8, _mm_shuffle_ps(u, u, _MM_SHUFFLE(1, 3, 2, 0)));     // z2 x3 y3 z3
  }
};

}  // namespace TRIPSITTER_RENDER_ISA
}  // namespace tripsitter::render::simd

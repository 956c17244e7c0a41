// Eight floats at a time: one AVX register where the translation unit is compiled for AVX, two SSE registers
// otherwise. Every operation is the IEEE operation of each lane, so a lane computes bit for bit what the same scalar
// expression computes, provided no multiply and add are fused: GCC, by default and where FMA is available, fuses
// these intrinsics as it fuses plain float arithmetic, so code that must give the scalar kernel's bits
// (sphere_lanes.h) is compiled with -ffp-contract=off, as the whole render library is (render/CMakeLists.txt).
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
  int bits() const { return _mm_movemask_ps(lo) | (_mm_movemask_ps(hi) << 4); }
  float min_lane() const { return min4(_mm_min_ps(lo, hi)); }
#endif
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
};

}  // namespace TRIPSITTER_RENDER_ISA
}  // namespace tripsitter::render::simd

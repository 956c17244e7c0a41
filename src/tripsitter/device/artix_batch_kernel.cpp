#include <tripsitter/device/artix_batch_kernel.h>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#endif

namespace tripsitter::device::artix::batch {

#if defined(__AVX2__) && defined(__FMA__)

// A group of kLanes entries in one AVX register each step. The fused multiply-adds round nothing: every product and
// sum is an integer below 2^53.
void meets_line(const double* __restrict cx, const double* __restrict cy, const double* __restrict cz,
                const double* __restrict down, const double* __restrict r2s, std::size_t n, const double o[3],
                const double d[3], double scaled_max, std::uint8_t* __restrict meets) {
  static_assert(kLanes == 4);
  const __m256d ox = _mm256_set1_pd(o[0]), oy = _mm256_set1_pd(o[1]), oz = _mm256_set1_pd(o[2]);
  const __m256d dx = _mm256_set1_pd(d[0]), dy = _mm256_set1_pd(d[1]), dz = _mm256_set1_pd(d[2]);
  const __m256d half_grid = _mm256_set1_pd(65536.0), to_grid = _mm256_set1_pd(0x1p-17), from_grid = _mm256_set1_pd(131072.0);
  const __m256d widest = _mm256_set1_pd(scaled_max);
  const __m256d sign = _mm256_set1_pd(-0.0);
  for (std::size_t j = 0; j < n; j += kLanes) {
    const __m256d ocx = _mm256_sub_pd(_mm256_loadu_pd(cx + j), ox);  // the pre-adder
    const __m256d ocy = _mm256_sub_pd(_mm256_loadu_pd(cy + j), oy);
    const __m256d ocz = _mm256_sub_pd(_mm256_loadu_pd(cz + j), oz);
    const __m256d bd = _mm256_fmadd_pd(ocz, dz, _mm256_fmadd_pd(ocy, dy, _mm256_mul_pd(ocx, dx)));  // d.oc, 2^17
    const __m256d b = _mm256_floor_pd(_mm256_mul_pd(_mm256_add_pd(bd, half_grid), to_grid));     // to the grid
    const __m256d scale = _mm256_loadu_pd(down + j);
    const __m256d fx = _mm256_floor_pd(_mm256_mul_pd(_mm256_fnmadd_pd(b, dx, _mm256_mul_pd(ocx, from_grid)), scale));
    const __m256d fy = _mm256_floor_pd(_mm256_mul_pd(_mm256_fnmadd_pd(b, dy, _mm256_mul_pd(ocy, from_grid)), scale));
    const __m256d fz = _mm256_floor_pd(_mm256_mul_pd(_mm256_fnmadd_pd(b, dz, _mm256_mul_pd(ocz, from_grid)), scale));
    const __m256d far = _mm256_max_pd(_mm256_andnot_pd(sign, fx),
                                      _mm256_max_pd(_mm256_andnot_pd(sign, fy), _mm256_andnot_pd(sign, fz)));
    const __m256d ff = _mm256_fmadd_pd(fz, fz, _mm256_fmadd_pd(fy, fy, _mm256_mul_pd(fx, fx)));
    const __m256d meet = _mm256_and_pd(_mm256_cmp_pd(far, widest, _CMP_LE_OQ),
                                       _mm256_cmp_pd(_mm256_loadu_pd(r2s + j), ff, _CMP_GE_OQ));
    const int mask = _mm256_movemask_pd(meet);
    for (std::size_t k = 0; k < kLanes; ++k) meets[j + k] = static_cast<std::uint8_t>((mask >> k) & 1);
  }
}

#else

void meets_line(const double* __restrict cx, const double* __restrict cy, const double* __restrict cz,
                const double* __restrict down, const double* __restrict r2s, std::size_t n, const double o[3],
                const double d[3], double scaled_max, std::uint8_t* __restrict meets) {
  for (std::size_t j = 0; j < n; ++j) {
    const double ocx = cx[j] - o[0], ocy = cy[j] - o[1], ocz = cz[j] - o[2];  // the pre-adder
    const double bd = ocx * d[0] + ocy * d[1] + ocz * d[2];                   // d.oc times 2^17
    const double b = __builtin_floor((bd + 65536.0) * 0x1p-17);              // to the position grid
    const double fx = __builtin_floor((ocx * 131072.0 - b * d[0]) * down[j]);
    const double fy = __builtin_floor((ocy * 131072.0 - b * d[1]) * down[j]);
    const double fz = __builtin_floor((ocz * 131072.0 - b * d[2]) * down[j]);
    meets[j] = __builtin_fabs(fx) <= scaled_max && __builtin_fabs(fy) <= scaled_max &&
               __builtin_fabs(fz) <= scaled_max && r2s[j] >= fx * fx + fy * fy + fz * fz;
  }
}

#endif

}  // namespace tripsitter::device::artix::batch

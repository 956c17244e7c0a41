#include <tripsitter/device/artix_batch_kernel.h>

#if defined(__AVX2__) && defined(__FMA__) && defined(__BMI2__)
#include <immintrin.h>
#endif

// Every value below is an integer below 2^53 times a power of two, so each sum, product and fused multiply-add is
// exact and only the floors round, as the units' shifts do (artix_batch.h):
//   b = floor(c.d 2^-17 - (o.d 2^-17 - 1/2)), the units' (d.(c - o) + 2^16) >> 17 (|c.d| < 2^41, |o.d| < 2^42),
//   F_k = floor((c_k - o_k) 2^-e - b d_k 2^-(17 + e)), the units' ((oc_k << 17) - b d_k) >> (17 + e), as
//   oc_k 2^17 - b d_k is an integer below 2^45,
//   disc >= 0 as r^2 / 4^e - F_x^2 >= F_y^2 + F_z^2: exact while every |F_k| <= 2^17 - 1. When one is beyond (the
//   units saturate it and miss), its square is at least 2^34 however it rounds, above r^2 / 4^e: the left side is
//   then negative or the right side above r^2 / 4^e, and the test fails, as the units do.
// The order of the operations keeps the chain from the loads to the test short (the filter's cost is its latency:
// a walk's runs are a few entries long).
namespace tripsitter::device::artix::batch {

#if defined(__AVX2__) && defined(__FMA__) && defined(__BMI2__)

void meets_line(const double* fields, std::size_t stride, std::size_t n, const Ray& ray,
                std::uint8_t* __restrict meets) {
  static_assert(kLanes == 4);
  const double* const cx = fields + kCx * stride;
  const double* const cy = fields + kCy * stride;
  const double* const cz = fields + kCz * stride;
  const double* const down = fields + kDown * stride;
  const double* const up = fields + kUp * stride;
  const double* const r2s = fields + kR2s * stride;
  const double od = ray.o[0] * ray.d[0] + ray.o[1] * ray.d[1] + ray.o[2] * ray.d[2];
  const __m256d ox = _mm256_set1_pd(ray.o[0]), oy = _mm256_set1_pd(ray.o[1]), oz = _mm256_set1_pd(ray.o[2]);
  const __m256d dx = _mm256_set1_pd(ray.d[0]), dy = _mm256_set1_pd(ray.d[1]), dz = _mm256_set1_pd(ray.d[2]);
  // d 2^-17 and o.d 2^-17 - 1/2, for b.
  const __m256d gx = _mm256_set1_pd(ray.d[0] * 0x1p-17), gy = _mm256_set1_pd(ray.d[1] * 0x1p-17),
                gz = _mm256_set1_pd(ray.d[2] * 0x1p-17), g0 = _mm256_set1_pd(od * 0x1p-17 - 0.5);
  for (std::size_t j = 0; j < n; j += kLanes) {
    const __m256d x = _mm256_loadu_pd(cx + j), y = _mm256_loadu_pd(cy + j), z = _mm256_loadu_pd(cz + j);
    const __m256d b =
        _mm256_floor_pd(_mm256_add_pd(_mm256_fmsub_pd(x, gx, g0), _mm256_fmadd_pd(z, gz, _mm256_mul_pd(y, gy))));
    const __m256d scale_down = _mm256_loadu_pd(down + j), scale_up = _mm256_loadu_pd(up + j);
    // F_k = floor(oc_k 2^-e - b (d_k 2^-(17 + e))): both products are taken while b is on its way.
    const auto f = [&](__m256d c, __m256d o, __m256d d) {
      return _mm256_floor_pd(
          _mm256_fnmadd_pd(b, _mm256_mul_pd(d, scale_down), _mm256_mul_pd(_mm256_sub_pd(c, o), scale_up)));
    };
    const __m256d fx = f(x, ox, dx), fy = f(y, oy, dy), fz = f(z, oz, dz);
    const __m256d left = _mm256_fnmadd_pd(fx, fx, _mm256_loadu_pd(r2s + j));
    const __m256d right = _mm256_fmadd_pd(fz, fz, _mm256_mul_pd(fy, fy));
    const auto mask = static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(left, right, _CMP_GE_OQ)));
    const std::uint32_t bytes = _pdep_u32(mask, 0x01010101u);  // lane k's bit to byte k
    __builtin_memcpy(meets + j, &bytes, sizeof bytes);
  }
}

#else

void meets_line(const double* fields, std::size_t stride, std::size_t n, const Ray& ray,
                std::uint8_t* __restrict meets) {
  const double od = ray.o[0] * ray.d[0] + ray.o[1] * ray.d[1] + ray.o[2] * ray.d[2];
  for (std::size_t j = 0; j < n; ++j) {
    const double x = fields[kCx * stride + j], y = fields[kCy * stride + j], z = fields[kCz * stride + j];
    const double down = fields[kDown * stride + j], up = fields[kUp * stride + j];
    const double b = __builtin_floor((x * ray.d[0] - od + y * ray.d[1] + z * ray.d[2]) * 0x1p-17 + 0.5);
    const double fx = __builtin_floor((x - ray.o[0]) * up - b * (ray.d[0] * down));
    const double fy = __builtin_floor((y - ray.o[1]) * up - b * (ray.d[1] * down));
    const double fz = __builtin_floor((z - ray.o[2]) * up - b * (ray.d[2] * down));
    meets[j] = fields[kR2s * stride + j] - fx * fx >= fy * fy + fz * fz;
  }
}

#endif

}  // namespace tripsitter::device::artix::batch

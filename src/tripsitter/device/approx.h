// The path preset's arithmetic beyond adds, multiplies and the square-root unit: the approximations the
// device's path tracer uses, each the candidate the benchmark chose (docs/device.md, "Approximations", where
// the table of every candidate's error, cycles and multipliers says why; `tripsitter approx` regenerates it).
//
// Formats: a unit vector has components times 2^14 (kUnit = 1.0); a reflectance or a fifth power is a
// fraction times 2^14 as well.
#pragma once

#include <array>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>

#include <tripsitter/core/fixed.h>
#include <tripsitter/core/vec.h>
#include <tripsitter/device/sqrt_unit.h>

namespace tripsitter::device::approx {

inline constexpr int kUnitBits = 14;
inline constexpr std::int64_t kUnit = std::int64_t{1} << kUnitBits;

using Unit3 = core::Vec3<std::int64_t>;  // a unit vector, components times 2^14

// x >> s rounded to nearest, ties away from zero (symmetric in sign). s >= 1.
constexpr std::int64_t round_shift(std::int64_t x, int s) {
  const std::int64_t half = std::int64_t{1} << (s - 1);
  return x >= 0 ? (x + half) >> s : -((-x + half) >> s);
}

// 1 / sqrt(x) for x = m / 2^30 in [1, 4), times 2^16: a 192-entry table indexed by m's top 8 bits (the
// reciprocal square root at each bin's middle, 17 bits) and one Newton-Raphson step
// y1 = y0 (3 - x y0^2) / 2: three multiplies. REQUIRES 2^30 <= m < 2^32.
class RsqrtTable {
 public:
  RsqrtTable() {
    for (int i = 0; i < kEntries; ++i) {
      const double x = (static_cast<double>(i + kFirst) + 0.5) / 64.0;
      table_[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(std::lround(65536.0 / std::sqrt(x)));
    }
  }
  std::uint64_t operator()(std::uint64_t m) const {
    assert(m >= (std::uint64_t{1} << 30) && m < (std::uint64_t{1} << 32));
    const std::uint64_t y0 = table_[static_cast<std::size_t>((m >> 24) - kFirst)];
    const std::uint64_t t = (y0 * y0 * m) >> 32;  // x y0^2 times 2^30: y0^2 < 2^34, m < 2^32, so < 2^66 / 2^32
    return (y0 * ((std::uint64_t{3} << 30) - t) + (std::uint64_t{1} << 30)) >> 31;
  }

 private:
  static constexpr int kFirst = 64;  // m >> 24 is 64..255
  static constexpr int kEntries = 192;
  std::array<std::uint32_t, kEntries> table_{};
};

inline const RsqrtTable& rsqrt_table() {
  static const RsqrtTable table;
  return table;
}

// v / |v| as a unit vector times 2^bits (the path preset's 14, the artix path preset's 17), each component rounded
// to nearest: v.v normalised by an even shift into m in [2^30, 2^32), its reciprocal square root from RsqrtTable,
// then one multiply and a shift per component. REQUIRES v != 0, |v_k| < 2^30, and v.v >= 2^(2 (bits - 14)).
inline Unit3 unit(const core::Vec3<core::Int128>& v, int bits = kUnitBits) {
  const auto s = static_cast<std::uint64_t>(v.x * v.x + v.y * v.y + v.z * v.z);  // < 2^61.6
  assert(s > 0);
  const int e = std::bit_width(s) - 31;
  const int k = e >= 0 ? e / 2 : -((1 - e) / 2);  // floor(e / 2)
  const std::uint64_t m = k >= 0 ? s >> (2 * k) : s << (-2 * k);
  const auto y = static_cast<std::int64_t>(rsqrt_table()(m));
  // 1/|v| = y 2^-16 2^-15 2^-k, so v_k 2^bits / |v| = v_k y / 2^(31 - bits + k); k >= -15.
  const int shift = 31 - bits + k;
  assert(shift >= 1);
  return {round_shift(static_cast<std::int64_t>(v.x) * y, shift), round_shift(static_cast<std::int64_t>(v.y) * y, shift),
          round_shift(static_cast<std::int64_t>(v.z) * y, shift)};
}

// sin and cos of phi = 2 pi i / 4096 (i 12 bits) times 2^14, from a quarter-wave table of 1025 entries.
class SineTable {
 public:
  SineTable() {
    for (unsigned i = 0; i <= kQuarter; ++i)
      table_[static_cast<std::size_t>(i)] =
          static_cast<std::int32_t>(std::lround(16384.0 * std::sin(1.5707963267948966 * static_cast<double>(i) / kQuarter)));
  }
  std::int64_t sin(unsigned i) const {
    const unsigned j = i & (kQuarter - 1);
    switch ((i >> 10) & 3) {
      case 0: return table_[j];
      case 1: return table_[kQuarter - j];
      case 2: return -table_[j];
      default: return -table_[kQuarter - j];
    }
  }
  std::int64_t cos(unsigned i) const { return sin(i + kQuarter); }

 private:
  static constexpr unsigned kQuarter = 1024;
  std::array<std::int32_t, kQuarter + 1> table_{};
};

inline const SineTable& sine_table() {
  static const SineTable table;
  return table;
}

// A unit vector uniform on the sphere from one 32-bit draw: z uniform in (-1, 1) from the top 15 bits (odd
// multiples of 2^-15), the azimuth from the next 12 bits; rho = sqrt(1 - z^2) from the square-root unit, sqrt(x)
// (the unit's recurrence, or its closed form in the fast model).
template <class Sqrt>
Unit3 random_unit(std::uint32_t draw, const Sqrt& sqrt) {
  const std::int64_t zq = 2 * static_cast<std::int64_t>(draw >> 17) + 1 - 32768;  // z times 2^15, odd
  const std::int64_t q = (std::int64_t{1} << 30) - zq * zq;                          // (1 - z^2) 2^30 > 0
  const auto rho = static_cast<std::int64_t>(sqrt(core::Int128{q >> 2}));            // times 2^14
  const unsigned phi = (draw >> 5) & 4095u;
  const SineTable& t = sine_table();
  return {round_shift(rho * t.cos(phi), kUnitBits), round_shift(rho * t.sin(phi), kUnitBits), round_shift(zq, 1)};
}

// (m / 2^14)^5 times 2^14 for 0 <= m <= 2^14: repeated squaring, three multiplies, each rounded.
constexpr std::int64_t pow5(std::int64_t m) {
  const std::int64_t m2 = round_shift(m * m, kUnitBits);
  const std::int64_t m4 = round_shift(m2 * m2, kUnitBits);
  return round_shift(m4 * m, kUnitBits);
}

// A unit vector's dot product, times 2^14, rounded.
constexpr std::int64_t dot_unit(const Unit3& a, const Unit3& b) { return round_shift(core::dot(a, b), kUnitBits); }

// The mirror image of the unit vector d about the unit normal n: d - 2 (d.n) n, each component rounded.
constexpr Unit3 reflect(const Unit3& d, const Unit3& n) {
  const std::int64_t dn2 = 2 * dot_unit(d, n);
  return {d.x - round_shift(dn2 * n.x, kUnitBits), d.y - round_shift(dn2 * n.y, kUnitBits),
          d.z - round_shift(dn2 * n.z, kUnitBits)};
}

}  // namespace tripsitter::device::approx

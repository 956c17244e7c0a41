#include <tripsitter/approx/approx_bench.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <utility>

#include <tripsitter/core/fixed.h>
#include <tripsitter/core/vec.h>
#include <tripsitter/device/approx.h>
#include <tripsitter/device/frame_memory.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/device/resources.h>
#include <tripsitter/device/sqrt_unit.h>
#include <tripsitter/device/worker.h>

namespace tripsitter::approx_bench {
namespace {

// What the device runs, measured here beside its rivals.
namespace approx = device::approx;
using device::display_mean;
using device::FixedArith;
using device::kMaxSamples;
using device::kSampleBits;
using device::path_preset;
using device::SqrtUnit;

using approx::kUnit;
using approx::kUnitBits;
using approx::round_shift;
using core::Int128;
using core::UInt128;
using Vec = core::Vec3<Int128>;

constexpr double kPi = std::numbers::pi;

// ---- Sampling and measuring ----

// Uniform in [0, 1) from the generator's top 53 bits (std::uniform_real_distribution's output is not the same on
// every standard library; this is).
double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }

// Log-uniform in [lo, hi): every octave equally often.
double log_uniform(std::mt19937_64& rng, double lo, double hi) { return lo * std::pow(hi / lo, uniform(rng)); }

// A non-zero integer vector of about the given length in a uniform direction.
Vec integer_vector(std::mt19937_64& rng, double length) {
  while (true) {
    const double z = 2 * uniform(rng) - 1, phi = 2 * kPi * uniform(rng), rho = std::sqrt(1 - z * z);
    const Vec v{std::llround(length * rho * std::cos(phi)), std::llround(length * rho * std::sin(phi)),
                std::llround(length * z)};
    if (v != Vec{}) return v;
  }
}

// The camera's ray through a random pixel (core::device_ray).
Vec camera_ray(std::mt19937_64& rng) {
  const auto col = static_cast<std::int64_t>(rng() % 640), row = static_cast<std::int64_t>(rng() % 480);
  return {col - 320, row - 240, 320};
}

// The worst and the mean of the errors added.
class ErrorSum {
 public:
  void add(double e) {
    worst_ = std::max(worst_, e);
    sum_ += e;
    ++count_;
  }
  Error error() const { return {worst_, count_ > 0 ? sum_ / static_cast<double>(count_) : 0.0}; }

 private:
  double worst_ = 0, sum_ = 0;
  std::int64_t count_ = 0;
};

// |x - reference| for an integer result.
double off(Int128 x, double reference) { return std::abs(static_cast<double>(x) - reference); }

Int128 round_shift_wide(Int128 x, int s) {
  const Int128 half = Int128{1} << (s - 1);
  return x >= 0 ? (x + half) >> s : -((-x + half) >> s);
}

int bit_width_wide(UInt128 v) {
  const auto hi = static_cast<std::uint64_t>(v >> 64);
  return hi != 0 ? 64 + std::bit_width(hi) : std::bit_width(static_cast<std::uint64_t>(v));
}

Candidate candidate(std::string name, int cycles, std::string why, std::vector<Multiply> multiplies,
                    std::int64_t table_bits, bool chosen = false) {
  Candidate c;
  c.name = std::move(name);
  c.chosen = chosen;
  c.cycles = cycles;
  c.cycles_why = std::move(why);
  c.multiplies = std::move(multiplies);
  c.table_bits = table_bits;
  return c;
}

// ---- Reciprocal square roots: s = m 4^k with m in [2^30, 2^32), as approx::unit normalises v.v ----

struct Normalised {
  std::uint64_t m;
  int k;
};

Normalised normalise(std::uint64_t s) {
  const int e = std::bit_width(s) - 31;
  const int k = e >= 0 ? e / 2 : -((1 - e) / 2);  // floor(e / 2)
  return {k >= 0 ? s >> (2 * k) : s << (-2 * k), k};
}

// One Newton-Raphson step y (3 - x y^2) / 2 for 1/sqrt(x), x = m / 2^30, y times 2^16: RsqrtTable's step, in 128
// bits since a seed here may exceed 2^16.
std::uint64_t rsqrt_step(std::uint64_t y, std::uint64_t m) {
  const UInt128 t = (UInt128{y} * y * m) >> 32;
  return static_cast<std::uint64_t>((UInt128{y} * ((UInt128{3} << 30) - t) + (UInt128{1} << 30)) >> 31);
}

// 2^16 / sqrt(x) at the middle of each bin of m's top `index_bits` bits (3/4 of 2^index_bits bins, since m's top
// bit is bit 30 or 31), then `steps` Newton-Raphson steps. index_bits 8 with one step is RsqrtTable.
class RsqrtSeeded {
 public:
  RsqrtSeeded(int index_bits, int steps) : index_bits_(index_bits), steps_(steps), first_(1 << (index_bits - 2)) {
    for (int i = first_; i < (1 << index_bits); ++i)
      table_.push_back(static_cast<std::uint64_t>(std::lround(65536.0 / std::sqrt((i + 0.5) / first_))));
  }
  std::uint64_t operator()(std::uint64_t m) const {
    std::uint64_t y = table_[static_cast<std::size_t>((m >> (32 - index_bits_)) - static_cast<std::uint64_t>(first_))];
    for (int i = 0; i < steps_; ++i) y = rsqrt_step(y, m);
    return y;
  }
  std::int64_t table_bits() const {
    return static_cast<std::int64_t>(table_.size()) * std::bit_width(table_.front());  // the first is the largest
  }

 private:
  int index_bits_, steps_, first_;
  std::vector<std::uint64_t> table_;
};

// The seed of the well-known single-precision bit trick: m as a float (its exponent from the leading-zero
// count, its mantissa m's next 23 bits), 0x5f3759df minus half that bit pattern, read back as a float: 1/sqrt(m)
// within 3.5%. Times 2^31 it is 2^16 / sqrt(m / 2^30). Then `steps` Newton-Raphson steps; no table.
std::uint64_t rsqrt_bit_trick(std::uint64_t m, int steps) {
  const int e = std::bit_width(m) - 1;
  const auto mantissa = static_cast<std::uint32_t>((m >> (e - 23)) & 0x7fffffu);
  const std::uint32_t bits = (static_cast<std::uint32_t>(e + 127) << 23) | mantissa;
  const float y = std::bit_cast<float>(0x5f3759dfu - (bits >> 1));
  auto r = static_cast<std::uint64_t>(std::lround(std::ldexp(static_cast<double>(y), 31)));
  for (int i = 0; i < steps; ++i) r = rsqrt_step(r, m);
  return r;
}

// ---- 1. Normalising a vector ----

// approx::unit with another reciprocal square root: v_k y / 2^(31 - bits + k), a unit vector times 2^bits.
template <class Rsqrt>
approx::Unit3 unit_by(const Vec& v, const Rsqrt& rsqrt, int bits = kUnitBits) {
  const Normalised n = normalise(static_cast<std::uint64_t>(core::dot(v, v)));
  const auto y = static_cast<std::int64_t>(rsqrt(n.m));
  const int shift = 31 - bits + n.k;
  approx::Unit3 out;
  for (int k = 0; k < 3; ++k) out[k] = round_shift(static_cast<std::int64_t>(v[k]) * y, shift);
  return out;
}

// |v| from the square-root unit (m's root, 16 bits: |v| = root 2^k), then each v_k 2^14 / |v| from an exact
// rounding divider.
approx::Unit3 unit_by_division(const Vec& v, const SqrtUnit& sqrt_unit) {
  const Normalised n = normalise(static_cast<std::uint64_t>(core::dot(v, v)));
  const Int128 root = sqrt_unit(n.m);
  approx::Unit3 out;
  for (int k = 0; k < 3; ++k)
    out[k] = static_cast<std::int64_t>(FixedArith::round_div(v[k] * (Int128{1} << (kUnitBits - n.k)), root));
  return out;
}

Operation normalising(const SqrtUnit& sqrt_unit) {
  std::mt19937_64 rng(1);
  std::vector<Vec> inputs;
  for (int i = 0; i < 32768; ++i) inputs.push_back(integer_vector(rng, log_uniform(rng, 1, 0x1p24)));
  for (int i = 0; i < 8192; ++i) inputs.push_back(camera_ray(rng));
  for (int i = 0; i < 16384; ++i) inputs.push_back(integer_vector(rng, log_uniform(rng, 0x1p8, 0x1p15)));

  const auto measure = [&inputs](const auto& f) {
    ErrorSum e;
    for (const Vec& v : inputs) {
      const approx::Unit3 u = f(v);
      const double length = std::sqrt(static_cast<double>(core::dot(v, v)));
      for (int k = 0; k < 3; ++k) e.add(off(u[k], static_cast<double>(v[k]) * kUnit / length));
    }
    return e.error();
  };
  const Multiply kComponents{26, 17, 3};  // v_k y, the three in parallel
  const std::int64_t device_table = 192 * 16;  // RsqrtTable: 2^16 / sqrt(x) < 2^16

  Operation op;
  op.name = "Normalising a vector (`approx::unit`)";
  op.fed = "The hit's normal m = p - c (|m| about the radius, 1 to 2^24 raw units) and every ray's direction "
           "d (components up to 2^20). Sampled: 32,768 integer vectors of log-uniform length in [1, 2^24), "
           "8,192 camera rays of random pixels, 16,384 directions of log-uniform length in [2^8, 2^15) (the "
           "bounces' n + u, reflections, refractions); uniform directions. Output: v / |v| times 2^14, "
           "error per component in 2^-14. Every candidate starts from v·v (three 26-bit squares) and its "
           "normalisation by an even shift into [2^30, 2^32) (a leading-zero count), not counted below.";
  Candidate c = candidate("192-entry reciprocal-square-root table, 1 Newton-Raphson step", 12,
                          "shift 1, table 1, the step's three multiplies in series 7, components 2, round 1",
                          {{16, 16}, {32, 32}, {16, 32}, kComponents}, device_table, true);
  c.error = measure([](const Vec& v) { return approx::unit(v); });
  op.candidates.push_back(c);

  const RsqrtSeeded small(6, 2);
  c = candidate("48-entry table, 2 Newton-Raphson steps", 19,
                "shift 1, table 1, two steps of three multiplies in series 14, components 2, round 1",
                {{16, 16}, {32, 32}, {16, 32}, {17, 17}, {34, 32}, {17, 32}, kComponents}, small.table_bits());
  c.error = measure([&small](const Vec& v) { return unit_by(v, small); });
  op.candidates.push_back(c);

  const RsqrtSeeded large(12, 0);
  c = candidate("3,072-entry table, no Newton-Raphson step", 6,
                "shift 1, table 2 (block RAM), components 2, round 1", {kComponents}, large.table_bits());
  c.error = measure([&large](const Vec& v) { return unit_by(v, large); });
  op.candidates.push_back(c);

  c = candidate("bit-trick seed (0x5f3759df), 2 Newton-Raphson steps", 19,
                "shift 1, seed (a subtract) 1, two steps 14, components 2, round 1",
                {{17, 17, 2}, {34, 32, 2}, {17, 32, 2}, kComponents}, 0);
  c.error = measure([](const Vec& v) { return unit_by(v, [](std::uint64_t m) { return rsqrt_bit_trick(m, 2); }); });
  op.candidates.push_back(c);

  c = candidate("square-root unit (Zhou-Hu, 16 iterations), then three rounding dividers", 34,
                "shift 1, 16 iterations, 16 radix-2 divider iterations (15-bit quotients and a rounding bit), "
                "round 1",
                {}, 0);
  c.error = measure([&sqrt_unit](const Vec& v) { return unit_by_division(v, sqrt_unit); });
  op.candidates.push_back(c);
  return op;
}

// ---- 1b. Normalising a scattered direction to the artix units' 2^17 (the artix path preset) ----

Operation normalising_for_units() {
  constexpr int kBits = 17;
  std::mt19937_64 rng(7);
  std::vector<Vec> inputs;
  for (int i = 0; i < 32768; ++i) inputs.push_back(integer_vector(rng, log_uniform(rng, 8, 0x1p15)));
  const auto measure = [&inputs](const auto& f) {
    ErrorSum e;
    for (const Vec& v : inputs) {
      const approx::Unit3 u = f(v);
      const double length = std::sqrt(static_cast<double>(core::dot(v, v)));
      for (int k = 0; k < 3; ++k) e.add(off(u[k], static_cast<double>(v[k]) * 0x1p17 / length));
    }
    return e.error();
  };
  const Multiply kComponents{16, 17, 3};  // v_k y: |v_k| < 2^15 after the scatter
  Operation op;
  op.name = "Normalising a scattered direction to the sphere units' 2^17 (`approx::unit` at 17 bits, artix path)";
  op.fed = "The artix path preset's bounce (artix_path.h): the scattered direction, in the path preset's 2^14 "
           "unit vectors (n + u, a reflection with its fuzz, a refraction), made a unit direction times 2^17 for "
           "the sphere units, whose geometric test takes |d| = 1. Sampled: 32,768 directions of log-uniform "
           "length in [2^3, 2^15) (the bounce ends a path shorter than 2^3), uniform directions. Output: v / |v| "
           "times 2^17, error per component in 2^-17. The table is approx::unit's, shared with the other "
           "normalisations.";
  Candidate c = candidate("192-entry table, 1 Newton-Raphson step, components at 17 bits", 12,
                          "approx::unit's: shift 1, table 1, the step 7, components 2, round 1",
                          {{16, 16}, {32, 32}, {16, 32}, kComponents}, 192 * 16, true);
  c.error = measure([](const Vec& v) { return approx::unit(v, kBits); });
  op.candidates.push_back(c);

  const RsqrtSeeded twice(8, 2);
  c = candidate("192-entry table, 2 Newton-Raphson steps", 19, "shift 1, table 1, two steps 14, components 2, round 1",
                {{16, 16}, {32, 32}, {16, 32}, {17, 17}, {34, 32}, {17, 32}, kComponents}, twice.table_bits());
  c.error = measure([&twice](const Vec& v) { return unit_by(v, twice, kBits); });
  op.candidates.push_back(c);

  c = candidate("the path preset's 2^14 unit vector, shifted left 3", 12, "approx::unit's, the shift free",
                {{16, 16}, {32, 32}, {16, 32}, kComponents}, 192 * 16);
  c.error = measure([](const Vec& v) {
    const approx::Unit3 u = approx::unit(v);
    return approx::Unit3{u.x * 8, u.y * 8, u.z * 8};
  });
  op.candidates.push_back(c);
  return op;
}

// ---- 2. Square roots: the refraction's and the random unit vector's ----

// floor(sqrt(v)) for v < 4^bits, a result bit a step: bring down two bits of v into the remainder, and keep the
// bit when the remainder holds 4 root + 1 (a compare and a subtract, no multiplier).
std::uint64_t digit_isqrt(std::uint64_t v, int bits) {
  std::uint64_t root = 0, rem = 0;
  for (int i = bits - 1; i >= 0; --i) {
    rem = (rem << 2) | ((v >> (2 * i)) & 3);
    const std::uint64_t trial = (root << 2) | 1;
    root <<= 1;
    if (rem >= trial) {
      rem -= trial;
      root |= 1;
    }
  }
  return root;
}

// sqrt(q) from sqrt(m) interpolated linearly between 97 nodes i 2^25, i = 32..128 (m's top 7 bits pick the
// interval, its next 16 the fraction), the nodes times 4.
class SqrtLerp {
 public:
  SqrtLerp() {
    for (int i = 32; i <= 128; ++i) table_.push_back(std::llround(4 * std::sqrt(i * 0x1p25)));
  }
  std::int64_t operator()(std::uint64_t q) const {
    if (q == 0) return 0;
    const Normalised n = normalise(q);
    const auto i = static_cast<std::size_t>((n.m >> 25) - 32);
    const auto f = static_cast<std::int64_t>((n.m >> 9) & 0xffff);
    const std::int64_t root4 = table_[i] + (((table_[i + 1] - table_[i]) * f) >> 16);  // sqrt(m) times 4
    return round_shift(root4, 2 - n.k);                                              // sqrt(q) = sqrt(m) 2^k
  }
  std::int64_t table_bits() const {
    return static_cast<std::int64_t>(table_.size()) * std::bit_width(static_cast<std::uint64_t>(table_.back()));
  }

 private:
  std::vector<std::int64_t> table_;
};

// Hyperbolic CORDIC in vectoring mode: from (x, y) = (w + c, w - c) with w = m / 2^32 in [1/4, 1), driving y to 0
// by shift-and-add rotations leaves x = A sqrt(x^2 - y^2) = A sqrt(4 c w), A the rotations' gain; c = 1 / (4 A^2)
// makes that sqrt(w), so no multiply remains. Shifts 1, 2, ..., `last`, with 4 and 13 taken twice (the repeats
// the hyperbolic rotations need to converge); 24 fractional bits.
class HyperbolicSqrt {
 public:
  explicit HyperbolicSqrt(int last) {
    double gain = 1;
    for (int s = 1; s <= last; ++s) {
      for (int r = 0; r < (s == 4 || s == 13 ? 2 : 1); ++r) {
        shifts_.push_back(s);
        gain *= std::sqrt(1 - std::ldexp(1.0, -2 * s));
      }
    }
    c_ = std::llround(std::ldexp(1 / (4 * gain * gain), kFrac));
  }
  std::int64_t operator()(std::uint64_t q) const {
    if (q == 0) return 0;
    const Normalised n = normalise(q);
    const auto w = static_cast<std::int64_t>(n.m >> (32 - kFrac));
    std::int64_t x = w + c_, y = w - c_;
    for (const int s : shifts_) {
      const std::int64_t dx = y >> s, dy = x >> s;
      if (y > 0) {
        x -= dx;
        y -= dy;
      } else {
        x += dx;
        y += dy;
      }
    }
    return round_shift(x, kFrac - 16 - n.k);  // x = sqrt(m) 2^(kFrac - 16); sqrt(q) = sqrt(m) 2^k
  }
  int iterations() const { return static_cast<int>(shifts_.size()); }

 private:
  static constexpr int kFrac = 24;
  std::vector<int> shifts_;
  std::int64_t c_ = 0;
};

Operation square_root(const SqrtUnit& sqrt_unit) {
  std::vector<std::uint64_t> inputs;
  for (std::int64_t zq = 1; zq < 32768; zq += 2)  // random_unit: (1 - z^2) 2^28 for every z it draws
    inputs.push_back(static_cast<std::uint64_t>(((std::int64_t{1} << 30) - zq * zq) >> 2));
  std::mt19937_64 rng(2);
  for (int i = 0; i < 65536; ++i) inputs.push_back(rng() % ((std::uint64_t{1} << 28) + 1));

  const auto measure = [&inputs](const auto& f) {
    ErrorSum e;
    for (const std::uint64_t q : inputs) e.add(off(f(q), std::sqrt(static_cast<double>(q))));
    return e.error();
  };

  Operation op;
  op.name = "Square root (the refraction's cos, random_unit's rho)";
  op.fed = "q <= 2^28, a Q28 value in [0, 1]: the refraction's |1 - |perp|^2| (|perp| = eta sin of the "
           "incidence, at most 1 without total internal reflection, a rounding past it at worst) and random_unit's "
           "1 - z^2. Sampled: the 16,384 inputs random_unit can produce (every odd z times 2^15), and 65,536 "
           "uniform in [0, 2^28]. Output: sqrt(q), a Q14 value, in 2^-14.";
  Candidate c = candidate("square-root unit (Zhou-Hu digit recurrence, 16 iterations)", 17,
                          "normalise 1, 16 iterations, one per cycle", {}, 0, true);
  c.error = measure([&sqrt_unit](std::uint64_t q) { return sqrt_unit(q); });
  op.candidates.push_back(c);

  c = candidate("digit-by-digit integer square root, exact (with a rounding bit)", 17,
                "16 iterations of sqrt(4q), one per cycle, round 1", {}, 0);
  c.error = measure([](std::uint64_t q) { return static_cast<Int128>((digit_isqrt(4 * q, 16) + 1) >> 1); });
  op.candidates.push_back(c);

  c = candidate("Newton-Raphson: m times approx::unit's reciprocal square root (its table shared)", 12,
                "shift 1, table 1, the step 7, m y 2, round 1", {{16, 16}, {32, 32}, {16, 32}, {32, 17}}, 0);
  c.error = measure([](std::uint64_t q) -> Int128 {
    if (q == 0) return 0;
    const Normalised n = normalise(q);
    const std::uint64_t y = approx::rsqrt_table()(n.m);  // sqrt(m) = m y / 2^31
    return round_shift(static_cast<std::int64_t>(n.m * y), 31 - n.k);
  });
  op.candidates.push_back(c);

  const SqrtLerp lerp;
  c = candidate("97-entry table, linear interpolation", 5, "normalise 1, table 1, multiply 2, add and round 1",
                {{12, 16}}, lerp.table_bits());
  c.error = measure([&lerp](std::uint64_t q) { return static_cast<Int128>(lerp(q)); });
  op.candidates.push_back(c);

  const HyperbolicSqrt cordic(10);
  c = candidate("hyperbolic CORDIC, " + std::to_string(cordic.iterations()) + " iterations, no multiplier",
                cordic.iterations() + 2, "normalise 1, one shift-and-add rotation per cycle, round 1", {}, 0);
  c.error = measure([&cordic](std::uint64_t q) { return static_cast<Int128>(cordic(q)); });
  op.candidates.push_back(c);
  return op;
}

// ---- 3a. The hit point's division: p_k = o_k + num d_k / 2a ----

// A divisor d >= 1 as X in [2^33, 2^34) (its top 34 bits; x = X / 2^33 in [1, 2)) and its bit length:
// d = x 2^(bits - 1), so n / d = n (2^32 / x) / 2^(31 + bits).
struct Divisor {
  std::uint64_t x;
  int bits;
};

Divisor normalise_divisor(Int128 d) {
  const auto u = static_cast<UInt128>(d);
  const int bits = bit_width_wide(u);
  return {static_cast<std::uint64_t>(bits <= 34 ? u << (34 - bits) : u >> (bits - 34)), bits};
}

// n / d from r = 2^32 / x: a seed from a table of 2^index_bits entries (the reciprocal at each bin's middle, 16
// bits) and `steps` Newton-Raphson steps r (2 - x r), then one multiply by the numerator.
class NewtonReciprocal {
 public:
  NewtonReciprocal(int index_bits, int steps) : index_bits_(index_bits), steps_(steps) {
    for (int i = 0; i < (1 << index_bits); ++i)
      seeds_.push_back(static_cast<std::uint64_t>(std::lround(65536 / (1 + (i + 0.5) / (1 << index_bits)))));
  }
  Int128 divide(Int128 n, Int128 d) const {
    const Divisor v = normalise_divisor(d);
    std::uint64_t r = seeds_[static_cast<std::size_t>((v.x >> (33 - index_bits_)) & ((1u << index_bits_) - 1))] << 16;
    for (int i = 0; i < steps_; ++i) {
      const UInt128 xr = (UInt128{v.x} * r) >> 33;  // x r times 2^32
      r = static_cast<std::uint64_t>((UInt128{r} * ((UInt128{1} << 33) - xr)) >> 32);
    }
    return round_shift_wide(n * static_cast<Int128>(r), 31 + v.bits);
  }
  std::int64_t table_bits() const { return static_cast<std::int64_t>(seeds_.size()) * 16; }

 private:
  int index_bits_, steps_;
  std::vector<std::uint64_t> seeds_;
};

// n / d from r = 2^32 / x interpolated linearly between 1025 nodes (x's next 10 bits pick the interval, the 23
// after them the fraction), then one multiply by the numerator.
class ReciprocalLerp {
 public:
  ReciprocalLerp() {
    for (int j = 0; j <= 1024; ++j)
      table_.push_back(static_cast<std::uint64_t>(std::llround(0x1p32 / (1 + j / 1024.0))));
  }
  Int128 divide(Int128 n, Int128 d) const {
    const Divisor v = normalise_divisor(d);
    const auto j = static_cast<std::size_t>((v.x >> 23) & 1023);
    const std::uint64_t f = v.x & ((std::uint64_t{1} << 23) - 1);
    const std::uint64_t r = table_[j] - (((table_[j] - table_[j + 1]) * f) >> 23);
    return round_shift_wide(n * static_cast<Int128>(r), 31 + v.bits);
  }
  std::int64_t table_bits() const { return static_cast<std::int64_t>(table_.size()) * 33; }

 private:
  std::vector<std::uint64_t> table_;
};

Operation hit_point_division() {
  struct Quotient {
    Int128 n, d;
  };
  std::mt19937_64 rng(3);
  std::vector<Quotient> inputs;
  for (int i = 0; i < 16384; ++i) {
    const Vec d = i % 2 == 0 ? camera_ray(rng) : integer_vector(rng, log_uniform(rng, 0x1p8, 0x1p20));
    const Int128 two_a = 2 * core::dot(d, d);
    const double distance = log_uniform(rng, 1, 0x1p25);  // |p - o| in raw units
    const Int128 num = std::max<std::int64_t>(
        1, std::llround(distance * static_cast<double>(two_a) / std::sqrt(static_cast<double>(two_a / 2))));
    for (int k = 0; k < 3; ++k) inputs.push_back({num * d[k], two_a});
  }
  // Exactly: |q - n/d| = |q d - n| / d.
  const auto measure = [&inputs](const auto& f) {
    ErrorSum e;
    for (const Quotient& in : inputs) {
      const Int128 miss = f(in.n, in.d) * in.d - in.n;
      e.add(static_cast<double>(miss < 0 ? -miss : miss) / static_cast<double>(in.d));
    }
    return e.error();
  };
  const Multiply kNumerators{70, 33, 3};  // num d_k times r, the three in parallel

  Operation op;
  op.name = "Division: the hit point p = o + num d / 2a";
  op.fed = "n = num d_k (|n| < 2^70) over 2a (< 2^43), rounded to the position grid; the quotient, "
           "p_k - o_k, is below 2^26. Sampled: 16,384 rays, half camera rays of random pixels, half directions "
           "of log-uniform length in [2^8, 2^20); the hit at a log-uniform distance in [1, 2^25) raw units; "
           "each of the three components. Output: raw units; the error is exact (|q 2a - n| / 2a).";
  Candidate c = candidate("radix-2 digit-recurrence divider, exact (FixedArith::round_div)", 28,
                          "26 quotient bits and a rounding bit, one 44-bit subtract per cycle, sign 1", {}, 0, true);
  c.error = measure([](Int128 n, Int128 d) { return FixedArith::round_div(n, d); });
  op.candidates.push_back(c);

  const NewtonReciprocal two_steps(8, 2);
  c = candidate("Newton-Raphson reciprocal: 256-entry seed, 2 steps, times n", 16,
                "normalise 1, table 1, four multiplies in series 10, n r 3, round 1",
                {{34, 16}, {16, 34}, {34, 33}, {33, 34}, kNumerators}, two_steps.table_bits());
  c.error = measure([&two_steps](Int128 n, Int128 d) { return two_steps.divide(n, d); });
  op.candidates.push_back(c);

  const NewtonReciprocal one_step(12, 1);
  c = candidate("Newton-Raphson reciprocal: 4,096-entry seed, 1 step, times n", 11,
                "normalise 1, table 2 (block RAM), two multiplies 4, n r 3, round 1",
                {{34, 16}, {16, 34}, kNumerators}, one_step.table_bits());
  c.error = measure([&one_step](Int128 n, Int128 d) { return one_step.divide(n, d); });
  op.candidates.push_back(c);

  const ReciprocalLerp lerp;
  c = candidate("1,025-entry reciprocal table, linear interpolation, times n", 10,
                "normalise 1, table 2 (block RAM), interpolation (multiply, subtract) 3, n r 3, round 1",
                {{23, 23}, kNumerators}, lerp.table_bits());
  c.error = measure([&lerp](Int128 n, Int128 d) { return lerp.divide(n, d); });
  op.candidates.push_back(c);
  return op;
}

// ---- 3b. The display's mean: sum / count ----

// sum times a table's round(2^bits / count), rounded (the display's display_mean has bits = 18).
std::uint64_t mean_by_table(std::uint64_t sum, std::uint64_t count, int bits) {
  const std::uint64_t r = ((std::uint64_t{1} << bits) + count / 2) / count;
  return (sum * r + (std::uint64_t{1} << (bits - 1))) >> bits;
}

Operation mean_division() {
  constexpr std::uint64_t kLargest = (1u << kSampleBits) - 1;  // a sample's channel
  ErrorSum table18, table14, exact;
  for (std::uint64_t count = 1; count <= kMaxSamples; ++count) {
    for (std::uint64_t sum = 0; sum <= count * kLargest; ++sum) {
      const double reference = static_cast<double>(sum) / static_cast<double>(count);
      table18.add(off(display_mean(static_cast<std::uint32_t>(sum), static_cast<int>(count)), reference));
      table14.add(off(mean_by_table(sum, count, 14), reference));
      exact.add(off((2 * sum + count) / (2 * count), reference));
    }
  }
  Operation op;
  op.name = "Division: the display's mean sum / count";
  op.fed = "A frame-memory entry's channel sum (at most 511 times the count) over its count, 1 to 255. Sampled: every "
           "pair, 16.7 million. Output: the 9-bit mean, in its last place.";
  Candidate c = candidate("255-entry table of round(2^18 / count), times sum", 3, "table 1, multiply 2",
                          {{19, 17}}, 255 * 19, true);
  c.error = table18.error();
  op.candidates.push_back(c);
  c = candidate("255-entry table of round(2^14 / count), times sum", 3, "table 1, multiply 2", {{15, 17}}, 255 * 15);
  c.error = table14.error();
  op.candidates.push_back(c);
  c = candidate("radix-2 digit-recurrence divider, exact", 10, "9 quotient bits and a rounding bit, one per cycle",
                {}, 0);
  c.error = exact.error();
  op.candidates.push_back(c);
  return op;
}

// ---- 4. Schlick's fifth power ----

Operation fifth_power() {
  std::vector<std::int64_t> coarse;  // (m / 2^14)^5 at the middle of each 16-wide bin, and at 1
  for (int j = 0; j < 1024; ++j) coarse.push_back(std::llround(std::pow((j + 0.5) / 1024, 5) * kUnit));
  coarse.push_back(kUnit);
  std::vector<std::int64_t> nodes;  // at every 256th m
  for (int j = 0; j <= 64; ++j) nodes.push_back(std::llround(std::pow(j / 64.0, 5) * kUnit));

  const auto measure = [](const auto& f) {
    ErrorSum e;
    for (std::int64_t m = 0; m <= kUnit; ++m) e.add(off(f(m), std::pow(static_cast<double>(m) / kUnit, 5) * kUnit));
    return e.error();
  };

  Operation op;
  op.name = "Schlick's fifth power (1 - cos)^5";
  op.fed = "m = 1 - cos times 2^14, 0 to 2^14. Sampled: every value. Output: (m / 2^14)^5 times 2^14, in 2^-14.";
  Candidate c = candidate("repeated squaring, each product rounded (approx::pow5)", 6,
                          "three multiplies in series (m^2, m^4, m^5), 2 each", {{15, 15, 3}}, 0, true);
  c.error = measure([](std::int64_t m) { return static_cast<Int128>(approx::pow5(m)); });
  op.candidates.push_back(c);

  c = candidate("four multiplies by m in series, each rounded", 8, "four multiplies in series, 2 each",
                {{15, 15, 4}}, 0);
  c.error = measure([](std::int64_t m) {
    std::int64_t p = m;
    for (int i = 0; i < 4; ++i) p = round_shift(p * m, kUnitBits);
    return static_cast<Int128>(p);
  });
  op.candidates.push_back(c);

  c = candidate("repeated squaring, full-width products rounded once (exact)", 8,
                "three multiplies in series, the wide two 3 each", {{15, 15}, {29, 29}, {57, 15}}, 0);
  c.error = measure([](std::int64_t m) {
    const UInt128 m2 = static_cast<UInt128>(m * m);
    return static_cast<Int128>((m2 * m2 * static_cast<UInt128>(m) + (UInt128{1} << 55)) >> 56);
  });
  op.candidates.push_back(c);

  c = candidate("1,025-entry table of m / 16", 2, "table 2 (block RAM)", {},
                static_cast<std::int64_t>(coarse.size()) * 15);
  c.error = measure([&coarse](std::int64_t m) { return Int128{coarse[static_cast<std::size_t>(m >> 4)]}; });
  op.candidates.push_back(c);

  c = candidate("65-entry table, linear interpolation", 4, "table 1, multiply 2, add and round 1", {{11, 8}},
                static_cast<std::int64_t>(nodes.size()) * 15);
  c.error = measure([&nodes](std::int64_t m) {
    const auto j = static_cast<std::size_t>(m >> 8);
    const std::int64_t next = nodes[std::min<std::size_t>(j + 1, 64)];
    return static_cast<Int128>(nodes[j] + (((next - nodes[j]) * (m & 255) + 128) >> 8));
  });
  op.candidates.push_back(c);
  return op;
}

// ---- 5. sin and cos of the random azimuth ----

// sin and cos of angle i (of 4096 to the turn) from f(j) = sin(pi/2 j/1024) times 2^14 on the quarter wave,
// j = 0..1024, folded by quadrant as SineTable does.
template <class Quarter>
std::pair<std::int64_t, std::int64_t> sin_cos_by(unsigned i, const Quarter& f) {
  const auto sin = [&f](unsigned a) -> std::int64_t {
    const unsigned j = a & 1023u;
    switch ((a >> 10) & 3u) {
      case 0: return f(j);
      case 1: return f(1024 - j);
      case 2: return -f(j);
      default: return -f(1024 - j);
    }
  };
  return {sin(i), sin(i + 1024)};
}

// Circular CORDIC in rotation mode: (x, y) = (K, 0) turned by j/4096 of a turn (j < 1024) in `iterations`
// shift-and-add rotations by +-atan(2^-s), K the inverse of their gain, so (x, y) ends at (cos, sin); the angle
// kept in 2^-24 turns (so the 12-bit angle needs no conversion to radians), x and y with 20 fractional bits.
class CordicSinCos {
 public:
  explicit CordicSinCos(int iterations) {
    double gain = 1;
    for (int s = 0; s < iterations; ++s) {
      angles_.push_back(std::llround(std::atan(std::ldexp(1.0, -s)) / (2 * kPi) * 0x1p24));
      gain *= std::sqrt(1 + std::ldexp(1.0, -2 * s));
    }
    start_ = std::llround(std::ldexp(1 / gain, kFrac));
  }
  std::pair<std::int64_t, std::int64_t> operator()(unsigned i) const {
    const unsigned quadrant = (i >> 10) & 3u;
    std::int64_t x = start_, y = 0, z = static_cast<std::int64_t>(i & 1023u) << 12;
    for (std::size_t s = 0; s < angles_.size(); ++s) {
      const std::int64_t dx = y >> s, dy = x >> s;
      if (z >= 0) {
        x -= dx;
        y += dy;
        z -= angles_[s];
      } else {
        x += dx;
        y -= dy;
        z += angles_[s];
      }
    }
    const std::int64_t c = round_shift(x, kFrac - kUnitBits), s = round_shift(y, kFrac - kUnitBits);
    switch (quadrant) {
      case 0: return {s, c};
      case 1: return {c, -s};
      case 2: return {-s, -c};
      default: return {-c, s};
    }
  }
  std::int64_t table_bits() const {
    return static_cast<std::int64_t>(angles_.size()) * std::bit_width(static_cast<std::uint64_t>(angles_.front()));
  }

 private:
  static constexpr int kFrac = 20;
  std::vector<std::int64_t> angles_;
  std::int64_t start_ = 0;
};

// Solves a x = b (4 unknowns) by Gaussian elimination with partial pivoting.
std::array<double, 4> solve(std::array<std::array<double, 5>, 4> a) {
  for (std::size_t col = 0; col < 4; ++col) {
    std::size_t pivot = col;
    for (std::size_t r = col + 1; r < 4; ++r)
      if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
    std::swap(a[col], a[pivot]);
    for (std::size_t r = 0; r < 4; ++r) {
      if (r == col) continue;
      const double factor = a[r][col] / a[col][col];
      for (std::size_t k = col; k < 5; ++k) a[r][k] -= factor * a[col][k];
    }
  }
  return {a[0][4] / a[0][0], a[1][4] / a[1][1], a[2][4] / a[2][2], a[3][4] / a[3][3]};
}

// The odd quintic a1 u + a3 u^3 + a5 u^5 nearest to sin(pi/2 u) on [0, 1] in the worst case, by Remez exchange:
// make the error equal and alternating at four points, move each to the extreme of the error between sign
// changes, repeat.
std::array<double, 3> sine_minimax() {
  const auto target = [](double u) { return std::sin(kPi / 2 * u); };
  std::array<double, 4> points{0.2, 0.55, 0.85, 1.0};
  std::array<double, 3> a{};
  for (int round = 0; round < 8; ++round) {
    std::array<std::array<double, 5>, 4> system{};
    for (std::size_t j = 0; j < 4; ++j) {
      const double u = points[j];
      system[j] = {u, u * u * u, u * u * u * u * u, j % 2 == 0 ? 1.0 : -1.0, target(u)};
    }
    const std::array<double, 4> x = solve(system);
    a = {x[0], x[1], x[2]};
    const auto error = [&a](double u) { return u * (a[0] + u * u * (a[1] + u * u * a[2])) - std::sin(kPi / 2 * u); };
    std::vector<double> extremes;  // where |error| peaks on each run of one sign
    double best = -1, best_u = 0;
    bool positive = false;
    for (int g = 1; g <= 4096; ++g) {
      const double u = g / 4096.0, e = error(u);
      if (g > 1 && (e > 0) != positive) {
        extremes.push_back(best_u);
        best = -1;
      }
      positive = e > 0;
      if (std::abs(e) > best) {
        best = std::abs(e);
        best_u = u;
      }
    }
    extremes.push_back(best_u);
    if (extremes.size() != 4) break;  // not four runs of one sign: keep this solution
    std::copy(extremes.begin(), extremes.end(), points.begin());
  }
  return a;
}

// sin(pi/2 u) for u = j / 1024 by the minimax quintic in Horner form in u^2, coefficients and products with 16
// fractional bits, each product rounded.
class SinePolynomial {
 public:
  SinePolynomial() {
    const std::array<double, 3> a = sine_minimax();
    for (std::size_t k = 0; k < 3; ++k) coefficients_[k] = std::llround(std::ldexp(a[k], 16));
  }
  std::int64_t operator()(unsigned j) const {
    const std::int64_t u = static_cast<std::int64_t>(j) << 6;  // j / 1024 times 2^16
    const std::int64_t t = round_shift(u * u, 16);
    std::int64_t p = round_shift(coefficients_[2] * t, 16) + coefficients_[1];
    p = round_shift(p * t, 16) + coefficients_[0];
    return round_shift(u * p, 32 - kUnitBits);
  }

 private:
  std::array<std::int64_t, 3> coefficients_{};
};

Operation sine_cosine() {
  const auto measure = [](const auto& f) {
    ErrorSum e;
    for (unsigned i = 0; i < 4096; ++i) {
      const auto [s, c] = f(i);
      const double phi = 2 * kPi * i / 4096;
      e.add(off(s, kUnit * std::sin(phi)));
      e.add(off(c, kUnit * std::cos(phi)));
    }
    return e.error();
  };

  Operation op;
  op.name = "sin and cos of the random azimuth";
  op.fed = "A 12-bit angle i, phi = 2 pi i / 4096. Sampled: every angle, both outputs. Output: sin and cos "
           "times 2^14, in 2^-14.";
  Candidate c = candidate("1,025-entry quarter-wave table (approx::SineTable)", 3,
                          "fold the quadrant 1, block RAM read 2 (sin and cos on its two ports)", {}, 1025 * 15, true);
  c.error = measure([](unsigned i) {
    const approx::SineTable& t = approx::sine_table();
    return std::pair{t.sin(i), t.cos(i)};
  });
  op.candidates.push_back(c);

  const CordicSinCos cordic(14);
  c = candidate("circular CORDIC, 14 iterations, no multiplier", 16,
                "14 shift-and-add rotations, one per cycle, fold the quadrant and round 2", {}, cordic.table_bits());
  c.error = measure([&cordic](unsigned i) { return cordic(i); });
  op.candidates.push_back(c);

  const SinePolynomial poly;
  c = candidate("minimax odd quintic on the quarter wave, Horner in u^2", 10,
                "fold 1, four multiplies in series 8 (sin and cos in parallel), round 1", {{17, 17, 4}, {13, 17, 2},
                {16, 17, 2}}, 0);
  c.error = measure([&poly](unsigned i) { return sin_cos_by(i, poly); });
  op.candidates.push_back(c);

  std::vector<std::int64_t> nodes;
  for (int k = 0; k <= 64; ++k) nodes.push_back(std::llround(kUnit * std::sin(kPi / 2 * k / 64)));
  c = candidate("65-entry quarter-wave table, linear interpolation", 5,
                "fold 1, table 1, multiply 2 (sin and cos in parallel), add and round 1", {{9, 4, 2}},
                static_cast<std::int64_t>(nodes.size()) * 15);
  c.error = measure([&nodes](unsigned i) {
    return sin_cos_by(i, [&nodes](unsigned j) {
      const std::size_t k = j >> 4;
      const std::int64_t next = nodes[std::min<std::size_t>(k + 1, 64)];
      return nodes[k] + (((next - nodes[k]) * (j & 15) + 8) >> 4);
    });
  });
  op.candidates.push_back(c);
  return op;
}

// ---- Markdown ----

std::string decimal(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", v);
  return text;
}

// 49152 as "49,152".
std::string grouped(std::int64_t v) {
  std::string digits = std::to_string(v), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string multiplies_text(const Candidate& c) {
  if (c.multiplies.empty()) return "0";
  std::string out = std::to_string(c.multiply_count()) + " (" + std::to_string(c.dsp()) + " DSP):";
  for (std::size_t i = 0; i < c.multiplies.size(); ++i) {
    const Multiply& m = c.multiplies[i];
    out += i == 0 ? " " : ", ";
    if (m.count > 1) out += std::to_string(m.count) + " of ";
    out += std::to_string(m.a_bits) + "x" + std::to_string(m.b_bits);
  }
  return out;
}

}  // namespace

int Candidate::multiply_count() const {
  int n = 0;
  for (const Multiply& m : multiplies) n += m.count;
  return n;
}

int Candidate::dsp() const {
  int n = 0;
  for (const Multiply& m : multiplies) n += m.count * device::dsp_slices(m.a_bits, m.b_bits);
  return n;
}

std::vector<Operation> evaluate() {
  const SqrtUnit sqrt_unit(path_preset().sqrt_iterations);
  return {normalising(sqrt_unit), normalising_for_units(), square_root(sqrt_unit), hit_point_division(),
          mean_division(), fifth_power(), sine_cosine()};
}

std::string markdown(const std::vector<Operation>& operations) {
  std::string out;
  for (std::size_t i = 0; i < operations.size(); ++i) {
    const Operation& op = operations[i];
    if (i > 0) out += "\n";
    out += "**" + std::to_string(i + 1) + ". " + op.name + ".** " + op.fed + "\n\n";
    out += "| candidate | worst | mean | cycles | why those cycles | multiplies | table bits |\n";
    out += "| --- | ---: | ---: | ---: | --- | --- | ---: |\n";
    for (const Candidate& c : op.candidates) {
      const std::string name = c.chosen ? "chosen: **" + c.name + "**" : c.name;
      out += "| " + name + " | " + decimal(c.error.worst) + " | " + decimal(c.error.mean) + " | " +
             std::to_string(c.cycles) + " | " + c.cycles_why + " | " + multiplies_text(c) + " | " +
             grouped(c.table_bits) + " |\n";
    }
  }
  return out;
}

std::string approximations_table() { return markdown(evaluate()); }

}  // namespace tripsitter::approx_bench

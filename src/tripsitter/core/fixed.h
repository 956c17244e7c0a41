// Fixed-point number formats of the device.
//
// A FixedFormat describes an integer of `total_bits` bits (two's complement when signed) that stands for
// raw * 2^-frac_bits. Values are held as their raw integer (std::int64_t); the only way in from floating
// point is FixedFormat::quantize, which rounds to nearest (ties away from zero) and saturates to the
// format's range, reporting whether it had to.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace tripsitter::core {

// 128-bit integers for the device's widest intermediates (b^2 needs up to about 90 bits in the wide preset).
__extension__ typedef __int128 Int128;
__extension__ typedef unsigned __int128 UInt128;

// Thrown by a fixed-point check (device/worker.h): an intermediate outside the width docs/device.md gives it, which the
// board's registers would have silently wrapped.
class FixedPointOverflow : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

struct Quantized {
  std::int64_t raw = 0;
  bool saturated = false;  // the value was outside the range (or not a number) and was clamped
};

struct FixedFormat {
  int total_bits = 16;  // 1..62
  int frac_bits = 3;    // 0..total_bits
  bool is_signed = true;

  constexpr std::int64_t max_raw() const {
    return is_signed ? (std::int64_t{1} << (total_bits - 1)) - 1 : (std::int64_t{1} << total_bits) - 1;
  }
  constexpr std::int64_t min_raw() const { return is_signed ? -(std::int64_t{1} << (total_bits - 1)) : 0; }
  constexpr bool contains(std::int64_t raw) const { return raw >= min_raw() && raw <= max_raw(); }
  constexpr double step() const { return 1.0 / static_cast<double>(std::int64_t{1} << frac_bits); }
  constexpr double to_double(std::int64_t raw) const { return static_cast<double>(raw) * step(); }
  constexpr double max_value() const { return to_double(max_raw()); }
  constexpr double min_value() const { return to_double(min_raw()); }

  // Round to nearest (ties away from zero), saturate to [min_raw, max_raw]. NaN saturates to 0.
  Quantized quantize(double value) const;

  // "s16.3" for signed 16 bits with 3 fractional bits, "u12.3" for unsigned.
  std::string name() const;

  constexpr bool operator==(const FixedFormat&) const = default;
};

// Re-expresses a raw value given with `from_frac` fractional bits with `to_frac` fractional bits,
// rounding to nearest (ties away from zero) when bits are dropped. REQUIRES the result fits in 63 bits.
std::int64_t rescale_raw(std::int64_t raw, int from_frac, int to_frac);

}  // namespace tripsitter::core

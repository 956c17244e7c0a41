#include <tripsitter/core/fixed.h>

#include <cmath>

namespace tripsitter::core {

Quantized FixedFormat::quantize(double value) const {
  if (std::isnan(value)) return {0, true};
  const double scaled = std::round(std::ldexp(value, frac_bits));  // std::round: ties away from zero
  if (scaled > static_cast<double>(max_raw())) return {max_raw(), true};
  if (scaled < static_cast<double>(min_raw())) return {min_raw(), true};
  return {static_cast<std::int64_t>(scaled), false};
}

std::string FixedFormat::name() const {
  std::string out(is_signed ? "s" : "u");
  out += std::to_string(total_bits);
  out += '.';
  out += std::to_string(frac_bits);
  return out;
}

std::int64_t rescale_raw(std::int64_t raw, int from_frac, int to_frac) {
  if (to_frac >= from_frac) return raw * (std::int64_t{1} << (to_frac - from_frac));
  const int shift = from_frac - to_frac;
  const std::int64_t half = std::int64_t{1} << (shift - 1);
  const std::int64_t magnitude = raw < 0 ? -raw : raw;
  const std::int64_t rounded = (magnitude + half) >> shift;
  return raw < 0 ? -rounded : rounded;
}

}  // namespace tripsitter::core

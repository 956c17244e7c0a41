#include <tripsitter/device/sqrt_unit.h>

#include <stdexcept>

namespace tripsitter::device {

SqrtUnit::SqrtUnit(int iterations) : iterations_(iterations) {
  if (iterations < 1 || iterations > kMaxSqrtIterations) throw std::invalid_argument("sqrt iterations out of range");
}

core::Int128 SqrtUnit::operator()(core::UInt128 input) const {
  if (input == 0) return 0;
  const int n = iterations_;
  const Normalised in = normalise(input);
  const std::uint64_t m = in.m;

  // x has n fractional bits, c = x^2 has 2n.
  std::uint64_t x = std::uint64_t{1} << (n - 1);        // 1/2
  std::uint64_t c = std::uint64_t{1} << (2 * n - 2);    // 1/4
  for (int k = 0; k < n; ++k) {
    const std::uint64_t cross = x << (n - k);               // x * 2^-k in units of 2^-2n
    const std::uint64_t step_sq = std::uint64_t{1} << (2 * n - 2 * k - 2);  // 2^-2(k+1)
    const std::uint64_t step = std::uint64_t{1} << (n - k - 1);            // 2^-(k+1)
    if (c < m) {
      c = c + cross + step_sq;
      x += step;
    } else {
      c = c + step_sq - cross;  // (x - d)^2 >= 0, so no wrap-around
      x -= step;
    }
  }
  return denormalise(x, in.e);
}

}  // namespace tripsitter::device

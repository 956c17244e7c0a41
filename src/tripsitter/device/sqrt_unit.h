// The device's square-root unit: the digit recurrence of Zhou & Hu, "A novel square root algorithm and
// its FPGA simulation" (J. Phys.: Conf. Ser. 1314, 2019), as SPEC.md section B describes it.
//
// The input D is normalised by an even shift 2e into m = D / 4^e in [1/4, 1), held in a register of
// 2N fractional bits (lower bits are truncated, as a hardware register of that width would). Starting
// from x_0 = 1/2, c_0 = 1/4, each of the N steps compares c_k with m and moves x by -/+ 2^-(k+1),
// updating c with (x +- 2^-(k+1))^2 = x^2 +- x 2^-k + 2^-2(k+1): shifts and adds, no multiplier.
// The result x_N 2^e is rounded to the nearest integer.
//
// Accuracy: |x_N - sqrt(m)| <= 2^-N, so the result is within about 2^(e-N) + 1/2 of sqrt(D); for inputs
// below 4^N it is within one unit. README gives the measured worst case for N = 16.
#pragma once

#include <cstdint>

#include <tripsitter/core/fixed.h>

namespace tripsitter::device {

inline constexpr int kMaxSqrtIterations = 30;

class SqrtUnit {
 public:
  // REQUIRES 1 <= iterations <= kMaxSqrtIterations.
  explicit SqrtUnit(int iterations);

  // sqrt(input) rounded as described above. input < 2^126.
  core::Int128 operator()(core::UInt128 input) const;
  int iterations() const { return iterations_; }

 private:
  int iterations_;
};

// Exact floor(sqrt(v)), the reference the tests compare the unit against.
std::uint64_t exact_isqrt(core::UInt128 v);

}  // namespace tripsitter::device

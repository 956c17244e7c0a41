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
// below 4^N it is within one unit. docs/measured.md gives the measured worst case for N = 16.
//
// The recurrence in closed form (docs/device.md, "Square-root unit"). In units of 2^-N, x_0 = 2^(N-1) and
// step k moves x by 2^(N-1-k); c_k = x_k^2 exactly, so "c_k < m" is "x_k < sqrt(M)" with M = m 4^N, the
// register as an integer. For N >= 2 the visited x_k are the inner nodes of a binary search tree whose nodes
// are the even integers and whose leaves the odd ones, so x_N is the odd integer 2j + 1 with
// 2j < sqrt(M) <= 2j + 2: j = floor(isqrt(M - 1) / 2). For N = 1, x_1 = 2 if M > 1, else 0.
// `closed_form` computes that with core::isqrt (core/isqrt.h); sqrt_unit_test.cpp checks it against the
// recurrence for every register value with N <= 12 and around every leaf boundary for N = 16.
#pragma once

#include <bit>
#include <cstdint>

#include <tripsitter/core/fixed.h>
#include <tripsitter/core/isqrt.h>

namespace tripsitter::device {

inline constexpr int kMaxSqrtIterations = 30;

class SqrtUnit {
 public:
  // REQUIRES 1 <= iterations <= kMaxSqrtIterations.
  explicit SqrtUnit(int iterations);

  // sqrt(input) rounded as described above, the recurrence step by step (the plain model). input < 2^126.
  core::Int128 operator()(core::UInt128 input) const;
  // The same value from one integer square root (the fast model). input < 2^126.
  core::Int128 closed_form(core::UInt128 input) const {
    if (input == 0) return 0;
    const Normalised in = normalise(input);
    std::uint64_t x = 0;
    if (iterations_ == 1) {
      x = in.m > 1 ? 2 : 0;
    } else {
      x = 2 * (core::isqrt(in.m - 1) / 2) + 1;
    }
    return denormalise(x, in.e);
  }
  int iterations() const { return iterations_; }

 private:
  struct Normalised {
    std::uint64_t m;  // input / 4^e with 2N fractional bits, truncated: in [4^(N-1), 4^N)
    int e;
  };
  Normalised normalise(core::UInt128 input) const {
    const auto hi = static_cast<std::uint64_t>(input >> 64);
    const int bits = hi != 0 ? 128 - std::countl_zero(hi) : 64 - std::countl_zero(static_cast<std::uint64_t>(input));
    const int e = (bits + 1) / 2;
    const int shift = 2 * iterations_ - 2 * e;
    return {static_cast<std::uint64_t>(shift >= 0 ? input << shift : input >> (-shift)), e};
  }
  // x (N fractional bits) times 2^e, rounded to the nearest integer.
  core::Int128 denormalise(std::uint64_t x, int e) const {
    const int out_shift = e - iterations_;
    if (out_shift >= 0) return static_cast<core::Int128>(x) << out_shift;
    const int drop = -out_shift;
    return static_cast<core::Int128>((x + (std::uint64_t{1} << (drop - 1))) >> drop);
  }
  int iterations_;
};

}  // namespace tripsitter::device

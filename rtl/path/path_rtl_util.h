// What the tests of rtl/path/ share: random unit vectors as the model's 2^14 vectors, and the blocks' vector ports
// (three signed fields, x in the low bits).
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include "rtl_ports.h"

#include <tripsitter/device/approx.h>

namespace tripsitter::rtl::path {

using device::approx::Unit3;

// A direction uniform on the sphere, each component times 2^14, rounded.
inline Unit3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  const double x = g(rng), y = g(rng), z = g(rng), len = std::sqrt(x * x + y * y + z * z) + 1e-12;
  return {std::llround(x / len * 16384), std::llround(y / len * 16384), std::llround(z / len * 16384)};
}

// v as a port of three `bits`-bit two's complement fields.
inline UInt128 pack(const Unit3& v, int bits = 17) {
  const auto field = [bits](std::int64_t c, int k) {
    return static_cast<UInt128>(static_cast<std::uint64_t>(c) & static_cast<std::uint64_t>(mask(bits))) << (bits * k);
  };
  return field(v.x, 0) | field(v.y, 1) | field(v.z, 2);
}

// A port of three `bits`-bit two's complement fields as a vector.
inline Unit3 unpack(UInt128 port, int bits = 24) {
  return {static_cast<std::int64_t>(sign_extend(port, bits)), static_cast<std::int64_t>(sign_extend(port >> bits, bits)),
          static_cast<std::int64_t>(sign_extend(port >> (2 * bits), bits))};
}

}  // namespace tripsitter::rtl::path

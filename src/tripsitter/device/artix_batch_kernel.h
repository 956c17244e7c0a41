// artix_batch.h's loop on bare arrays: the one file of the device library compiled for x86-64-v3 when the build is
// (src/tripsitter/device/CMakeLists.txt), in AVX2 then and in plain C++ otherwise, with the same results. It
// includes nothing that another file could share, so no inline function is compiled twice with two instruction
// sets.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tripsitter::device::artix::batch {

// The entries a group: a block holds padding after its entries so that a run from any entry can be read a whole
// group at a time (SphereBlock), and meets has room for as many.
inline constexpr std::size_t kLanes = 4;

// A block's fields, each an array of `stride` doubles (field k of entry j at fields[k * stride + j]): the centre,
// F's scales 2^-(17 + e) and 2^-e, and r^2 / 4^e (below 2^34; -1 for padding).
enum Field : std::size_t { kCx, kCy, kCz, kDown, kUp, kR2s, kFields };

// A ray as the loop reads it: origin o and direction d times 2^17.
struct Ray {
  double o[3];
  double d[3];
};

// meets[j] = whether the sphere units' disc of the ray and entry j is >= 0, for j below n rounded up to a multiple
// of kLanes.
void meets_line(const double* fields, std::size_t stride, std::size_t n, const Ray& ray,
                std::uint8_t* __restrict meets);

}  // namespace tripsitter::device::artix::batch

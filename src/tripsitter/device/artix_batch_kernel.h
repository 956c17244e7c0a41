// artix_batch.h's loop on bare arrays: the one function of the device library compiled for x86-64-v3 when the
// build is (src/tripsitter/device/CMakeLists.txt), in AVX2 then and in plain C++ otherwise, with the same results.
// It includes nothing that another file could share, so no inline function is compiled twice with two instruction
// sets.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tripsitter::device::artix::batch {

// The entries a group: the arrays hold n rounded up to a whole group (SphereBlock's padding), meets as many.
inline constexpr std::size_t kLanes = 4;

// meets[j] = whether the sphere units' disc of the ray (origin o, direction d times 2^17) and sphere j (centre
// (cx, cy, cz)[j], F scale down[j] = 2^-(17 + e), r^2 / 4^e = r2s[j]) is >= 0, F's components within
// +-scaled_max, for j below n rounded up to a multiple of kLanes.
void meets_line(const double* __restrict cx, const double* __restrict cy, const double* __restrict cz,
                const double* __restrict down, const double* __restrict r2s, std::size_t n, const double o[3],
                const double d[3], double scaled_max, std::uint8_t* __restrict meets);

}  // namespace tripsitter::device::artix::batch

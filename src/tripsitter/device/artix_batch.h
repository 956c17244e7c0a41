// The fast model's filter before the sphere units' integer quadratic (artix_kernel.h), a block of spheres at a time:
// whether the units find disc = r^2 / 4^e - F.F >= 0 for the ray's line and each sphere. It is computed in doubles
// in which every intermediate is an integer below 2^53 times a power of two (oc below 2^25, products below 2^42,
// sums below 2^45, F.F below 2^36 unless a component of F is beyond the units' 18 bits, and then above every
// r^2 / 4^e), and each rounding the units make (b to the position grid, f scaled down to F) is a floor by a power
// of two: the units' disc exactly, so a sphere the filter drops is one the units miss, and the fast model gives the
// plain model's answer. The loop works in vector registers (AVX2 where the build is for x86-64-v3, as the render
// library; artix_batch_kernel.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <tripsitter/device/artix_batch_kernel.h>
#include <tripsitter/device/artix_kernel.h>

namespace tripsitter::device::artix {

// Spheres as the filter reads them: one array a field (artix_batch_kernel.h), each followed by padding (entries no
// line meets) so that the filter can read any run of entries a whole vector register at a time.
class SphereBlock {
 public:
  SphereBlock();  // empty
  explicit SphereBlock(std::span<const UnitSphere> spheres);
  std::size_t size() const { return size_; }
  void push_back(const UnitSphere& s);

  // The fields from entry `first` on, and the distance from one field to the next.
  const double* fields(std::size_t first) const { return data_.data() + first; }
  std::size_t stride() const { return stride_; }

 private:
  void reserve(std::size_t entries);  // room for this many entries and the padding
  void set(std::size_t j, const UnitSphere& s);
  void set_padding(std::size_t j);
  std::size_t size_ = 0;
  std::size_t stride_ = 0;
  std::vector<double> data_;  // batch::kFields arrays of stride_
};

// The ray as the filter reads it.
inline batch::Ray batch_ray(const UnitRay& ray) {
  return {{static_cast<double>(ray.o[0]), static_cast<double>(ray.o[1]), static_cast<double>(ray.o[2])},
          {static_cast<double>(ray.d[0]), static_cast<double>(ray.d[1]), static_cast<double>(ray.d[2])}};
}

// The room meets_line needs for n entries: n rounded up to the filter's vector width.
inline std::size_t meets_room(std::size_t n) { return (n + batch::kLanes - 1) / batch::kLanes * batch::kLanes; }

// meets[j] = 1 when the units' disc of the ray and block sphere first + j is >= 0, else 0, for j < n (and up to
// meets_room(n), meaningless there). REQUIRES first + n <= block.size().
inline void meets_line(const UnitRay& ray, const SphereBlock& block, std::size_t first, std::size_t n,
                       std::uint8_t* meets) {
  batch::meets_line(block.fields(first), block.stride(), n, batch_ray(ray), meets);
}

}  // namespace tripsitter::device::artix

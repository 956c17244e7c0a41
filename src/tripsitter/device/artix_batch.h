// The fast model's filter before the sphere units' integer quadratic (artix_kernel.h), a block of spheres at a
// time: whether the units find disc = r^2 / 4^e - F.F >= 0 for the ray's line and each sphere. It is computed in
// doubles in which every intermediate is an integer below 2^53 (oc below 2^25, products below 2^42, sums below
// 2^44, F.F below 2^36) and each rounding the units make (b to the position grid, f scaled down to F) is a floor
// by a power of two: the units' disc exactly, so a sphere the filter drops is one the units miss, and the fast
// model gives the plain model's answer. The loop works in vector registers (AVX2 where the build is for
// x86-64-v3, as the render library).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <tripsitter/device/artix_kernel.h>

namespace tripsitter::device::artix {

// Spheres as the filter reads them: one array a field, followed by padding (entries no line meets) so that the
// filter can read any run of entries a whole vector register at a time.
class SphereBlock {
 public:
  SphereBlock();  // empty
  explicit SphereBlock(std::span<const UnitSphere> spheres);
  std::size_t size() const { return size_; }
  void push_back(const UnitSphere& s);

 private:
  friend void meets_line(const UnitRay&, const SphereBlock&, std::size_t, std::size_t, std::uint8_t*);
  void append(const UnitSphere& s);  // unpadded
  void pad();
  std::size_t size_ = 0;
  std::vector<double> cx_, cy_, cz_;
  std::vector<double> down_;  // 2^-(17 + e): f scaled to the sphere's F
  std::vector<double> r2s_;
};

// The room meets_line needs for n entries: n rounded up to the filter's vector width.
std::size_t meets_room(std::size_t n);

// meets[j] = 1 when the units' disc of the ray and block sphere first + j is >= 0, else 0, for j < n (and up to
// meets_room(n), meaningless there). REQUIRES first + n <= block.size().
void meets_line(const UnitRay& ray, const SphereBlock& block, std::size_t first, std::size_t n, std::uint8_t* meets);

}  // namespace tripsitter::device::artix

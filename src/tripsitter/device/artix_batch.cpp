#include <tripsitter/device/artix_batch.h>

#include <cassert>
#include <cmath>

#include <tripsitter/device/artix_batch_kernel.h>

namespace tripsitter::device::artix {

SphereBlock::SphereBlock() { pad(); }

SphereBlock::SphereBlock(std::span<const UnitSphere> spheres) {
  for (std::vector<double>* v : {&cx_, &cy_, &cz_, &down_, &r2s_}) v->reserve(spheres.size() + batch::kLanes - 1);
  for (const UnitSphere& s : spheres) append(s);
  pad();
}

// kLanes - 1 entries past the last sphere, which no line meets (r^2 / 4^e = -1).
void SphereBlock::pad() {
  for (std::vector<double>* v : {&cx_, &cy_, &cz_, &down_, &r2s_}) v->resize(size_ + batch::kLanes - 1, 0.0);
  std::fill(r2s_.begin() + static_cast<std::ptrdiff_t>(size_), r2s_.end(), -1.0);
}

void SphereBlock::append(const UnitSphere& s) {
  cx_.push_back(static_cast<double>(s.c[0]));
  cy_.push_back(static_cast<double>(s.c[1]));
  cz_.push_back(static_cast<double>(s.c[2]));
  down_.push_back(std::ldexp(1.0, -(kDirectionFrac + s.e)));
  r2s_.push_back(static_cast<double>(s.r2s));
  ++size_;
}

void SphereBlock::push_back(const UnitSphere& s) {
  for (std::vector<double>* v : {&cx_, &cy_, &cz_, &down_, &r2s_}) v->resize(size_);
  append(s);
  pad();
}

std::size_t meets_room(std::size_t n) { return (n + batch::kLanes - 1) / batch::kLanes * batch::kLanes; }

void meets_line(const UnitRay& ray, const SphereBlock& block, std::size_t first, std::size_t n, std::uint8_t* meets) {
  assert(first + n <= block.size());
  const double o[3] = {static_cast<double>(ray.o[0]), static_cast<double>(ray.o[1]), static_cast<double>(ray.o[2])};
  const double d[3] = {static_cast<double>(ray.d[0]), static_cast<double>(ray.d[1]), static_cast<double>(ray.d[2])};
  batch::meets_line(block.cx_.data() + first, block.cy_.data() + first, block.cz_.data() + first,
                    block.down_.data() + first, block.r2s_.data() + first, n, o, d, static_cast<double>(kScaledMax),
                    meets);
}

}  // namespace tripsitter::device::artix

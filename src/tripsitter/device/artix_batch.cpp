#include <tripsitter/device/artix_batch.h>

#include <algorithm>
#include <cmath>

namespace tripsitter::device::artix {

SphereBlock::SphereBlock() { reserve(0); }

SphereBlock::SphereBlock(std::span<const UnitSphere> spheres) {
  reserve(spheres.size());
  for (const UnitSphere& s : spheres) set(size_++, s);
}

// Room for `entries` and kLanes - 1 entries of padding after them (and after any that follow), the entries kept.
void SphereBlock::reserve(std::size_t entries) {
  const std::size_t stride = entries + batch::kLanes - 1;
  if (stride <= stride_ && !data_.empty()) return;
  std::vector<double> data(batch::kFields * stride);
  for (std::size_t k = 0; k < batch::kFields; ++k)
    std::copy_n(data_.begin() + static_cast<std::ptrdiff_t>(k * stride_), size_,
                data.begin() + static_cast<std::ptrdiff_t>(k * stride));
  data_ = std::move(data);
  stride_ = stride;
  for (std::size_t j = size_; j < stride_; ++j) set_padding(j);
}

void SphereBlock::set(std::size_t j, const UnitSphere& s) {
  const double f[batch::kFields] = {static_cast<double>(s.c[0]),
                                    static_cast<double>(s.c[1]),
                                    static_cast<double>(s.c[2]),
                                    std::ldexp(1.0, -(kDirectionFrac + s.e)),
                                    std::ldexp(1.0, -s.e),
                                    static_cast<double>(s.r2s)};
  for (std::size_t k = 0; k < batch::kFields; ++k) data_[k * stride_ + j] = f[k];
}

// An entry no line meets: r^2 / 4^e = -1.
void SphereBlock::set_padding(std::size_t j) {
  for (std::size_t k = 0; k < batch::kFields; ++k) data_[k * stride_ + j] = k == batch::kR2s ? -1.0 : 0.0;
}

void SphereBlock::push_back(const UnitSphere& s) {
  reserve(std::max(size_ + 1, 2 * size_));
  set(size_++, s);
}

}  // namespace tripsitter::device::artix

#include <tripsitter/render/image_error.h>

#include <algorithm>
#include <vector>

namespace tripsitter::render {
namespace {

constexpr int kBlock = 8;

double channel(const core::Vec3f& v, int c) { return static_cast<double>(v[c]); }

}  // namespace

ImageError image_error(std::span<const core::Vec3f> image, std::span<const core::Vec3f> reference, int width,
                       int height) {
  ImageError e;
  const std::size_t n = image.size();
  if (n == 0) return e;
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double x = channel(image[i], c), r = channel(reference[i], c);
      e.relmse += (x - r) * (x - r) / (r * r + 0.01);
      e.bias += (x - r) / (r + 0.01);
    }
  }
  e.relmse /= static_cast<double>(3 * n);
  e.bias /= static_cast<double>(3 * n);
  std::size_t blocks = 0;
  for (int by = 0; by < height; by += kBlock) {
    for (int bx = 0; bx < width; bx += kBlock) {
      double x[3] = {}, r[3] = {};
      const int rows = std::min(kBlock, height - by), cols = std::min(kBlock, width - bx);
      for (int y = by; y < by + rows; ++y) {
        for (int xx = bx; xx < bx + cols; ++xx) {
          const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(xx);
          for (int c = 0; c < 3; ++c) {
            x[c] += channel(image[i], c);
            r[c] += channel(reference[i], c);
          }
        }
      }
      const double area = static_cast<double>(rows * cols);
      for (int c = 0; c < 3; ++c) {
        const double mx = x[c] / area, mr = r[c] / area;
        e.block_relmse += (mx - mr) * (mx - mr) / (mr * mr + 0.01);
      }
      ++blocks;
    }
  }
  e.block_relmse /= static_cast<double>(3 * blocks);
  return e;
}

}  // namespace tripsitter::render

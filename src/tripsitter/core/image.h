// Images: 12-bit colour as the monitor shows it, 24-bit colour as the float renderer writes it, and linear float
// radiance as the float renderers compute it (colour.h encodes it to 24-bit sRGB).
#pragma once

#include <cstddef>
#include <cstdint>
#include <algorithm>
#include <cstdlib>
#include <vector>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/core/vec.h>

namespace tripsitter::core {

struct Image444 {
  int width = 0;
  int height = 0;
  std::vector<Rgb444> pixels;  // width * height, row-major

  Image444() = default;
  Image444(int w, int h, Rgb444 fill = kBlack)
      : width(w), height(h), pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill) {}
  Rgb444& at(int x, int y) { return pixels[index(x, y)]; }
  const Rgb444& at(int x, int y) const { return pixels[index(x, y)]; }
  bool operator==(const Image444&) const = default;

 private:
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
  }
};

// 24-bit colour, as the float renderer writes it: r, g, b bytes per pixel, row-major, top row first.
struct ImageRgb8 {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // 3 * width * height

  ImageRgb8() = default;
  ImageRgb8(int w, int h) : width(w), height(h), pixels(3 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h)) {}
  bool operator==(const ImageRgb8&) const = default;
};

// Linear radiance per pixel (the mean of its samples, for the path tracer), row-major, top row first.
struct ImageRgbF {
  int width = 0;
  int height = 0;
  std::vector<Vec3f> pixels;  // width * height
};

// 12-bit to 24-bit colour, each channel v * 17.
inline ImageRgb8 to_rgb8(const Image444& image) {
  ImageRgb8 out(image.width, image.height);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    out.pixels[3 * i + 0] = Rgb444::expand(image.pixels[i].r());
    out.pixels[3 * i + 1] = Rgb444::expand(image.pixels[i].g());
    out.pixels[3 * i + 2] = Rgb444::expand(image.pixels[i].b());
  }
  return out;
}

// How two images of the same size differ, channel by channel, in 4-bit levels.
struct ImageDiff {
  std::size_t pixels = 0;             // pixels compared
  std::size_t differing = 0;          // pixels with any channel different
  std::size_t over_one_level = 0;     // pixels with some channel more than one level off
  int max_level_difference = 0;       // largest channel difference, 0..15
};

// REQUIRES a and b of the same size.
inline ImageDiff diff(const Image444& a, const Image444& b) {
  ImageDiff d;
  d.pixels = a.pixels.size();
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const Rgb444 p = a.pixels[i], q = b.pixels[i];
    const int m = std::max({std::abs(p.r() - q.r()), std::abs(p.g() - q.g()), std::abs(p.b() - q.b())});
    if (m > 0) ++d.differing;
    if (m > 1) ++d.over_one_level;
    d.max_level_difference = std::max(d.max_level_difference, m);
  }
  return d;
}

}  // namespace tripsitter::core

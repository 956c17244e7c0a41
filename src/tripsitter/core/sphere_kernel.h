// The per-pixel function of the board, written once for every arithmetic (SPEC.md section B, report table 1).
//
// A ray leaves the origin along d; for each sphere (centre c, radius r):
//   a = d.d,  b = 2 d.c,  c' = c.c - r^2,  D = b^2 - 4 a c'
// no hit when D < 0, else the near distance is t = (b - sqrt(D)) / (2a). The closest t > 0 wins.
// The unit normal at the hit, n = (t d - c) / r, is the colour: channel_k = floor(7 n_k + 7), clamped to 0..14.
//
// Everything is kept as ratios so that no division happens before the colour: with num = b - sqrt(D),
// t = num / (2a) and n_k = (num d_k - 2a c_k) / (2a r). Because a is the same for every sphere of a
// pixel, comparing num compares t. In fixed point, positions carry 2^-F and the formula is homogeneous
// in that scale, so the kernel never needs to know F: only the host's rounding does.
//
// The Arith policy supplies the number types and the two non-ring operations:
//   typename Arith::Coord        sphere coordinates and radius (raw fixed point, or double)
//   typename Arith::Wide         products and sums of products (128-bit integer, or double)
//   Wide arith.sqrt(Wide D)      D >= 0
//   int  Arith::floor_div(Wide n, Wide d)   d > 0; floor(n / d), saturated to the int range
#pragma once

#include <algorithm>
#include <span>

#include <tripsitter/core/rgb444.h>
#include <tripsitter/core/vec.h>

namespace tripsitter::core {

template <class Coord>
struct KernelSphere {
  Vec3<Coord> center;
  Coord radius{};
};

template <class Wide>
struct KernelHit {
  int index = -1;  // closest sphere, -1 when nothing is hit in front of the camera
  Wide num{};      // b - sqrt(D) of that sphere: t * 2a
};

// Closest hit along direction d (integer pixel coordinates) over all spheres.
template <class Arith>
KernelHit<typename Arith::Wide> closest_hit(const Arith& arith, const Vec3<typename Arith::Wide>& d,
                                            std::span<const KernelSphere<typename Arith::Coord>> spheres) {
  using Wide = typename Arith::Wide;
  const Wide a = dot(d, d);
  KernelHit<Wide> best;
  for (int i = 0; i < static_cast<int>(spheres.size()); ++i) {
    const auto& s = spheres[static_cast<std::size_t>(i)];
    const Vec3<Wide> c{Wide(s.center.x), Wide(s.center.y), Wide(s.center.z)};
    const Wide r = Wide(s.radius);
    const Wide b = Wide(2) * dot(d, c);
    const Wide c_prime = dot(c, c) - r * r;
    const Wide disc = b * b - Wide(4) * a * c_prime;
    if (disc < Wide(0)) continue;
    const Wide num = b - arith.sqrt(disc);
    if (!(num > Wide(0))) continue;  // the near intersection is behind the camera (or the camera is inside)
    if (best.index < 0 || num < best.num) best = {i, num};
  }
  return best;
}

// Normal-map colour of a hit (SPEC.md section B).
template <class Arith>
Rgb444 normal_colour(const Vec3<typename Arith::Wide>& d, const KernelSphere<typename Arith::Coord>& s,
                     typename Arith::Wide num) {
  using Wide = typename Arith::Wide;
  const Wide two_a = Wide(2) * dot(d, d);
  const Wide den = two_a * Wide(s.radius);
  int ch[3];
  for (int k = 0; k < 3; ++k) {
    const Wide n_num = num * d[k] - two_a * Wide(s.center[k]);  // n_k = n_num / den
    ch[k] = std::clamp(Arith::floor_div(Wide(7) * n_num + Wide(7) * den, den), 0, 14);
  }
  return Rgb444::from_channels(ch[0], ch[1], ch[2]);
}

template <class Arith>
Rgb444 normal_shade_pixel(const Arith& arith, const Vec3<typename Arith::Wide>& d,
                          std::span<const KernelSphere<typename Arith::Coord>> spheres, Rgb444 background) {
  const auto hit = closest_hit(arith, d, spheres);
  if (hit.index < 0) return background;
  return normal_colour<Arith>(d, spheres[static_cast<std::size_t>(hit.index)], hit.num);
}

}  // namespace tripsitter::core

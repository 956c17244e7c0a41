#include <tripsitter/scene/builtin.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace tripsitter::scene {
namespace {

Material lambertian(double r, double g, double b) { return {MaterialType::kLambertian, {r, g, b}, 0.0, 1.5}; }
Material metal(double r, double g, double b, double fuzz) { return {MaterialType::kMetal, {r, g, b}, fuzz, 1.5}; }
Material dielectric(double ior) { return {MaterialType::kDielectric, {1, 1, 1}, 0.0, ior}; }

// The board's demo: one sphere straight ahead. With 32 view units per world unit it is the sphere of
// SPEC.md section B: centre (0, 0, 400), radius 64 (2^6) pixel units.
Scene demo() {
  Scene s;
  s.name = "demo";
  s.camera.lookfrom = {0, 0, -10};
  s.camera.lookat = {0, 0, 0};
  s.camera.vfov = 73.739795291688;  // the device's vertical field of view: 2 atan(240 / 320)
  s.units_per_world = 32;
  s.spheres.push_back({{0, 0, 2.5}, 2.0, lambertian(0.8, 0.3, 0.3)});
  return s;
}

// Several overlapping spheres of different sizes and depths, some partly off screen.
Scene cluster() {
  Scene s;
  s.name = "cluster";
  s.camera.lookfrom = {0, 1, -12};
  s.camera.lookat = {0, 0, 0};
  s.camera.vfov = 73.739795291688;
  s.camera.focus_dist = 12;
  s.spheres = {
      {{0, 0, 0}, 2.0, lambertian(0.8, 0.3, 0.3)},
      {{2.2, 0.6, -1.5}, 1.2, metal(0.8, 0.8, 0.8, 0.0)},
      {{-2.4, -0.4, 1.0}, 1.6, dielectric(1.5)},
      {{-0.8, 1.8, -2.5}, 0.7, lambertian(0.2, 0.7, 0.3)},
      {{3.5, -1.8, 2.0}, 2.2, metal(0.9, 0.6, 0.2, 0.2)},
      {{-5.5, 2.5, 6.0}, 3.0, lambertian(0.3, 0.3, 0.8)},
      {{1.0, -1.6, -4.0}, 0.5, lambertian(0.9, 0.9, 0.2)},
      {{6.5, 3.0, 9.0}, 4.0, metal(0.7, 0.7, 0.9, 0.05)},
  };
  return s;
}

// Uniform double in [0, 1) from a 64-bit draw; unlike std::uniform_real_distribution, the same on every library.
double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// The classic cover image of sphere ray tracers: a huge ground sphere, a 22 x 22 grid of small spheres
// of mixed materials, and three large ones (glass, matte, metal). 488 spheres.
Scene field() {
  Scene s;
  s.name = "field";
  s.camera.lookfrom = {13, 2, 3};
  s.camera.lookat = {0, 0, 0};
  s.camera.vfov = 20;
  s.camera.defocus_angle = 0.6;
  s.camera.focus_dist = 10;
  s.render = {640, 360, 16, 50};
  s.spheres.push_back({{0, -1000, 0}, 1000, lambertian(0.5, 0.5, 0.5)});
  std::mt19937_64 rng(2023);
  for (int a = -11; a < 11; ++a) {
    for (int b = -11; b < 11; ++b) {
      const double choose = unit(rng);
      const Vec3d centre{a + 0.9 * unit(rng), 0.2, b + 0.9 * unit(rng)};
      Material m;
      if (choose < 0.8) {
        m = lambertian(unit(rng) * unit(rng), unit(rng) * unit(rng), unit(rng) * unit(rng));
      } else if (choose < 0.95) {
        m = metal(0.5 + 0.5 * unit(rng), 0.5 + 0.5 * unit(rng), 0.5 + 0.5 * unit(rng), 0.5 * unit(rng));
      } else {
        m = dielectric(1.5);
      }
      s.spheres.push_back({centre, 0.2, m});
    }
  }
  s.spheres.push_back({{0, 1, 0}, 1.0, dielectric(1.5)});
  s.spheres.push_back({{-4, 1, 0}, 1.0, lambertian(0.4, 0.2, 0.1)});
  s.spheres.push_back({{4, 1, 0}, 1.0, metal(0.7, 0.6, 0.5, 0.0)});
  return s;
}

}  // namespace

std::vector<std::string> builtin_names() { return {"demo", "cluster", "field"}; }

std::optional<Scene> builtin(std::string_view name) {
  if (name == "demo") return demo();
  if (name == "cluster") return cluster();
  if (name == "field") return field();
  // random-N: random_spheres(N, 1), N from 0 to kMaxSpheres.
  if (name.starts_with("random-") && name.size() > 7 && name.size() <= 15) {
    std::size_t n = 0;
    for (char c : name.substr(7)) {
      if (c < '0' || c > '9') return std::nullopt;
      n = n * 10 + static_cast<std::size_t>(c - '0');
    }
    if (n <= kMaxSpheres) return random_spheres(static_cast<int>(n), 1);
  }
  return std::nullopt;
}

Scene random_spheres(int count, std::uint32_t seed) {
  Scene s;
  s.name = "random-" + std::to_string(count);
  s.camera.lookfrom = {0, 0, -20};
  s.camera.lookat = {0, 0, 0};
  s.camera.vfov = 73.739795291688;
  s.camera.focus_dist = 20;
  std::mt19937_64 rng(seed);
  s.spheres.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    // Depth first, then a position inside the view frustum at that depth (half-widths 1 and 0.75 per unit depth).
    const double depth = 5 + 30 * unit(rng);
    const double x = (2 * unit(rng) - 1) * depth;
    const double y = (2 * unit(rng) - 1) * depth * 0.75;
    // Past 64 spheres they shrink with the cube root of the count, so a million still leave gaps.
    const double radius = (0.3 + 1.7 * unit(rng)) * std::min(1.0, std::cbrt(64.0 / std::max(count, 1)));
    const double kind = unit(rng);
    Material m;
    if (kind < 0.6) {
      m = lambertian(unit(rng), unit(rng), unit(rng));
    } else if (kind < 0.85) {
      m = metal(0.5 + 0.5 * unit(rng), 0.5 + 0.5 * unit(rng), 0.5 + 0.5 * unit(rng), 0.3 * unit(rng));
    } else {
      m = dielectric(1.5);
    }
    s.spheres.push_back({{x, y, depth - 20}, radius, m});
  }
  return s;
}

}  // namespace tripsitter::scene

#include <tripsitter/scene/builtin.h>

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

}  // namespace

std::vector<std::string> builtin_names() { return {"demo", "cluster"}; }

std::optional<Scene> builtin(std::string_view name) {
  if (name == "demo") return demo();
  if (name == "cluster") return cluster();
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
    const double radius = 0.3 + 1.7 * unit(rng);
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

// A scene as a user writes it: camera, render settings and spheres with materials, in world units
// (y up, right-handed). Loaded from JSON (scene_json.h) or built in (builtin.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <tripsitter/core/vec.h>

namespace tripsitter::scene {

using core::Vec3d;

enum class MaterialType : std::uint8_t { kLambertian = 0, kMetal = 1, kDielectric = 2 };

const char* material_name(MaterialType type);

struct Material {
  MaterialType type = MaterialType::kLambertian;
  Vec3d albedo{0.5, 0.5, 0.5};  // reflectance per channel, each in [0, 1]
  double fuzz = 0.0;            // metal only: radius of the random perturbation of the mirror direction, [0, 1]
  double ior = 1.5;             // dielectric only: index of refraction, > 0
};

struct Sphere {
  Vec3d center;
  double radius = 1.0;  // > 0
  Material material;
};

struct CameraSettings {
  Vec3d lookfrom{0, 0, -10};  // eye position
  Vec3d lookat{0, 0, 0};      // point the camera looks at (the orbit target)
  Vec3d vup{0, 1, 0};         // world up direction
  double vfov = 60;           // vertical field of view in degrees (float renderer; the device's is fixed, see docs/scene_format.md)
  double defocus_angle = 0;   // degrees of the thin-lens cone; 0 is a pinhole
  double focus_dist = 10;     // distance to the plane in perfect focus
};

struct RenderSettings {
  int width = 640;
  int height = 480;
  int spp = 1;         // samples per pixel
  int max_depth = 50;  // bounce cut-off
};

struct Scene {
  std::string name;
  CameraSettings camera;
  RenderSettings render;
  // Device view-space pixel units per world unit; 0 means derived: 320 / |lookat - lookfrom|, which
  // puts the look-at point on the device's image plane (z = 320).
  double units_per_world = 0;
  std::vector<Sphere> spheres;
};

// Limits enforced by every loader before memory is allocated.
inline constexpr int kMaxImageSide = 16384;
inline constexpr int kMaxSpp = 1 << 16;
inline constexpr int kMaxDepth = 1024;
inline constexpr std::size_t kMaxSpheres = 10'000'000;

}  // namespace tripsitter::scene

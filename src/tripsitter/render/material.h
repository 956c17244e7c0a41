// How light leaves a surface: the three materials of the report's section 7 (SPEC.md section C).
#pragma once

#include <algorithm>
#include <cmath>

#include <tripsitter/render/ray.h>
#include <tripsitter/render/rng.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::render {

struct PathMaterial {
  scene::MaterialType type = scene::MaterialType::kLambertian;
  Vec3f albedo{0.5f, 0.5f, 0.5f};
  float fuzz = 0;
  float ior = 1.5f;
};

struct SurfacePoint {
  Vec3f p;        // where the ray hit
  Vec3f normal;   // unit, facing against the incoming ray
  bool front_face = true;  // the ray came from outside the sphere
};

struct Scatter {
  bool scattered = false;  // false: the surface absorbed the ray
  Vec3f attenuation;
  Vec3f dir;
};

inline Vec3f reflect(const Vec3f& v, const Vec3f& n) { return v - n * (2 * core::dot(v, n)); }

// Snell's law for a unit incident direction; eta_ratio = eta_incident / eta_transmitted.
inline Vec3f refract(const Vec3f& unit_in, const Vec3f& n, float eta_ratio) {
  // std::min and std::max here and below: single instructions, where std::fmin and std::fmax are library calls (they
  // differ only for NaN, which finite rays do not make).
  const float cos_theta = std::min(-core::dot(unit_in, n), 1.0f);
  const Vec3f perpendicular = (unit_in + n * cos_theta) * eta_ratio;
  const Vec3f parallel = n * -std::sqrt(std::fabs(1.0f - core::dot(perpendicular, perpendicular)));
  return perpendicular + parallel;
}

// Schlick's approximation of the Fresnel reflectance.
inline float schlick(float cosine, float eta_ratio) {
  float r0 = (1 - eta_ratio) / (1 + eta_ratio);
  r0 = r0 * r0;
  const float m = 1 - cosine;
  return r0 + (1 - r0) * m * m * m * m * m;
}

// The surface's answer to a ray arriving along dir_in. `rng` is where its random numbers come from: an Rng, or one
// SquareSample (sampler.h) of which it takes one unit vector (lambertian, fuzzed metal) or one uniform (dielectric).
template <class Source>
inline Scatter scatter(const PathMaterial& m, const Vec3f& dir_in, const SurfacePoint& s, Source&& rng) {
  switch (m.type) {
    case scene::MaterialType::kLambertian: {
      // A cosine-weighted bounce: the normal plus a uniform unit vector.
      Vec3f d = s.normal + rng.unit_vector();
      if (core::dot(d, d) < 1e-12f) d = s.normal;
      return {true, m.albedo, d};
    }
    case scene::MaterialType::kMetal: {
      const Vec3f mirrored = reflect(core::normalize(dir_in), s.normal);
      const Vec3f d = m.fuzz > 0 ? mirrored + rng.unit_vector() * m.fuzz : mirrored;
      // Fuzz can push the ray below the surface: it is absorbed.
      return {core::dot(d, s.normal) > 0, m.albedo, d};
    }
    case scene::MaterialType::kDielectric: {
      // Matching indices make no interface: the exact Fresnel reflectance is 0 and the ray goes straight on.
      // (Schlick's approximation would still reflect a little at grazing angles.)
      if (m.ior == 1.0f) return {true, m.albedo, dir_in};
      const float eta = s.front_face ? 1.0f / m.ior : m.ior;
      const Vec3f unit_in = core::normalize(dir_in);
      const float cos_theta = std::min(-core::dot(unit_in, s.normal), 1.0f);
      const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
      const bool total_internal = eta * sin_theta > 1.0f;
      // One of reflect or refract per ray, with the Fresnel probability.
      const Vec3f d = total_internal || schlick(cos_theta, eta) > rng.uniform() ? reflect(unit_in, s.normal)
                                                                                  : refract(unit_in, s.normal, eta);
      return {true, m.albedo, d};
    }
  }
  return {};
}

}  // namespace tripsitter::render

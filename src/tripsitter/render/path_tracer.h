// The float path tracer (--mode path): materials, bounces, samples per pixel, thin-lens camera
// (SPEC.md section C). Deterministic: the same seed gives the same image whatever the thread count,
// because every pixel draws from its own random numbers (sampler.h) and sums its samples in a fixed order.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <tripsitter/core/image.h>
#include <tripsitter/render/aov.h>
#include <tripsitter/render/bvh.h>
#include <tripsitter/render/camera.h>
#include <tripsitter/render/material.h>
#include <tripsitter/render/sampler.h>
#include <tripsitter/scene/scene.h>

namespace tripsitter::render {

// Rays that leave the scene: white at the bottom to `top` at the top, blended by 0.5 (y + 1) of the
// unit direction. A uniform sky has bottom == top.
struct Sky {
  Vec3f bottom{1.0f, 1.0f, 1.0f};
  Vec3f top{0.5f, 0.7f, 1.0f};
  Vec3f radiance(const Vec3f& dir) const {
    const float a = 0.5f * (core::normalize(dir).y + 1.0f);
    return bottom * (1.0f - a) + top * a;
  }
};

// Spheres ready to trace: float arrays, materials and a BVH over them.
class PathScene {
 public:
  explicit PathScene(std::span<const scene::Sphere> spheres);
  std::size_t size() const { return radii_.size(); }
  const Bvh& bvh() const { return bvh_; }
  bool intersect(const Ray& ray, float t_min, float t_max, SphereHit& hit) const { return bvh_.intersect(ray, t_min, t_max, hit); }
  // The surface point of a hit, its normal facing the ray.
  SurfacePoint surface(const Ray& ray, const SphereHit& hit) const;
  const PathMaterial& material(std::uint32_t sphere) const { return materials_[sphere]; }
  const Vec3f& center(std::uint32_t sphere) const { return centers_[sphere]; }
  float radius(std::uint32_t sphere) const { return radii_[sphere]; }
  std::span<const Vec3f> centers() const { return centers_; }
  std::span<const float> radii() const { return radii_; }

 private:
  std::vector<Vec3f> centers_;
  std::vector<float> radii_;
  std::vector<PathMaterial> materials_;
  Bvh bvh_;
};

struct PathSettings {
  int width = 640;
  int height = 480;
  int spp = 1;
  int max_depth = 50;     // rays followed per path; a path still bouncing after that contributes black
  std::uint64_t seed = 1;
  int threads = 0;        // 0: all hardware threads
  Sky sky;
  SamplerKind sampler = SamplerKind::kSobol;  // where the random numbers come from (sampler.h)
  // The index of each pixel's first sample in its sequence: the render takes samples first_sample to
  // first_sample + spp - 1, so that passes of one sample each (first_sample 0, 1, 2, ... with one seed) continue
  // one sequence. kSobol: a sample depends only on (seed, pixel, index), so such passes add up to the render of
  // many, bit for bit. kIndependent: first_sample 0 draws all spp samples from the pixel's stream of `seed`, one
  // after the other; first_sample k > 0 does the same from the pixel's stream of seed + k (what a pass of one
  // sample with seed + k gives).
  std::uint32_t first_sample = 0;

  // Samples in one row of the image: width * spp.
  std::uint64_t row_samples() const {
    return static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(spp);
  }
};

// Nearest hit distance a ray accepts, so that a bounced ray does not hit the surface it leaves (world
// units: bounced rays have unit directions).
inline constexpr float kRayEpsilon = 1e-3f;

// Radiance along one ray, the bounces drawing from `rng` (kIndependent).
Vec3f trace_path(const PathScene& scene, Ray ray, int max_depth, const Sky& sky, Rng& rng);
// The same under kSobol, for sample `index` of the pixel with key `pixel_key` (SobolSampler::pixel_key): bounce d
// takes the point SobolSampler::sample(pixel_key, index, bounce_pair(d)) while d <= kSobolBounces, then draws
// from `rng` (SobolSampler::stream(pixel, index)).
Vec3f trace_path(const PathScene& scene, Ray ray, int max_depth, const Sky& sky, std::uint32_t pixel_key,
                 std::uint32_t index, Rng& rng);

// Renders the image. `on_samples(n)` is called, from worker threads, as rows of n samples complete. With `aovs`,
// also fills *aovs (aov.h: the first hits of the camera rays, means over the same samples; resized to width x
// height); the image is the same bytes either way.
core::ImageRgbF render_path(const PathScene& scene, const ThinLensCamera& camera, const PathSettings& settings,
                            const std::function<void(std::uint64_t)>& on_samples = {}, Aovs* aovs = nullptr);

// Renders only rows first, first + step, first + 2 step, ... of the image into `image` (sized width x height;
// other rows are left as they are). Every pixel gets exactly the value render_path gives it, whatever the
// split: a job can share an image's rows among processes. `on_row(row)` is called, from the worker thread
// that traced it, as each row is written (width x spp samples). With `aovs` (sized width x height by the caller),
// the same rows of *aovs are written too. REQUIRES 0 <= first, step >= 1.
void render_path_rows(const PathScene& scene, const ThinLensCamera& camera, const PathSettings& settings, int first,
                      int step, core::ImageRgbF& image, const std::function<void(int)>& on_row = {},
                      Aovs* aovs = nullptr);

// A closest-hit query in place of the scene's BVH, with Bvh::intersect's contract, so that other tracers can be
// measured on exactly the path tracer's work (`tripsitter bench` runs it over Embree and over brute force).
class HitQuery {
 public:
  virtual ~HitQuery() = default;
  virtual bool intersect(const Ray& ray, float t_min, float t_max, SphereHit& hit) const = 0;
};

// Every sphere tested for every ray: the straightforward tracer.
class BruteForceQuery final : public HitQuery {
 public:
  explicit BruteForceQuery(const PathScene& scene) : scene_(scene) {}
  bool intersect(const Ray& ray, float t_min, float t_max, SphereHit& hit) const override;

 private:
  const PathScene& scene_;
};

// render_path with `query` finding the hits (one virtual call per ray).
core::ImageRgbF render_path(const PathScene& scene, const HitQuery& query, const ThinLensCamera& camera,
                            const PathSettings& settings);

}  // namespace tripsitter::render

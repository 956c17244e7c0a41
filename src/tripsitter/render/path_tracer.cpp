#include <tripsitter/render/path_tracer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include <tripsitter/core/parallel.h>

namespace tripsitter::render {
namespace {

using core::hadamard;

Vec3f to_f(const core::Vec3d& v) { return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)}; }

std::vector<Vec3f> centers_of(std::span<const scene::Sphere> spheres) {
  std::vector<Vec3f> c;
  c.reserve(spheres.size());
  for (const auto& s : spheres) c.push_back(to_f(s.center));
  return c;
}

std::vector<float> radii_of(std::span<const scene::Sphere> spheres) {
  std::vector<float> r;
  r.reserve(spheres.size());
  for (const auto& s : spheres) r.push_back(static_cast<float>(s.radius));
  return r;
}

}  // namespace

PathScene::PathScene(std::span<const scene::Sphere> spheres)
    : centers_(centers_of(spheres)), radii_(radii_of(spheres)), bvh_(Bvh::build(centers_, radii_)) {
  materials_.reserve(spheres.size());
  for (const auto& s : spheres)
    materials_.push_back({s.material.type, to_f(s.material.albedo), static_cast<float>(s.material.fuzz),
                          static_cast<float>(s.material.ior)});
}

SurfacePoint PathScene::surface(const Ray& ray, const SphereHit& hit) const {
  SurfacePoint s;
  s.p = ray.at(hit.t);
  // p - centre is the outward normal times the radius: its sign against the ray tells the side, so one reciprocal,
  // negated for a ray from inside, scales it to the unit normal facing the ray.
  const Vec3f radial = s.p - centers_[hit.sphere];
  s.front_face = core::dot(ray.dir, radial) < 0;
  const float inv_radius = 1.0f / radii_[hit.sphere];
  s.normal = radial * (s.front_face ? inv_radius : -inv_radius);
  return s;
}

namespace {

// One bounce of a path at its hit on `sphere`, at surface point `s`: the path ends there (false) when the surface
// absorbs the ray or `depth` rays, max_depth of them, have been followed; otherwise the throughput takes the
// surface's attenuation and `ray` becomes the bounced ray. `source`: the bounce's random numbers, as scatter's.
template <class Source>
inline bool bounce(const PathScene& scene, const SurfacePoint& s, std::uint32_t sphere, int depth, int max_depth,
                   Ray& ray, Vec3f& throughput, Source&& source) {
  const Scatter sc = scatter(scene.material(sphere), ray.dir, s, source);
  if (!sc.scattered || depth == max_depth) return false;
  throughput = hadamard(throughput, sc.attenuation);
  // Unit directions keep kRayEpsilon a distance in world units, whatever length the scatter produced.
  ray = {s.p, core::normalize(sc.dir)};
  return true;
}

// The path tracer over any closest-hit query with Bvh::intersect's contract: the scene's own BVH, called directly,
// or a HitQuery. `with_source(depth, f)` calls f with the random numbers of bounce `depth` and returns its result.
template <class Query, class WithSource>
Vec3f trace_path_over(const PathScene& scene, const Query& query, Ray ray, int max_depth, const Sky& sky,
                      WithSource&& with_source) {
  Vec3f throughput{1, 1, 1};
  for (int depth = 1;; ++depth) {
    SphereHit hit;
    if (!query.intersect(ray, kRayEpsilon, INFINITY, hit)) return hadamard(throughput, sky.radiance(ray.dir));
    const SurfacePoint s = scene.surface(ray, hit);
    const bool on = with_source(depth, [&](auto&& source) {
      return bounce(scene, s, hit.sphere, depth, max_depth, ray, throughput, source);
    });
    if (!on) return {0, 0, 0};
  }
}

// Pixels go in groups of a row's kGroup neighbours. Their camera rays travel together, so the BVH walks the tree
// once for all of them (Bvh::intersect_packet); then their paths advance in lockstep, one bounce each per round,
// and the round's bounced rays go to the BVH together too while most of the group's paths are alive: they start
// near each other, so their walks share most nodes and leaves, and one packet walk costs less than their separate
// walks. Fewer live paths go one at a time.
constexpr int kGroup = Bvh::kWidth;

// The hits of the rays of the live lanes, one ray at a time.
template <class Query>
unsigned hits_one_by_one(const Query& query, unsigned live, const Ray (&rays)[kGroup], SphereHit (&hits)[kGroup]) {
  unsigned found = 0;
  for (; live != 0; live &= live - 1) {
    const int i = std::countr_zero(live);
    found |= query.intersect(rays[i], kRayEpsilon, INFINITY, hits[i]) ? 1u << i : 0u;
  }
  return found;
}

// The hits of the bounced rays of the live lanes: a packet for the BVH while Bvh::kMinPacket lanes live, else ray by
// ray (Bvh::intersect_live).
unsigned next_hits(const Bvh& bvh, unsigned live, const Ray (&rays)[kGroup], SphereHit (&hits)[kGroup]) {
  return bvh.intersect_live(live, rays, kRayEpsilon, INFINITY, hits);
}

unsigned next_hits(const HitQuery& query, unsigned live, const Ray (&rays)[kGroup], SphereHit (&hits)[kGroup]) {
  return hits_one_by_one(query, live, rays, hits);
}

// The hits of the camera rays of a group's lanes in `used`: one packet of all kGroup lanes for the BVH
// (Bvh::intersect_packet; lanes past `used` hold copies of a used lane's ray), ray by ray for a HitQuery.
unsigned first_hits(const Bvh& bvh, unsigned used, const Ray (&rays)[kGroup], SphereHit (&hits)[kGroup]) {
  return bvh.intersect_packet(rays, kRayEpsilon, INFINITY, hits) & used;
}

unsigned first_hits(const HitQuery& query, unsigned used, const Ray (&rays)[kGroup], SphereHit (&hits)[kGroup]) {
  return hits_one_by_one(query, used, rays, hits);
}

// The random numbers of a group's pixels under each sampler: every pixel draws them in the order it would alone
// (trace_path), so the image is the same as tracing pixel by pixel. start_sample(s, camera) begins sample s,
// camera_ray(camera, lane, col, row) gives a lane's camera ray (lanes in order), start_round(depth) begins the
// round of bounce `depth`, and with_source(lane, f) calls f with the lane's random numbers for that bounce.
template <SamplerKind kKind>
class GroupSamples;

// Rngs for the group's lanes: stream(lane).
template <class Stream, std::size_t... I>
std::array<Rng, kGroup> lane_streams(const Stream& stream, std::index_sequence<I...>) {
  return {stream(I)...};
}

// kIndependent: each pixel's stream, camera ray then bounces, one sample after the other.
template <>
class GroupSamples<SamplerKind::kIndependent> {
 public:
  struct Job {
    RngStreams streams;
    explicit Job(const PathSettings& s) : streams(s.seed + s.first_sample) {}
  };
  GroupSamples(const Job& job, std::uint64_t first_pixel)
      : rng_(lane_streams([&](std::size_t lane) { return job.streams.stream(first_pixel + lane); },
                          std::make_index_sequence<kGroup>())) {}

  void start_sample(int /*sample*/, const ThinLensCamera& /*camera*/) {}
  Ray camera_ray(const ThinLensCamera& camera, int lane, int col, int row) { return camera.ray(col, row, rng_[lane]); }
  void start_round(int /*depth*/) {}
  template <class F>
  bool with_source(int lane, F&& f) {
    return f(rng_[lane]);
  }

 private:
  std::array<Rng, kGroup> rng_;
};

// kSobol: the pairs of a sample for all lanes at once (sobol::samples8), the camera's when a sample starts and a
// bounce's when a round starts; past kSobolBounces the sample's stream of each pixel. (Computing all of a sample's
// pairs when it starts, so that their independent computations overlap, was no faster.)
template <>
class GroupSamples<SamplerKind::kSobol> {
 public:
  struct Job {
    SobolSampler sampler;
    std::uint32_t first_sample;
    explicit Job(const PathSettings& s) : sampler(s.seed), first_sample(s.first_sample) {}
  };
  GroupSamples(const Job& job, std::uint64_t first_pixel)
      : job_(job), first_pixel_(first_pixel), rng_index_(job.first_sample), rng_(streams(rng_index_)) {
    for (int i = 0; i < kGroup; ++i) keys_[i] = job.sampler.pixel_key(first_pixel + static_cast<std::uint64_t>(i));
  }

  void start_sample(int sample, const ThinLensCamera& camera) {
    index_ = job_.first_sample + static_cast<std::uint32_t>(sample);
    sobol::samples8(keys_, index_, kPixelPair, jitter_);
    if (camera.defocus()) sobol::samples8(keys_, index_, kLensPair, lens_);
  }
  Ray camera_ray(const ThinLensCamera& camera, int lane, int col, int row) {
    return camera.ray(col, row, jitter_[lane], lens_[lane]);
  }
  void start_round(int depth) {
    low_discrepancy_ = depth <= kSobolBounces;
    if (low_discrepancy_) {
      sobol::samples8(keys_, index_, bounce_pair(depth), bounce_);
    } else if (rng_index_ != index_) {  // the sample's streams, made when a path first needs them
      rng_ = streams(index_);
      rng_index_ = index_;
    }
  }
  template <class F>
  bool with_source(int lane, F&& f) {
    return low_discrepancy_ ? f(bounce_[lane]) : f(rng_[lane]);
  }

 private:
  std::array<Rng, kGroup> streams(std::uint32_t index) const {
    return lane_streams([&](std::size_t lane) { return job_.sampler.stream(first_pixel_ + lane, index); },
                        std::make_index_sequence<kGroup>());
  }

  const Job& job_;
  std::uint64_t first_pixel_;
  std::uint32_t index_ = 0;
  std::uint32_t rng_index_;  // the sample whose streams rng_ holds
  std::array<Rng, kGroup> rng_;
  std::uint32_t keys_[kGroup];
  sobol::Samples8 jitter_;
  sobol::Samples8 lens_{};  // zero without defocus
  sobol::Samples8 bounce_;  // the round's
  bool low_discrepancy_ = false;  // the round's bounce takes bounce_
};

// The first hits of one pixel's camera rays, summed over its samples (aov.h).
struct AovSums {
  Vec3f albedo{0, 0, 0};
  Vec3f normal{0, 0, 0};
  float depth = 0;
  int hits = 0;
};

// kAovs: *aovs is written (a template parameter, so that renders without it pay nothing for it).
template <SamplerKind kKind, bool kAovs, class Query>
void render_rows_over(const PathScene& scene, const Query& query, const ThinLensCamera& camera,
                      const PathSettings& settings, int first, int step, core::ImageRgbF& image,
                      const std::function<void(int)>& on_row, Aovs* aovs) {
  const int rows = first < settings.height ? (settings.height - first + step - 1) / step : 0;
  const float inv_spp = 1.0f / static_cast<float>(settings.spp);
  const typename GroupSamples<kKind>::Job job(settings);
  core::parallel_for(0, rows, settings.threads, [&](int k) {
    const int row = first + k * step;
    // Settings copied to locals: through the captured reference the compiler reloads them after every call.
    const int width = settings.width, spp = settings.spp, max_depth = settings.max_depth;
    const Sky sky = settings.sky;
    const std::uint64_t row_start = static_cast<std::uint64_t>(row) * static_cast<std::uint64_t>(width);
    Vec3f* const pixels = image.pixels.data() + row_start;
    for (int col0 = 0; col0 < width; col0 += kGroup) {
      // Lanes past the row's end hold a copy of the first lane's camera ray, for the BVH's packet, and are dropped.
      const int used = std::min(kGroup, width - col0);
      const unsigned used_lanes = (1u << used) - 1;
      GroupSamples<kKind> samples(job, row_start + static_cast<std::uint64_t>(col0));
      Vec3f sum[kGroup] = {};
      AovSums aov[kGroup];
      for (int s = 0; s < spp; ++s) {
        samples.start_sample(s, camera);
        Ray ray[kGroup];
        for (int i = 0; i < kGroup; ++i) ray[i] = i < used ? samples.camera_ray(camera, i, col0 + i, row) : ray[0];
        SphereHit hit[kGroup];
        unsigned found = first_hits(query, used_lanes, ray, hit);  // bit i: ray[i] hits, at hit[i]
        Vec3f throughput[kGroup];
        for (Vec3f& t : throughput) t = {1, 1, 1};
        unsigned alive = used_lanes;
        for (int depth = 1; alive != 0; ++depth) {
          samples.start_round(depth);
          const bool first_hit_aovs = kAovs && depth == 1;
          for (unsigned live = alive; live != 0; live &= live - 1) {
            const int i = std::countr_zero(live);
            if (!(found >> i & 1)) {
              sum[i] += hadamard(throughput[i], sky.radiance(ray[i].dir));
              if (first_hit_aovs) aov[i].albedo += Vec3f{1, 1, 1};
              alive &= ~(1u << i);
              continue;
            }
            const SurfacePoint sp = scene.surface(ray[i], hit[i]);
            if (first_hit_aovs) {
              aov[i].albedo += scene.material(hit[i].sphere).albedo;
              aov[i].normal += sp.normal;
              aov[i].depth += hit[i].t * core::length(ray[i].dir);
              ++aov[i].hits;
            }
            const bool on = samples.with_source(i, [&](auto&& source) {
              return bounce(scene, sp, hit[i].sphere, depth, max_depth, ray[i], throughput[i], source);
            });
            if (!on) alive &= ~(1u << i);
          }
          found = next_hits(query, alive, ray, hit);
        }
      }
      for (int i = 0; i < used; ++i) pixels[col0 + i] = sum[i] * inv_spp;
      if constexpr (kAovs) {
        for (int i = 0; i < used; ++i) {
          const std::size_t p = static_cast<std::size_t>(row_start) + static_cast<std::size_t>(col0 + i);
          aovs->albedo[p] = aov[i].albedo * inv_spp;
          aovs->normal[p] = aov[i].normal * inv_spp;
          aovs->depth[p] = aov[i].hits > 0 ? aov[i].depth / static_cast<float>(aov[i].hits) : INFINITY;
        }
      }
    }
    if (on_row) on_row(row);
  });
}

template <SamplerKind kKind, class Query>
void render_rows_of(const PathScene& scene, const Query& query, const ThinLensCamera& camera,
                    const PathSettings& settings, int first, int step, core::ImageRgbF& image,
                    const std::function<void(int)>& on_row, Aovs* aovs) {
  if (aovs != nullptr) {
    render_rows_over<kKind, true>(scene, query, camera, settings, first, step, image, on_row, aovs);
  } else {
    render_rows_over<kKind, false>(scene, query, camera, settings, first, step, image, on_row, aovs);
  }
}

template <class Query>
void render_rows(const PathScene& scene, const Query& query, const ThinLensCamera& camera,
                 const PathSettings& settings, int first, int step, core::ImageRgbF& image,
                 const std::function<void(int)>& on_row, Aovs* aovs) {
  switch (settings.sampler) {
    case SamplerKind::kSobol:
      return render_rows_of<SamplerKind::kSobol>(scene, query, camera, settings, first, step, image, on_row, aovs);
    case SamplerKind::kIndependent:
      return render_rows_of<SamplerKind::kIndependent>(scene, query, camera, settings, first, step, image, on_row,
                                                       aovs);
  }
}

// Sizes `aovs` to width x height, keeping its buffers (every pixel is written) when they already are.
void fit(Aovs& aovs, int width, int height) {
  const std::size_t n = Aovs::pixels(width, height);
  if (aovs.width != width || aovs.height != height || aovs.albedo.size() != n || aovs.normal.size() != n ||
      aovs.depth.size() != n)
    aovs = Aovs(width, height);
}

core::ImageRgbF blank_image(const PathSettings& settings) {
  return {settings.width, settings.height,
          std::vector<Vec3f>(static_cast<std::size_t>(settings.width) * static_cast<std::size_t>(settings.height))};
}

}  // namespace

Vec3f trace_path(const PathScene& scene, Ray ray, int max_depth, const Sky& sky, Rng& rng) {
  return trace_path_over(scene, scene.bvh(), ray, max_depth, sky, [&](int, auto&& f) { return f(rng); });
}

Vec3f trace_path(const PathScene& scene, Ray ray, int max_depth, const Sky& sky, std::uint32_t pixel_key,
                 std::uint32_t index, Rng& rng) {
  return trace_path_over(scene, scene.bvh(), ray, max_depth, sky, [&](int depth, auto&& f) {
    return depth <= kSobolBounces ? f(SobolSampler::sample(pixel_key, index, bounce_pair(depth))) : f(rng);
  });
}

void render_path_rows(const PathScene& scene, const ThinLensCamera& camera, const PathSettings& settings, int first,
                      int step, core::ImageRgbF& image, const std::function<void(int)>& on_row, Aovs* aovs) {
  render_rows(scene, scene.bvh(), camera, settings, first, step, image, on_row, aovs);
}

core::ImageRgbF render_path(const PathScene& scene, const ThinLensCamera& camera, const PathSettings& settings,
                            const std::function<void(std::uint64_t)>& on_samples, Aovs* aovs) {
  core::ImageRgbF image = blank_image(settings);
  if (aovs != nullptr) fit(*aovs, settings.width, settings.height);
  render_rows(
      scene, scene.bvh(), camera, settings, 0, 1, image,
      [&](int) {
        if (on_samples) on_samples(settings.row_samples());
      },
      aovs);
  return image;
}

core::ImageRgbF render_path(const PathScene& scene, const HitQuery& query, const ThinLensCamera& camera,
                            const PathSettings& settings) {
  core::ImageRgbF image = blank_image(settings);
  render_rows(scene, query, camera, settings, 0, 1, image, {}, nullptr);
  return image;
}

bool BruteForceQuery::intersect(const Ray& ray, float t_min, float t_max, SphereHit& hit) const {
  return intersect_brute_force(scene_.centers(), scene_.radii(), ray, t_min, t_max, hit);
}

}  // namespace tripsitter::render

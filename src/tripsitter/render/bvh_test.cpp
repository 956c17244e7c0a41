// Tests of the float ray-sphere kernel against a double reference, and of the BVH against brute force.
#include <tripsitter/render/bvh.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include <tripsitter/core/sanitizers.h>
#include <tripsitter/render/test_util.h>

namespace tripsitter::render {
namespace {

using core::Vec3d;
using testing::kInf;
using testing::uniform;
using testing::uniform_in_box;

constexpr double kFloatEps = 0x1p-24;  // unit roundoff of float

Vec3d to_double(const Vec3f& v) { return {v.x, v.y, v.z}; }

float log_uniform(std::mt19937& rng, float lo, float hi) {
  return std::exp(uniform(rng, std::log(lo), std::log(hi)));
}
Vec3f random_unit(std::mt19937& rng) {
  std::normal_distribution<float> n;
  for (;;) {
    const Vec3f v{n(rng), n(rng), n(rng)};
    const float len = length(v);
    if (len > 1e-3f) return v / len;
  }
}

// Both roots of ray and sphere in double from the exact float inputs, and how far the line passes from the
// surface (|r - |f||: near zero means a grazing ray, whose hit or miss float cannot decide).
struct Reference {
  bool hits = false;
  double t_near = 0, t_far = 0;
  double graze = 0;
  double condition = 1;  // 1 + |f| / half chord: how much an error in f moves the roots (large when grazing)
};

Reference reference(const Ray& ray, const Vec3f& center, float radius) {
  const Vec3d o = to_double(ray.origin), d = to_double(ray.dir), c = to_double(center);
  const double r = radius;
  const Vec3d oc = o - c;
  const double a = dot(d, d), b = dot(oc, d);
  const Vec3d f = oc - d * (b / a);
  const double f_len = length(f);
  Reference ref;
  ref.graze = std::abs(r - f_len);
  const double disc = a * (r - f_len) * (r + f_len);
  if (disc < 0) return ref;
  const double q = -(b + std::copysign(std::sqrt(disc), b));
  const double t0 = q / a, t1 = dot(oc, oc) - r * r == 0 ? 0 : (dot(oc, oc) - r * r) / q;
  ref.hits = true;
  ref.condition = 1 + f_len / std::sqrt((r - f_len) * (r + f_len));
  ref.t_near = std::min(t0, t1);
  ref.t_far = std::max(t0, t1);
  return ref;
}

// The float kernel's error budget: 1e-4 relative, plus a few float ulps of |origin - center| + r in units of |dir|,
// amplified by the root's condition number (1 / sine of the incidence angle, roughly). The second term comes from
// rounding origin - center itself, which no float formulation avoids; it only matters for an origin much closer to
// a huge sphere's surface than the sphere's size, or for shallow rays there.
double tolerance(const Ray& ray, const Vec3f& center, float radius, const Reference& ref, double t) {
  const double scale = (length(to_double(ray.origin) - to_double(center)) + radius) / length(to_double(ray.dir));
  return 1e-4 * std::abs(t) + 8 * kFloatEps * scale * ref.condition;
}

// A family of rays and spheres for the kernel test.
struct KernelCase {
  Ray ray;
  Vec3f center;
  float radius;
  float t_min, t_max;
};

// Checks intersect_sphere on one family; returns how many cases were decidable (not grazing, roots not at the
// interval's ends) so that each family can insist on being mostly decidable.
int check_kernel(const std::vector<KernelCase>& cases, const char* family) {
  int decidable = 0, hits = 0;
  for (const KernelCase& k : cases) {
    const Reference ref = reference(k.ray, k.center, k.radius);
    const double scale = length(to_double(k.ray.origin) - to_double(k.center)) + k.radius;
    if (ref.graze < 1e-3 * k.radius + 8 * kFloatEps * scale) continue;
    // The reference's choice, skipped when a root sits within tolerance of t_min or t_max.
    bool near_boundary = false;
    for (double root : {ref.t_near, ref.t_far}) {
      const double tol = tolerance(k.ray, k.center, k.radius, ref, root);
      if (ref.hits && (std::abs(root - k.t_min) < tol || std::abs(root - k.t_max) < tol)) near_boundary = true;
    }
    if (near_boundary) continue;
    ++decidable;
    bool want = false;
    double want_t = 0;
    if (ref.hits && ref.t_near > k.t_min && ref.t_near < k.t_max) {
      want = true;
      want_t = ref.t_near;
    } else if (ref.hits && ref.t_far > k.t_min && ref.t_far < k.t_max) {
      want = true;
      want_t = ref.t_far;
    }
    float t = -1;
    const bool got = intersect_sphere(k.ray, k.center, k.radius, k.t_min, k.t_max, t);
    EXPECT_EQ(got, want) << family << ": origin " << k.ray.origin.x << "," << k.ray.origin.y << ","
                         << k.ray.origin.z << " radius " << k.radius;
    if (got && want) {
      ++hits;
      EXPECT_NEAR(t, want_t, tolerance(k.ray, k.center, k.radius, ref, want_t)) << family;
    }
  }
  EXPECT_GT(decidable, static_cast<int>(cases.size()) * 8 / 10) << family;
  EXPECT_GT(hits, static_cast<int>(cases.size()) / 5) << family;
  return decidable;
}

TEST(IntersectSphere, SmallScenesMatchDoubleReference) {
  std::mt19937 rng(1);
  std::vector<KernelCase> cases;
  for (int i = 0; i < 20000; ++i) {
    KernelCase k;
    k.center = uniform_in_box(rng, -10, 10);
    k.radius = log_uniform(rng, 0.05f, 5.0f);
    k.ray.origin = uniform_in_box(rng, -20, 20);
    // Aim near the sphere so that about half the rays hit; scale the direction away from unit length.
    const Vec3f target = k.center + random_unit(rng) * (k.radius * uniform(rng, 0, 1.5f));
    k.ray.dir = normalize(target - k.ray.origin) * log_uniform(rng, 0.01f, 100.0f);
    k.t_min = 0;
    k.t_max = kInf;
    cases.push_back(k);
  }
  check_kernel(cases, "small");
}

TEST(IntersectSphere, GroundSphereOfRadius1000MatchesDoubleReference) {
  std::mt19937 rng(2);
  std::vector<KernelCase> cases;
  for (int i = 0; i < 20000; ++i) {
    KernelCase k;
    k.center = {0, -1000, 0};
    k.radius = 1000;
    // From just above the ground to ~1000 away, as a camera over the cover scene or a view of the whole globe.
    const float height = log_uniform(rng, 0.5f, 2000.0f);
    k.ray.origin = {uniform(rng, -50, 50), height, uniform(rng, -50, 50)};
    k.ray.dir = random_unit(rng) * uniform(rng, 0.5f, 2.0f);
    k.t_min = 1e-3f;
    k.t_max = kInf;
    cases.push_back(k);
  }
  check_kernel(cases, "ground 1e3");
}

TEST(IntersectSphere, HugeSphereOfRadius1e6MatchesDoubleReference) {
  std::mt19937 rng(3);
  std::vector<KernelCase> cases;
  for (int i = 0; i < 20000; ++i) {
    KernelCase k;
    k.center = {0, -1e6f, 0};
    k.radius = 1e6f;
    const float height = log_uniform(rng, 1.0f, 3e6f);
    k.ray.origin = {uniform(rng, -1000, 1000), height, uniform(rng, -1000, 1000)};
    k.ray.dir = random_unit(rng);
    k.t_min = 1e-3f;
    k.t_max = kInf;
    cases.push_back(k);
  }
  check_kernel(cases, "ground 1e6");
}

TEST(IntersectSphere, FarSpheresMatchDoubleReference) {
  // The textbook b^2 - 4ac loses every digit here: both terms are ~|oc|^4 while their difference is ~|oc|^2 r^2.
  std::mt19937 rng(4);
  std::vector<KernelCase> cases;
  for (int i = 0; i < 20000; ++i) {
    KernelCase k;
    k.center = random_unit(rng) * log_uniform(rng, 1e3f, 1e6f);
    k.radius = log_uniform(rng, 0.5f, 100.0f);
    k.ray.origin = uniform_in_box(rng, -10, 10);
    const Vec3f target = k.center + random_unit(rng) * (k.radius * uniform(rng, 0, 1.5f));
    k.ray.dir = normalize(target - k.ray.origin);
    k.t_min = 1e-3f;
    k.t_max = kInf;
    cases.push_back(k);
  }
  check_kernel(cases, "far");
}

TEST(IntersectSphere, FromInsideReturnsTheFarRoot) {
  std::mt19937 rng(5);
  for (int i = 0; i < 5000; ++i) {
    const Vec3f center = uniform_in_box(rng, -100, 100);
    const float radius = log_uniform(rng, 0.01f, 1e4f);
    const Ray ray{center + random_unit(rng) * (radius * uniform(rng, 0, 0.9f)), random_unit(rng) * 3.0f};
    const Reference ref = reference(ray, center, radius);
    ASSERT_TRUE(ref.hits);
    ASSERT_LT(ref.t_near, 0);
    float t = 0;
    ASSERT_TRUE(intersect_sphere(ray, center, radius, 0, kInf, t));
    EXPECT_NEAR(t, ref.t_far, tolerance(ray, center, radius, ref, ref.t_far));
  }
}

TEST(IntersectSphere, RespectsOpenInterval) {
  const Ray ray{{0, 0, -10}, {0, 0, 2}};  // meets the unit sphere at z = -1 and 1: t = 4.5 and 5.5
  const Vec3f center{0, 0, 0};
  float t = 0;
  ASSERT_TRUE(intersect_sphere(ray, center, 1, 0, kInf, t));
  EXPECT_FLOAT_EQ(t, 4.5f);
  ASSERT_TRUE(intersect_sphere(ray, center, 1, 5, kInf, t));
  EXPECT_FLOAT_EQ(t, 5.5f);
  EXPECT_FALSE(intersect_sphere(ray, center, 1, 6, kInf, t));
  EXPECT_FALSE(intersect_sphere(ray, center, 1, 0, 4, t));
  ASSERT_TRUE(intersect_sphere(ray, center, 1, 0, 5, t));
  EXPECT_FLOAT_EQ(t, 4.5f);
  // The ends are excluded: a root equal to t_min or t_max is not returned.
  EXPECT_FALSE(intersect_sphere(ray, center, 1, 0, 4.5f, t));
  ASSERT_TRUE(intersect_sphere(ray, center, 1, 4.5f, kInf, t));
  EXPECT_FLOAT_EQ(t, 5.5f);
  EXPECT_FALSE(intersect_sphere(ray, center, 1, 5.5f, kInf, t));
  // Behind the origin.
  EXPECT_FALSE(intersect_sphere({{0, 0, 10}, {0, 0, 1}}, center, 1, 0, kInf, t));
}

TEST(IntersectSphere, ZeroDirectionNeverHits) {
  float t = 0;
  EXPECT_FALSE(intersect_sphere({{0, 0, 0}, {0, 0, 0}}, {0, 0, 0}, 1, 0, kInf, t));
  EXPECT_FALSE(intersect_sphere({{0, 0, -5}, {0, 0, 0}}, {0, 0, 0}, 1, -kInf, kInf, t));
}

TEST(BruteForce, ClosestHitAndTiesToLowerIndex) {
  const std::vector<Vec3f> centers{{0, 0, 10}, {0, 0, 5}, {0, 0, 5}, {0, 0, 20}};
  const std::vector<float> radii{1, 1, 1, 1};
  SphereHit hit;
  ASSERT_TRUE(intersect_brute_force(centers, radii, {{0, 0, 0}, {0, 0, 1}}, 0, kInf, hit));
  EXPECT_EQ(hit.sphere, 1u);
  EXPECT_FLOAT_EQ(hit.t, 4);
  ASSERT_TRUE(intersect_brute_force(centers, radii, {{0, 0, 0}, {0, 0, 1}}, 7, kInf, hit));
  EXPECT_EQ(hit.sphere, 0u);
  EXPECT_FALSE(intersect_brute_force(centers, radii, {{0, 0, 0}, {0, 0, -1}}, 0, kInf, hit));
  EXPECT_FALSE(intersect_brute_force({}, {}, {{0, 0, 0}, {0, 0, 1}}, 0, kInf, hit));
}

// ---------------------------------------------------------------------------------------------------------------
// BVH against brute force.

struct Scene {
  std::vector<Vec3f> centers;
  std::vector<float> radii;
};

// A random ray for a scene spanning about [-extent, extent]^3: from outside or inside the scene, from inside a
// sphere, with some direction components exactly +0 or -0, and with varied t_min and t_max.
struct Query {
  Ray ray;
  float t_min, t_max;
};

Query random_query(std::mt19937& rng, const Scene& scene, float extent) {
  Query q;
  const int kind = std::uniform_int_distribution<int>(0, 9)(rng);
  if (kind < 3 && !scene.centers.empty()) {
    // From inside (or on) a sphere.
    const auto i = std::uniform_int_distribution<std::size_t>(0, scene.centers.size() - 1)(rng);
    q.ray.origin = scene.centers[i] + random_unit(rng) * (scene.radii[i] * uniform(rng, 0, 1));
  } else {
    q.ray.origin = uniform_in_box(rng, -2 * extent, 2 * extent);
  }
  if (kind >= 3 && kind < 6 && !scene.centers.empty()) {
    // Aimed at a sphere, so that most rays hit something.
    const auto i = std::uniform_int_distribution<std::size_t>(0, scene.centers.size() - 1)(rng);
    q.ray.dir = scene.centers[i] + random_unit(rng) * scene.radii[i] - q.ray.origin;
    if (dot(q.ray.dir, q.ray.dir) == 0) q.ray.dir = random_unit(rng);
  } else {
    q.ray.dir = random_unit(rng) * log_uniform(rng, 0.1f, 10.0f);
  }
  // Zero components, both signs: the slab test meets +-inf and 0 * inf.
  const int zeros = std::uniform_int_distribution<int>(0, 3)(rng) == 0 ? std::uniform_int_distribution<int>(1, 2)(rng) : 0;
  for (int z = 0; z < zeros; ++z) {
    const int axis = std::uniform_int_distribution<int>(0, 2)(rng);
    q.ray.dir[axis] = (rng() & 1) ? 0.0f : -0.0f;
  }
  if (dot(q.ray.dir, q.ray.dir) == 0) q.ray.dir = {0, 0, 1};
  // Occasionally place the origin exactly on a box plane of a sphere, where 0 * inf = NaN appears in the slab test.
  if (zeros > 0 && !scene.centers.empty() && (rng() & 3) == 0) {
    const auto i = std::uniform_int_distribution<std::size_t>(0, scene.centers.size() - 1)(rng);
    for (int a = 0; a < 3; ++a) {
      if (q.ray.dir[a] == 0) q.ray.origin[a] = scene.centers[i][a] + scene.radii[i];
    }
  }
  q.t_min = (rng() & 1) ? 0.0f : 1e-3f;
  q.t_max = (rng() & 3) == 0 ? log_uniform(rng, 0.1f, 4 * extent) : kInf;
  return q;
}

// Expects the BVH to return what brute force returns; returns the number of hits. The exception, rare and checked,
// is a tie: spheres whose t are equal, or equal up to rounding (overlapping spheres seen from very far away), which
// box culling cannot order (bvh.h). The BVH's sphere must then give a t no smaller than brute force's and within
// rounding of it.
// `found[i]` and `got[i]` are the BVH's answer to queries[i] (by default, Bvh::intersect's).
int expect_matches_brute_force(const Scene& scene, const Bvh& bvh, const std::vector<Query>& queries,
                               std::vector<bool> found = {}, std::vector<SphereHit> got_hits = {}) {
  if (found.empty()) {
    found.resize(queries.size());
    got_hits.resize(queries.size());
    for (std::size_t i = 0; i < queries.size(); ++i) {
      SphereHit h;
      found[i] = bvh.intersect(queries[i].ray, queries[i].t_min, queries[i].t_max, h);
      got_hits[i] = h;
    }
  }
  int hits = 0, ties = 0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const Query& q = queries[i];
    SphereHit want;
    const bool want_hit = intersect_brute_force(scene.centers, scene.radii, q.ray, q.t_min, q.t_max, want);
    const bool got_hit = found[i];
    const SphereHit got = got_hits[i];
    EXPECT_EQ(got_hit, want_hit) << "origin " << q.ray.origin.x << "," << q.ray.origin.y << "," << q.ray.origin.z
                                 << " dir " << q.ray.dir.x << "," << q.ray.dir.y << "," << q.ray.dir.z;
    if (!got_hit || !want_hit) continue;
    ++hits;
    if (got.sphere == want.sphere) {
      EXPECT_EQ(got.t, want.t);
      continue;
    }
    ++ties;
    const Vec3d to_center = to_double(scene.centers[want.sphere]) - to_double(q.ray.origin);
    const double rounding = 1e-5 * want.t + 16 * kFloatEps * (length(to_center) + scene.radii[want.sphere]) /
                                                length(to_double(q.ray.dir));
    EXPECT_GE(got.t, want.t);
    EXPECT_LE(got.t - want.t, rounding) << "sphere " << got.sphere << " instead of " << want.sphere;
    float t = 0;
    EXPECT_TRUE(intersect_sphere(q.ray, scene.centers[got.sphere], scene.radii[got.sphere], q.t_min, q.t_max, t));
    EXPECT_EQ(t, got.t);
  }
  EXPECT_LE(ties, hits / 100 + 2);
  return hits;
}

Scene random_scene(std::mt19937& rng, std::size_t n, float extent) {
  Scene s;
  const int layout = std::uniform_int_distribution<int>(0, 3)(rng);
  std::vector<Vec3f> clusters;
  for (int i = 0; i < 8; ++i) clusters.push_back(uniform_in_box(rng, -extent, extent));
  for (std::size_t i = 0; i < n; ++i) {
    Vec3f c;
    switch (layout) {
      case 0:  // uniform
        c = uniform_in_box(rng, -extent, extent);
        break;
      case 1:  // clustered
        c = clusters[i % clusters.size()] + random_unit(rng) * (extent * 0.05f * uniform(rng, 0, 1));
        break;
      case 2:  // flat layer on a ground, as in the cover scenes
        c = {uniform(rng, -extent, extent), uniform(rng, 0, 0.5f), uniform(rng, -extent, extent)};
        break;
      default:  // on a line
        c = {uniform(rng, -extent, extent), 0, 0};
        break;
    }
    s.centers.push_back(c);
    s.radii.push_back(log_uniform(rng, 1e-3f * extent, 0.2f * extent));
  }
  if (n > 1 && (rng() & 1)) {  // a huge ground sphere replaces one of them
    s.centers[0] = {0, -1000 * extent, 0};
    s.radii[0] = 1000 * extent;
  }
  return s;
}

// Runs `check(scene, bvh, extent)`, which returns {hits, queries} of its comparisons, on `count` random scenes
// (the first eight of 1 to 8 spheres, then of 1 to 2000), and expects a quarter of all queries to hit: the
// comparisons are not vacuous.
template <class Check>
void on_random_scenes(std::mt19937& rng, int count, Check&& check) {
  int hits = 0, queries_total = 0;
  for (int scene_index = 0; scene_index < count; ++scene_index) {
    const std::size_t n = scene_index < 8 ? static_cast<std::size_t>(scene_index + 1)
                                          : std::uniform_int_distribution<std::size_t>(1, 2000)(rng);
    const float extent = log_uniform(rng, 1.0f, 1000.0f);
    const Scene scene = random_scene(rng, n, extent);
    const Bvh bvh = Bvh::build(scene.centers, scene.radii);
    EXPECT_EQ(bvh.sphere_count(), n);
    const auto [h, q] = check(scene, bvh, extent);
    hits += h;
    queries_total += q;
  }
  EXPECT_GT(hits, queries_total / 4);
}

// Queries answered `Group` at a time by `answer(rays, t_min, t_max, hits)`, which returns the lanes that hit
// (every query of a group takes the first one's interval), held to brute force; returns {hits, queries}.
template <int Group, class Answer>
std::pair<int, int> expect_groups_match_brute_force(const Scene& scene, const Bvh& bvh, std::vector<Query> queries,
                                                    Answer&& answer) {
  std::vector<bool> found(queries.size());
  std::vector<SphereHit> got(queries.size());
  for (std::size_t i = 0; i + Group <= queries.size(); i += Group) {
    for (std::size_t k = 1; k < Group; ++k) {
      queries[i + k].t_min = queries[i].t_min;
      queries[i + k].t_max = queries[i].t_max;
    }
    Ray rays[Group];
    for (std::size_t k = 0; k < Group; ++k) rays[k] = queries[i + k].ray;
    SphereHit hits[Group];
    const unsigned lanes = answer(rays, queries[i].t_min, queries[i].t_max, hits);
    for (std::size_t k = 0; k < Group; ++k) {
      found[i + k] = (lanes >> k & 1) != 0;
      got[i + k] = hits[k];
    }
  }
  return {expect_matches_brute_force(scene, bvh, queries, found, got), static_cast<int>(queries.size())};
}

TEST(Bvh, MatchesBruteForceOnRandomScenes) {
  std::mt19937 rng(6);
  on_random_scenes(rng, 50, [&](const Scene& scene, const Bvh& bvh, float extent) {
    std::vector<Query> queries;
    for (int i = 0; i < 2000; ++i) queries.push_back(random_query(rng, scene, extent));
    return std::pair{expect_matches_brute_force(scene, bvh, queries), static_cast<int>(queries.size())};
  });
}

// Packets of eight rays, every other one as scattered as single queries, the others as close as a row of camera
// rays (one origin, nearby directions), held to brute force; returns {hits, queries}.
std::pair<int, int> expect_packets_match_brute_force(std::mt19937& rng, const Scene& scene, const Bvh& bvh,
                                                     float extent, int packets) {
  std::vector<Query> queries;
  for (int packet = 0; packet < packets; ++packet) {
    const Query first = random_query(rng, scene, extent);
    const bool coherent = packet % 2 == 1;
    for (int k = 0; k < Bvh::kWidth; ++k) {
      Query q = k == 0 || !coherent ? random_query(rng, scene, extent) : first;
      if (coherent) q.ray.dir = first.ray.dir + random_unit(rng) * (0.01f * length(first.ray.dir));
      queries.push_back(q);
    }
  }
  return expect_groups_match_brute_force<Bvh::kWidth>(
      scene, bvh, queries, [&](const Ray(&rays)[Bvh::kWidth], float t_min, float t_max, SphereHit(&hits)[Bvh::kWidth]) {
        return bvh.intersect_packet(rays, t_min, t_max, hits);
      });
}

// Packets get each ray's own answer.
TEST(Bvh, PacketsMatchBruteForce) {
  std::mt19937 rng(16);
  on_random_scenes(rng, 40, [&](const Scene& scene, const Bvh& bvh, float extent) {
    return expect_packets_match_brute_force(rng, scene, bvh, extent, 200);
  });
}

// Spheres whose boxes dwarf the rest of the scene, as grounds of radius 1e3 and 1e6 under a scene of size ~10, or
// walls and domes around it: single rays and packets against brute force, each scene built and queried as is.
// Returns {hits, queries}.
std::pair<int, int> expect_scene_matches_brute_force(std::mt19937& rng, const Scene& scene, float extent) {
  const Bvh bvh = Bvh::build(scene.centers, scene.radii);
  EXPECT_EQ(bvh.sphere_count(), scene.centers.size());
  std::vector<Query> queries;
  for (int i = 0; i < 2000; ++i) queries.push_back(random_query(rng, scene, extent));
  const int hits = expect_matches_brute_force(scene, bvh, queries);
  const auto [packet_hits, packet_queries] = expect_packets_match_brute_force(rng, scene, bvh, extent, 100);
  return {hits + packet_hits, static_cast<int>(queries.size()) + packet_queries};
}

// Inserts a sphere at a random index, so that huge spheres come before, among and after the others.
void insert_at_random(std::mt19937& rng, Scene& scene, const Vec3f& center, float radius) {
  const auto i = std::uniform_int_distribution<std::size_t>(0, scene.centers.size())(rng);
  scene.centers.insert(scene.centers.begin() + static_cast<std::ptrdiff_t>(i), center);
  scene.radii.insert(scene.radii.begin() + static_cast<std::ptrdiff_t>(i), radius);
}

// Small spheres in [-extent, extent]^3, none of them huge.
Scene small_spheres(std::mt19937& rng, std::size_t n, float extent) {
  Scene s;
  for (std::size_t i = 0; i < n; ++i) {
    s.centers.push_back(uniform_in_box(rng, -extent, extent));
    s.radii.push_back(log_uniform(rng, 1e-3f * extent, 0.2f * extent));
  }
  return s;
}

TEST(Bvh, GroundSpheresMatchBruteForce) {
  std::mt19937 rng(17);
  int hits = 0, queries = 0;
  for (const float ground : {1e3f, 1e6f}) {
    for (int scene_index = 0; scene_index < 12; ++scene_index) {
      // 0 to 2000 small spheres: the ground alone, with fewer spheres than a leaf holds, and with many.
      const std::size_t n = scene_index < 4 ? static_cast<std::size_t>(scene_index) * 3
                                            : std::uniform_int_distribution<std::size_t>(8, 2000)(rng);
      Scene scene = small_spheres(rng, n, 10);
      insert_at_random(rng, scene, {0, -ground, 0}, ground);
      const auto [h, q] = expect_scene_matches_brute_force(rng, scene, 10);
      hits += h;
      queries += q;
    }
  }
  EXPECT_GT(hits, queries / 4);
}

TEST(Bvh, SeveralHugeSpheresMatchBruteForce) {
  std::mt19937 rng(18);
  int hits = 0, queries = 0;
  for (int scene_index = 0; scene_index < 24; ++scene_index) {
    const float extent = log_uniform(rng, 1.0f, 100.0f);
    Scene scene = small_spheres(rng, std::uniform_int_distribution<std::size_t>(1, 1000)(rng), extent);
    // 2 to 20 huge spheres, more than a leaf holds in some scenes: grounds and walls whose surface passes near the
    // scene, and domes that enclose it.
    const int huge = std::uniform_int_distribution<int>(2, 20)(rng);
    for (int i = 0; i < huge; ++i) {
      const float radius = extent * log_uniform(rng, 10.0f, 1e5f);
      const Vec3f center = (rng() & 3) == 0 ? uniform_in_box(rng, -extent, extent)
                                            : random_unit(rng) * (radius + extent * uniform(rng, 0.5f, 2.0f));
      insert_at_random(rng, scene, center, radius);
    }
    const auto [h, q] = expect_scene_matches_brute_force(rng, scene, extent);
    hits += h;
    queries += q;
  }
  EXPECT_GT(hits, queries / 4);
}

TEST(Bvh, AllSpheresHugeMatchBruteForce) {
  std::mt19937 rng(19);
  int hits = 0, queries = 0;
  for (int scene_index = 0; scene_index < 24; ++scene_index) {
    // 1 to 20 spheres of radius 1e3 to 1e6, equal or not, around a region of size 1e3: rays meet them from outside
    // and from inside.
    const int n = scene_index < 20 ? scene_index + 1 : std::uniform_int_distribution<int>(1, 20)(rng);
    const bool equal = scene_index % 3 == 0;
    const float common = log_uniform(rng, 1e3f, 1e6f);
    Scene scene;
    for (int i = 0; i < n; ++i) {
      const float radius = equal ? common : log_uniform(rng, 1e3f, 1e6f);
      insert_at_random(rng, scene, random_unit(rng) * (radius + uniform(rng, -500.0f, 500.0f)), radius);
    }
    const auto [h, q] = expect_scene_matches_brute_force(rng, scene, 1e3f);
    hits += h;
    queries += q;
  }
  EXPECT_GT(hits, queries / 4);
}

TEST(Bvh, OneHugeSphereAndNoSphere) {
  std::mt19937 rng(20);
  for (const float radius : {1e3f, 1e6f}) {
    Scene scene;
    scene.centers.push_back({0, -radius, 0});
    scene.radii.push_back(radius);
    const auto [hits, queries] = expect_scene_matches_brute_force(rng, scene, 10);
    EXPECT_GT(hits, queries / 4);
  }
  const Bvh bvh = Bvh::build({}, {});
  Ray rays[Bvh::kWidth];
  for (Ray& ray : rays) ray = {uniform_in_box(rng, -1, 1), random_unit(rng)};
  SphereHit hits[Bvh::kWidth];
  EXPECT_EQ(bvh.intersect_packet(rays, 0, kInf, hits), 0u);
  std::size_t leaves = 0;
  bvh.traverse([](const float*, const float*) { return 0.0f; }, [] { return kInf; },
               [&](const Bvh::Leaf&, std::uint32_t) { ++leaves; });
  EXPECT_EQ(leaves, 0u);
}

// A huge sphere and a small one that a ray meets at exactly the same t (both kernels give 5: the roots are exact
// in float), with either one first in the arrays and many small spheres about so that the tree has depth: the
// lower index wins, in single rays and in packets, whichever sphere the BVH tests first.
TEST(Bvh, TieBetweenHugeAndSmallSphereGoesToTheLowerIndex) {
  std::mt19937 rng(21);
  for (const bool huge_first : {true, false}) {
    Scene scene = small_spheres(rng, 500, 50);
    for (Vec3f& c : scene.centers) c.z = std::abs(c.z) + 20;  // out of the ray's way
    const Vec3f huge_center{0, 0, 1005}, small_center{0, 0, 6};
    const std::size_t huge_index = huge_first ? 0 : 1, small_index = 1 - huge_index;
    scene.centers.insert(scene.centers.begin(), {Vec3f{}, Vec3f{}});
    scene.radii.insert(scene.radii.begin(), {0.0f, 0.0f});
    scene.centers[huge_index] = huge_center;
    scene.radii[huge_index] = 1000;
    scene.centers[small_index] = small_center;
    scene.radii[small_index] = 1;
    const Ray ray{{0, 0, 0}, {0, 0, 1}};
    float t_huge = 0, t_small = 0;
    ASSERT_TRUE(intersect_sphere(ray, huge_center, 1000, 0, kInf, t_huge));
    ASSERT_TRUE(intersect_sphere(ray, small_center, 1, 0, kInf, t_small));
    ASSERT_EQ(t_huge, 5.0f);
    ASSERT_EQ(t_small, 5.0f);
    const Bvh bvh = Bvh::build(scene.centers, scene.radii);
    SphereHit hit;
    ASSERT_TRUE(bvh.intersect(ray, 0, kInf, hit));
    EXPECT_EQ(hit.sphere, 0u);
    EXPECT_EQ(hit.t, 5.0f);
    Ray rays[Bvh::kWidth];
    for (Ray& r : rays) r = ray;
    SphereHit hits[Bvh::kWidth];
    ASSERT_EQ(bvh.intersect_packet(rays, 0, kInf, hits), (1u << Bvh::kWidth) - 1);
    for (const SphereHit& h : hits) EXPECT_EQ(h.sphere, 0u);
  }
}

TEST(Bvh, EmptyNeverHits) {
  const Bvh bvh = Bvh::build({}, {});
  EXPECT_EQ(bvh.sphere_count(), 0u);
  EXPECT_EQ(bvh.node_count(), 0u);
  std::mt19937 rng(7);
  for (int i = 0; i < 100; ++i) {
    SphereHit hit;
    EXPECT_FALSE(bvh.intersect({uniform_in_box(rng, -1, 1), random_unit(rng)}, -kInf, kInf, hit));
  }
}

TEST(Bvh, SingleSphere) {
  const std::vector<Vec3f> centers{{1, 2, 3}};
  const std::vector<float> radii{0.5f};
  const Bvh bvh = Bvh::build(centers, radii);
  EXPECT_EQ(bvh.sphere_count(), 1u);
  SphereHit hit;
  ASSERT_TRUE(bvh.intersect({{1, 2, 0}, {0, 0, 1}}, 0, kInf, hit));
  EXPECT_EQ(hit.sphere, 0u);
  EXPECT_FLOAT_EQ(hit.t, 2.5f);
  EXPECT_FALSE(bvh.intersect({{1, 2, 0}, {0, 0, -1}}, 0, kInf, hit));
  EXPECT_FALSE(bvh.intersect({{1, 2, 0}, {0, 0, 1}}, 0, 2.5f, hit));
}

TEST(Bvh, AllSpheresAtOneCentre) {
  std::mt19937 rng(8);
  Scene scene;
  for (int i = 0; i < 1000; ++i) {
    scene.centers.push_back({3, -2, 7});
    scene.radii.push_back(log_uniform(rng, 0.01f, 10.0f));
  }
  // Exact duplicates too: equal t everywhere, so only the index tie-break decides.
  for (int i = 0; i < 20; ++i) {
    scene.centers.push_back({3, -2, 7});
    scene.radii.push_back(1.0f);
  }
  const Bvh bvh = Bvh::build(scene.centers, scene.radii);
  std::vector<Query> queries;
  for (int i = 0; i < 2000; ++i) queries.push_back(random_query(rng, scene, 10));
  EXPECT_GT(expect_matches_brute_force(scene, bvh, queries), 100);
}

TEST(Bvh, ExactDuplicatesResolveToTheLowestIndex) {
  const std::vector<Vec3f> centers(100, Vec3f{0, 0, 5});
  const std::vector<float> radii(100, 1.0f);
  const Bvh bvh = Bvh::build(centers, radii);
  SphereHit hit;
  ASSERT_TRUE(bvh.intersect({{0, 0, 0}, {0, 0, 1}}, 0, kInf, hit));
  EXPECT_EQ(hit.sphere, 0u);
  EXPECT_FLOAT_EQ(hit.t, 4.0f);
  // Every lane of a packet too, whichever leaf it meets first.
  Ray rays[Bvh::kWidth];
  for (int k = 0; k < Bvh::kWidth; ++k) rays[k] = {{0.1f * static_cast<float>(k - 4), 0, 0}, {0, 0, 1}};
  SphereHit hits[Bvh::kWidth];
  ASSERT_EQ(bvh.intersect_packet(rays, 0, kInf, hits), (1u << Bvh::kWidth) - 1);
  for (const SphereHit& h : hits) EXPECT_EQ(h.sphere, 0u);
}

TEST(Bvh, ExtremeCoordinatesAndSkewedDistributions) {
  std::mt19937 rng(9);
  Scene scene;
  // Coordinates up to 1e6 with radii from 1e-2 to 1e4, and an exponential spread along x that would make a pure
  // SAH build deep (the build falls back to median splits past a depth limit).
  for (int i = 0; i < 1500; ++i) {
    scene.centers.push_back(uniform_in_box(rng, -1e6f, 1e6f));
    scene.radii.push_back(log_uniform(rng, 1e-2f, 1e4f));
  }
  for (int i = 0; i < 1500; ++i) {
    scene.centers.push_back({std::pow(1.01f, static_cast<float>(i)) - 1.0f, 0, 0});
    scene.radii.push_back(0.25f);
  }
  const Bvh bvh = Bvh::build(scene.centers, scene.radii);
  std::vector<Query> queries;
  for (int i = 0; i < 3000; ++i) queries.push_back(random_query(rng, scene, i % 2 ? 1e6f : 3e6f));
  // Rays along the x axis through the chain.
  for (int i = 0; i < 200; ++i) {
    queries.push_back({{{-10, uniform(rng, -0.2f, 0.2f), uniform(rng, -0.2f, 0.2f)}, {1, 0, 0}}, 0, kInf});
  }
  EXPECT_GT(expect_matches_brute_force(scene, bvh, queries), 200);
}

TEST(Bvh, MillionSpheres) {
  // A million under 10 s in Release; fewer under the sanitizers (the thread sanitizer as much as the address one:
  // the build and the queries run on this one thread, so it has nothing of its own to find here, and every bound
  // below is relative to n).
  const std::size_t n = core::kSanitized ? 200'000 : 1'000'000;
  std::mt19937 rng(10);
  Scene scene;
  scene.centers.reserve(n);
  scene.radii.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    scene.centers.push_back(uniform_in_box(rng, -100, 100));
    scene.radii.push_back(log_uniform(rng, 0.01f, 0.5f));
  }
  const Bvh bvh = Bvh::build(scene.centers, scene.radii);
  EXPECT_EQ(bvh.sphere_count(), n);
  // 8-wide nodes over full leaves of up to 8 spheres (measured: 37,424 nodes and 30.9 MB for this million).
  EXPECT_GT(bvh.node_count(), n / 64);
  EXPECT_LT(bvh.node_count(), n / 16);
  EXPECT_LT(bvh.memory_bytes(), n * 40);  // 40 MB for a million
  std::vector<Query> queries;
  for (int i = 0; i < 300; ++i) queries.push_back(random_query(rng, scene, 100));
  EXPECT_GT(expect_matches_brute_force(scene, bvh, queries), 30);
}

}  // namespace
}  // namespace tripsitter::render

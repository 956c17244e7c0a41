// Primary rays in tiles of 8 x 8 pixels. All rays of a tile leave the camera's eye, so a tile is a frustum:
// the BVH is walked once per tile (boxes outside the frustum, or farther than every ray's hit so far, are
// skipped), each sphere of a leaf is checked against the tile's side planes and against the plane of each row
// of pixels, and only rows it can touch are intersected, eight rays at a time.
//
// Exactness: a lane computes the same float operations, in the same order, as the scalar kernel in ray_sphere.h
// (sphere_root) on the ray camera.centre_ray gives, and breaks ties towards the lower sphere index, so a pixel
// gets the sphere and t that testing every sphere gives. The plane and box tests only skip what cannot be hit,
// with margins far above float rounding.
#include <tripsitter/render/primary.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include <tripsitter/core/parallel.h>
#include <tripsitter/render/simd8.h>
#include <tripsitter/render/sphere_lanes.h>

namespace tripsitter::render {
namespace {

using namespace simd;  // F8 and the lane kernel (sphere_lanes, LaneRoots, keep_nearest)

constexpr int kTile = 8;
constexpr float kInf = std::numeric_limits<float>::infinity();
// Relative margin of the plane tests: the rays of a tile stray from the planes through its corner rays by a few
// float roundings (~1e-7); 1e-4 of the distance is far beyond that and costs nothing measurable.
constexpr float kPlaneMargin = 1e-4f;

float l1(const Vec3f& v) { return std::abs(v.x) + std::abs(v.y) + std::abs(v.z); }

// A plane through the eye: points x with dot(normal, x - eye) >= 0 are inside.
struct Plane {
  Vec3f normal;
  float norm;  // |normal|
  // Inside or within the margin of `point`, grown by `radius`.
  bool reaches(const Vec3f& offset, float radius) const {
    return core::dot(normal, offset) >= -radius * norm - kPlaneMargin * norm * l1(offset);
  }
};

Plane plane(const Vec3f& a, const Vec3f& b) {
  const Vec3f n = core::cross(a, b);
  return {n, core::length(n)};
}

bool is_mirror(const PathMaterial& m, const GuideSettings& guide) {
  return m.type == scene::MaterialType::kMetal && m.fuzz <= guide.max_fuzz;
}

// A mirror pixel's centre ray on its way from mirror to mirror (render_primary_guides).
struct Chain {
  std::size_t pixel;
  Ray ray;        // unit direction
  SphereHit hit;  // where `ray` meets the next surface (t a distance)
  Vec3f tint;     // the mirrors' albedos so far
  float length;   // of the chain so far
};

// Follows up to Bvh::kWidth chains together, as render_primary_guides describes, and writes their guides; their
// reflected rays go to the BVH together (Bvh::intersect_live).
void follow(const PathScene& scene, std::span<Chain> chains, const GuideSettings& guide, Aovs& guides) {
  Ray rays[Bvh::kWidth];
  SphereHit hits[Bvh::kWidth];
  const auto write = [&guides](const Chain& c, const Vec3f& normal, float depth) {
    guides.albedo[c.pixel] = c.tint;
    guides.normal[c.pixel] = normal;
    guides.depth[c.pixel] = depth;
  };
  unsigned live = (1u << chains.size()) - 1;
  for (int bounce = 0; live != 0; ++bounce) {
    for (unsigned l = live; l != 0; l &= l - 1) {
      const int k = std::countr_zero(l);
      Chain& c = chains[static_cast<std::size_t>(k)];
      const PathMaterial& m = scene.material(c.hit.sphere);
      const SurfacePoint s = scene.surface(c.ray, c.hit);
      c.length += c.hit.t;
      c.tint = core::hadamard(c.tint, m.albedo);
      if (!is_mirror(m, guide) || bounce == guide.max_bounces) {
        write(c, s.normal, c.length);
        live &= ~(1u << k);
        continue;
      }
      c.ray = rays[k] = {s.p, core::normalize(reflect(c.ray.dir, s.normal))};
    }
    const unsigned found = scene.bvh().intersect_live(live, rays, kRayEpsilon, kInf, hits);
    for (unsigned l = live; l != 0; l &= l - 1) {
      const int k = std::countr_zero(l);
      Chain& c = chains[static_cast<std::size_t>(k)];
      if (found >> k & 1)
        c.hit = hits[k];
      else
        write(c, {0, 0, 0}, kInf);  // the sky: white, seen through every mirror's tint
    }
    live = found;
  }
}

// The mirror pixels of the band of tiles this thread traces (render_primary_guides).
std::vector<Chain>& band_mirrors() {
  thread_local std::vector<Chain> mirrors;
  return mirrors;
}

class Tile {
 public:
  Tile(const PathScene& scene, const ThinLensCamera& camera, int col0, int row0, int width, int height)
      : scene_(scene), eye_(camera.pinhole().origin), col0_(col0), row0_(row0) {
    // The rays are the camera's centre rays themselves, so a lane computes on exactly what the scalar kernel gets.
    const auto dir_of = [&camera](int col, int row) { return camera.centre_ray(col, row).dir; };
    const ThinLensCamera::Pinhole cam = camera.pinhole();
    // Pixels beyond the image repeat the last column or row: their lanes do real work but are never written.
    const auto col_at = [&](int k) { return std::min(col0 + k, width - 1); };
    const auto row_at = [&](int k) { return std::min(row0 + k, height - 1); };
    for (int r = 0; r < kTile; ++r) {
      for (int c = 0; c < kTile; ++c) {
        const Vec3f d = dir_of(col_at(c), row_at(r));
        dx_[r][c] = d.x;
        dy_[r][c] = d.y;
        dz_[r][c] = d.z;
        a_[r][c] = core::dot(d, d);
        inv_a_[r][c] = 1.0f / a_[r][c];
        len_[r][c] = std::sqrt(a_[r][c]);
        t_[r][c] = kInf;
        id_[r][c] = 0.0f;
      }
    }
    // Inward side planes through the tile's outer pixel edges (the camera's du points right, dv down), and the
    // plane of each row's rays, widened by half a pixel each way; a sphere that no row plane meets within its
    // radius is missed by every ray of the tile.
    const Vec3f half_u = cam.du * 0.5f, half_v = cam.dv * 0.5f;
    const Vec3f tl = dir_of(col_at(0), row_at(0)) - half_u - half_v;
    const Vec3f tr = dir_of(col_at(kTile - 1), row_at(0)) + half_u - half_v;
    const Vec3f bl = dir_of(col_at(0), row_at(kTile - 1)) - half_u + half_v;
    const Vec3f br = dir_of(col_at(kTile - 1), row_at(kTile - 1)) + half_u + half_v;
    sides_[0] = plane(bl, tl);  // left
    sides_[1] = plane(tr, br);  // right
    sides_[2] = plane(tl, tr);  // top
    sides_[3] = plane(br, bl);  // bottom
    for (int r = 0; r < kTile; ++r)
      rows_[r] = plane(dir_of(col_at(0), row_at(r)) - half_u, dir_of(col_at(kTile - 1), row_at(r)) + half_u);
  }

  // Distance from the eye to the box, or +inf when the box lies outside the tile's frustum.
  float reach(const float lo[3], const float hi[3]) const {
    const Vec3f o = eye_;
    for (const Plane& p : sides_) {
      // The box corner farthest along the inward normal.
      const Vec3f corner{p.normal.x >= 0 ? hi[0] : lo[0], p.normal.y >= 0 ? hi[1] : lo[1], p.normal.z >= 0 ? hi[2] : lo[2]};
      if (!p.reaches(corner - o, 0.0f)) return kInf;
    }
    const Vec3f gap{std::max({lo[0] - o.x, 0.0f, o.x - hi[0]}), std::max({lo[1] - o.y, 0.0f, o.y - hi[1]}),
                    std::max({lo[2] - o.z, 0.0f, o.z - hi[2]})};
    return core::length(gap) * (1.0f - kPlaneMargin);
  }

  // Boxes farther than this hold nothing nearer than what every ray has hit.
  float limit() const { return limit_; }

  void leaf(const Bvh::Leaf& leaf, std::uint32_t count) {
    bool updated = false;
    for (std::uint32_t i = 0; i < count; ++i)
      updated |= sphere({leaf.cx[i], leaf.cy[i], leaf.cz[i]}, leaf.radius[i], leaf.original[i]);
    if (updated) update_limit();
  }

  // Writes the tile's pixels that lie in the image.
  void shade(const PathScene& scene, const ThinLensCamera& camera, core::ImageRgb8& image) const {
    for (int r = 0; r < kTile && row0_ + r < image.height; ++r) {
      for (int c = 0; c < kTile && col0_ + c < image.width; ++c) {
        if (t_[r][c] == kInf) continue;
        const int col = col0_ + c, row = row0_ + r;
        shade_primary(scene, camera.centre_ray(col, row), {t_[r][c], std::bit_cast<std::uint32_t>(id_[r][c])},
                      &image.pixels[3 * (static_cast<std::size_t>(row) * static_cast<std::size_t>(image.width) +
                                         static_cast<std::size_t>(col))]);
      }
    }
  }

  // Writes the tile's pixels that lie in the image as feature buffers (aov.h): one sample per pixel, its centre.
  // With `mirrors`, the pixels whose first hit is a mirror (GuideSettings) are added to it as chains to follow.
  void features(const PathScene& scene, Aovs& aovs, std::vector<Chain>* mirrors = nullptr,
                const GuideSettings& guide = {}) const {
    for (int r = 0; r < kTile && row0_ + r < aovs.height; ++r) {
      for (int c = 0; c < kTile && col0_ + c < aovs.width; ++c) {
        const std::size_t i = static_cast<std::size_t>(row0_ + r) * static_cast<std::size_t>(aovs.width) +
                              static_cast<std::size_t>(col0_ + c);
        if (t_[r][c] == kInf) {
          aovs.albedo[i] = {1, 1, 1};
          aovs.normal[i] = {0, 0, 0};
          aovs.depth[i] = kInf;
          continue;
        }
        const std::uint32_t sphere = std::bit_cast<std::uint32_t>(id_[r][c]);
        const Vec3f dir{dx_[r][c], dy_[r][c], dz_[r][c]};
        const Vec3f outward = (eye_ + dir * t_[r][c] - scene.center(sphere)) * (1.0f / scene.radius(sphere));
        aovs.albedo[i] = scene.material(sphere).albedo;
        aovs.normal[i] = core::dot(outward, dir) > 0 ? -outward : outward;
        aovs.depth[i] = t_[r][c] * len_[r][c];
        if (mirrors != nullptr && is_mirror(scene.material(sphere), guide))
          mirrors->push_back({i, {eye_, dir * (1.0f / len_[r][c])}, {t_[r][c] * len_[r][c], sphere}, {1, 1, 1}, 0});
      }
    }
  }

 private:
  // Intersects one sphere with the rows of rays it can touch; true when some ray's closest hit changed.
  bool sphere(const Vec3f& center, float radius, std::uint32_t index) {
    const Vec3f offset = center - eye_;
    for (const Plane& p : sides_) {
      if (!p.reaches(offset, radius)) return false;
    }
    // The scalar kernel's per-sphere terms: oc = origin - center.
    const Vec3f oc = eye_ - center;
    const F8 ocx = F8::set1(oc.x), ocy = F8::set1(oc.y), ocz = F8::set1(oc.z), r2 = F8::set1(radius * radius);
    const F8 zero = F8::set1(0.0f);
    bool updated = false;
    for (int r = 0; r < kTile; ++r) {
      const Plane& row = rows_[r];
      if (std::abs(core::dot(row.normal, offset)) > radius * row.norm + kPlaneMargin * row.norm * l1(offset)) continue;
      const LaneRoots roots = sphere_lanes(ocx, ocy, ocz, F8::load(dx_[r]), F8::load(dy_[r]), F8::load(dz_[r]),
                                           F8::load(a_[r]), F8::load(inv_a_[r]), r2, zero);
      if (roots.hit.bits() != 0) updated |= keep_nearest(roots.hit, roots.t, index, t_[r], id_[r]) != 0;
    }
    return updated;
  }

  void update_limit() {
    float farthest = 0.0f;
    for (int r = 0; r < kTile; ++r) {
      for (int c = 0; c < kTile; ++c) farthest = std::max(farthest, t_[r][c] * len_[r][c]);
    }
    // Distances of the boxes are measured from the eye in world units; a hit at t lies t |d| away.
    limit_ = farthest * (1.0f + kPlaneMargin);
  }

  const PathScene& scene_;
  Vec3f eye_;
  int col0_, row0_;
  alignas(32) float dx_[kTile][kTile], dy_[kTile][kTile], dz_[kTile][kTile];
  alignas(32) float a_[kTile][kTile], inv_a_[kTile][kTile], len_[kTile][kTile];
  alignas(32) float t_[kTile][kTile];
  alignas(32) float id_[kTile][kTile];  // the sphere hit at t_, its original index's bits
  Plane sides_[4];
  Plane rows_[kTile];
  float limit_ = kInf;
};

// Walks the BVH once per tile of the image, on the settings' threads, and hands each finished tile to `done`;
// after the last tile of each band of kTile rows, calls band(first row, rows in the band) on the same thread.
template <class Done, class Band>
void trace_tiles(const PathScene& scene, const ThinLensCamera& camera, const PrimarySettings& settings,
                 const Done& done, const Band& band) {
  const int tiles_x = (settings.width + kTile - 1) / kTile;
  core::parallel_for(0, (settings.height + kTile - 1) / kTile, settings.threads, [&](int tile_row) {
    for (int tx = 0; tx < tiles_x; ++tx) {
      Tile tile(scene, camera, tx * kTile, tile_row * kTile, settings.width, settings.height);
      scene.bvh().traverse([&](const float lo[3], const float hi[3]) { return tile.reach(lo, hi); },
                           [&] { return tile.limit(); },
                           [&](const Bvh::Leaf& leaf, std::uint32_t n) { tile.leaf(leaf, n); });
      done(tile);
    }
    band(tile_row * kTile, std::min(kTile, settings.height - tile_row * kTile));
  });
}

template <class Done>
void trace_tiles(const PathScene& scene, const ThinLensCamera& camera, const PrimarySettings& settings,
                 const Done& done) {
  trace_tiles(scene, camera, settings, done, [](int, int) {});
}

}  // namespace

core::ImageRgb8 render_primary(const PathScene& scene, const ThinLensCamera& camera, const PrimarySettings& settings) {
  core::ImageRgb8 image(settings.width, settings.height);
  trace_tiles(scene, camera, settings, [&](const Tile& tile) { tile.shade(scene, camera, image); });
  return image;
}

void render_primary_aovs(const PathScene& scene, const ThinLensCamera& camera, const PrimarySettings& settings,
                         Aovs& aovs) {
  if (aovs.width != settings.width || aovs.height != settings.height) aovs = Aovs(settings.width, settings.height);
  trace_tiles(scene, camera, settings, [&](const Tile& tile) { tile.features(scene, aovs); });
}

void render_primary_guides(const PathScene& scene, const ThinLensCamera& camera, const PrimarySettings& settings,
                           const GuideSettings& guide, Aovs& first_hits, Aovs& guides) {
  if (first_hits.width != settings.width || first_hits.height != settings.height)
    first_hits = Aovs(settings.width, settings.height);
  if (guides.width != settings.width || guides.height != settings.height)
    guides = Aovs(settings.width, settings.height);
  // A band's guides are its first hits, copied row after row once its tiles are done (faster than writing them
  // pixel by pixel in the tiles' order), and then, on its mirror pixels, the ends of their chains.
  trace_tiles(
      scene, camera, settings,
      [&](const Tile& tile) { tile.features(scene, first_hits, &band_mirrors(), guide); },
      [&](int row, int rows) {
        const std::size_t first = static_cast<std::size_t>(row) * static_cast<std::size_t>(settings.width);
        const std::size_t n = static_cast<std::size_t>(rows) * static_cast<std::size_t>(settings.width);
        std::copy_n(first_hits.albedo.data() + first, n, guides.albedo.data() + first);
        std::copy_n(first_hits.normal.data() + first, n, guides.normal.data() + first);
        std::copy_n(first_hits.depth.data() + first, n, guides.depth.data() + first);
        std::vector<Chain>& mirrors = band_mirrors();
        for (std::size_t k = 0; k < mirrors.size(); k += Bvh::kWidth) {
          const std::size_t lanes = std::min<std::size_t>(Bvh::kWidth, mirrors.size() - k);
          follow(scene, std::span(mirrors).subspan(k, lanes), guide, guides);
        }
        mirrors.clear();
      });
}

}  // namespace tripsitter::render

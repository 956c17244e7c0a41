#include <tripsitter/render/normal.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <vector>

#include <tripsitter/core/parallel.h>
#include <tripsitter/core/screen.h>

namespace tripsitter::render {
namespace {

// The spheres and surfaces as the kernel takes them.
struct KernelWorld {
  std::vector<core::KernelSphere<double>> spheres;
  std::vector<core::KernelSurface> surfaces;
};

KernelWorld kernel_world(std::span<const scene::Sphere> view_spheres, int max_bounces) {
  if (max_bounces < 0 || max_bounces > core::kMaxBounces) throw std::invalid_argument("max bounces must be 0 to 6");
  KernelWorld w;
  w.spheres.reserve(view_spheres.size());
  w.surfaces.reserve(view_spheres.size());
  for (const auto& s : view_spheres) {
    w.spheres.push_back({s.center, s.radius});
    const core::Vec3d& a = s.material.albedo;
    w.surfaces.push_back({s.material.type == scene::MaterialType::kMetal,
                          {albedo_byte(a.x), albedo_byte(a.y), albedo_byte(a.z)}});
  }
  return w;
}

// The camera ray of pixel (col, row): (col - width/2, row - height/2, width/2), integer halves.
core::Vec3d camera_dir(int col, int row, int width, int height) {
  return core::pixel_ray<double>(col, row, width, height);
}

// Screen-space bounds (core/screen.h). The camera rays of column col all lie in one plane through the eye, the
// column's plane, with normal (f, 0, -(col - width/2)), f = width/2; those of row `row` in the row's plane, normal
// (0, f, -(row - height/2)). A ray that meets a sphere passes within its radius of the centre, and so does every
// plane holding the ray. The kernel decides on the sign of its discriminant b^2 - 4ac', which is 4a (r^2 - s^2)
// for a ray at distance s from the centre; computed in double it is off by less than 6e-15 a (|oc|^2 + r^2)
// (the rounding of b = 2 d.oc, b^2, c' = oc.oc - r^2 and the products), so a ray with s^2 > r^2 + 1.5e-15 (|c|^2
// + r^2) is a miss (oc = c for the eye at the origin). The planes below are tested with a margin a million times
// wider, far beyond the rounding of the test itself: a plane found not to meet the sphere holds no ray the kernel
// finds a hit on.
constexpr double kMargin = 1e-9;

using core::ScreenBounds;

// The columns and rows a sphere's camera-ray hits can lie in (inclusive; empty when lo > hi): the planes' test in
// double, r2 being radius^2 plus the margin above.
ScreenBounds screen_bounds(const core::KernelSphere<double>& s, int width, int height) {
  const core::Vec3d& c = s.center;
  const double r2 = s.radius * s.radius + kMargin * (dot(c, c) + s.radius * s.radius);
  return core::screen_bounds<double>(c, r2, width, height, width);
}

constexpr int kTile = 8;

}  // namespace

core::Image444 render_normal(std::span<const scene::Sphere> view_spheres, int width, int height, int max_bounces) {
  const KernelWorld w = kernel_world(view_spheres, max_bounces);
  const auto surface_of = [&w](int i) { return w.surfaces[static_cast<std::size_t>(i)]; };
  core::Image444 image(width, height);
  const DoubleArith arith;
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      image.at(col, row) = core::trace_pixel(arith, camera_dir(col, row, width, height),
                                             std::span<const core::KernelSphere<double>>(w.spheres), surface_of,
                                             core::kBackground, max_bounces)
                               .colour;
    }
  }
  return image;
}

core::Image444 render_normal_fast(std::span<const scene::Sphere> view_spheres, int width, int height,
                                  int max_bounces, int threads) {
  const KernelWorld w = kernel_world(view_spheres, max_bounces);
  const std::span<const core::KernelSphere<double>> all(w.spheres);
  const auto surface_of = [&w](int i) { return w.surfaces[static_cast<std::size_t>(i)]; };
  std::vector<ScreenBounds> bounds;
  bounds.reserve(w.spheres.size());
  for (const auto& s : w.spheres) bounds.push_back(screen_bounds(s, width, height));

  core::Image444 image(width, height);
  const DoubleArith arith;
  const int tile_rows = (height + kTile - 1) / kTile;
  core::parallel_for(0, tile_rows, threads, [&](int tile_row) {
    const int row0 = tile_row * kTile, row1 = std::min(row0 + kTile, height) - 1;
    // The spheres of this row of tiles, then of each tile, in index order: the kernel breaks ties towards the
    // lower index, so a tile's search finds the sphere the search over all of them finds.
    std::vector<int> in_rows;
    for (int i = 0; i < static_cast<int>(bounds.size()); ++i) {
      const ScreenBounds& b = bounds[static_cast<std::size_t>(i)];
      if (b.row_lo <= row1 && b.row_hi >= row0) in_rows.push_back(i);
    }
    std::vector<int> ids;
    std::vector<core::KernelSphere<double>> spheres;
    for (int col0 = 0; col0 < width; col0 += kTile) {
      const int col1 = std::min(col0 + kTile, width) - 1;
      ids.clear();
      spheres.clear();
      for (const int i : in_rows) {
        const ScreenBounds& b = bounds[static_cast<std::size_t>(i)];
        if (b.col_lo > col1 || b.col_hi < col0) continue;
        ids.push_back(i);
        spheres.push_back(w.spheres[static_cast<std::size_t>(i)]);
      }
      const std::span<const core::KernelSphere<double>> tile(spheres);
      // The camera ray (pass 0) searches the tile's spheres; reflected rays search them all.
      const auto closest = [&](const core::KernelRay<double>& ray, int excluded, int pass) {
        if (pass > 0) return core::closest_hit(arith, ray, all, excluded);
        core::KernelHit<double> hit = core::closest_hit(arith, ray, tile);
        if (hit.index >= 0) hit.index = ids[static_cast<std::size_t>(hit.index)];
        return hit;
      };
      for (int row = row0; row <= row1; ++row) {
        for (int col = col0; col <= col1; ++col) {
          image.at(col, row) = core::trace_pixel_with(arith, camera_dir(col, row, width, height), all, surface_of,
                                                      core::kBackground, max_bounces, closest)
                                   .colour;
        }
      }
    }
  });
  return image;
}

}  // namespace tripsitter::render

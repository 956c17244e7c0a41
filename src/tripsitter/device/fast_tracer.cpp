#include <tripsitter/device/fast_tracer.h>

#include <algorithm>
#include <array>
#include <cstdlib>

#include <tripsitter/core/isqrt.h>
#include <tripsitter/core/screen.h>

namespace tripsitter::device {
namespace {

using core::Int128;
using core::kScreenHeight;
using core::kScreenWidth;

}  // namespace

FastTracer::FastTracer(const DevicePreset& preset)
    : preset_(preset),
      controller_(preset),
      arith_{SqrtUnit(preset.sqrt_iterations), FixedArith::extra_bits_of(preset)},
      narrow_arith_{arith_},
      path_arith_{arith_} {}

void FastTracer::load(const SceneMemory& scene) {
  scene_ = &scene;
  if (preset_.units) {  // the units check their own operands (artix::prepare_sphere)
    units_ = artix::prepare_world(scene);
    if (preset_.path) artix::add_fast_search(units_);  // for bounced rays
    narrow_ = true;
    return;
  }
  const std::size_t n = scene.geometry.size();
  // The fast paths' bounds derive from these inputs. Their quadratics and shading are the kernel's and check
  // their widths as the plain model does (NarrowArith); the plane and ball tests are the fast model's own.
  for (const auto& s : scene.geometry) {
    for (int k = 0; k < 3; ++k) arith_.check(s.center[k], core::Width::kCentre);
    arith_.check(s.radius, core::Width::kRadius);
  }
  narrow_ = std::all_of(scene.geometry.begin(), scene.geometry.end(), [](const core::KernelSphere<std::int64_t>& s) {
    return std::abs(s.center.x) < kNarrowLimit && std::abs(s.center.y) < kNarrowLimit &&
           std::abs(s.center.z) < kNarrowLimit && s.radius >= 0 && s.radius < kNarrowLimit;
  });
  if (!narrow_) return;
  // (A path pixel that has converged costs one issue slot, so on the path preset any column can be on time. With
  // trace_late_pixels the late columns are traced too, for the line's demand.)
  columns_ = preset_.path || preset_.trace_late_pixels
                 ? kScreenWidth
                 : std::min(kScreenWidth, preset_.workers * controller_.pixels_in_time(static_cast<std::int64_t>(n)));
  cx_.resize(n);
  cy_.resize(n);
  cz_.resize(n);
  r2_.resize(n);
  c_prime_.resize(n);
  col_lo_.resize(n);
  col_hi_.resize(n);
  std::vector<std::array<int, 2>> rows(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& s = scene.geometry[i];
    cx_[i] = s.center.x;
    cy_[i] = s.center.y;
    cz_[i] = s.center.z;
    r2_[i] = s.radius * s.radius;
    c_prime_[i] = s.center.x * s.center.x + s.center.y * s.center.y + s.center.z * s.center.z - r2_[i];
    // Wholly behind the camera (every point at z <= 0): a camera ray meets it only at t <= 0, so b <= 0
    // and num = b - sqrt(D) <= 0, no hit.
    if (s.center.z + s.radius <= 0) {
      col_lo_[i] = 0;
      col_hi_[i] = -1;
      rows[i] = {0, -1};
      continue;
    }
    // Screen-space bounds, exact in integers (no margin: r2 is r^2): with |c_k| < 2^28, the image plane at
    // 320 and |offset| <= 320, the plane tests' sums stay below 2^38 and their products below 2^76.
    const core::ScreenBounds b =
        core::screen_bounds<Int128>(s.center, r2_[i], kScreenWidth, kScreenHeight, columns_);
    col_lo_[i] = b.col_lo;
    col_hi_[i] = b.col_hi;
    rows[i] = {b.row_lo, b.row_hi};
  }
  balls_ = build_ball_tree(
      n, [&](int i) { return std::array<std::int64_t, 3>{cx_[static_cast<std::size_t>(i)], cy_[static_cast<std::size_t>(i)], cz_[static_cast<std::size_t>(i)]}; },
      [&](int i) { return scene.geometry[static_cast<std::size_t>(i)].radius; });

  row_start_.assign(kScreenHeight + 1, 0);
  for (const auto& r : rows)
    for (int y = r[0]; y <= r[1]; ++y) ++row_start_[static_cast<std::size_t>(y) + 1];
  for (int y = 0; y < kScreenHeight; ++y)
    row_start_[static_cast<std::size_t>(y) + 1] += row_start_[static_cast<std::size_t>(y)];
  row_spheres_.resize(static_cast<std::size_t>(row_start_[kScreenHeight]));
  std::vector<int> fill(row_start_.begin(), row_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    for (int y = rows[i][0]; y <= rows[i][1]; ++y)
      row_spheres_[static_cast<std::size_t>(fill[static_cast<std::size_t>(y)]++)] = static_cast<int>(i);
}

void FastTracer::primary_hits(int row, std::array<int, kLineWidth>& best,
                              std::array<std::int64_t, kLineWidth>& best_num) const {
  // Every camera ray of the row against the row's spheres, sphere by sphere over its columns. The ray of
  // column col is d = (x, dy, 320) (core::device_ray): a = x^2 + e, b = 2u with u = d.c = x c_x + u0, c' as
  // loaded; the kernel's hit_num takes it from there. |u| < 880 * 2^28 and a < 2^19, so b fits 64 bits (as
  // NarrowArith requires), and b^2, 4ac' < 2^80 fit 128.
  const core::Vec3<std::int64_t> row_ray = core::device_ray<std::int64_t>(0, row);
  const std::int64_t dy = row_ray.y;
  const std::int64_t e = dy * dy + row_ray.z * row_ray.z;
  best.fill(-1);
  for (int k = row_start_[static_cast<std::size_t>(row)]; k < row_start_[static_cast<std::size_t>(row) + 1]; ++k) {
    const auto i = static_cast<std::size_t>(row_spheres_[static_cast<std::size_t>(k)]);
    const std::int64_t cx = cx_[i];
    const std::int64_t u0 = dy * cy_[i] + row_ray.z * cz_[i];
    const std::int64_t c_prime = c_prime_[i];
    for (int col = col_lo_[i]; col <= col_hi_[i]; ++col) {
      const std::int64_t x = core::device_ray<std::int64_t>(col, row).x;
      const std::int64_t u = x * cx + u0;
      if (u <= 0) continue;  // b <= 0: num = b - sqrt(D) <= 0, behind the camera
      const std::int64_t num = core::hit_num(narrow_arith_, x * x + e, 2 * u, c_prime);
      if (num <= 0) continue;  // a miss (or a hit behind the camera)
      const auto c = static_cast<std::size_t>(col);
      if (best[c] < 0 || num < best_num[c]) {  // ties keep the sphere sent first, as the plain search does
        best[c] = static_cast<int>(i);
        best_num[c] = num;
      }
    }
  }
}

LineResult FastTracer::render_line(int row, std::span<core::Rgb444> line) const {
  if (preset_.units) return artix::render_line(preset_, units_, row, line, artix::Search::kTiles);
  const SceneMemory& scene = *scene_;
  if (!narrow_) return controller_.render_line(row, scene, line);
  std::array<int, kLineWidth> best;
  std::array<std::int64_t, kLineWidth> best_num;
  primary_hits(row, best, best_num);
  const std::span<const core::KernelSphere<std::int64_t>> spheres(scene.geometry);
  const auto surface_of = [&scene](int i) { return kernel_surface(scene, i); };
  return schedule_line(preset_, static_cast<std::int64_t>(spheres.size()), line, [&](int col) {
    // The schedule starts a worker's first late pixel before it knows it is late; from columns_ on, a
    // pixel is late whatever it shows, so it needs no tracing (the schedule's lower bound on the line's demand
    // does not read it; with trace_late_pixels columns_ is the whole line).
    if (col >= columns_) return core::PixelTrace{core::kBlack, 0};
    const auto c = static_cast<std::size_t>(col);
    // The first pass of trace_pixel_with, for the pixels it ends: a miss, or a hit on a sphere that does
    // not reflect (shaded in 64 bits).
    if (best[c] < 0) return core::PixelTrace{core::kBackground, 0};
    if (preset_.max_bounces == 0 || !kernel_surface(scene, best[c]).metal) {
      const core::KernelRay<std::int64_t> camera{{}, core::device_ray<std::int64_t>(col, row)};
      return core::PixelTrace{
          core::normal_colour(narrow_arith_, camera, spheres[static_cast<std::size_t>(best[c])], best_num[c]), 0};
    }
    const core::KernelHit<Int128> primary{best[c], Int128{best_num[c]}};
    return core::trace_pixel_with(
        arith_, device_ray(col, row), spheres, surface_of, core::kBackground, preset_.max_bounces,
        [&](const core::KernelRay<Int128>& ray, int excluded, int pass) {
          return pass == 0 ? primary : closest_hit(ray, excluded);
        });
  });
}

LineResult FastTracer::render_path_line(int row, const PathFrame& frame, std::span<AccumEntry> memory,
                                        std::span<core::Rgb444> line, PathCounters& counters) const {
  if (preset_.units) return artix::render_path_line(preset_, units_, row, frame, memory, line, counters, artix::Search::kTiles);
  const SceneMemory& scene = *scene_;
  if (!narrow_) return controller_.render_path_line(row, scene, frame, memory, line, counters);
  // Every sample of a pixel starts with the same camera ray (the device's rays have no jitter): its closest hit
  // is the row's search's; the bounced rays search the balls.
  std::array<int, kLineWidth> best;
  std::array<std::int64_t, kLineWidth> best_num;
  primary_hits(row, best, best_num);
  const std::span<const core::KernelSphere<std::int64_t>> spheres(scene.geometry);
  return schedule_path_line(preset_, static_cast<std::int64_t>(spheres.size()), line, memory, [&](int col) {
    const auto c = static_cast<std::size_t>(col);
    const PathHit primary{best[c], best_num[c], false};
    const auto closest = [&](const PathRay& path) {
      if (path.from < 0) return primary;
      return with_far_side(path_arith_, path, closest_hit(path.ray, path.from), spheres);
    };
    return trace_path_pixel(path_arith_, col, row, memory[c], spheres, frame, counters, closest);
  });
}

core::KernelHit<Int128> FastTracer::closest_hit(const core::KernelRay<Int128>& ray, int excluded) const {
  // A reflected ray starts on a sphere (|o_k| <= |c_k| + r + 2) and its direction is scaled to 2^20 per
  // component; beyond |o_k| < 2^30 and |d_k| <= 2^21 take the plain search. Within them, with |c_k| < 2^28:
  // |oc_k| < 2^30.4, |b| < 2^54, oc.oc < 2^62.3, 4a < 2^45.6, and b^2, 4ac' < 2^108; against a ball
  // (centre within 2^29, radius below 2^30.1): |oc_k| < 1.5 2^30, |d.oc| < 2^53.2, oc.oc < 2^62.8, and
  // the products with a below 2^108.
  constexpr Int128 kOrigin = Int128{1} << 30;
  constexpr Int128 kDirection = Int128{1} << 21;
  for (int k = 0; k < 3; ++k) {
    if (ray.origin[k] >= kOrigin || ray.origin[k] <= -kOrigin || ray.direction[k] > kDirection ||
        ray.direction[k] < -kDirection)
      return core::closest_hit(arith_, ray, std::span<const core::KernelSphere<std::int64_t>>(scene_->geometry),
                               excluded);
  }
  const auto ox = static_cast<std::int64_t>(ray.origin.x);
  const auto oy = static_cast<std::int64_t>(ray.origin.y);
  const auto oz = static_cast<std::int64_t>(ray.origin.z);
  const auto dx = static_cast<std::int64_t>(ray.direction.x);
  const auto dy = static_cast<std::int64_t>(ray.direction.y);
  const auto dz = static_cast<std::int64_t>(ray.direction.z);
  for (int k = 0; k < 3; ++k) {
    core::check_width(narrow_arith_, ray.origin[k], core::Width::kOrigin);
    core::check_width(narrow_arith_, ray.direction[k], core::Width::kDirection);
  }
  const std::int64_t a = dx * dx + dy * dy + dz * dz;
  core::check_width(narrow_arith_, a, core::Width::kA);
  int best = -1;
  std::int64_t best_num = 0;
  for_each_ball_member(balls_, {ox, oy, oz}, {dx, dy, dz}, a, [&](int i) {
    if (i == excluded) return;
    const auto s = static_cast<std::size_t>(i);
    const std::int64_t ocx = cx_[s] - ox, ocy = cy_[s] - oy, ocz = cz_[s] - oz;
    core::check_width(narrow_arith_, ocx, core::Width::kToCentre);
    core::check_width(narrow_arith_, ocy, core::Width::kToCentre);
    core::check_width(narrow_arith_, ocz, core::Width::kToCentre);
    // The kernel's b = 2 d.oc and c' = oc.oc - r^2 (r^2 as loaded), then its quadratic.
    const std::int64_t b = 2 * (dx * ocx + dy * ocy + dz * ocz);
    if (b <= 0) return;  // num = b - sqrt(D) <= 0
    const std::int64_t c_prime = ocx * ocx + ocy * ocy + ocz * ocz - r2_[s];
    const std::int64_t num = core::hit_num(narrow_arith_, a, b, c_prime);
    if (num <= 0) return;  // a miss (or a hit behind the origin)
    // The smallest num, and on a tie the sphere sent first, whatever order the balls are visited in.
    if (best < 0 || num < best_num || (num == best_num && i < best)) {
      best = i;
      best_num = num;
    }
  });
  return {best, best_num};
}

}  // namespace tripsitter::device

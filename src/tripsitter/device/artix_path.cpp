#include <tripsitter/device/artix_path.h>

#include <algorithm>

namespace tripsitter::device::artix {

PathUnitHit with_far_side(const PathUnitRay& path, const Hit& near, std::span<const UnitSphere> spheres) {
  PathUnitHit hit{near.index, near.td, false};
  if (!path.into) return hit;
  const std::int64_t far = far_td(path.ray, spheres[static_cast<std::size_t>(path.from)]);
  if (far > 0 && (hit.index < 0 || far < hit.td || (far == hit.td && path.from < hit.index)))
    hit = {path.from, far, true};
  return hit;
}

Vec3i unit_direction(const approx::Unit3& v) {
  const approx::Unit3 u = approx::unit({v.x, v.y, v.z}, kDirectionFrac);
  return {std::clamp(u.x, -kDirectionMax, kDirectionMax), std::clamp(u.y, -kDirectionMax, kDirectionMax),
          std::clamp(u.z, -kDirectionMax, kDirectionMax)};
}

PathSample trace_path_sample(int col, int row, std::span<const UnitSphere> spheres,
                             std::span<const PathSurface> surfaces, int depth, PathRng& rng, PathCounters& counters) {
  return trace_path_sample(col, row, spheres, surfaces, depth, rng, counters, [&](const PathUnitRay& path) {
    return with_far_side(path, closest_hit(path.ray, spheres, path.from), spheres);
  });
}

}  // namespace tripsitter::device::artix

// intersect_brute_force (bvh.h): the float ray-sphere kernel (ray_sphere.h) on every sphere in index order, the
// reference the BVH and the primary-ray tiles are held to.
#include <tripsitter/render/bvh.h>
#include <tripsitter/render/ray_sphere.h>

#include <cassert>

namespace tripsitter::render {

bool intersect_brute_force(std::span<const Vec3f> centers, std::span<const float> radii, const Ray& ray,
                           float t_min, float t_max, SphereHit& hit) {
  assert(centers.size() == radii.size());
  const KernelRay kray = make_kernel_ray(ray);
  bool found = false;
  for (std::size_t i = 0; i < centers.size(); ++i) {
    float t;
    if (sphere_root(kray, centers[i], radii[i], t_min, t) && t < t_max) {  // strict: ties keep the lower index
      t_max = t;
      hit = {t, static_cast<std::uint32_t>(i)};
      found = true;
    }
  }
  return found;
}

}  // namespace tripsitter::render

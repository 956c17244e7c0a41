// intersect_sphere (bvh.h): the float ray-sphere kernel (ray_sphere.h) on one sphere.
#include <tripsitter/render/bvh.h>
#include <tripsitter/render/ray_sphere.h>

namespace tripsitter::render {

bool intersect_sphere(const Ray& ray, const Vec3f& center, float radius, float t_min, float t_max, float& t) {
  float root;
  if (!sphere_root(make_kernel_ray(ray), center, radius, t_min, root) || !(root < t_max)) return false;
  t = root;
  return true;
}

}  // namespace tripsitter::render

#include <tripsitter/render/primary.h>

#include <cmath>

#include <tripsitter/core/parallel.h>

namespace tripsitter::render {

core::ImageRgb8 render_primary(const PathScene& scene, const ThinLensCamera& camera, const PrimarySettings& settings) {
  core::ImageRgb8 image(settings.width, settings.height);
  core::parallel_for(0, settings.height, settings.threads, [&](int row) {
    std::uint8_t* out = &image.pixels[3 * static_cast<std::size_t>(row) * static_cast<std::size_t>(settings.width)];
    for (int col = 0; col < settings.width; ++col, out += 3) {
      const Ray ray = camera.centre_ray(col, row);
      SphereHit hit;
      if (scene.intersect(ray, 0.0f, INFINITY, hit)) shade_primary(scene, ray, hit, out);
    }
  });
  return image;
}

}  // namespace tripsitter::render

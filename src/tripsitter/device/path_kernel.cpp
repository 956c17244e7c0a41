#include <tripsitter/device/path_kernel.h>

#include <algorithm>

namespace tripsitter::device {

PathSurface path_surface(const SurfaceWord& word) {
  PathSurface s;
  s.material = word.material;
  for (std::size_t k = 0; k < 3; ++k) s.albedo[k] = word.albedo[k] * 257u + (word.albedo[k] >> 7);
  s.fuzz = word.fuzz;
  // The receiver refuses indices outside the supported range; scene memory written directly gets the nearest.
  const std::int64_t ior = std::clamp(word.ior, kPathIorMin, kPathIorMax);  // times 2^12
  s.passes_straight = ior == 4096;
  s.eta_enter = ((std::int64_t{1} << 26) + ior / 2) / ior;  // 2^14 / (ior / 2^12)
  s.eta_leave = ior * 4;
  const std::int64_t diff = ior - 4096, sum = ior + 4096;
  s.r0 = ((diff * diff << 14) + sum * sum / 2) / (sum * sum);
  return s;
}

PathCounters& PathCounters::operator+=(const PathCounters& o) {
  samples += o.samples;
  rays += o.rays;
  lambertian += o.lambertian;
  metal += o.metal;
  dielectric += o.dielectric;
  refracted += o.refracted;
  absorbed += o.absorbed;
  sky += o.sky;
  cut += o.cut;
  draws += o.draws;
  return *this;
}

}  // namespace tripsitter::device

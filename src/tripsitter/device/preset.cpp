#include <tripsitter/device/preset.h>

#include <algorithm>

#include <tripsitter/device/artix_kernel.h>
#include <tripsitter/device/frame_memory.h>
#include <tripsitter/device/sqrt_unit.h>

namespace tripsitter::device {

namespace {

// One sphere test, from the pair entering to the closest-hit register holding its result.
std::int64_t per_sphere_cycles(const DevicePreset& p) {
  return p.costs.sphere_test + std::int64_t{p.sqrt_iterations} * p.costs.sqrt_cycles_per_iteration +
         p.costs.closest_update;
}

}  // namespace

std::int64_t DevicePreset::pixel_occupancy(std::int64_t spheres, int bounces) const {
  const std::int64_t passes = std::int64_t{bounces} + 1;
  if (costs.pipelined) {
    const std::int64_t pass_latency = costs.pixel_setup + per_sphere_cycles(*this);
    return passes * std::max<std::int64_t>(spheres, 1) * costs.issue_interval + bounces * (pass_latency + costs.reflect);
  }
  return costs.pixel_setup + passes * spheres * per_sphere_cycles(*this) + bounces * costs.reflect + costs.shade;
}

std::int64_t DevicePreset::path_occupancy(std::int64_t spheres, std::int64_t rays,
                                          const std::array<std::int64_t, 3>& bounces) const {
  const std::int64_t scatters = bounces[0] * costs.scatter_lambertian + bounces[1] * costs.scatter_metal +
                                bounces[2] * costs.scatter_dielectric;
  const std::int64_t stalls = bounces[0] + bounces[1] + bounces[2];
  if (costs.pipelined) {
    const std::int64_t pass_latency = costs.pixel_setup + per_sphere_cycles(*this);
    // A converged pixel traces nothing but still takes an issue slot to be read and shown.
    return std::max<std::int64_t>(costs.issue_interval,
                                  rays * std::max<std::int64_t>(spheres, 1) * costs.issue_interval +
                                      stalls * pass_latency + scatters);
  }
  return costs.pixel_setup + rays * spheres * per_sphere_cycles(*this) + scatters + costs.sky + costs.accumulate;
}

std::int64_t DevicePreset::path_drain_cycles() const {
  // The last pass's hit known, then the longest way a path can end (the sky, or a scatter that absorbs), then
  // the frame-memory read-modify-write and display.
  if (!costs.pipelined) return 0;
  const int ending = std::max({costs.sky, costs.scatter_lambertian, costs.scatter_metal, costs.scatter_dielectric});
  return costs.pixel_setup + per_sphere_cycles(*this) + ending + costs.accumulate;
}

std::int64_t DevicePreset::drain_cycles() const {
  return costs.pipelined ? costs.pixel_setup + per_sphere_cycles(*this) + costs.shade : 0;
}

std::int64_t DevicePreset::finish_cycle(std::int64_t k, std::int64_t spheres) const {
  return (k + 1) * pixel_occupancy(spheres, 0) + drain_cycles();
}

std::optional<std::string> DevicePreset::validate() const {
  const int f = x.frac_bits;
  if (y.frac_bits != f || z.frac_bits != f || radius.frac_bits != f)
    return "x, y, z and radius must have the same number of fractional bits";
  if (f > 30) return "at most 30 fractional bits";
  for (const auto* fmt : {&x, &y, &z, &radius})
    if (fmt->total_bits < 2 || fmt->total_bits > 32) return "formats must be 2 to 32 bits wide (the v2 wire carries 32)";
  if (!x.is_signed || !y.is_signed || !z.is_signed || radius.is_signed)
    return "coordinates must be signed and the radius unsigned";
  if (sqrt_iterations < 1 || sqrt_iterations > kMaxSqrtIterations) return "sqrt iterations must be 1 to 30";
  if (max_bounces < 0 || max_bounces > core::kMaxBounces) return "max bounces must be 0 to 6";
  if (costs.reflect < 0) return "the reflection cost must not be negative";
  if (workers < 1 || workers > kLineWidth) return "workers must be 1 to 640";
  if (lead_cycles < 1 || lead_cycles > kLineCycles) return "lead cycles must be 1 to 3200";
  if (max_spheres < 1 || max_spheres > 1'000'000) return "scene memory must hold 1 to 1000000 spheres";
  if (costs.scatter_lambertian < 0 || costs.scatter_metal < 0 || costs.scatter_dielectric < 0 || costs.sky < 0 ||
      costs.accumulate < 0)
    return "the path costs must not be negative";
  if (units) {
    if (units->tile_columns < 1 || kLineWidth % units->tile_columns != 0) return "tile columns must divide 640";
    if (units->min_pass < 1) return "a pass takes at least one cycle";
    if (units->hit_latency < 0 || units->reflect_latency < 0 || units->shade_latency < 0 || units->walk_lead < 0 ||
        units->walk_wait < 0 || units->paths < 0)
      return "the units' latencies must not be negative";
    if (x.total_bits > artix::kMaxCoordinateBits || y.total_bits > artix::kMaxCoordinateBits ||
        z.total_bits > artix::kMaxCoordinateBits || radius.total_bits > artix::kMaxRadiusBits)
      return "the sphere units take coordinates of at most 22 bits and radii of at most 21";
  }
  if (path) {
    if (path->spp < 1 || path->spp > kMaxSamples) return "samples per pixel must be 1 to 255";
    if (path->depth < 1 || path->depth > kMaxPathDepth) return "path depth must be 1 to 16";
    if (sqrt_iterations < 15 && !units) return "the path preset's square roots need at least 15 iterations";
    for (const auto* fmt : {&x, &y, &z, &radius})
      if (fmt->total_bits > 24) return "the path preset's formats must be at most 24 bits wide";
  }
  return std::nullopt;
}

DevicePreset wide_preset() {
  DevicePreset p;
  p.name = "wide";
  p.summary =
      "s24.4 coordinates, 16-step sqrt, 10 pipelined workers, mirrors up to 3 bounces: every line on time with up to "
      "49 spheres and no metal in view";
  p.x = {24, 4, true};
  p.y = {24, 4, true};
  p.z = {24, 4, true};
  p.radius = {24, 4, false};
  p.sqrt_iterations = 16;
  p.max_bounces = 3;
  p.workers = 10;
  p.lead_cycles = kLineCycles;  // the next line starts as soon as the current one is handed to the VGA block
  p.costs = {.pipelined = true, .pixel_setup = 2, .sphere_test = 12, .sqrt_cycles_per_iteration = 1,
             .closest_update = 1, .shade = 4, .reflect = 10, .issue_interval = 1};
  p.max_spheres = 4096;
  return p;
}

DevicePreset board_2023_preset() {
  DevicePreset p;
  p.name = "board-2023";
  p.summary = "the original board: v1 formats, 10 workers, 51 cycles per pixel, 3000-cycle lead";
  p.x = {16, 3, true};
  p.y = {15, 3, true};
  p.z = {15, 3, true};
  p.radius = {16, 3, false};  // 2^r for r <= 12 (the board itself failed above r = 8)
  p.sqrt_iterations = 16;
  p.max_bounces = 0;  // the board had no reflections
  p.workers = 10;
  p.lead_cycles = 3000;
  // 2 + (12 + 16 * 2 + 1) + 4 = 51 cycles per pixel with one sphere, as measured on the board's design.
  p.costs = {.pipelined = false, .pixel_setup = 2, .sphere_test = 12, .sqrt_cycles_per_iteration = 2,
             .closest_update = 1, .shade = 4, .reflect = 10, .issue_interval = 1};
  p.max_spheres = 64;
  return p;
}

DevicePreset path_preset() {
  DevicePreset p = wide_preset();
  p.name = "path";
  p.summary =
      "wide's formats, 64 pipelined workers path-tracing lambertian, metal and dielectric spheres, 1 sample per pixel "
      "per frame accumulated in frame memory, 4 rays per path";
  p.max_bounces = 0;
  p.workers = 64;
  p.path = DevicePath{};
  return p;
}

DevicePreset artix_preset() {
  DevicePreset p;
  p.name = "artix";
  p.summary =
      "the XC7A100T's datapath: s22.4 coordinates, 18-bit unit directions, 9 pipelined sphere units shared by a "
      "line's rays, camera rays culled per 32-column tile, mirrors up to 3 bounces";
  p.x = {22, 4, true};
  p.y = {22, 4, true};
  p.z = {22, 4, true};
  p.radius = {21, 4, false};
  p.sqrt_iterations = 17;  // the units' exact square root takes 17 digit steps (the parameter does not change it)
  p.max_bounces = 3;
  p.workers = 9;  // sphere units: 9 fit the chip's LUTs with 15% to spare (docs/rtl.md, "The artix device")
  p.lead_cycles = kLineCycles;
  // The units' cycle costs are DeviceUnits; CycleCosts (the workers') does not apply.
  p.max_spheres = 256;
  p.units = DeviceUnits{};
  return p;
}

DevicePreset artix_path_preset() {
  DevicePreset p = artix_preset();
  p.name = "artix-path";
  p.summary =
      "the artix datapath path-tracing: the path preset's materials, 1 sample per pixel per frame, 4 rays per path, "
      "on 9 sphere units shared by a line's rays and bounces, one bounce stage shared by the units (the model; its RTL "
      "is written block by block, with no top yet)";
  p.max_bounces = 0;
  p.path = DevicePath{};
  // One bounce stage for all units (hit point, scatter, normalisation, the light's book-keeping and the sky's):
  // a hit that bounces, or a ray that escapes, enters it in its unit's cycle and comes out 51 cycles later, as the
  // next ray or as the sample's light: the turn's register, ts_path_bounce's 49 cycles (every material's bounce
  // the same: the scatter unit waits its lambertian and metal results for its dielectric's), and the cycle before
  // the ray is known in the unit's queue (ts_artix_pkg::BounceLatency). A sample's end (its light, or its cut)
  // goes through its unit's pixel port and the column's entry is final 2 cycles later (ts_artix_pkg::PixelLatency:
  // the bank's registered read, then the sum written); the display reads the final entries as the line is shown.
  p.units->shared_bounce = true;
  p.units->paths = 32;
  p.units->reflect_latency = 51;
  p.units->pixel_port = true;
  p.units->shade_latency = 2;
  return p;
}

bool traces_paths(const DevicePreset& preset, link::WireVersion wire) {
  return preset.path.has_value() && wire != link::WireVersion::kV1;
}

std::vector<std::string> preset_names() { return {"wide", "board-2023", "path", "artix", "artix-path"}; }

std::optional<DevicePreset> preset_by_name(std::string_view name) {
  if (name == "wide") return wide_preset();
  if (name == "board-2023") return board_2023_preset();
  if (name == "path") return path_preset();
  if (name == "artix") return artix_preset();
  if (name == "artix-path") return artix_path_preset();
  return std::nullopt;
}

}  // namespace tripsitter::device

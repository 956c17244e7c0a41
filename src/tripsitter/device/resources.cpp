#include <tripsitter/device/resources.h>

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <utility>

#include <tripsitter/core/screen.h>
#include <tripsitter/device/artix_kernel.h>

namespace tripsitter::device {
namespace {

constexpr int ceil_div(int a, int b) { return (a + b - 1) / b; }

Block block(std::string name, std::vector<std::pair<std::pair<int, int>, int>> multiplies, int additions,
            int square_roots = 0, int divisions = 0) {
  return {std::move(name), std::move(multiplies), additions, square_roots, divisions};
}

// The memories of the design in block RAM (resources.h lists them and their widths).
std::vector<BramMemory> bram_memories(const DevicePreset& p) {
  std::vector<BramMemory> out;
  const auto memory = [&](std::string name, std::int64_t depth, int width) {
    out.push_back({std::move(name), depth, width, ramb18_count(depth, width)});
  };
  for (const char* which : {"line buffer (front)", "line buffer (back)"}) memory(which, kLineWidth, 12);
  int sphere_bits = p.x.total_bits + p.y.total_bits + p.z.total_bits + p.radius.total_bits;
  if (p.path) {
    sphere_bits += 2 + 3 * 8 + 16 + 16;  // material, albedo, fuzz, index of refraction (u4.12)
  } else if (p.max_bounces > 0) {
    sphere_bits += 1 + 3 * 8;  // metal, albedo
  }
  if (p.units) {
    sphere_bits += 1 + 3 * 8 + 5 + 34 + 19;  // metal, albedo; e, r^2 / 4^e, 1 / r
    const int replicas = (p.workers + 1) / 2;
    for (const char* which : {"scene memory (front)", "scene memory (back)"})
      for (int k = 0; k < replicas; ++k) memory(which, p.max_spheres, sphere_bits);
    for (const char* which : {"cull bounds (front)", "cull bounds (back)"}) memory(which, p.max_spheres, 40);
    const int index_bits = std::max(1, static_cast<int>(std::bit_width(p.max_spheres - 1)));
    const std::int64_t entries = std::int64_t{p.max_spheres} * (kLineWidth / p.units->tile_columns);
    for (const char* which : {"tile lists (this line)", "tile lists (next line)"})
      for (int k = 0; k < replicas; ++k) memory(which, entries, index_bits);
    memory("camera rays' seed table", artix::kSeedEntries, 17);
    return out;
  }
  for (const char* which : {"scene memory (front)", "scene memory (back)"}) memory(which, p.max_spheres, sphere_bits);
  if (p.path) {
    memory("reciprocal table (display)", 256, 19);
    memory("sRGB table (display)", 512, 8);
    memory("reciprocal square-root table (normalise)", 192, 17);
    memory("quarter-wave sine table (random unit vector)", 1025, 15);
    if (p.path->frame_memory == FrameMemoryPlace::kBlockRam)
      memory("frame memory", std::int64_t{core::kScreenWidth} * core::kScreenHeight, 64);
  }
  return out;
}

// Adds `times` uses of b to ops.
void add(Operations& ops, const Block& b, double times) {
  if (times == 0) return;
  for (const auto& [widths, count] : b.multiplies)
    ops.multiplies[std::to_string(widths.first) + "x" + std::to_string(widths.second)] += times * count;
  ops.additions += times * b.additions;
  ops.square_roots += times * b.square_roots;
  ops.divisions += times * b.divisions;
}

}  // namespace

int dsp_slices(int a_bits, int b_bits) {
  return std::min(ceil_div(a_bits, 24) * ceil_div(b_bits, 17), ceil_div(b_bits, 24) * ceil_div(a_bits, 17));
}

int ramb18_count(std::int64_t depth, int width) {
  if (depth <= 0 || width <= 0) return 0;
  constexpr std::array<std::pair<std::int64_t, std::int64_t>, 6> kShapes{
      {{16384, 1}, {8192, 2}, {4096, 4}, {2048, 9}, {1024, 18}, {512, 36}}};
  std::int64_t best = std::numeric_limits<std::int64_t>::max();
  for (const auto& [d, w] : kShapes) best = std::min(best, ((width + w - 1) / w) * ((depth + d - 1) / d));
  return static_cast<int>(best);
}

int Block::dsp() const {
  int total = 0;
  for (const auto& [widths, count] : multiplies) total += count * dsp_slices(widths.first, widths.second);
  return total;
}

WorkerBlocks worker_blocks(const DevicePreset& p) {
  // Magnitude bits, from the formats as the Widths table derives them for `wide` (docs/device.md): a ray with an
  // origin (a reflection or a path) has a 21-bit direction and moves oc two bits past the coordinates; the
  // camera's rays alone have |d| <= 512.3 and oc = c.
  const bool origins = p.max_bounces > 0 || p.path.has_value();
  const int coordinate = std::max({p.x.total_bits, p.y.total_bits, p.z.total_bits});
  const int r = p.radius.total_bits;
  const int d = origins ? 21 : 10;
  const int oc = origins ? coordinate + 2 : coordinate;
  const int a = 2 * d + 2;
  const int b = d + oc + 2;
  const int c_prime = 2 * std::max(oc, r) + 2;
  const int num = b + 1;
  const int m = r + 1;            // the hit normal p - c
  const int v = std::max(m, d);   // what the normalisation takes: m or a direction
  WorkerBlocks w;
  w.ray_setup = block("ray set-up: a = d.d", {{{d, d}, 3}}, 2);
  w.sphere_test = block("sphere test: b, c', b^2, 4ac', D, sqrt(D), num, compare",
                        {{{d, oc}, 3}, {{oc, oc}, 3}, {{r, r}, 1}, {{b, b}, 1}, {{a, c_prime}, 1}}, 3 + 2 + 3 + 1 + 1 + 1, 1);
  w.reflect = block("mirror reflection: hit point, m.m, d.m, r",
                    {{{num, d}, 3}, {{m, m}, 3}, {{d, m}, 3}, {{d, 2 * m + 2}, 3}, {{d + m + 2, m}, 3}}, 3 + 3 + 4 + 3, 0, 3);
  w.hit_point = block("hit point p = o + num d / 2a, m = p - c", {{{num, d}, 3}}, 6, 0, 3);
  w.normalise = block("normalise: v.v, shift, 192-entry table, one Newton step, scale",
                      {{{v, v}, 3}, {{17, 17}, 1}, {{34, 32}, 1}, {{17, 32}, 1}, {{v, 17}, 3}}, 4);
  w.random_unit = block("random unit vector: z, sqrt(1 - z^2), sine table", {{{16, 16}, 1}, {{15, 15}, 2}}, 2, 1);
  w.lambertian = block("lambertian: n + u, its length", {{{16, 16}, 3}}, 5);
  w.metal = block("metal: d^.n, d^ - 2(d^.n)n, fuzz u, absorption test", {{{15, 15}, 3}, {{16, 15}, 3}, {{16, 15}, 3}, {{17, 15}, 3}}, 10);
  w.dielectric_common = block("dielectric: cos, sin^2, eta^2 sin^2, (1 - cos)^5, Schlick",
                              {{{15, 15}, 3}, {{15, 15}, 1}, {{18, 18}, 1}, {{35, 29}, 1}, {{15, 15}, 3}, {{15, 15}, 1}}, 6);
  w.dielectric_reflect = block("dielectric reflection", {{{16, 15}, 3}}, 3);
  w.dielectric_refract = block("refraction: eta (d^ + cos n), 1 - |perp|^2, sqrt, along n",
                               {{{15, 15}, 3}, {{18, 16}, 3}, {{19, 19}, 3}, {{15, 15}, 3}}, 9, 1);
  w.throughput = block("throughput times albedo", {{{17, 17}, 3}}, 0);
  w.sky = block("sky: blend by d^.up, times throughput", {{{17, 15}, 3}, {{17, 17}, 3}}, 6);
  w.seed_hash = block("seed hash: two constant multiplies", {{{32, 32}, 2}}, 6);
  w.accumulate = block("frame memory: add 9-bit samples, mean by reciprocal table", {{{17, 18}, 3}}, 3);
  w.unit_sphere_test = block("sphere unit: b = d.oc, f = oc - b d, F.F, D, sqrt(D), t, compare",
                             {{{24, 17}, 3}, {{24, 17}, 3}, {{17, 17}, 3}}, 3 + 2 + 3 + 2 + 1 + 1 + 1, 1);
  w.unit_shade_reflect = block("unit shading and reflection, a channel a cycle: beta d, s d, n / r, d.n, (d.n) n, p",
                               {{{17, 17}, 1}, {{17, 17}, 1}, {{17, 19}, 1}, {{17, 17}, 1}, {{17, 17}, 1}, {{24, 17}, 1}},
                               8, 0, 1);
  w.camera_rays = block("camera rays: x^2 + y^2 + 320^2, seed, one Newton step, v g",
                        {{{17, 17}, 1}, {{19, 34}, 1}, {{17, 22}, 1}, {{10, 20}, 3}}, 5);
  return w;
}

Resources resources(const DevicePreset& p) {
  const WorkerBlocks w = worker_blocks(p);
  Resources out;
  out.dsp_per_worker = w.ray_setup.dsp() + w.sphere_test.dsp();
  if (p.units) {
    out.dsp_per_worker = w.unit_sphere_test.dsp() + w.unit_shade_reflect.dsp();
    out.dsp_shared = w.camera_rays.dsp();
  } else if (p.path) {
    // One pipelined scatter unit serves every worker: a pixel's bounces are a few against its rays * spheres
    // sphere tests, so a line's bounces (about 640 * 1.5 at 1 spp) need far fewer than its 3200 cycles, one
    // accepted per cycle. Its normalisation serves the normal, the incoming direction and the sky in turn, so it
    // is there once. (The cycle model charges each bounce its latency and ignores two workers meeting there in
    // the same cycle: docs/device.md.)
    for (const Block* b : {&w.hit_point, &w.normalise, &w.random_unit, &w.lambertian, &w.metal, &w.dielectric_common,
                           &w.dielectric_reflect, &w.dielectric_refract, &w.throughput, &w.sky, &w.seed_hash,
                           &w.accumulate})
      out.dsp_shared += b->dsp();
    out.frame_memory_bits = std::int64_t{64} * core::kScreenWidth * core::kScreenHeight;
    out.frame_memory_in_bram = out.frame_memory_bits <= kBoardBramBits;
    if (p.path->frame_memory == FrameMemoryPlace::kExternal)
      out.frame_memory_bits_per_cycle = 2.0 * 64 * kLineWidth / kLineCycles;
  } else if (p.max_bounces > 0) {
    out.dsp_per_worker += w.reflect.dsp();
  }
  out.workers_fitting = std::max(0, (kBoardDsp - out.dsp_shared) / out.dsp_per_worker);
  out.memories = bram_memories(p);
  for (const BramMemory& m : out.memories) out.bram18 += m.ramb18;
  out.bram_bits = std::int64_t{out.bram18} * kRamb18Bits;
  out.bram_fits = out.bram_bits <= kBoardBramBits;
  return out;
}

double Operations::total_multiplies() const {
  double total = 0;
  for (const auto& [widths, count] : multiplies) total += count;
  return total;
}

Operations path_operations_per_pixel(const DevicePreset& p, const PathCounters& c, std::int64_t spheres,
                                     std::uint64_t pixels) {
  const WorkerBlocks w = worker_blocks(p);
  Operations ops;
  const auto n = [](std::uint64_t v) { return static_cast<double>(v); };
  const std::uint64_t bounces = c.lambertian + c.metal + c.dielectric;
  add(ops, w.ray_setup, n(c.rays));
  add(ops, w.sphere_test, n(c.rays) * static_cast<double>(spheres));
  add(ops, w.hit_point, n(bounces));
  // Normalised: every hit normal, the incoming direction at metals and dielectrics, every escaping direction.
  add(ops, w.normalise, n(bounces + c.metal + c.dielectric + c.sky));
  add(ops, w.random_unit, n(c.lambertian + c.metal));
  add(ops, w.lambertian, n(c.lambertian));
  add(ops, w.metal, n(c.metal));
  add(ops, w.dielectric_common, n(c.dielectric));
  add(ops, w.dielectric_refract, n(c.refracted));
  add(ops, w.dielectric_reflect, n(c.dielectric - c.refracted));
  add(ops, w.throughput, n(bounces - c.absorbed));
  add(ops, w.sky, n(c.sky));
  add(ops, w.seed_hash, n(c.samples));
  ops.random_draws = n(c.draws);
  if (pixels > 0) {
    const double per = 1.0 / static_cast<double>(pixels);
    for (auto& [widths, count] : ops.multiplies) count *= per;
    ops.additions *= per;
    ops.square_roots *= per;
    ops.divisions *= per;
    ops.random_draws *= per;
  }
  // Every pixel accumulates and displays once per frame.
  add(ops, w.accumulate, 1.0);
  return ops;
}

Operations mirror_operations_per_pixel(const DevicePreset& p, std::int64_t spheres, std::uint64_t reflections,
                                       std::uint64_t pixels) {
  if (pixels == 0) return {};
  const WorkerBlocks w = worker_blocks(p);
  const double per = 1.0 / static_cast<double>(pixels);
  const double passes = static_cast<double>(pixels + reflections) * per;  // 1 + the reflections, on average
  Operations ops;
  if (p.units) {  // an upper bound there: the cull spares camera rays most spheres
    add(ops, w.camera_rays, 1);
    add(ops, w.unit_sphere_test, passes * static_cast<double>(spheres));
    add(ops, w.unit_shade_reflect, 3 * passes);  // a channel at a time
    return ops;
  }
  add(ops, w.ray_setup, passes);
  add(ops, w.sphere_test, passes * static_cast<double>(spheres));
  add(ops, w.reflect, static_cast<double>(reflections) * per);
  return ops;
}

}  // namespace tripsitter::device

// What the device would take on the board's FPGA (docs/device.md, "Resources"): the multiplies of each
// datapath block with their operand widths, DSP48E1 slices per worker and how many workers fit the XC7A100T,
// the memories in block RAM, and the operations a frame's pixels cost.
//
// Assumption: a DSP48E1 multiplies 25 x 18 bits signed, so an unsigned a x b magnitude product takes
// ceil(a / 24) * ceil(b / 17) slices in the cheaper orientation (partial products summed in the slices' adders).
// Every multiply of a block gets its own slices (a fully parallel datapath). Each worker has its own sphere-test
// pipeline; the path preset's scatter unit is one pipelined unit shared by all workers. Constant multiplies (the
// seed hash) are counted as multiplies too. The artix preset has sphere units instead of workers (dsp_per_worker is
// then per unit), each with its own shading and reflection block taking one channel a cycle, and one camera-ray
// block; its scene memory adds the per-world constants (e, r^2 / 4^e, 1 / r: 58 bits) and has a replica per pair
// of units (one read port each), its cull keeps 40 bits of screen bounds per sphere (two copies), and each pair
// of units reads the line's tile lists from its own double-buffered copy (spheres x tiles entries of the sphere
// index's bits), besides the 313 x 17-bit seed table of the camera rays. These are the model's plan until the
// preset's RTL is synthesised.
//
// Block RAM is counted in RAMB18E1 halves (18 Kbit; a 36-Kbit RAMB36E1 is two). Assumption: each memory takes
// its own halves, in the one aspect ratio (depth x width) of 16384x1, 8192x2, 4096x4, 2048x9, 1024x18 and 512x36
// that needs the fewest: ceil(W / w) * ceil(D / d) for a memory of D entries of W bits (512x36 is the
// simple-dual-port shape: one read and one write port). The memories: the two line buffers (640 x 12 bits); the
// two copies of scene memory, an entry per sphere of the preset's x, y, z and radius bits plus the surface fields
// its workers read (the mirror model with bounces: a metal bit and the 24-bit albedo; the path preset: the v2
// wire's 2-bit material, 24-bit albedo, 16-bit fuzz and 16-bit u4.12 index of refraction, as carried; none
// otherwise), one copy serving every worker; the path preset's tables, once (the scatter unit and the display
// are shared): reciprocals 256 x 19 bits (2^18 / count, up to 2^18), sRGB 512 x 8, reciprocal square roots
// 192 x 17 (approx::RsqrtTable) and the quarter-wave sine 1025 x 15 (approx::SineTable, up to 2^14); and frame
// memory, 640 x 480 x 64 bits, when DevicePath::frame_memory places it in block RAM. The 4x4 dither thresholds
// are logic, not memory.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/preset.h>

namespace tripsitter::device {

// The XC7A100T of the report's board.
inline constexpr int kBoardDsp = 240;
inline constexpr std::int64_t kBoardBramBits = 4'860 * 1024;  // 135 blocks of 36 Kbit
inline constexpr std::int64_t kRamb18Bits = 18 * 1024;        // a RAMB18E1, half a 36-Kbit block
inline constexpr int kBoardRamb18 = static_cast<int>(kBoardBramBits / kRamb18Bits);  // 270

int dsp_slices(int a_bits, int b_bits);

// RAMB18E1 halves a memory of `depth` entries of `width` bits takes in its best aspect ratio (0 when empty).
int ramb18_count(std::int64_t depth, int width);

// One memory of the design in block RAM.
struct BramMemory {
  std::string name;
  std::int64_t depth = 0;  // entries
  int width = 0;           // bits per entry
  int ramb18 = 0;          // ramb18_count(depth, width)
  bool operator==(const BramMemory&) const = default;
};

// One block of a datapath, as used once: its multiplies (operand magnitude bits, count) and other operations.
struct Block {
  std::string name;
  std::vector<std::pair<std::pair<int, int>, int>> multiplies;  // {{a_bits, b_bits}, count}
  int additions = 0;
  int square_roots = 0;
  int divisions = 0;
  int dsp() const;
};

// The blocks of a preset's worker (widths grow with the formats beyond 24 bits, as the Widths table does).
struct WorkerBlocks {
  Block ray_setup;    // a = d.d, per ray
  Block sphere_test;  // b, c', b^2, 4ac', D, sqrt, num, compare: per ray and sphere
  Block reflect;      // the mirror model's reflection
  // The path preset's: per bounce the hit point and normal, then the material's; per sample the seed hash;
  // per escaping ray the sky; per pixel the frame-memory accumulate and display.
  Block hit_point, normalise, random_unit, lambertian, metal, dielectric_common, dielectric_reflect,
      dielectric_refract, throughput, sky, seed_hash, accumulate;
  // The artix preset's (artix_kernel.h), per sphere unit: the unit's pair a cycle (b, f, f.f in the sphere's scale),
  // and its shading and reflection block, one channel a cycle; once per device: the camera rays' directions.
  Block unit_sphere_test, unit_shade_reflect, camera_rays;
};
WorkerBlocks worker_blocks(const DevicePreset& preset);

struct Resources {
  int dsp_per_worker = 0;   // the sphere-test pipeline and ray set-up, plus the mirror model's reflect unit
  int dsp_shared = 0;       // once per device: the path preset's scatter unit and display
  int workers_fitting = 0;  // in kBoardDsp
  std::int64_t frame_memory_bits = 0;  // path preset: 64 bits per pixel
  bool frame_memory_in_bram = false;   // whether frame memory's bits alone would fit the block RAM
  // External SRAM traffic: frame memory's read and write of every pixel once per line time (0 when frame memory
  // is in block RAM, or there is none).
  double frame_memory_bits_per_cycle = 0;
  // Block RAM: every memory of the design (the header's list) and their total, in whole RAMB18E1 halves and in
  // bits (halves times kRamb18Bits, so that Kbit figures are whole halves), against the XC7A100T's.
  std::vector<BramMemory> memories;
  int bram18 = 0;
  std::int64_t bram_bits = 0;
  bool bram_fits = false;  // bram_bits <= kBoardBramBits
};
Resources resources(const DevicePreset& preset);

// Operations per pixel of a path frame, from its counters: multiplies by operand widths ("AxB"), additions,
// square roots, divisions and random draws, averaged over `pixels`. Sphere tests count every sphere of every
// ray, as the hardware tests them all.
struct Operations {
  std::map<std::string, double> multiplies;
  double additions = 0, square_roots = 0, divisions = 0, random_draws = 0;
  double total_multiplies() const;
};
Operations path_operations_per_pixel(const DevicePreset& preset, const PathCounters& counters, std::int64_t spheres,
                                     std::uint64_t pixels);
// Operations per pixel of the mirror model's frame of `pixels` pixels that traced `reflections` reflections
// (FrameStats::reflections) with `spheres` spheres: each pixel makes 1 + its reflections passes, each pass a ray
// set-up (a = d.d) and a sphere test per sphere, and each reflection one reflect block (worker_blocks). The
// normal-map shading is not in the ledger (as in the DSP count), nor the tint of reflected colours. The artix
// preset: a camera ray, every pass's sphere tests (every sphere: an upper bound, as its cull spares camera rays
// most of them) and each pass's shading or reflection, a channel at a time.
Operations mirror_operations_per_pixel(const DevicePreset& preset, std::int64_t spheres, std::uint64_t reflections,
                                       std::uint64_t pixels);

}  // namespace tripsitter::device

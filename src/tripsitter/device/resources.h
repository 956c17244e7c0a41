// What the device would take on the board's FPGA (docs/device.md, "Resources"): the multiplies of each
// datapath block with their operand widths, DSP48E1 slices per worker and how many workers fit the XC7A100T,
// the path preset's frame memory against the block RAM, and the operations a frame's pixels cost.
//
// Assumption: a DSP48E1 multiplies 25 x 18 bits signed, so an unsigned a x b magnitude product takes
// ceil(a / 24) * ceil(b / 17) slices in the cheaper orientation (partial products summed in the slices' adders).
// Every multiply of a block gets its own slices (a fully parallel datapath). Each worker has its own sphere-test
// pipeline; the path preset's scatter unit is one pipelined unit shared by all workers. Constant multiplies (the
// seed hash) are counted as multiplies too.
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

int dsp_slices(int a_bits, int b_bits);

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
};
WorkerBlocks worker_blocks(const DevicePreset& preset);

struct Resources {
  int dsp_per_worker = 0;   // the sphere-test pipeline and ray set-up, plus the mirror model's reflect unit
  int dsp_shared = 0;       // once per device: the path preset's scatter unit and display
  int workers_fitting = 0;  // in kBoardDsp
  std::int64_t frame_memory_bits = 0;  // path preset: 64 bits per pixel
  bool frame_memory_in_bram = false;
  double frame_memory_bits_per_cycle = 0;  // read and write of every pixel once per line time
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

}  // namespace tripsitter::device

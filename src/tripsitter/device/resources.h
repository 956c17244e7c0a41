// What the device takes of the board's FPGA (docs/device.md, "Resources"): the multiplies of each datapath block
// with their operand widths, DSP48E1 slices per worker and how many workers fit the XC7A100T, the memories in
// block RAM, and the operations a frame's pixels cost.
//
// Two ledgers. A preset with RTL (wide, board-2023 and their variants: ts_device's per-pixel mirror-model workers;
// artix: ts_artix_device's sphere units) is counted as its RTL is built: rtl_blocks, below, a model of what Yosys's
// synth_xilinx makes of each block of the preset's top, held within 10% of the synthesis table rtl/synth_table.tsv
// by resources_test.cpp. The path preset, which has no RTL, is counted as planned, with the assumptions that follow.
//
// The plan's assumptions. A DSP48E1 multiplies 25 x 18 bits signed, so an unsigned a x b magnitude product takes
// ceil(a / 24) * ceil(b / 17) slices in the cheaper orientation (partial products summed in the slices' adders).
// Every multiply of a block gets its own slices (a fully parallel datapath). Each worker has its own sphere-test
// pipeline; the path preset's scatter unit is one pipelined unit shared by all workers. Constant multiplies (the
// seed hash) are counted as multiplies too.
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
inline constexpr int kBoardLuts = 63'400;
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
  int ramb18 = 0;          // RAMB18E1 halves: ramb18_count(depth, width), or as Yosys maps the RTL's (rtl_blocks)
  int lutram = 0;          // LUTs when the RTL's memory is LUT RAM (then ramb18 is 0)
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
  // and its shading and reflection block, one channel a cycle; once per device: the camera rays' directions. Their
  // operations per pixel (mirror_operations_per_pixel); the resources are its RTL's (rtl_blocks).
  Block unit_sphere_test, unit_shade_reflect, camera_rays;
};
WorkerBlocks worker_blocks(const DevicePreset& preset);

// --- What Yosys builds of the device's RTL (rtl/) ---
//
// For the presets of per-pixel mirror-model workers (wide, board-2023 and their variants), the ledger counts what
// ts_device builds as the preset configures it, and for the artix preset what ts_artix_device builds with the
// preset's units, block by block, as Yosys 0.23's synth_xilinx -family xc7 maps it (docs/device.md, "The ledger and
// Yosys"); resources_test.cpp holds it within 10% of the synthesis table scripts/synth.sh records in
// rtl/synth_table.tsv. The blocks are the table's (scripts/synth.sh says which modules each holds).
//
// DSP48E1: every product of the RTL with the operand widths Yosys sees (its wreduce pass drops sign and zero
// extension), tiled as its mul2dsp pass tiles it (yosys_product); constant multiplies take slices like the others.
// Block RAM: each memory with its ports as Yosys's memory mapping places it (LUT RAM while it costs no more LUTs
// than 64 for each RAMB18 it would take).
// LUTs: the block's adders, subtractors and comparators (a LUT a bit, on a carry chain), multiplexers (a LUT6
// selects among 4), shifters, and the partial sums of products tiled in two directions, with the unit costs and the
// few measured constants resources.cpp states beside each block; LUT RAM (the artix blocks' delays are rings in it)
// and shift registers as LUTs as memory.

// A product's DSP48E1 slices and fabric LUTs as Yosys tiles it: a 25 x 18 signed slice; a wider operand is cut into
// 17-bit pieces (and an unsigned one made signed by a bit); pieces along one operand are summed in the slices'
// cascade, pieces along both in fabric adders. Operand widths as Yosys sees them after wreduce; y_bits: the
// product's width as used.
struct ProductTiling {
  int dsp = 0;
  int luts = 0;
};
ProductTiling yosys_product(int a_bits, bool a_signed, int b_bits, bool b_signed, int y_bits);

// One block of ts_device, per instance.
struct RtlBlock {
  std::string name;         // as in rtl/synth_table.tsv
  int instances = 1;        // in the top
  bool per_worker = false;  // one in each worker or sphere unit (instances = the preset's workers)
  int dsp = 0;              // DSP48E1
  int luts = 0;             // LUTs as logic
  int lutram = 0;           // LUTs as memory
  int ramb18 = 0;           // RAMB18E1 halves (a RAMB36E1 is two)
  std::vector<BramMemory> memories;  // its memories, in block RAM or LUT RAM
  int total_luts() const { return luts + lutram; }
};
// The blocks of the preset's top as `preset` configures it, `wire` its link version (rtl_wire: v3 with bounces, else
// v2): ts_device for a preset of per-pixel mirror-model workers, ts_artix_device for artix (its blocks scale with the
// units: a unit's own blocks, scene memory's and the tile lists' replicas per pair, the constants' per unit, the line
// buffers' banks); empty for the path preset, which has no RTL. Where the top cannot be built as configured (has_rtl
// false: for ts_device bounces with formats over 24 bits, or without pipelining; for ts_artix_device anything but its
// package's formats, capacity, bounces, latencies and tiles) the blocks extrapolate the RTL's width rules, so that
// explore's sweeps stay on one ledger.
std::vector<RtlBlock> rtl_blocks(const DevicePreset& preset, int wire);
std::vector<RtlBlock> rtl_blocks(const DevicePreset& preset);
int rtl_wire(const DevicePreset& preset);
bool has_rtl(const DevicePreset& preset);  // ts_device builds the preset's configuration as it is

struct Resources {
  // A preset with RTL: the blocks of rtl_blocks, and DSP48E1 per worker or sphere unit (its blocks: ts_device's
  // worker logic, sphere test, square-root unit, shading, reflection; ts_artix_device's unit, sphere unit, shading
  // and reflection) and shared (the rest: artix's camera and cull). The path preset (no blocks): the plan's count
  // (the header's assumptions).
  std::vector<RtlBlock> blocks;
  int dsp_per_worker = 0;   // the plan: the sphere-test pipeline and ray set-up, plus the reflect unit
  int dsp_shared = 0;       // once per device (the plan: the path preset's scatter unit and display)
  int luts = 0;             // the blocks' LUTs, as logic and as memory (0 without blocks)
  int workers_fitting = 0;  // in kBoardDsp
  // With blocks: the most workers (artix: units), from 1 up, whose blocks fit the XC7A100T's DSP48E1, LUTs and
  // block RAM all three, and which of them stops one more (0 and "" without blocks, or when not even one fits).
  int workers_fitting_chip = 0;
  std::string chip_limit;
  std::int64_t frame_memory_bits = 0;  // path preset: 64 bits per pixel
  bool frame_memory_in_bram = false;   // whether frame memory's bits alone would fit the block RAM
  // External frame memory's traffic: its read and write of every pixel once per line time, in bits per device cycle
  // (0 when frame memory is in block RAM, or there is none).
  double frame_memory_bits_per_cycle = 0;
  // The external part (frame_dram.h; empty when frame memory is in block RAM or there is none), the FPGA pins it
  // takes, and a frame's traffic through it: the worst line period's bytes as a share of what its pins carry in a
  // line period, and the share of the line period the controller takes for them (dram::LineTraffic).
  std::string frame_memory_part;
  int frame_memory_pins = 0;
  double frame_memory_demand = 0;
  double frame_memory_busy = 0;
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
// normal-map shading and the tint are not counted here (rtl_blocks counts their slices). The artix
// preset: a camera ray, every pass's sphere tests (every sphere: an upper bound, as its cull spares camera rays
// most of them) and each pass's shading or reflection, a channel at a time.
Operations mirror_operations_per_pixel(const DevicePreset& preset, std::int64_t spheres, std::uint64_t reflections,
                                       std::uint64_t pixels);

}  // namespace tripsitter::device

#include <tripsitter/device/resources.h>

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <utility>

#include <tripsitter/core/screen.h>
#include <tripsitter/device/artix_kernel.h>
#include <tripsitter/device/frame_dram.h>
#include <tripsitter/device/frame_memory.h>

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
  Resources out;
  out.blocks = rtl_blocks(p);
  if (!out.blocks.empty()) {  // the RTL, as Yosys builds it
    for (const RtlBlock& b : out.blocks) {
      if (b.per_worker) out.dsp_per_worker += b.dsp;
      else out.dsp_shared += b.dsp * b.instances;
      out.luts += b.total_luts() * b.instances;
      out.bram18 += b.ramb18 * b.instances;
      for (const BramMemory& m : b.memories)
        for (int k = 0; k < b.instances; ++k) out.memories.push_back(m);
    }
    out.workers_fitting = out.dsp_per_worker > 0 ? std::max(0, (kBoardDsp - out.dsp_shared) / out.dsp_per_worker) : 0;
    out.bram_bits = std::int64_t{out.bram18} * kRamb18Bits;
    out.bram_fits = out.bram_bits <= kBoardBramBits;
    // The most workers or units that fit all three: the ledger at 1, 2, ... until one does not.
    for (int n = 1; n < kLineWidth; ++n) {
      DevicePreset q = p;
      q.workers = n;
      int dsp = 0, luts = 0, ramb18 = 0;
      for (const RtlBlock& b : rtl_blocks(q)) {
        dsp += b.dsp * b.instances;
        luts += b.total_luts() * b.instances;
        ramb18 += b.ramb18 * b.instances;
      }
      out.chip_limit = dsp > kBoardDsp         ? "DSP48E1"
                       : luts > kBoardLuts       ? "LUTs"
                       : ramb18 > kBoardRamb18   ? "block RAM"
                                                 : "";
      if (!out.chip_limit.empty()) break;
      out.workers_fitting_chip = n;
    }
    return out;
  }
  const WorkerBlocks w = worker_blocks(p);
  out.dsp_per_worker = w.ray_setup.dsp() + w.sphere_test.dsp();
  // The path presets' shared scatter unit beyond the hit point: the bounce by material, the sky, the seeds and the
  // accumulation.
  int scatter_dsp = 0;
  for (const Block* b : {&w.normalise, &w.random_unit, &w.lambertian, &w.metal, &w.dielectric_common,
                         &w.dielectric_reflect, &w.dielectric_refract, &w.throughput, &w.sky, &w.seed_hash,
                         &w.accumulate})
    scatter_dsp += b->dsp();
  if (p.path && p.units) {
    // The artix path preset, before its RTL: a sphere unit each, and once the camera, the cull and the scatter
    // unit the units share, which takes the units' hit point and normal (their shading and reflection block's
    // products) and the path preset's bounce, sky, seeds and accumulation.
    out.dsp_per_worker = w.unit_sphere_test.dsp();
    out.dsp_shared = w.camera_rays.dsp() + 1 + w.unit_shade_reflect.dsp() + scatter_dsp;
  } else if (p.path) {
    // One pipelined scatter unit serves every worker: a pixel's bounces are a few against its rays * spheres
    // sphere tests, so a line's bounces (about 640 * 1.5 at 1 spp) need far fewer than its 3200 cycles, one
    // accepted per cycle. Its normalisation serves the normal, the incoming direction and the sky in turn, so it
    // is there once. (The cycle model charges each bounce its latency and ignores two workers meeting there in
    // the same cycle: docs/device.md.)
    out.dsp_shared = w.hit_point.dsp() + scatter_dsp;
  } else if (p.max_bounces > 0) {
    out.dsp_per_worker += w.reflect.dsp();
  }
  if (p.path) {
    out.frame_memory_bits = std::int64_t{kAccumEntryBits} * core::kScreenWidth * core::kScreenHeight;
    out.frame_memory_in_bram = out.frame_memory_bits <= kBoardBramBits;
    if (p.path->frame_memory == FrameMemoryPlace::kExternal) {
      out.frame_memory_bits_per_cycle = 2.0 * kAccumEntryBits * kLineWidth / kLineCycles;
      static const dram::LineTraffic traffic = dram::frame_traffic(kAccumEntryBits);
      out.frame_memory_part = dram::kPartName;
      out.frame_memory_pins = dram::kPins;
      out.frame_memory_demand = traffic.demand();
      out.frame_memory_busy = traffic.busy();
    }
  }
  out.workers_fitting = std::max(0, (kBoardDsp - out.dsp_shared) / out.dsp_per_worker);
  out.memories = bram_memories(p);
  for (const BramMemory& m : out.memories) out.bram18 += m.ramb18;
  out.bram_bits = std::int64_t{out.bram18} * kRamb18Bits;
  out.bram_fits = out.bram_bits <= kBoardBramBits;
  return out;
}


// --- The RTL's blocks (resources.h) ---

namespace {

int clog2(std::int64_t v) {  // SystemVerilog's $clog2
  int bits = 0;
  while ((std::int64_t{1} << bits) < v) ++bits;
  return bits;
}

// The worker's widths, as ts_worker.sv derives them from the formats (docs/device.md, "Widths").
struct WorkerWidths {
  int cw, rw, lw, extra, dw, aaw, ow, ocw, bw, cpw, sqm, dsw, rtw, numw, yw, pw, aw;
  bool reflect;
  bool shared;  // the one-pixel-at-a-time worker (not pipelined): the shading borrows the sphere test's multipliers
};

WorkerWidths worker_widths(const DevicePreset& p) {
  WorkerWidths w{};
  w.cw = std::max({p.x.total_bits, p.y.total_bits, p.z.total_bits});
  w.rw = p.radius.total_bits;
  w.lw = std::max(w.cw, w.rw);
  w.extra = std::max(0, w.lw - 24);
  w.reflect = p.max_bounces > 0;
  w.shared = !p.costs.pipelined;
  w.dw = w.reflect ? 22 : 10;
  w.aaw = w.reflect ? 42 : 19;
  w.ow = w.reflect ? 26 + w.extra : 1;
  w.ocw = w.reflect ? 27 + w.extra : w.cw;
  w.bw = w.reflect ? 49 + w.extra : w.cw + 11;
  w.cpw = w.reflect ? 52 + 2 * w.extra : 2 * w.lw + 1;
  w.sqm = w.reflect ? 95 + 2 * w.extra : std::max(2 * w.cw + 20, 2 * w.lw + 21);
  w.dsw = w.sqm + 1;
  w.rtw = (w.sqm + 1) / 2 + 1;
  w.numw = std::max(w.bw, w.rtw + 1) + 1;
  w.yw = w.reflect ? 75 + w.extra : w.lw + 25;
  w.pw = w.reflect ? 8 * p.max_bounces : 1;
  w.aw = std::max(1, clog2(p.max_spheres));
  return w;
}

RtlBlock named(std::string name) {
  RtlBlock b;
  b.name = std::move(name);
  return b;
}

// Unit costs of LUT mapping. An adder, subtractor or magnitude comparator of two variable operands: a LUT a bit
// (feeding a CARRY4); n operands summed: n - 1 adders. A k-input multiplexer: a LUT6 selects among 4, so
// ceil((k - 1) / 3) LUTs a bit. A shifter: each output bit selects among the positions, in stages of 4:1
// (ceil(log4 positions)), half as many again for the wider inner stages. A comparison with a constant or an
// equality: a LUT for 6 or 3 bits.
int adder(int bits, int operands = 2) { return bits * (operands - 1); }
int mux(int bits, int inputs = 2) { return bits * ((inputs + 1) / 3); }
int shifter(int out_bits, int positions) { return out_bits * ((clog2(positions) + 1) / 2) * 3 / 2; }
int equal(int bits) { return (bits + 2) / 3; }
int compare_constant(int bits) { return (bits + 5) / 6; }

// Calibrated: what the counts of the shading and the reflection leave out, the registers' loads and choices that
// their pipelines and step sequencing build and the products' sign extension, is about a tenth of what they count
// (ts_shade: Yosys 1,372 and 3,985 LUTs for board-2023 and wide, against 1,302 and 3,559 counted).
int glue(int counted) { return counted / 10; }

// A product through yosys_product, added to a block.
void product(RtlBlock& b, int count, int a_bits, bool a_signed, int b_bits, bool b_signed, int y_bits) {
  const ProductTiling t = yosys_product(a_bits, a_signed, b_bits, b_signed, y_bits);
  b.dsp += count * t.dsp;
  b.luts += count * t.luts;
}

// How a memory's ports are used: one write port and one read port (kWriteRead); a write port that reads too and
// another port that reads (kReadOnWrite: a true dual port); one port that writes and reads (kSingle).
enum class Ports { kWriteRead, kReadOnWrite, kSingle };

// A memory of depth x width, as Yosys's memory mapping places it, by cost: in LUT RAM (RAM32M: 32 x 6 bits in 4
// LUTs, RAM64M: 64 x 3 in 4, with separate write and read addresses; RAM64X1D: 64 x 1 in 2 when the write port
// reads too; RAM64X1S: 64 x 1 in 1 for a single port), or in block RAM (ramb18_count's shapes, 512 x 36 only
// without a second port beside a reading write port), a RAMB18 costing as much as 64 LUTs. Measured on
// ts_line_buffers' banks of 13 bits: 54 to 160 deep in LUT RAM, 214 and 320 in block RAM. LUT RAM deeper than its
// cells is cut in depth, each read port choosing among the pieces and each piece's write enabled by its own decode
// (measured on the artix preset's banks of 72: 16 LUTs each besides the 36 of RAM32M).
void memory(RtlBlock& b, std::string name, std::int64_t depth, int width, Ports ports) {
  BramMemory m{std::move(name), depth, width, 0, 0};
  const auto cells = [&](std::int64_t d, int w) {
    return static_cast<int>(((depth + d - 1) / d) * ((width + w - 1) / w));
  };
  int lutram = 0;
  std::int64_t cell_depth = 64;
  if (ports == Ports::kReadOnWrite) {
    lutram = 2 * cells(64, 1);
  } else if (ports == Ports::kSingle) {
    lutram = cells(64, 1);
  } else {
    lutram = 4 * std::min(cells(32, 6), cells(64, 3));
    if (cells(32, 6) < cells(64, 3)) cell_depth = 32;
  }
  int halves = std::numeric_limits<int>::max();
  for (const auto& [d, w] : std::array<std::pair<std::int64_t, int>, 6>{
           {{16384, 1}, {8192, 2}, {4096, 4}, {2048, 9}, {1024, 18}, {512, 36}}})
    if (w <= 18 || ports != Ports::kReadOnWrite) halves = std::min(halves, cells(d, w));
  if (lutram <= 64 * halves) {
    m.lutram = lutram;
    const int pieces = static_cast<int>((depth + cell_depth - 1) / cell_depth);
    if (pieces > 1) b.luts += (ports == Ports::kReadOnWrite ? 2 : 1) * width * ((pieces + 3) / 4) + pieces;
  } else {
    m.ramb18 = halves;
  }
  b.lutram += m.lutram;
  b.ramb18 += m.ramb18;
  b.memories.push_back(std::move(m));
}

// ts_sphere_test.sv without its square-root unit: the camera ray's squares and a, oc = c - o, seven products, b
// and c' (summed in the slices' post-adders when each product takes one slice), b^2 and 4ac', D clamped at 0,
// num = b - sqrt(D) and the hit.
RtlBlock sphere_test(const WorkerWidths& w) {
  RtlBlock b = named("sphere_test");
  if (w.shared) {
    // The one-pixel worker's nine multipliers serve more than one use each (ts_sphere_test.sv, "Multipliers"): the
    // camera ray's dx^2 and dy^2 on those of d_x oc_x and d_y oc_y, a cycle earlier; the shading's a oc_k on those
    // of oc_k^2 (a: AAW + 1 bits signed), a r on that of r^2, num d_x and num d_y on those of b^2 and 4ac'. Each
    // multiplier's operands are chosen by the cycle's use.
    const int qw = std::max(w.aaw + 1, w.ocw);
    const int rqw = std::max(w.aaw, w.rw);
    product(b, 3, w.ocw, true, qw, true, w.ocw + qw);      // oc_k^2, a oc_k
    product(b, 1, w.rw, false, rqw, false, w.rw + rqw);    // r^2, a r
    b.luts += 2 * (mux(w.dw) + mux(w.ocw));                // d_x oc_x, d_y oc_y, or the squares
    b.luts += 3 * (mux(w.ocw) + mux(qw)) + mux(w.rw) + mux(rqw);  // oc_k^2 or a oc_k; r^2 or a r
    b.luts += 2 * mux(w.bw) + mux(w.aaw + 1) + mux(w.cpw);  // b^2 or num d_x; a c' or num d_y
    // Calibrated: beside those choices Yosys builds 166 LUTs more than for the sphere test with multipliers of its
    // own (board-2023, one worker: 469 with the choices taken out of the RTL, 303 unshared), where the products the
    // shading takes leave the module in their own cycle, unregistered. Not derived.
    b.luts += 166;
  } else {
    product(b, 1, 11, true, 11, true, 18);                // dx^2
    product(b, 1, 10, true, 10, true, 18);                // dy^2
    product(b, 3, w.ocw, true, w.ocw, true, 2 * w.ocw);    // oc_k^2
    product(b, 1, w.rw, false, w.rw, false, 2 * w.rw);     // r^2
  }
  product(b, 3, w.dw, true, w.ocw, true, w.dw + w.ocw);  // d_k oc_k (dz = 320 on camera rays: a constant)
  product(b, 1, w.bw, true, w.bw, true, w.dsw);          // b^2
  product(b, 1, w.aaw + 1, true, w.cpw, true, w.dsw);    // 4 a c'
  b.luts += 2 * (adder(11) + adder(10));                 // the pixel's dx, dy (at the input and for the d mux)
  b.luts += adder(19);                                   // a = dx^2 + dy^2 + 320^2
  if (w.reflect) b.luts += 3 * adder(w.ocw) + 3 * mux(w.dw) + mux(w.aaw);  // oc = c - o; the reflected ray's d, a
  if (yosys_product(w.dw, true, w.ocw, true, w.dw + w.ocw).dsp > 1) b.luts += adder(w.bw, 3);
  if (yosys_product(w.ocw, true, w.ocw, true, 2 * w.ocw).dsp > 1) b.luts += adder(w.cpw, 4);
  b.luts += adder(w.dsw) + mux(w.sqm);                   // D, and 0 when negative
  b.luts += adder(w.numw) + compare_constant(w.numw);    // num, num > 0
  b.luts += 20;                                          // valid, kill and hit logic
  return b;
}

// ts_sqrt_unit.sv: the leading zero pairs, the normalising shift, N steps (a stage each when pipelined, one unit
// used N times otherwise) and the rounding shift.
RtlBlock sqrt_unit(const WorkerWidths& w, const DevicePreset& p) {
  RtlBlock b = named("sqrt_unit");
  const int n = p.sqrt_iterations;
  const int mw = 2 * n;
  const int pairs = (w.sqm + 1) / 2;
  b.luts += pairs;                                      // leading zero pairs
  b.luts += shifter(mw, pairs + 1);                     // m = the top 2N bits of D 4^z
  b.luts += shifter(pairs + 1, pairs + 1) + adder(pairs + 1);  // round(x 2^e / 2^N)
  if (p.costs.pipelined) {
    // Stage k: c < m over 2N + 1 bits, c +- x 2^-k + 2^-2(k+1) (two adders and a choice), x +- 2^-(k+1). The
    // bits of c and x below the step are constant zeros Yosys removes: the adders are 2k + 3 bits wide.
    for (int k = 0; k < n; ++k) {
      const int live = 2 * k + 3;
      b.luts += live + compare_constant(mw + 1 - live);  // c < m
      b.luts += 2 * adder(live) + mux(live);
      b.luts += 2 * adder(k + 1) + mux(k + 1);
    }
  } else {
    b.luts += adder(mw + 1);                             // c < m
    b.luts += 2 * (2 * adder(mw + 1) + mux(mw + 1));     // c and x 2^-k, each up or down
    b.luts += 20;                                        // the iteration counter, phase and busy
  }
  return b;
}

// ts_shade.sv: 7 num, 7 oc_k - 8 r and den = 2ar; the six products (7 num) d_k and 2a (7 oc_k - 8 r); Y_k; four
// restoring division steps a channel (a subtraction and a choice each); with reflections the tint: B_k times the
// albedos' product and four more steps by 255^k.
RtlBlock shade(const WorkerWidths& w, const DevicePreset& p) {
  RtlBlock b = named("shade");
  const int n7w = w.numw + 3;
  const int ww = std::max(w.ocw, w.rw) + 5;
  const int denw = w.aaw + 1 + w.rw;
  const int remw = std::max(w.yw, denw + 4);
  if (w.shared) {
    // The products come in from the sphere test's multipliers (num d_x, num d_y, a oc_k, a r: SHARED = 1); num d_z
    // is the camera's 320 num, shifts and adds, and so are (7 num) d_k and 2a (7 oc_k - 8 r) from them.
    b.luts += adder(w.yw) + 3 * adder(w.yw) + 3 * adder(w.yw, 3);
  } else {
    product(b, 1, w.aaw, false, w.rw, false, denw);        // den = 2ar
    product(b, 3, n7w, true, w.dw, true, w.yw);            // (7 num) d_k
    product(b, 3, w.aaw + 1, false, ww, true, w.yw);       // 2a (7 oc_k - 8 r)
    b.luts += adder(n7w) + 3 * adder(ww, 3);               // 7 num; 7 oc_k - 8 r
  }
  b.luts += 3 * adder(w.yw);                               // Y_k
  b.luts += 3 * 4 * (adder(remw) + mux(remw + 1));         // the quotient bits
  b.luts += 3 * 8;                                         // the clamp and the background
  if (p.max_bounces > 0) {
    const int xw = w.pw + 4;
    product(b, 3, 4, false, w.pw, false, xw);              // B_k prod(albedo)
    b.luts += 3 * 4 * (adder(xw) + mux(xw + 1)) + 10;      // the tint's quotient bits; 255^k
    for (int k = 2; k <= p.max_bounces; ++k) product(b, 1, xw, false, 8, false, xw);  // 255^k: a variable times 255
  }
  b.luts += glue(b.luts);
  return b;
}

// ts_reflect.sv: the multiples of 2a, three radix-8 dividers (seven comparisons, an 8:1 choice and a subtraction a
// digit), the hit point and normal, the two shared multipliers per axis with their operand choices, m.m and d.m,
// r_k and |r_k|, the bit length, and d' = r / 2^s rounded.
RtlBlock reflect(const WorkerWidths& w) {
  RtlBlock b = named("reflect");
  const int ew = w.aaw + 1;
  const int prw = ew + 3;
  const int vw = w.numw + w.dw + 1;
  const int qw = 27;
  const int mw = w.ow;
  const int mmw = 2 * mw - 2;
  const int dmw = w.dw + mw - 1;
  const int rrw = w.dw + mmw + 1;
  const int xaw = std::max(w.numw, mmw + 1);
  const int yaw = std::max(mw, w.dw + 1);
  const int xbw = std::max(dmw, w.dw);
  product(b, 3, xaw, true, yaw, true, xaw + yaw);          // A: num |d_k|, m_k^2, (m.m) d_k, d'_k^2
  product(b, 3, xbw, true, mw, true, xbw + mw);            // B: d_k m_k, (d.m) m_k
  b.luts += 3 * adder(prw);                                // 3, 5 and 7 times 2a
  b.luts += 3 * adder(vw);                                 // V_k = num |d_k| + a
  b.luts += 3 * (7 * adder(prw) + mux(prw, 8) + adder(prw));  // a digit
  b.luts += 3 * 2 * mux(qw);                               // the quotient and the dividend's digits
  b.luts += 3 * (2 * mux(qw) + 2 * adder(mw));             // +-Q, p = o +- Q, m = +-Q - oc
  b.luts += 3 * (mux(xaw, 4) + mux(yaw, 4) + mux(xbw));    // the multipliers' operands
  b.luts += adder(mmw, 3) + adder(dmw, 3);                 // m.m, d.m
  b.luts += 3 * 3 * adder(rrw);                            // r_k and |r_k|
  b.luts += rrw / 3 + 14;                                  // the bit length, s
  b.luts += 3 * (2 * adder(rrw + 1) + shifter(w.dw, rrw - 20));  // d'_k: the bias, and r >> s
  b.luts += adder(w.aaw, 3);                               // a' = d'.d'
  b.luts += 30;                                            // the step counter
  b.luts += glue(b.luts);
  return b;
}

// ts_worker.sv's own logic: the issue (a queue of pixels in flight when pipelined, counters otherwise), the closest
// update (a comparison of num and a choice of the pass's nearest hit), the pass's ray and the albedos' products.
RtlBlock worker_control(const WorkerWidths& w, const DevicePreset& p) {
  RtlBlock b = named("worker");
  const int carried = w.numw + 3 * w.ocw + w.rw + w.aw + (w.reflect ? 25 : 0);  // the closest hit's fields
  b.luts += adder(w.numw) + mux(carried);                  // the closest update
  b.luts += 2 * adder(10) + 1;                             // the pass's camera ray
  if (p.costs.pipelined) {
    constexpr int kQueueBits = 6;                          // 32 pixels in flight and a wrap bit
    memory(b, "pixels in flight (worker)", 32, 10 + 9, Ports::kWriteRead);  // the queue of their columns and rows
    b.luts += 4 * adder(kQueueBits) + 2 * mux(kQueueBits); // head, issue, tail, in flight
    b.luts += 2 * adder(w.aw + 1) + mux(w.aw + 1) + equal(w.aw);  // the pass's next sphere, its last, the metal
    b.luts += mux(19) + 10 + 20;                           // the pixel issued; the stall counter; ready
  } else {
    const int cntw = w.aw + 8;
    // busy: loaded, or counted down (a decrement is a carry chain alone); the sphere slot's and index's counters
    b.luts += mux(cntw) + 2 * adder(6) + 3 * adder(w.aw + 1) + mux(w.aw + 1) + equal(w.aw + 1);
    b.luts += mux(19) + mux(12) + 10;                      // the pixel issued; the colour held
    // The occupancy: spheres times the cycles a sphere takes (45 on board-2023), a constant: shifts and adds, an
    // adder of the count's width for each of its set bits but one.
    const int per_sphere = p.costs.sphere_test + p.sqrt_iterations * p.costs.sqrt_cycles_per_iteration +
                           p.costs.closest_update;
    b.luts += (std::popcount(static_cast<unsigned>(per_sphere)) - 1) * adder(w.aw + 1);
  }
  if (w.reflect) {
    b.luts += 3 * mux(w.dw) + mux(w.aaw) + 3 * mux(w.ow);   // the pass's ray: camera or reflected
    product(b, 3, w.pw, false, 8, false, w.pw);            // the albedos' products
    b.luts += 3 * mux(w.pw);                               // reset to 1 at a new pixel
  }
  return b;
}

// The receiver (ts_receiver with ts_crc32 and ts_spi_rx; in ts_device under ts_receiver_top): every byte since a
// frame's start in a block-RAM buffer (the largest frame plus a quarter and 512 bytes), the header's and sphere
// records' checks, the counters, and on v3 the cut rule's window, a second CRC unit and the ring of ended sessions.
RtlBlock receiver(const DevicePreset& p, int wire) {
  RtlBlock b = named("receiver");
  const int buf_aw = clog2((wire == 3 ? 32 : 24) * 5 / 4 + 30 * std::int64_t{p.max_spheres} + 512);
  memory(b, "receiver's byte buffer", std::int64_t{1} << buf_aw, 8, Ports::kReadOnWrite);
  constexpr int kCounters = 10, kCounterBits = 32;
  const int crc_units = wire == 3 ? 2 : 1;
  b.luts += 7 + crc_units * 67;                         // the SPI slave; CRC-32 units (ts_crc32: 67 LUTs)
  b.luts += kCounters * adder(kCounterBits);            // ReceiverStats' counters
  // Calibrated: the engine (ts_receiver's blocks, ts_rx_frame, ts_rx_sequence, ts_rx_v1_word and ts_rx_commit: their
  // states, the header's and records' checks, buffer positions, the copy into scene memory; on v3 also the window,
  // the candidate header and the ring of 16 sessions) is Yosys's own count of the receiver less the counters, the
  // SPI slave and the CRC units: 409 LUTs on v2 with board-2023's formats, 1,544 on v3 with wide's, 1,402 on v3 with
  // artix's (narrower records, 256 spheres), as the synthesis table of the split receiver counts them (before the
  // split: 489, 2,219 and 2,076). Not derived.
  b.luts += wire == 3 ? (p.units ? 1402 : 1544) : 409;
  return b;
}

// Scene memory (ts_scene_memory): two copies of the world, a replica per pair of read ports (port A writes the back
// copy or reads for one, port B reads for the other), and each port's choice between the copies. With
// `odd_single`, the last replica of an odd count is a single-port memory (its port A alone), as Yosys maps it
// (measured on artix's 9 units: 512 x 72 halves).
RtlBlock scene_memory(const DevicePreset& p, int aw, bool odd_single) {
  RtlBlock b = named("scene_memory");
  const int n = p.workers;
  const int word = p.x.total_bits + p.y.total_bits + p.z.total_bits + p.radius.total_bits + 1 + 24;
  const int replicas = (n + 1) / 2;
  for (int k = 0; k < 2 * replicas; ++k) {
    const std::string copy = k % 2 ? "scene memory (back), replica " : "scene memory (front), replica ";
    const bool single = odd_single && n % 2 == 1 && k / 2 == replicas - 1;
    memory(b, copy + std::to_string(k / 2 + 1), std::int64_t{1} << aw, word,
           single ? Ports::kSingle : Ports::kReadOnWrite);
  }
  b.luts += n * mux(word) + 2 * replicas * mux(aw) + mux(aw + 1 + 32) + 6;
  return b;
}

// --- The artix preset's RTL (rtl/artix/: ts_artix_device) ---
//
// The datapath's register widths are the package's (rtl/artix/ts_artix_pkg.sv, which artix_pkg_test holds to the
// model): fixed by the arithmetic, whatever the formats. The memories' words and addresses take the preset's formats
// and capacity, and the unit count N sets the replicas (scene memory and the tile lists a pair of units each, the
// per-world constants one a unit), the line buffers' banks, each unit's pixel slots and the tile lists' read ports.
namespace pkg {
constexpr int kOriginW = artix::kOriginBits;  // 24
constexpr int kDirW = 18;
constexpr int kDirFrac = artix::kDirectionFrac;  // 17
constexpr int kOcW = artix::kOcBits;  // 25
constexpr int kBdW = 44;
constexpr int kFW = artix::kFBits;  // 48
constexpr int kExpW = 6;
constexpr int kR2sW = 34;
constexpr int kRinvW = 19;
constexpr int kSqrtW = 17;
constexpr int kTdW = 45;
constexpr int kHitFW = 39;  // a hit's f_k, carried to the shading
constexpr int kSceneReadCycles = 2;
constexpr int kUnitStages = 35;  // ts_artix_sphere_unit's registers, ports to result
}  // namespace pkg

// Unit costs of the artix blocks, beside those above, measured on Yosys's mapping of lone operators (synth_xilinx
// -family xc7): a choice among k inputs, up to 16, takes ceil(k / 4) LUTs in one slice (LUT6 4:1 joined by MUXF7
// and MUXF8): a 48-bit shift right by one of 8 multiples of 4 took 94 LUTs, by 0..3 47. A shift left by a variable
// amount goes in stages of 4:1, each as wide as its output so far (17 bits by 5 into 38: 95 LUTs; counted 90).
// Adding a constant takes no LUT (the carry chain takes the operand's bits as they are), nor do the bits of a
// subtraction from a constant zero (inverters, which Vivado folds into their neighbours and the table leaves out).
int select(int bits, int inputs) { return bits * ((inputs + 3) / 4); }

// x >>> (step k), k = 0 .. positions - 1, of a signed `bits`-bit x: each output bit chooses among its distinct
// inputs (a shift past the top brings the sign bit).
int shift_right(int bits, int positions, int step) {
  int luts = 0;
  for (int i = 0; i < bits; ++i) {
    const int within = std::min(positions, (bits - 1 - i) / step + 1);
    const int inputs = within + (within < positions && (bits - 1 - i) % step != 0 ? 1 : 0);
    if (inputs > 1) luts += (inputs + 3) / 4;
  }
  return luts;
}

// x << s of an `in_bits`-bit x by a `shift_bits`-bit s, kept to `out_bits`.
int shift_left(int in_bits, int shift_bits, int out_bits) {
  int luts = 0;
  int width = in_bits;
  for (int b = 0; b < shift_bits; b += 2) {
    const int stage = std::min(2, shift_bits - b);
    width = std::min(out_bits, width + ((1 << stage) - 1) * (1 << b));
    luts += width;
  }
  return luts;
}

// An `in_bits`-bit value saturated to +-(2^17 - 1) in `out_bits`: two comparisons with constants and a choice.
int saturate(int in_bits, int out_bits) { return 2 * compare_constant(in_bits) + out_bits; }

// ts_artix_delay: `width` bits `cycles` cycles: flip-flops for 1 or 2, from 3 on a ring of 2^ceil(log2 cycles)
// words in LUT RAM, its pointers counters with constant offsets (carry chains alone).
void delay(RtlBlock& b, int width, int cycles) {
  if (cycles >= 3)
    memory(b, "delay of " + std::to_string(width) + " bits by " + std::to_string(cycles),
           std::int64_t{1} << clog2(cycles), width, Ports::kWriteRead);
}

// ts_artix_fifo's pointers: the write and read positions (increments: carry chains alone), the count up and down,
// empty and the overflow check (Yosys: 16 LUTs for 32 entries).
int fifo_pointers(int aw) { return 2 * adder(aw + 1) + equal(aw + 1) + 2; }

struct ArtixWidths {
  int n = 1;           // units
  int coord = 22;      // x, y, z in scene memory
  int radius = 21;
  int aw = 8;          // a sphere's index
  int slot_w = 1;      // a unit's pixel slot (ceil(640 / N) slots)
  int tag_w = 1;       // what the shading carries of a pass: its slot and the sphere its reflection leaves
  int state_w = 1;     // a pixel between passes: slot, ray, the sphere left, a flag, bounces, tint
  int carry_w = 1;     // the hit sphere's fields the shading needs, carried through the sphere unit
  int tint_w = 24;     // a product of up to max_bounces albedo bytes
};

ArtixWidths artix_widths(const DevicePreset& p) {
  ArtixWidths w;
  w.n = p.workers;
  w.coord = std::max({p.x.total_bits, p.y.total_bits, p.z.total_bits});
  w.radius = p.radius.total_bits;
  w.aw = std::max(1, clog2(p.max_spheres));
  const int slots = (kLineWidth + w.n - 1) / w.n;
  w.slot_w = std::max(1, clog2(slots));
  w.tag_w = w.slot_w + w.aw;
  w.tint_w = 8 * std::max(1, p.max_bounces);
  w.state_w = w.slot_w + 3 * pkg::kOriginW + 3 * pkg::kDirW + w.aw + 1 + 2 + 3 * w.tint_w;
  w.carry_w = w.aw + w.radius + pkg::kRinvW + 1 + 24;
  return w;
}

// ts_artix_sphere_unit with its square root (ts_artix_isqrt) and delays: one pair a cycle. Nine products of one
// slice each (oc_k d_k, b d_k, F_k^2; two sums of each three in the slices' post-adders), the adders, the shifts by
// the sphere's scale, and the closest-hit register (its result and its best are one register: no choice).
RtlBlock artix_sphere_unit(const ArtixWidths& w, const DeviceUnits& u) {
  using namespace pkg;
  RtlBlock b = named("sphere_unit");
  product(b, 3, kOcW, true, kDirW, true, kOcW + kDirW);       // oc_k d_k
  product(b, 3, kOcW, true, kDirW, true, kOcW + kDirW);       // b d_k (b: 25 bits)
  product(b, 3, kDirW, true, kDirW, true, 2 * kDirW);         // F_k^2
  b.luts += 3 * adder(kOcW);                                  // oc = c - o
  b.luts += adder(kBdW);                                      // b d: the third product onto the post-adder's sum
  b.luts += 3 * adder(kFW - kDirFrac);                        // f = (oc << 17) - b d: its low bits a negation
  b.luts += 3 * (shift_right(kFW, 8, 4) + shift_right(kFW, 4, 1));  // F = f >> (17 + e): by 4s, then the rest
  b.luts += 3 * 2 * ((kFW - kDirW + 1 + 5) / 6);              // F_k beyond 18 bits: its top all ones or all zeros
  b.luts += adder(2 * kDirW);                                 // F.F: the third square onto the post-adder's sum
  b.luts += adder(2 * kDirW) + adder(kR2sW);                  // F.F > r^2 / 4^e, D = r^2 / 4^e - F.F
  b.luts += shift_left(kSqrtW, 5, kSqrtW + 21);               // s 2^(17 + e)
  b.luts += adder(kTdW);                                      // t d = b d - s 2^(17 + e)
  b.luts += adder(kTdW) + compare_constant(kTdW) + 5;         // t d below the pass's best, t d > 0, take
  // The square root: 17 digit steps, each a subtraction of the trial from the remainder (its borrow the comparison)
  // and a choice of the remainder, the last step the comparison alone.
  const int steps = kR2sW / 2;
  b.luts += steps * steps + (steps - 1) * steps;
  // Side data riding along, as the pipeline's comments list it: d (4 cycles), e (7), r^2 / 4^e (13), oc (5); D and
  // the flags (the pad before the root); b d, f, the carried fields and e to the result.
  const int pad = u.hit_latency + 1 - kSceneReadCycles - kUnitStages;
  for (int k = 0; k < 3; ++k) {
    delay(b, kDirW, 4);
    delay(b, kOcW, 5);
  }
  delay(b, kExpW, 7);
  delay(b, kR2sW, 13);
  delay(b, kR2sW + 4, pad);
  delay(b, kBdW, 27 + pad);
  delay(b, 3 * kHitFW, 26 + pad);
  delay(b, w.carry_w, 33 + pad);
  delay(b, kExpW, 24 + pad);
  b.lutram += 3 + 1;  // the slot's flags (15 stages) and the miss flag (3)
  // The root's tag (17 stages), and each bit of D that waits 3 steps or more for its turn (x's bits go two a step).
  b.lutram += 4;
  for (int j = 0; j < kR2sW; ++j)
    if ((kR2sW - 1 - j) / 2 >= 3) ++b.lutram;
  return b;
}

// ts_artix_shade_reflect: the three channels in turn through one datapath, so each product kind is one slice (beta
// d_k, s 2^e+ d_k, t d_k + o_k 2^17, the normal, d.n accumulated, (d.n) n_k + d_k 2^16); the scale's shifts, the
// channel's and the tint's four restoring steps each, the saturations, and the tint's product in LUTs.
RtlBlock artix_shade_reflect(const ArtixWidths& w, const DeviceUnits& u) {
  using namespace pkg;
  RtlBlock b = named("shade_reflect");
  product(b, 1, kDirFrac, true, kDirW, true, kDirFrac + kDirW);  // beta d_k
  product(b, 1, kSqrtW + 5, true, kDirW, true, kSqrtW + 5 + kDirW);  // s 2^e+ d_k
  product(b, 1, 25, true, kDirW, true, 25 + kDirW);            // t d_k, plus o_k 2^17 + 2^16 (post-adder)
  product(b, 1, kRinvW + 1, true, kDirW, true, kRinvW + 1 + kDirW);  // the normal: Q_k's top times rinv
  product(b, 2, kDirW, true, kDirW, true, 2 * kDirW + 1);      // d.n (accumulated), (d.n) n_k + d_k 2^16
  const int fz = kHitFW;                                       // f_k 2^z
  const int chan = kOriginW + kDirW + fz + w.tint_w + 8;       // a channel's fields
  const int wp = 44 - kDirFrac;                                // W / 2^17
  const int xw = w.tint_w + 4;                                 // c T_k
  b.luts += mux(chan, 3);                                      // the slot: channel 0 from the ports, 1, 2 held
  b.luts += 3 + shift_left(kSqrtW, 3, kSqrtW + 5) + 2 * 5 + 1;  // e+, s 2^e+, z = -e, whether it reflects
  b.luts += shift_left(fz, 5, fz) + shift_left(w.radius, 5, w.radius);  // f_k 2^z, r 2^z
  b.luts += shift_left(kDirW, 5, 34);                          // u = floor(beta d_k / 2^17) 2^z
  b.luts += adder(40);                                         // nh = f_k 2^z + p
  b.luts += adder(42 - kDirFrac) + adder(42);                  // y = R - f_k 2^z - p (R's low 17 bits zero)
  b.luts += 3 * adder(44);                                     // W = 8 u - u + 8 y - y
  b.luts += adder(41);                                         // Q_k = u - nh
  b.luts += 4 * (adder(wp + 1) + mux(wp));                     // the channel's four restoring steps
  b.luts += select(kDirW, 8) + 8;                              // Q_k / 2^(18 + e+); the channel, 14 at most
  b.luts += w.tint_w + adder(xw - 3) + adder(xw - 1) + adder(xw);  // the tint used; c T_k: four copies summed
  b.luts += saturate(20, kDirW);                               // n_k
  b.luts += 2 * w.tint_w;                                      // 255^bounces (a table), twice
  b.luts += 4 * (adder(xw + 1) + mux(xw));                     // the tint's four restoring steps
  b.luts += 2 * kDirW + 1;                                     // d.n restarting at channel 0
  b.luts += saturate(20, kDirW) + adder(kDirW);                // -(d.n)
  b.luts += saturate(21, kDirW);                               // d'_k
  b.luts += 4 * adder(kDirW) + 3 * adder(w.tint_w);            // T_k a_k: pairs of shifted copies, summed
  b.luts += 15;                                                // valid, channel, the outputs' enables
  // Side data to its stage, and the results to the latencies the schedule counts on.
  const int colour_out = u.shade_latency - 1 - 3;
  const int ray_out = u.reflect_latency - 3;
  const int bounce_w = clog2(std::max(1, w.tint_w / 8) + 1);
  delay(b, 3, 3);                                              // e+
  delay(b, kRinvW, 3);
  delay(b, 1, 4);                                              // the hit
  delay(b, w.tint_w, 5);
  delay(b, bounce_w, 5);
  delay(b, kDirW, 6);                                          // d_k to d.n, and on with n_k to d'
  delay(b, kDirW, 4);
  delay(b, kDirW, 4);
  delay(b, 4, colour_out - 8);                                 // the colour, then its tag
  delay(b, w.tag_w + 1, colour_out - 1);
  delay(b, kDirW, ray_out - 12);                               // the ray's d', o', tint and tag
  delay(b, kOriginW, ray_out - 2);
  delay(b, w.tint_w, ray_out - 3);
  delay(b, w.tag_w + 1 + bounce_w, ray_out - 1);
  b.lutram += 2 * 2;                                           // the channel's two bits, tapped in two runs
  return b;
}

// ts_artix_unit's own logic with its two queues (ts_artix_fifo, 32 pixel states each, LUT RAM): the issue port,
// the slots' reads, the pass's state chosen, and its pixels' directions (two banks: the row drawn, the row next).
RtlBlock artix_unit(const ArtixWidths& w) {
  RtlBlock b = named("unit");
  memory(b, "reflected rays waiting (unit)", 32, w.state_w, Ports::kWriteRead);
  memory(b, "passes in flight (unit)", 32, w.state_w, Ports::kWriteRead);
  memory(b, "directions, two banks (unit)", std::int64_t{2} << w.slot_w, 3 * pkg::kDirW, Ports::kWriteRead);
  b.luts += 2 * fifo_pointers(5);
  b.luts += mux(w.state_w);                 // the queue's front, or the ray arriving
  b.luts += mux(w.state_w, 3);              // the pass's state: its own, a reflected ray's, a camera ray's
  const int iw = w.aw + 1;
  b.luts += mux(iw) + 2 * adder(iw) + equal(w.aw) + 2;  // a pair: within the list, or a sphere but the one left
  b.luts += mux(w.aw);                      // the sphere read
  b.luts += mux(iw, 3) + compare_constant(iw) + mux(iw) + equal(iw) + 3;  // the pass's length, its last slot
  b.luts += iw + w.slot_w + 10 + 5;         // the slot, the camera pixel, its column, its tile
  b.luts += compare_constant(10) + 10;      // the port's choice
  return b;
}

// ts_artix_camera: a direction a cycle; six products of one slice, the tables of squares (read twice) and of seeds
// in LUTs, n, 320 g and the three saturations.
RtlBlock artix_camera() {
  RtlBlock b = named("camera");
  product(b, 1, 18, true, 18, true, 34);   // y0^2
  product(b, 2, 20, true, 18, true, 36);   // n y0^2: two halves, the high one with the low one's carry
  product(b, 1, 23, true, 18, true, 39);   // y0 h
  product(b, 2, 10, true, 21, true, 30);   // x g, y g
  b.luts += 2 * (compare_constant(10) + 9);  // |x|, |y|
  // The tables: 9 address bits, about 4 LUTs a bit of an entry (Yosys's count of the camera less the rest: 194
  // for three reads of 17 bits).
  b.luts += 3 * 17 * 4;
  b.luts += adder(19, 3) + adder(24);      // n = x^2 + y^2 + 320^2; 320 g = (g << 8) + (g << 6)
  b.luts += 3 * saturate(19, pkg::kDirW);  // d_k
  b.lutram += 10 + 9 + 1;                  // x, y and the tag wait for g and the result
  return b;
}

// ts_artix_world's own logic: the queue of the spheres written (ts_artix_fifo, a world's spheres, in block RAM),
// the engine, and the per-world constants (e, r^2 / 4^e, 1 / r) in two copies with a replica per unit.
RtlBlock artix_world(const DevicePreset& p, const ArtixWidths& w) {
  RtlBlock b = named("world");
  const int entry = w.aw + 3 * w.coord + w.radius;
  const int constants = pkg::kExpW + pkg::kR2sW + pkg::kRinvW;
  memory(b, "spheres to prepare (world)", p.max_spheres, entry, Ports::kWriteRead);
  b.luts += fifo_pointers(w.aw);
  // In block RAM the queue's front, an asynchronous read, becomes a registered one, and Yosys adds the word being
  // written for a read of it in the same cycle: a comparison of the addresses and a choice a bit.
  if (b.memories.back().ramb18 > 0) b.luts += mux(entry) + equal(w.aw);
  for (int k = 0; k < w.n; ++k)
    memory(b, "constants, two copies, replica " + std::to_string(k + 1), std::int64_t{2} * p.max_spheres, constants,
           Ports::kWriteRead);
  b.luts += mux(constants) + mux(1 + 2 * 10 + 2 * 9) + 10;  // the constants and the bounds written; the engine
  return b;
}

// ts_artix_prepare: e, r^2 / 4^e and 1 / r by shifts and adds, one step a cycle: r's bit length, R = r 2^s (and
// H, the same shift of r / 2), the product's and the quotient's steps and registers.
RtlBlock artix_prepare(const ArtixWidths& w) {
  RtlBlock b = named("prepare");
  b.luts += 2 * w.radius;                                // the bit length: a priority chain, the index from it
  b.luts += shift_left(w.radius, 5, w.radius);           // R = r << s
  b.luts += adder(w.radius + 1) + adder(w.radius + 2);   // the product's partial sum, the quotient's trial
  b.luts += mux(2 * w.radius) + mux(w.radius, 3) + mux(pkg::kRinvW);  // product, remainder and quotient registers
  b.luts += 5 + 5;                                       // the step's cycles (comparisons of the count); the count
  return b;
}

// ts_artix_cull: the setup's 24 steps on one slice (its pre-adder x = xa + xb), the accumulator, and four engines
// of a G and a D register stepping by forward differences, their hulls and margins.
RtlBlock artix_cull(const ArtixWidths& w) {
  RtlBlock b = named("cull");
  constexpr int kX = 25, kY = 18, kW = 28, kAcc = 53, kG = 62, kD = 60;
  product(b, 1, kX, true, kY, true, kX + kY);
  const int sum_w = w.coord + 2;
  b.luts += adder(w.radius + 1) + adder(sum_w);          // grown = r + r / 1024 + 4; grown + c_z
  b.luts += 17;                                          // the program: 24 steps of 17 bits
  b.luts += select(kX, 4) + select(kX, 3) + select(kW, 5);  // x's two terms; y's source
  b.luts += mux(kY, 3) + adder(kY) + mux(kY);            // y: 25 or a piece; negated
  b.luts += select(kAcc, 4) + adder(kAcc);               // the term shifted by 0, 7, 17 or 24; the accumulator
  b.luts += 10 + mux(kD, 3);                             // destinations; D's addend: 2A, C 2^12 or a value
  b.luts += 4 * adder(kG) + 4 * adder(kD);               // G += D, D += addend
  b.luts += 6 + 2 * (mux(10) + mux(9)) + 8;              // meets; the hull; in front of the camera
  b.luts += 2 * (compare_constant(10) + mux(10)) + 2 * (compare_constant(9) + mux(9));  // the margin, clamped
  b.luts += 9 + 6 + 10;                                  // the count, its ends, the phase
  return b;
}

// ts_artix_tiles: the world's bounds (two copies), the builder (two tiles a cycle), the lists' lengths (LUT RAM, a
// read port per unit) and the lists, a replica per pair of units of both banks (block RAM, both ports: the pair's
// reads, or the builder's writes), each bank of tiles x spheres entries cut in depth into RAMB18 of 2048 x 9.
RtlBlock artix_tiles(const DevicePreset& p, const ArtixWidths& w) {
  RtlBlock b = named("tiles");
  const int tiles = kLineWidth / p.units->tile_columns;
  const int tile_w = clog2(tiles);
  const int entry_aw = tile_w + w.aw;
  const std::int64_t entries = std::int64_t{tiles} * p.max_spheres;
  const int count_w = w.aw + 1;
  const int replicas = (w.n + 1) / 2;
  const int bounds = 2 * tile_w + 2 * 9;
  memory(b, "bounds, two copies (tiles)", std::int64_t{2} * p.max_spheres, bounds, Ports::kWriteRead);
  for (int k = 0; k < 2 * replicas; ++k)
    memory(b, std::string(k % 2 ? "tile lists (next row), replica " : "tile lists (this row), replica ") +
                  std::to_string(k / 2 + 1), entries, w.aw, Ports::kReadOnWrite);
  // The lengths: two memories (even and odd tiles) of both banks' counts, N read ports: RAM32M gives three read
  // ports of 2 bits (or, for one, 6 bits).
  const int columns = w.n == 1 ? (count_w + 5) / 6 : (w.n * ((count_w + 1) / 2) + 2) / 3;
  b.lutram += 2 * 4 * columns;
  b.luts += mux(bounds) + mux(count_w) + equal(count_w) + count_w + 4 + adder(count_w) + 2;  // the build's issue
  b.luts += 2 * adder(9) + 4 * adder(tile_w) + 2 * adder(count_w) + 10;  // the row, the two tiles; the lists' fill
  const int pieces = static_cast<int>((entries + 2047) / 2048);
  const int per_bank = 2 * mux(entry_aw) + 2 * pieces;  // the ports' addresses (read or built); pieces' writes
  const int per_port = select(w.aw, 2 * pieces);        // an entry among both banks' pieces
  b.luts += 2 * replicas * per_bank + w.n * per_port;
  b.luts += w.n * mux(count_w);                          // a port's length: the even or the odd tile's
  return b;
}

// ts_line_buffers with a bank per unit or worker (both tops use it): two buffers of n banks, and the read choice and
// write ports.
void add_line_buffers(RtlBlock& b, int n) {
  const int slots = (kLineWidth + n - 1) / n;
  const int slot_w = slots > 1 ? clog2(slots) : 1;
  for (int k = 0; k < 2 * n; ++k)
    memory(b, std::string(k < n ? "line buffer 0, bank " : "line buffer 1, bank ") + std::to_string(k % n), slots, 13,
           Ports::kWriteRead);
  b.luts += mux(13, 2 * n) + 2 * n * (slot_w + 1) + 16;
}

// The blocks of ts_artix_device as `preset` configures it (scripts/synth.sh's header lists the modules of each).
std::vector<RtlBlock> artix_blocks(const DevicePreset& p, int wire) {
  const ArtixWidths w = artix_widths(p);
  const DeviceUnits& u = *p.units;
  const int n = w.n;
  std::vector<RtlBlock> out;
  out.push_back(receiver(p, wire));
  out.push_back(scene_memory(p, w.aw, true));
  // ts_line_buffers (a bank a unit in each of the two buffers: the read choice, the write ports) and ts_vga_timing.
  {
    RtlBlock b = named("scanout");
    add_line_buffers(b, n);
    b.luts += 53;
    out.push_back(b);
  }
  for (RtlBlock b : {artix_unit(w), artix_sphere_unit(w, u), artix_shade_reflect(w, u)}) {
    b.instances = n;
    b.per_worker = true;
    out.push_back(std::move(b));
  }
  out.push_back(artix_camera());
  out.push_back(artix_world(p, w));
  out.push_back(artix_prepare(w));
  out.push_back(artix_cull(w));
  out.push_back(artix_tiles(p, w));
  // ts_artix_device's own: the line's events decoded a cycle ahead (its last two cycles; whether this line and the
  // next work and build) and the row built, the directions' feed to their unit and slot, and the colours written in
  // the window (an adder tree over the units). Per unit: its direction-write decode and its share of the adder tree,
  // 5 LUTs, calibrated on Yosys 0.23's mapping of 9 units (the table's device row: 100 LUTs, most of them LUT2; it
  // was 118 while the world's sphere count left the block through a 9-bit gate, now the count register's reset).
  {
    RtlBlock b = named("device");
    const int unit_w = n > 1 ? clog2(n) : 1;
    b.luts += 2 * 2 + 2 * 8 + 2 + mux(9, 3) + 2;
    b.luts += adder(10) + unit_w + w.slot_w + equal(unit_w);
    b.luts += n * (equal(unit_w) + 3);
    out.push_back(b);
  }
  return out;
}

}  // namespace

ProductTiling yosys_product(int a_bits, bool a_signed, int b_bits, bool b_signed, int y_bits) {
  // mul2dsp.v with xc7's parameters: A at most 25 bits, B 18, pieces of A 18 bits (17 and a sign bit), signed only.
  if (a_bits < 2 || b_bits < 2 || y_bits < 9) return {0, a_bits * b_bits};  // a LUT multiplier (none in the RTL)
  if (!a_signed) ++a_bits;
  if (!b_signed) ++b_bits;
  if (a_bits < b_bits) std::swap(a_bits, b_bits);
  // Along A: na pieces (cascaded when B takes one slice); each piece along B: nb pieces, cascaded.
  const int na = a_bits > 25 ? 1 + (a_bits - 9) / 17 : 1;
  const int nb = b_bits > 18 ? 1 + (b_bits - 2) / 17 : 1;
  ProductTiling t{na * nb, 0};
  // Pieces along both: the pieces along A are summed in fabric, the i-th over bits 17 i and up; Yosys merges a
  // third operand's low 17 bits into the second adder (measured on its tilings of 27 x 27 to 54 x 22 bits).
  if (na > 1 && nb > 1)
    for (int i = 1; i < na; ++i) t.luts += y_bits - 17 * i - (i > 1 ? 17 : 0);
  return t;
}

int rtl_wire(const DevicePreset& p) { return p.max_bounces > 0 ? 3 : 2; }

bool has_rtl(const DevicePreset& p) {
  if (p.path) return false;
  if (p.units) {  // ts_artix_device: its package's formats, capacity, bounces, line and tiles; any unit count
    const DevicePreset a = artix_preset();
    return p.x == a.x && p.y == a.y && p.z == a.z && p.radius == a.radius && p.max_spheres == a.max_spheres &&
           p.max_bounces == a.max_bounces && p.lead_cycles == a.lead_cycles && *p.units == *a.units &&
           p.workers >= 1 && p.workers < kLineWidth;
  }
  return (p.costs.pipelined || p.max_bounces == 0) && p.max_bounces <= 3 &&
         (p.max_bounces == 0 || std::max({p.x.total_bits, p.y.total_bits, p.z.total_bits, p.radius.total_bits}) <= 24);
}

std::vector<RtlBlock> rtl_blocks(const DevicePreset& p) { return rtl_blocks(p, rtl_wire(p)); }

std::vector<RtlBlock> rtl_blocks(const DevicePreset& p, int wire) {
  if (p.path) return {};
  if (p.units) return artix_blocks(p, wire);
  const WorkerWidths w = worker_widths(p);
  const int n = p.workers;
  std::vector<RtlBlock> out;
  out.push_back(receiver(p, wire));
  out.push_back(scene_memory(p, w.aw, false));
  // The back end (ts_scanout: ts_controller, ts_line_buffers, ts_vga_timing): per worker the controller's columns,
  // counts and pixels in flight; the line's sum of on-time counts; two line buffers split in a bank per worker.
  {
    RtlBlock b = named("scanout");
    add_line_buffers(b, n);
    // The controller (ts_controller, N = 10: 1,079 LUTs with board-2023's lead of 3,000 cycles, 1,084 with wide's
    // whole line; other runs counted 1,444 and, with the whole back end at 2,105 against 1,786 before, more for
    // wide's, the same RTL: Yosys's mapping moves with the design). The ledger takes the middle of what was seen:
    // the whole back end at 2,181 for wide and 1,957 for board-2023 in the table of ccfbb06 (Yosys reading the
    // receiver's hierarchy check beside it), 2,140 and 1,809 before.
    b.luts += 100 * n + 369;
    b.luts += 53;                                           // VGA timing
    out.push_back(b);
  }
  std::vector<RtlBlock> per_worker{worker_control(w, p), sphere_test(w), sqrt_unit(w, p), shade(w, p)};
  if (w.reflect) per_worker.push_back(reflect(w));
  for (RtlBlock& b : per_worker) {
    b.instances = n;
    b.per_worker = true;
    out.push_back(std::move(b));
  }
  // ts_device's own: the controller's least cycles a pixel takes (spheres times the cycles a sphere, a constant
  // product, when not pipelined).
  {
    RtlBlock b = named("device");
    if (p.costs.pipelined) {
      b.luts += mux(w.aw + 1) + compare_constant(w.aw + 1);
    } else {
      b.luts += mux(w.aw + 1);
      product(b, 1, w.aw + 1, false, 6, false, 16);
    }
    out.push_back(b);
  }
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

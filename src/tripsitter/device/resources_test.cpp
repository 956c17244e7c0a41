// The resource ledger: DSP slices per multiply, per worker, and the operations of a path frame.
#include <tripsitter/device/resources.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include <tripsitter/device/approx.h>
#include <tripsitter/device/frame_dram.h>
#include <tripsitter/device/frame_memory.h>

namespace tripsitter::device {
namespace {

TEST(Resources, ADspSliceMultiplies24By17MagnitudeBits) {
  EXPECT_EQ(dsp_slices(24, 17), 1);
  EXPECT_EQ(dsp_slices(17, 24), 1);
  EXPECT_EQ(dsp_slices(25, 17), 2);
  EXPECT_EQ(dsp_slices(21, 26), 2);  // 21 on the 25-bit port, 26 split over two 18-bit ones
  EXPECT_EQ(dsp_slices(48, 48), 6);
  EXPECT_EQ(dsp_slices(70, 33), 6);  // 3 x 2 in the cheaper order, not 2 x 5
}

TEST(Resources, NarrowerFormatsTakeFewerSlices) {
  const Resources board = resources(board_2023_preset());
  const Resources wide = resources(wide_preset());
  const Resources path = resources(path_preset());
  EXPECT_LT(board.dsp_per_worker, wide.dsp_per_worker);
  EXPECT_LT(path.dsp_per_worker, wide.dsp_per_worker);  // no reflect unit: the shared scatter unit reflects
  EXPECT_EQ(wide.dsp_shared, 0);
  EXPECT_GT(path.dsp_shared, path.dsp_per_worker);
  EXPECT_EQ(board.workers_fitting, (kBoardDsp - board.dsp_shared) / board.dsp_per_worker);
  EXPECT_GE(path.workers_fitting, 1);
  EXPECT_EQ(path.workers_fitting, (kBoardDsp - path.dsp_shared) / path.dsp_per_worker);
}

TEST(Resources, ThePathPresetsFrameMemoryNeedsMoreThanTheBlockRam) {
  const Resources path = resources(path_preset());
  EXPECT_EQ(path.frame_memory_bits, 64 * 640 * 480);
  EXPECT_FALSE(path.frame_memory_in_bram);
  EXPECT_DOUBLE_EQ(path.frame_memory_bits_per_cycle, 2.0 * 64 * 640 / 3200);
  EXPECT_EQ(resources(wide_preset()).frame_memory_bits, 0);
}

TEST(Resources, APixelOfSkyCostsItsSetUpNormalisationSkyHashAndAccumulate) {
  // One sample per pixel, one ray that escapes, no sphere: the ray's a, one normalisation, the sky, the seed hash
  // and the frame memory's reciprocal multiplies.
  PathCounters c;
  c.samples = 10;
  c.rays = 10;
  c.sky = 10;
  const Operations ops = path_operations_per_pixel(path_preset(), c, 0, 10);
  EXPECT_DOUBLE_EQ(ops.total_multiplies(), 3 + 9 + 6 + 2 + 3);
  EXPECT_DOUBLE_EQ(ops.square_roots, 0);
  EXPECT_DOUBLE_EQ(ops.divisions, 0);
  // Each sphere adds a sphere test per ray: 9 multiplies and a square root.
  const Operations with_spheres = path_operations_per_pixel(path_preset(), c, 4, 10);
  EXPECT_DOUBLE_EQ(with_spheres.total_multiplies() - ops.total_multiplies(), 4 * 9);
  EXPECT_DOUBLE_EQ(with_spheres.square_roots, 4);
}

// --- Block RAM ---

TEST(Resources, AMemoryTakesRamb18sInItsBestAspectRatio) {
  EXPECT_EQ(ramb18_count(0, 12), 0);
  EXPECT_EQ(ramb18_count(640, 12), 1);      // 1024 x 18
  EXPECT_EQ(ramb18_count(1024, 18), 1);
  EXPECT_EQ(ramb18_count(1025, 18), 2);     // one entry past a shape's depth takes another half
  EXPECT_EQ(ramb18_count(1025, 15), 2);     // 2048 x 9: two wide; 1024 x 18: two deep
  EXPECT_EQ(ramb18_count(64, 62), 2);       // 512 x 36, two wide
  EXPECT_EQ(ramb18_count(4096, 121), 28);   // 1024 x 18: 7 x 4 (or 2048 x 9: 14 x 2)
  EXPECT_EQ(ramb18_count(16384, 1), 1);
  EXPECT_EQ(ramb18_count(16385, 1), 2);
  EXPECT_EQ(ramb18_count(307200, 64), 1200);  // 512 x 36: 2 x 600
}

// The board as its RTL builds it (rtl/): the receiver's byte buffer of 4 KiB in block RAM (2048 x 9, two halves);
// scene memory's 64 spheres of 16 + 15 + 15 + 16 bits, a metal bit and 24 of albedo (87 bits), in LUT RAM: a
// replica per pair of its 10 workers, each of two copies a RAM64X1D a bit (2 LUTs); the line buffers, 2 x 10 banks
// of 64 x 13 bits, in RAM64M (3 bits in 4 LUTs): 2 halves of block RAM in all, 1,740 + 400 LUTs as memory.
TEST(Resources, TheBoardsMemoriesAsItsRtlPlacesThem) {
  const Resources r = resources(board_2023_preset());
  EXPECT_EQ(r.bram18, 2);
  EXPECT_EQ(r.bram_bits, 2 * 18432);
  EXPECT_TRUE(r.bram_fits);
  int scene = 0, lines = 0, lutram = 0;
  for (const BramMemory& m : r.memories) {
    lutram += m.lutram;
    if (m.name.starts_with("scene memory")) {
      ++scene;
      EXPECT_EQ(m.depth, 64);
      EXPECT_EQ(m.width, 87);
      EXPECT_EQ(m.lutram, 2 * 87);
      EXPECT_EQ(m.ramb18, 0);
    } else if (m.name.starts_with("line buffer")) {
      ++lines;
      EXPECT_EQ(m.lutram, 4 * 5);
    } else {
      EXPECT_EQ(m, (BramMemory{"receiver's byte buffer", 4096, 8, 2, 0}));
    }
  }
  EXPECT_EQ(scene, 10);
  EXPECT_EQ(lines, 20);
  EXPECT_EQ(lutram, 1740 + 400);
  EXPECT_DOUBLE_EQ(r.frame_memory_bits_per_cycle, 0);
}

// Wide's RTL: the receiver's 128 KiB buffer (64 halves) and five replicas of scene memory's two copies of 4096 x 121
// bits (28 halves each: 2048 x 9, 14 wide, two deep) take 344 halves, 172 of the XC7A100T's 135 blocks: ten wide
// workers do not fit its block RAM either. Two workers: one replica (56 halves), and the line buffers' four banks of
// 320 x 13 bits, too deep for LUT RAM now, take a half each.
TEST(Resources, TheWidePresetsReplicasOfSceneMemoryOverflowTheBlockRam) {
  const Resources r = resources(wide_preset());
  EXPECT_EQ(r.bram18, 64 + 10 * 28);
  EXPECT_FALSE(r.bram_fits);
  DevicePreset two = wide_preset();
  two.workers = 2;
  EXPECT_EQ(resources(two).bram18, 64 + 2 * 28 + 4);
  EXPECT_TRUE(resources(two).bram_fits);
}

// The path preset: scene memory of 96 + 2 + 24 + 16 + 16 = 154 bits (36 halves a copy), its four tables, and frame
// memory either in the development board's DDR3L (fits, 25.6 bits a cycle of its traffic, a quarter of what its 48
// pins carry: frame_dram.h) or in block RAM (1,200 halves more, four times the XC7A100T's 270).
TEST(Resources, ThePathPresetFitsOnlyWithFrameMemoryOutside) {
  const Resources external = resources(path_preset());
  EXPECT_EQ(external.memories[2].width, 154);
  EXPECT_EQ(external.memories[2].ramb18, 36);
  EXPECT_EQ(external.bram18, 2 + 72 + 1 + 1 + 1 + 2);
  EXPECT_TRUE(external.bram_fits);
  EXPECT_DOUBLE_EQ(external.frame_memory_bits_per_cycle, 2.0 * 64 * 640 / 3200);
  EXPECT_EQ(external.frame_memory_part, dram::kPartName);
  EXPECT_EQ(external.frame_memory_pins, 48);
  EXPECT_NEAR(external.frame_memory_demand, 10240.0 / (4 * 10399), 1e-9);
  EXPECT_GT(external.frame_memory_busy, external.frame_memory_demand);
  EXPECT_LT(external.frame_memory_busy, 0.8);
  DevicePreset p = path_preset();
  p.path->frame_memory = FrameMemoryPlace::kBlockRam;
  const Resources inside = resources(p);
  ASSERT_EQ(inside.memories.size(), external.memories.size() + 1);
  EXPECT_EQ(inside.memories.back(), (BramMemory{"frame memory", 640 * 480, 64, 1200}));
  EXPECT_EQ(inside.bram18, external.bram18 + 1200);
  EXPECT_FALSE(inside.bram_fits);
  EXPECT_DOUBLE_EQ(inside.frame_memory_bits_per_cycle, 0);
  EXPECT_TRUE(inside.frame_memory_part.empty());
  EXPECT_EQ(inside.frame_memory_bits, external.frame_memory_bits);
  EXPECT_FALSE(inside.frame_memory_in_bram);  // would not fit even alone
}

// The artix device's RTL (ts_artix_device, 9 units): scene memory's 256 spheres of 22 + 22 + 22 + 21 bits, a metal
// bit and 24 of albedo (112 bits), a replica per pair of units: four true dual-port pairs of copies in 1024 x 18
// halves (7 each) and the ninth unit's single-port pair in 512 x 72 (4 each); the tile lists, 20 tiles x 256
// entries of 8 bits a bank, 2048 x 9 halves three deep, two banks per replica, and the bounds (512 x 28, one half);
// the per-world constants (e, r^2 / 4^e, 1 / r: 59 bits, two copies of 256) a replica per unit, a RAMB36 each; the
// world's queue (256 x 95: 3 halves); each unit's directions (two banks of 128 x 54: 2 halves); the receiver's 16 KiB
// (8). 142 halves: Yosys's 90 RAMB18 and 26 RAMB36. The units' queues (32 pixel states) and the line buffers'
// banks (72 x 13) are LUT RAM.
TEST(Resources, TheArtixMemoriesAsItsRtlPlacesThem) {
  const Resources r = resources(artix_preset());
  std::map<std::string, int> halves, count;
  for (const BramMemory& m : r.memories) {
    const std::string kind = m.name.substr(0, m.name.find_first_of(",("));
    halves[kind] += m.ramb18;
    ++count[kind];
  }
  EXPECT_EQ(count.at("scene memory "), 10);
  EXPECT_EQ(halves.at("scene memory "), 4 * 2 * 7 + 2 * 4);
  EXPECT_EQ(count.at("tile lists "), 10);
  EXPECT_EQ(halves.at("tile lists "), 10 * 3);
  EXPECT_EQ(halves.at("bounds"), 1);
  EXPECT_EQ(count.at("constants"), 9);
  EXPECT_EQ(halves.at("constants"), 9 * 2);
  EXPECT_EQ(halves.at("spheres to prepare "), 3);
  EXPECT_EQ(count.at("directions"), 9);
  EXPECT_EQ(halves.at("directions"), 9 * 2);
  EXPECT_EQ(halves.at("receiver's byte buffer"), 8);
  EXPECT_EQ(halves.at("passes in flight "), 0);
  EXPECT_EQ(halves.at("line buffer 0"), 0);
  EXPECT_EQ(r.bram18, 142);
  EXPECT_TRUE(r.bram_fits);
}

// The tables' widths are those of the values they hold.
TEST(Resources, ThePathTablesHoldTheirValuesInTheirWidths) {
  EXPECT_EQ(approx::sine_table().sin(1024), 16384);  // the quarter wave's last entry, 1025th: 15 bits
  EXPECT_EQ(display_mean(511, 1), 511u);             // sum * 2^18 / 1: the reciprocal of 1 is 2^18, 19 bits
}

TEST(Resources, TheBreakdownSumsToTheTotal) {
  DevicePreset inside = path_preset();
  inside.path->frame_memory = FrameMemoryPlace::kBlockRam;
  for (const DevicePreset& p : {board_2023_preset(), wide_preset(), path_preset(), inside, artix_preset()}) {
    const Resources r = resources(p);
    int halves = 0;
    for (const BramMemory& m : r.memories) {
      if (r.blocks.empty()) {
        EXPECT_EQ(m.ramb18, ramb18_count(m.depth, m.width)) << p.name << " " << m.name;
      }
      EXPECT_TRUE(m.ramb18 == 0 || m.lutram == 0) << p.name << " " << m.name;
      halves += m.ramb18;
    }
    EXPECT_EQ(halves, r.bram18) << p.name;
    EXPECT_EQ(r.bram_bits, std::int64_t{r.bram18} * kRamb18Bits) << p.name;
    EXPECT_EQ(r.bram_fits, r.bram18 <= kBoardRamb18) << p.name;
  }
  EXPECT_EQ(kBoardRamb18, 270);
}

// --- Operations of the mirror model ---

// The board's worker (10-bit directions): a ray set-up is 3 multiplies 10 x 10 and 2 additions; a sphere test 9
// multiplies (3 of 10 x 16, 3 of 16 x 16, r^2 16 x 16, b^2 28 x 28, 4ac' 22 x 34), 11 additions and a square root.
TEST(Resources, AMirrorPixelOfTheBoardWithOneSphereCostsItsSetUpAndOneTest) {
  const Operations ops = mirror_operations_per_pixel(board_2023_preset(), 1, 0, 307200);
  EXPECT_DOUBLE_EQ(ops.total_multiplies(), 3 + 9);
  EXPECT_DOUBLE_EQ(ops.multiplies.at("10x10"), 3);
  EXPECT_DOUBLE_EQ(ops.multiplies.at("10x16"), 3);
  EXPECT_DOUBLE_EQ(ops.multiplies.at("16x16"), 4);
  EXPECT_DOUBLE_EQ(ops.multiplies.at("28x28"), 1);
  EXPECT_DOUBLE_EQ(ops.multiplies.at("22x34"), 1);
  EXPECT_DOUBLE_EQ(ops.additions, 2 + 11);
  EXPECT_DOUBLE_EQ(ops.square_roots, 1);
  EXPECT_DOUBLE_EQ(ops.divisions, 0);
  EXPECT_DOUBLE_EQ(ops.random_draws, 0);
  EXPECT_DOUBLE_EQ(mirror_operations_per_pixel(board_2023_preset(), 1, 0, 0).total_multiplies(), 0);
}

// With reflections: 10 pixels, 5 reflections, 2 spheres: 15 passes of a set-up (3 multiplies) and two sphere
// tests (9 each), and 5 reflections (15 multiplies, 13 additions, 3 divisions each), over 10 pixels.
TEST(Resources, AMirrorPixelsReflectionsAddPassesAndReflectBlocks) {
  DevicePreset p = board_2023_preset();
  p.max_bounces = 1;
  const WorkerBlocks w = worker_blocks(p);
  ASSERT_EQ(w.reflect.multiplies.size(), 5u);
  const Operations ops = mirror_operations_per_pixel(p, 2, 5, 10);
  EXPECT_DOUBLE_EQ(ops.total_multiplies(), (15 * (3 + 2 * 9) + 5 * 15) / 10.0);
  EXPECT_DOUBLE_EQ(ops.additions, (15 * (2 + 2 * 11) + 5 * 13) / 10.0);
  EXPECT_DOUBLE_EQ(ops.square_roots, 15 * 2 / 10.0);
  EXPECT_DOUBLE_EQ(ops.divisions, 5 * 3 / 10.0);
}

// --- The ledger against Yosys (rtl/synth_table.tsv) ---

// Yosys's tilings, as measured (a registered product alone: synth_xilinx -family xc7): one slice up to 25 x 18 signed
// (an unsigned operand takes a bit more); pieces along one operand summed in the cascade, along both in fabric.
TEST(Resources, ProductsAreTiledAsYosysTilesThem) {
  EXPECT_EQ(yosys_product(11, true, 11, true, 18).dsp, 1);
  EXPECT_EQ(yosys_product(19, false, 16, false, 36).dsp, 1);
  const ProductTiling cascade = yosys_product(33, true, 10, true, 41);  // two pieces of A, no fabric adder
  EXPECT_EQ(cascade.dsp, 2);
  EXPECT_EQ(cascade.luts, 0);
  EXPECT_EQ(yosys_product(24, false, 24, false, 48).dsp, 2);   // 25 x 25 signed: B in two
  const ProductTiling square = yosys_product(27, true, 27, true, 54);  // Yosys: 4 slices and 37 LUTs
  EXPECT_EQ(square.dsp, 4);
  EXPECT_EQ(square.luts, 37);
  EXPECT_EQ(yosys_product(49, true, 49, true, 96).dsp, 9);     // wide's b^2: Yosys 9 slices, 129 LUTs
  EXPECT_NEAR(yosys_product(49, true, 49, true, 96).luts, 129, 13);
  EXPECT_EQ(yosys_product(42, false, 52, true, 96).dsp, 9);    // wide's 4ac'
  EXPECT_EQ(yosys_product(54, true, 22, true, 75).dsp, 6);     // wide's (7 num) d_k: Yosys 81 LUTs
  EXPECT_NEAR(yosys_product(54, true, 22, true, 75).luts, 81, 9);
}

// One row of the synthesis table: per instance.
struct TableRow {
  int instances = 0, dsp = 0, luts = 0, lutram = 0, ffs = 0, ramb18 = 0, carry4 = 0;
};
struct SynthTable {
  std::map<std::string, std::map<std::string, TableRow>> rows;  // preset, block
  std::map<std::string, std::map<std::string, int>> params;     // preset: ts_device's parameters as synthesised
};

SynthTable read_synth_table() {
  SynthTable t;
  std::ifstream in(std::string(TRIPSITTER_SOURCE_DIR) + "/rtl/synth_table.tsv");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string preset, block;
    if (line.starts_with("# params ")) {
      std::string word;
      s >> word >> word >> preset;
      while (s >> word) {
        const auto eq = word.find('=');
        if (eq != std::string::npos) t.params[preset][word.substr(0, eq)] = std::stoi(word.substr(eq + 1));
      }
      continue;
    }
    if (line.empty() || line[0] == '#') continue;
    TableRow r;
    s >> preset >> block >> r.instances >> r.dsp >> r.luts >> r.lutram >> r.ffs >> r.ramb18 >> r.carry4;
    if (s) t.rows[preset][block] = r;
  }
  return t;
}

// Within a tenth of Yosys's figure (exactly, for figures below 10).
bool within_a_tenth(double ledger, double yosys) { return std::abs(ledger - yosys) <= 0.1 * yosys; }

TEST(Resources, TheTenPercentRuleWouldHaveFailedTheOldLedger) {
  EXPECT_FALSE(within_a_tenth(16, 31));   // the old ledger's board-2023 worker against Yosys's
  EXPECT_FALSE(within_a_tenth(94, 134));  // and wide's
  EXPECT_TRUE(within_a_tenth(31, 31));
  EXPECT_FALSE(within_a_tenth(0, 1));
}

// The table was synthesised from ts_device as the C++ presets configure it: a preset changed without regenerating
// the table (scripts/synth.sh table) fails here, not silently below.
TEST(Resources, TheSynthesisTableIsOfThePresetsAsConfigured) {
  const SynthTable t = read_synth_table();
  // The artix top takes everything but its unit count from its package (held to the preset by artix_pkg_test).
  const DevicePreset artix = artix_preset();
  ASSERT_TRUE(t.params.contains(artix.name)) << "no '# params' line of artix in rtl/synth_table.tsv";
  EXPECT_EQ(t.params.at(artix.name), (std::map<std::string, int>{{"N", artix.workers}}));
  EXPECT_TRUE(has_rtl(artix));
  for (const DevicePreset& p : {wide_preset(), board_2023_preset()}) {
    SCOPED_TRACE(p.name);
    ASSERT_TRUE(t.params.contains(p.name)) << "no '# params' line in rtl/synth_table.tsv";
    const std::map<std::string, int>& q = t.params.at(p.name);
    const auto param = [&](const char* name) { return q.contains(name) ? q.at(name) : -1; };
    EXPECT_EQ(param("N"), p.workers);
    EXPECT_EQ(param("FRAC"), p.frac_bits());
    EXPECT_EQ(param("X_W"), p.x.total_bits);
    EXPECT_EQ(param("Y_W"), p.y.total_bits);
    EXPECT_EQ(param("Z_W"), p.z.total_bits);
    EXPECT_EQ(param("R_W"), p.radius.total_bits);
    EXPECT_EQ(param("MAX_SPHERES"), static_cast<int>(p.max_spheres));
    EXPECT_EQ(param("WIRE"), rtl_wire(p));
    EXPECT_EQ(param("SQRT_ITERATIONS"), p.sqrt_iterations);
    EXPECT_EQ(param("PIPELINED"), p.costs.pipelined ? 1 : 0);
    EXPECT_EQ(param("MAX_BOUNCES"), p.max_bounces);
    EXPECT_EQ(param("LEAD_CYCLES"), p.lead_cycles);
    EXPECT_EQ(param("SQRT_CYCLES_PER_ITERATION"), p.costs.pipelined ? 1 : p.costs.sqrt_cycles_per_iteration);
  }
}

// The ledger agrees with Yosys block by block within 10%: DSP48E1, LUTs (as logic and as memory) and RAMB18 per
// instance, the instances, and the whole top. When the RTL changes, regenerate the table (scripts/synth.sh table)
// and, if a block leaves the 10%, model what the RTL now builds in resources.cpp.
TEST(Resources, TheLedgerAgreesWithYosysPerBlockWithinTenPercent) {
  const SynthTable t = read_synth_table();
  for (const DevicePreset& p : {wide_preset(), board_2023_preset(), artix_preset()}) {
    SCOPED_TRACE(p.name);
    ASSERT_TRUE(t.rows.contains(p.name)) << "rtl/synth_table.tsv has no rows of " << p.name;
    const std::map<std::string, TableRow>& rows = t.rows.at(p.name);
    const Resources r = resources(p);
    ASSERT_FALSE(r.blocks.empty());
    int dsp = 0, luts = 0, ramb18 = 0;
    for (const RtlBlock& b : r.blocks) {
      SCOPED_TRACE(b.name);
      ASSERT_TRUE(rows.contains(b.name)) << "a block of the ledger that Yosys's table lacks";
      const TableRow& y = rows.at(b.name);
      EXPECT_EQ(b.instances, y.instances);
      EXPECT_PRED2(within_a_tenth, b.dsp, y.dsp);
      EXPECT_PRED2(within_a_tenth, b.total_luts(), y.luts + y.lutram);
      EXPECT_PRED2(within_a_tenth, b.ramb18, y.ramb18);
      dsp += b.dsp * b.instances;
      luts += b.total_luts() * b.instances;
      ramb18 += b.ramb18 * b.instances;
    }
    for (const auto& [name, row] : rows) {  // and no block of the table is missing from the ledger
      const bool in_ledger =
          std::any_of(r.blocks.begin(), r.blocks.end(), [&](const RtlBlock& b) { return b.name == name; });
      EXPECT_TRUE(name == "total" || in_ledger) << name;
    }
    ASSERT_TRUE(rows.contains("total"));
    const TableRow& total = rows.at("total");
    EXPECT_PRED2(within_a_tenth, dsp, total.dsp);
    EXPECT_PRED2(within_a_tenth, luts, total.luts + total.lutram);
    EXPECT_PRED2(within_a_tenth, ramb18, total.ramb18);
    EXPECT_EQ(dsp, r.dsp_per_worker * p.workers + r.dsp_shared);
    EXPECT_EQ(luts, r.luts);
    EXPECT_EQ(ramb18, r.bram18);
  }
}

// The ledger grows with the units as the RTL does: a unit's own blocks each, a replica of scene memory and of the tile
// lists each pair, the constants' each unit, the line buffers' banks and slots. Held to Yosys away from the preset's
// 9 (`scripts/synth.sh 12 artix`, which synthesises 12 units and 1): DSP48E1 and RAMB18 exactly, the LUTs (logic
// and memory) of the whole top within 10%.
TEST(Resources, TheArtixLedgerScalesWithTheUnitsAsYosysCounts) {
  struct Synthesised {
    int units, dsp, luts, ramb18;
  };
  for (const Synthesised& y : {Synthesised{1, 22, 8'911, 36}, Synthesised{12, 187, 61'021, 180}}) {
    SCOPED_TRACE(y.units);
    DevicePreset p = artix_preset();
    p.workers = y.units;
    EXPECT_TRUE(has_rtl(p));
    const Resources r = resources(p);
    EXPECT_EQ(r.dsp_per_worker * y.units + r.dsp_shared, y.dsp);
    EXPECT_EQ(r.bram18, y.ramb18);
    EXPECT_PRED2(within_a_tenth, r.luts, y.luts);
  }
  DevicePreset wider = artix_preset();
  wider.x.frac_bits = wider.y.frac_bits = wider.z.frac_bits = wider.radius.frac_bits = 6;
  wider.x.total_bits = wider.y.total_bits = wider.z.total_bits = 24;
  EXPECT_FALSE(has_rtl(wider));  // not the package's formats: extrapolated
  EXPECT_GT(resources(wider).luts, resources(artix_preset()).luts);
}

// What fits the chip by the ledger: artix's units are limited by LUTs (Yosys: 12 units take 61,806 of the 63,400,
// `scripts/synth.sh 12 artix`, whose estimate from 12 and 1 puts the limit at 12), the per-pixel workers by DSP48E1.
TEST(Resources, TheLedgerSaysHowManyFitTheChipAndWhatLimitsThem) {
  const Resources artix = resources(artix_preset());
  EXPECT_EQ(artix.workers_fitting_chip, 12);
  EXPECT_EQ(artix.chip_limit, "LUTs");
  EXPECT_EQ(artix.workers_fitting, (kBoardDsp - artix.dsp_shared) / artix.dsp_per_worker);  // DSP48E1 alone: 15
  EXPECT_EQ(artix.dsp_per_worker, 15);
  EXPECT_EQ(artix.dsp_shared, 7);
  const Resources board = resources(board_2023_preset());
  EXPECT_EQ(board.workers_fitting_chip, board.workers_fitting);
  EXPECT_EQ(board.chip_limit, "DSP48E1");
  const Resources wide = resources(wide_preset());
  EXPECT_EQ(wide.workers_fitting_chip, 1);
  EXPECT_EQ(wide.chip_limit, "DSP48E1");
  EXPECT_EQ(resources(path_preset()).workers_fitting_chip, 0);  // no blocks
}

}  // namespace
}  // namespace tripsitter::device

// The resource ledger: DSP slices per multiply, per worker, and the operations of a path frame.
#include <tripsitter/device/resources.h>

#include <gtest/gtest.h>

#include <tripsitter/device/approx.h>
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
  EXPECT_EQ(board.workers_fitting, kBoardDsp / board.dsp_per_worker);
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

// The board: two line buffers of 640 x 12 bits (1024 x 18: one half each) and two scene memories of its
// 16 + 15 + 15 + 16 = 62-bit geometry (no surface: it never reflects), one half of 512 x 36 deep and two wide
// whether they hold its 64 spheres or the original board's one: 2 + 4 = 6 halves, 110,592 bits.
TEST(Resources, TheBoardsBlockRamByHand) {
  for (const std::uint32_t spheres : {1u, 64u}) {
    DevicePreset p = board_2023_preset();
    p.max_spheres = spheres;
    const Resources r = resources(p);
    ASSERT_EQ(r.memories.size(), 4u);
    EXPECT_EQ(r.memories[0], (BramMemory{"line buffer (front)", 640, 12, 1}));
    EXPECT_EQ(r.memories[1], (BramMemory{"line buffer (back)", 640, 12, 1}));
    EXPECT_EQ(r.memories[2], (BramMemory{"scene memory (front)", spheres, 62, 2}));
    EXPECT_EQ(r.memories[3], (BramMemory{"scene memory (back)", spheres, 62, 2}));
    EXPECT_EQ(r.bram18, 6);
    EXPECT_EQ(r.bram_bits, 6 * 18432);
    EXPECT_TRUE(r.bram_fits);
    EXPECT_DOUBLE_EQ(r.frame_memory_bits_per_cycle, 0);
  }
}

// The mirror model with bounces keeps each sphere's metal bit and albedo: wide's 4 x 24 + 1 + 24 = 121 bits of
// 4096 spheres, 28 halves a copy; 2 + 56 = 58 in all.
TEST(Resources, TheWidePresetsSceneMemoryHoldsItsMirrorsSurfaces) {
  const Resources r = resources(wide_preset());
  ASSERT_EQ(r.memories.size(), 4u);
  EXPECT_EQ(r.memories[2].width, 121);
  EXPECT_EQ(r.memories[2].depth, 4096);
  EXPECT_EQ(r.bram18, 58);
  EXPECT_TRUE(r.bram_fits);
  DevicePreset no_bounces = wide_preset();
  no_bounces.max_bounces = 0;
  EXPECT_EQ(resources(no_bounces).memories[2].width, 96);
}

// The path preset: scene memory of 96 + 2 + 24 + 16 + 16 = 154 bits (36 halves a copy), its four tables, and frame
// memory either in external SRAM (fits, 25.6 bits a cycle of SRAM traffic) or in block RAM (1,200 halves more,
// four times the XC7A100T's 270).
TEST(Resources, ThePathPresetFitsOnlyWithFrameMemoryOutside) {
  const Resources external = resources(path_preset());
  EXPECT_EQ(external.memories[2].width, 154);
  EXPECT_EQ(external.memories[2].ramb18, 36);
  EXPECT_EQ(external.bram18, 2 + 72 + 1 + 1 + 1 + 2);
  EXPECT_TRUE(external.bram_fits);
  EXPECT_DOUBLE_EQ(external.frame_memory_bits_per_cycle, 2.0 * 64 * 640 / 3200);
  DevicePreset p = path_preset();
  p.path->frame_memory = FrameMemoryPlace::kBlockRam;
  const Resources inside = resources(p);
  ASSERT_EQ(inside.memories.size(), external.memories.size() + 1);
  EXPECT_EQ(inside.memories.back(), (BramMemory{"frame memory", 640 * 480, 64, 1200}));
  EXPECT_EQ(inside.bram18, external.bram18 + 1200);
  EXPECT_FALSE(inside.bram_fits);
  EXPECT_DOUBLE_EQ(inside.frame_memory_bits_per_cycle, 0);
  EXPECT_EQ(inside.frame_memory_bits, external.frame_memory_bits);
  EXPECT_FALSE(inside.frame_memory_in_bram);  // would not fit even alone
}

// The tables' widths are those of the values they hold.
TEST(Resources, ThePathTablesHoldTheirValuesInTheirWidths) {
  EXPECT_EQ(approx::sine_table().sin(1024), 16384);  // the quarter wave's last entry, 1025th: 15 bits
  EXPECT_EQ(display_mean(511, 1), 511u);             // sum * 2^18 / 1: the reciprocal of 1 is 2^18, 19 bits
}

TEST(Resources, TheBreakdownSumsToTheTotal) {
  DevicePreset inside = path_preset();
  inside.path->frame_memory = FrameMemoryPlace::kBlockRam;
  for (const DevicePreset& p : {board_2023_preset(), wide_preset(), path_preset(), inside}) {
    const Resources r = resources(p);
    int halves = 0;
    for (const BramMemory& m : r.memories) {
      EXPECT_EQ(m.ramb18, ramb18_count(m.depth, m.width)) << p.name << " " << m.name;
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

}  // namespace
}  // namespace tripsitter::device

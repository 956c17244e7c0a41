// The resource ledger: DSP slices per multiply, per worker, and the operations of a path frame.
#include <tripsitter/device/resources.h>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace tripsitter::device

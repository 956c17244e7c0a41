#include <tripsitter/device/controller.h>

#include <array>

#include <gtest/gtest.h>

namespace tripsitter::device {
namespace {

SceneMemory one_sphere(const DevicePreset& p) {
  SceneMemory m;
  m.valid = true;
  m.geometry.push_back({{0, 0, p.z.quantize(400).raw}, p.radius.quantize(64).raw});
  m.surfaces.resize(1);
  return m;
}

TEST(Controller, BoardLeavesColumns580To639Black) {
  const DevicePreset p = board_2023_preset();
  const Controller c(p);
  EXPECT_EQ(c.pixels_in_time(1), 58);
  std::array<core::Rgb444, kLineWidth> line;
  line.fill(core::Rgb444(0xFFF));
  const LineResult r = c.render_line(240, one_sphere(p), line);
  EXPECT_EQ(r.late_pixels, 60);
  for (int col = 580; col < 640; ++col) EXPECT_EQ(line[col], core::kBlack) << col;
  for (int col = 0; col < 580; ++col) EXPECT_NE(line[col], core::kBlack) << col;
}

TEST(Controller, LinePixelsAreTheWorkersPureFunction) {
  const DevicePreset p = wide_preset();
  const Controller c(p);
  const Worker w(p.sqrt_iterations);
  const SceneMemory scene = one_sphere(p);
  std::array<core::Rgb444, kLineWidth> line;
  for (int row : {0, 200, 240, 479}) {
    EXPECT_EQ(c.render_line(row, scene, line).late_pixels, 0);
    for (int col = 0; col < kLineWidth; ++col) ASSERT_EQ(line[col], w.shade(col, row, scene)) << col << "," << row;
  }
}

TEST(Controller, FewerWorkersMeansLatePixelsInEachWorkersTail) {
  DevicePreset p = board_2023_preset();
  p.workers = 20;  // 32 pixels each: all on time
  EXPECT_EQ(Controller(p).pixels_in_time(1), 32);
  p.workers = 5;  // 128 pixels each, 58 on time: columns 5*58 = 290 onwards are late
  const Controller c(p);
  std::array<core::Rgb444, kLineWidth> line;
  EXPECT_EQ(c.render_line(10, one_sphere(p), line).late_pixels, 640 - 5 * 58);
  for (int col = 290; col < 640; ++col) EXPECT_EQ(line[col], core::kBlack);
}

TEST(Controller, CentreOfTheDemoSphereFacesTheCamera) {
  // SPEC.md section B: a sphere at (0, 0, 400) with radius 64, its point facing the camera coloured 0x770.
  const DevicePreset p = wide_preset();
  const Worker w(p.sqrt_iterations);
  EXPECT_EQ(w.shade(320, 240, one_sphere(p)), core::Rgb444(0x770));
  EXPECT_EQ(w.shade(0, 0, one_sphere(p)), core::kBackground);
}

}  // namespace
}  // namespace tripsitter::device

#include <tripsitter/explore/evaluate.h>

#include <cmath>

#include <gtest/gtest.h>

#include <tripsitter/device/resources.h>
#include <tripsitter/explore/sweep.h>
#include <tripsitter/scene/builtin.h>

namespace tripsitter::explore {
namespace {

Point measure(const Configuration& c, ReferenceCache& references, EvaluateSettings settings = {}) {
  return evaluate(c, *scene::builtin(c.scene), settings, references);
}

TEST(Evaluate, TheBoardAsItShippedIsLateAndItsLoadSaysByHowMuch) {
  ReferenceCache references;
  const Point p = measure(preset_configuration("demo", "board-2023"), references);
  // The report's board: the last 60 columns of every line late (tripsitter render --scene demo --preset board-2023).
  EXPECT_EQ(p.m.late_pixels, 60 * 480);
  EXPECT_EQ(p.m.late_lines, 480);
  EXPECT_FALSE(p.on_time());
  EXPECT_GT(p.m.line_load, 1.0);
  EXPECT_NEAR(p.m.fps, refresh_hz() / p.m.line_load, 1e-9);
  EXPECT_EQ(p.m.differing, 60u * 480u);  // exactly the late pixels differ from the float reference
  EXPECT_EQ(p.m.dsp, p.m.dsp_per_worker * 10 + p.m.dsp_shared);
  EXPECT_GT(p.m.multiplies, 0);
  EXPECT_GE(p.m.square_roots, 1.0);  // one sphere test per pixel at least
  ASSERT_GE(p.thumbnail_png.size(), 8u);
  EXPECT_EQ(p.thumbnail_png[1], 'P');  // \x89PNG
}

TEST(Evaluate, EnoughWorkersMeetEveryDeadlineAtTheMonitorsRate) {
  ReferenceCache references;
  Configuration c = preset_configuration("demo", "board-2023");
  c.workers = 12;  // 58 pixels of a line fit a worker: 640 / 12 = 54
  const Point p = measure(c, references);
  EXPECT_TRUE(p.on_time());
  EXPECT_LE(p.m.line_load, 1.0);
  EXPECT_DOUBLE_EQ(p.m.fps, refresh_hz());
  EXPECT_EQ(p.m.differing, 0u);
}

TEST(Evaluate, ASlowLinkLimitsTheFramesPerSecond) {
  ReferenceCache references;
  Configuration c = preset_configuration("demo", "wide");
  c.spi_hz = 1000;
  const Point p = measure(c, references);
  EXPECT_TRUE(p.on_time());
  EXPECT_GT(p.m.link_ms, 1000.0 * static_cast<double>(p.m.link_bits) / 1000.0 * 0.999);
  EXPECT_NEAR(p.m.fps, 1000.0 / p.m.link_ms, 1e-9);
  EXPECT_LT(p.m.fps, refresh_hz());
}

TEST(Evaluate, PathPointsOfOneWorldShareTheirReference) {
  ReferenceCache references;
  EvaluateSettings settings;
  settings.reference_spp = 4;
  settings.thumbnail = false;
  Configuration c = preset_configuration("demo", "path");
  const Point one = measure(c, references, settings);
  c.spp = 2;
  c.workers = 32;
  const Point two = measure(c, references, settings);
  EXPECT_EQ(references.size(), 1u);
  c.depth = 2;
  measure(c, references, settings);
  EXPECT_EQ(references.size(), 2u);
  for (const Point* p : {&one, &two}) {
    EXPECT_TRUE(std::isfinite(p->m.relmse));
    EXPECT_GT(p->m.relmse, 0.0);
    EXPECT_EQ(p->m.reference_spp, 4);
    EXPECT_GT(p->m.random_draws, 0.0);
    EXPECT_TRUE(p->thumbnail_png.empty());
  }
  EXPECT_LT(two.m.relmse, one.m.relmse);  // twice the samples, against the same reference
}

TEST(Evaluate, FrameMemoryInBlockRamDoesNotFit) {
  ReferenceCache references;
  EvaluateSettings settings;
  settings.reference_spp = 1;
  settings.thumbnail = false;
  Configuration c = preset_configuration("demo", "path");
  c.workers = 3;
  const Point external = measure(c, references, settings);
  c.frame_memory = "bram";
  const Point bram = measure(c, references, settings);
  EXPECT_TRUE(external.fits());
  EXPECT_GT(external.m.sram_bits_per_cycle, 0.0);
  EXPECT_FALSE(bram.bram_fits());
  EXPECT_EQ(bram.m.sram_bits_per_cycle, 0.0);
  EXPECT_GT(bram.m.bram_kbit, external.m.bram_kbit + 19'000.0);  // 640 x 480 x 64 bits
}

}  // namespace
}  // namespace tripsitter::explore

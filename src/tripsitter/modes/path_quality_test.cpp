// The quality figures of `bench` on a small picture: each one a finite error that falls with more samples, and a
// reference that comes back from the cache as it was rendered.
#include <tripsitter/modes/path_quality.h>

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include <tripsitter/scene/builtin.h>

namespace tripsitter::modes {
namespace {

QualitySettings small(const std::string& cache = "") {
  QualitySettings s;
  s.width = 80;
  s.height = 60;
  s.threads = 2;
  s.max_depth = 8;
  s.reference_spp = 256;
  s.orbit_reference_spp = 64;
  s.orbit_frames = 4;
  s.orbit_every = 2;
  s.cache_dir = cache;
  return s;
}

bool sane(const QualityFigure& f) {
  return std::isfinite(f.error.relmse) && f.error.relmse >= 0 && f.error.relmse < 10 && std::isfinite(f.error.bias);
}

TEST(PathQuality, MoreSamplesGiveALowerErrorAndEveryFigureIsFinite) {
  PathQuality q(*scene::builtin("field"), small());
  const QualityFigure one = q.plain(1, render::SamplerKind::kSobol);
  const QualityFigure many = q.plain(64, render::SamplerKind::kSobol);
  ASSERT_TRUE(sane(one));
  ASSERT_TRUE(sane(many));
  EXPECT_LT(many.error.relmse, one.error.relmse / 8);
  EXPECT_EQ(many.mean_samples, 64);

  const QualityFigure first = q.still(true, 1, 0);
  const QualityFigure later = q.still(true, 16, 0);
  ASSERT_TRUE(sane(first));
  ASSERT_TRUE(sane(later));
  EXPECT_EQ(later.frames, 16);
  EXPECT_LT(later.error.relmse, first.error.relmse);
  // The denoised single frame is cleaner than the raw one.
  EXPECT_LT(first.error.relmse, one.error.relmse);

  const QualityFigure orbit = q.orbit(true, true);
  ASSERT_TRUE(sane(orbit));
  EXPECT_EQ(orbit.frames, 5);
  EXPECT_GT(q.orbit_noise_relmse(), 0);
}

TEST(PathQuality, TheCachedReferenceIsTheOneRendered) {
  const auto dir = std::filesystem::path(testing::TempDir()) / "tripsitter-path-quality-cache";
  std::filesystem::remove_all(dir);
  // What is checked is the round trip through the cache, not the reference's quality: 16 samples per pixel do.
  QualitySettings settings = small(dir.string());
  settings.reference_spp = 16;
  PathQuality first(*scene::builtin("field"), settings);
  const Reference rendered = first.reference();
  EXPECT_FALSE(rendered.cached);
  PathQuality second(*scene::builtin("field"), settings);
  const Reference& read = second.reference();
  EXPECT_TRUE(read.cached);
  EXPECT_EQ(read.image.pixels, rendered.image.pixels);
  EXPECT_DOUBLE_EQ(read.noise_relmse, rendered.noise_relmse);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tripsitter::modes

#include <tripsitter/explore/summary.h>

#include <gtest/gtest.h>

#include <tripsitter/explore/evaluate.h>
#include <tripsitter/explore/sweep.h>

namespace tripsitter::explore {
namespace {

Point point(int index, Configuration c, int late_lines, int dsp, double fps = 0) {
  Point p;
  p.index = index;
  p.config = std::move(c);
  p.m.late_lines = late_lines;
  p.m.dsp = dsp;
  p.m.fps = fps;
  p.m.pixels = 100;
  return p;
}

TEST(Summary, CheapestOnTimeIsTheFewestDspsOfThePointsOnTime) {
  Configuration board = preset_configuration("demo", "board-2023");
  std::vector<Point> points;
  for (int w : {4, 8, 12, 16}) {
    Configuration c = board;
    c.workers = w;
    points.push_back(point(static_cast<int>(points.size()), c, w < 12 ? 480 : 0, 16 * w));
  }
  points.push_back(point(4, board, 480, 160));  // the board as it shipped: 10 workers, late
  const Summary s = summarise(points);
  ASSERT_EQ(s.cheapest_on_time.size(), 1u);
  EXPECT_EQ(s.cheapest_on_time[0].preset, "board-2023");
  EXPECT_EQ(s.cheapest_on_time[0].point, 2);  // 12 workers
  EXPECT_TRUE(s.sixty_hz.empty());           // no path points
  ASSERT_GE(s.thumbnails.size(), 2u);
  EXPECT_EQ(s.thumbnails[0].point, 4);  // the board as it shipped first
  EXPECT_NE(s.thumbnails[0].caption.find("shipped"), std::string::npos);
  const auto lines = describe(s, points);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NE(lines[0].find("12 workers"), std::string::npos) << lines[0];
}

TEST(Summary, TheCheapestOnTimeMustFitTheChip) {
  Configuration wide = preset_configuration("cluster", "wide");
  std::vector<Point> points;
  for (int w : {2, 5}) {
    Configuration c = wide;
    c.workers = w;
    points.push_back(point(static_cast<int>(points.size()), c, 0, 134 * w));  // both on time
  }
  points[0].m.luts = 200'000;  // the cheaper one's LUTs do not fit
  const Summary s = summarise(points);
  ASSERT_EQ(s.cheapest_on_time.size(), 1u);
  EXPECT_FALSE(s.cheapest_on_time[0].point);  // 5 workers: 670 DSP48E1, more than 240
  EXPECT_NE(describe(s, points)[0].find("fits the XC7A100T"), std::string::npos) << describe(s, points)[0];
  points[1].m.dsp = 200;
  EXPECT_EQ(summarise(points).cheapest_on_time[0].point, 1);
}

TEST(Summary, NoPointOnTimeIsSaid) {
  const std::vector<Point> points{point(0, preset_configuration("demo", "wide"), 3, 100)};
  const Summary s = summarise(points);
  ASSERT_EQ(s.cheapest_on_time.size(), 1u);
  EXPECT_FALSE(s.cheapest_on_time[0].point);
  EXPECT_TRUE(to_json(s)["cheapest_on_time"][0]["point"].is_null());
  EXPECT_NE(describe(s, points)[0].find("no point"), std::string::npos);
}

TEST(Summary, SixtyHertzIsTheMostSamplesThatFitAtTheRefreshRate) {
  const Configuration path = preset_configuration("cluster", "path");
  std::vector<Point> points;
  const auto add = [&](int spp, int depth, int dsp, double fps) {
    Configuration c = path;
    c.spp = spp;
    c.depth = depth;
    points.push_back(point(static_cast<int>(points.size()), c, 0, dsp, fps));
  };
  add(1, 4, 200, refresh_hz());
  add(2, 4, 200, refresh_hz());
  add(4, 4, 200, 40.0);              // too slow
  add(8, 4, 500, refresh_hz());      // does not fit
  const Summary s = summarise(points);
  ASSERT_EQ(s.sixty_hz.size(), 1u);
  EXPECT_EQ(s.sixty_hz[0].point, 1);
}

}  // namespace
}  // namespace tripsitter::explore

// What a sweep found, in a few lines (docs/explore.md, "The summary"): for each scene and preset the cheapest
// configuration that fits the XC7A100T and meets every line deadline, for each scene the path preset's best picture at the monitor's
// rate, and the points whose frames the report shows. The page draws it as a table; `explore` prints it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <tripsitter/explore/point.h>

namespace tripsitter::explore {

struct Finding {
  std::string scene;
  std::string preset;
  std::optional<int> point;  // index into the points (Point::index); none when no point qualifies
};

struct Thumbnail {
  int point = 0;
  std::string caption;
};

struct Summary {
  // Per scene and preset, in the order first met: of the points that fit the XC7A100T (Point::fits: DSP48E1,
  // LUTs and block RAM) and draw every line on time, the one with the fewest DSP slices (then fewer workers, then
  // the smaller error, then the earlier).
  std::vector<Finding> cheapest_on_time;
  // Per scene with path points: of the path points drawing complete frames at the monitor's rate (fps at the
  // refresh rate) and fitting the XC7A100T, the one with the most samples per frame (spp x depth; then the fewest
  // DSPs); none when no path point does.
  std::vector<Finding> sixty_hz;
  // At most 12 points, by scene: the board's choice (board-2023 as it shipped), each cheapest_on_time point, each
  // sixty_hz point and the path point with the most samples per frame.
  std::vector<Thumbnail> thumbnails;
};

// REQUIRES points[i].index == i.
Summary summarise(const std::vector<Point>& points);

nlohmann::ordered_json to_json(const Summary& summary);
// The summary as sentences, one per finding, for a terminal.
std::vector<std::string> describe(const Summary& summary, const std::vector<Point>& points);

}  // namespace tripsitter::explore

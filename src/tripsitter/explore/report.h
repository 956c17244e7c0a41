// The report of a sweep (`tripsitter explore`, docs/explore.md), in a directory: points.csv and points.json for
// scripts, and index.html for a person: one self-contained page, opening offline, with Chart.js (Debian's
// libjs-chart.js, compiled into the library) inlined, charts and tables drawn by its script from the points'
// JSON, and the monitor's frames at a few points as embedded thumbnails.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <tripsitter/core/result.h>
#include <tripsitter/display/io.h>
#include <tripsitter/explore/point.h>

namespace tripsitter::explore {

struct Report {
  std::vector<Point> points;  // the finished points, in index order (Point::thumbnail_png may be set)
  // From summarise(); any entry may be absent or null, any array empty:
  //   {"cheapest_on_time": [{"scene": "cluster", "preset": "board-2023", "point": 12}, {..., "point": null}],
  //    "sixty_hz": [{"scene": "cluster", "point": 40}],
  //    "thumbnails": [{"point": 3, "caption": "cluster, board-2023, 4 workers: 410 late lines"}]}
  // where "point" is a Point::index of `points`.
  nlohmann::ordered_json summary;
  // What ran: {"command": "...", "scenes": [...], "sweeps": ["workers=1..64", ...], "points_planned": N,
  //            "points_done": M, "interrupted": bool, "seconds": s}.
  nlohmann::ordered_json sweep;
};

// Writes DIR/points.csv (csv_header, then one csv_row per point), DIR/points.json ({"sweep", "summary",
// "columns": [{name, unit, description}...], "points": [to_json(point)...]}) and DIR/index.html, creating DIR if
// missing. Each file is written beside its name and renamed, so a failure leaves no half file (the files written
// before it stay). The thumbnails of summary.thumbnails whose point has thumbnail_png go into the page as
// data:image/png; entries naming no point or a point without one are left out.
core::Result<bool, display::IoError> write_report(const std::filesystem::path& dir, const Report& report);

// The page alone (what write_report writes as index.html), for tests and tools.
std::string report_page(const Report& report);

// RFC 4648 base64 of `bytes`, padded with '=' (data: URLs).
std::string base64(const std::vector<std::uint8_t>& bytes);

}  // namespace tripsitter::explore

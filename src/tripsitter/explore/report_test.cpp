// write_report: points.csv, points.json and index.html from hand-made points, read back as a script would, and
// the page checked as text (Chart.js inlined, the data, the thumbnails, nothing loaded from elsewhere, no way for a
// scene's name to end the script element). browser_test.cpp looks at the page in a browser.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <tripsitter/core/image.h>
#include <tripsitter/display/png.h>
#include <tripsitter/explore/report.h>

#include "report_test_util.h"

namespace tripsitter::explore {
namespace embedded {
std::string chart_js();  // report_page_text.cpp, made at build time
}  // namespace embedded

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// One CSV record (RFC 4180 quoting, as point.cpp writes it).
std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

std::vector<std::uint8_t> thumbnail(int seed) {
  core::ImageRgb8 image(16, 12);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      std::uint8_t* px = &image.pixels[3 * static_cast<std::size_t>(y * image.width + x)];
      px[0] = static_cast<std::uint8_t>(x * 16);
      px[1] = static_cast<std::uint8_t>(y * 20);
      px[2] = static_cast<std::uint8_t>(seed * 40);
    }
  }
  auto png = display::encode_png(image);
  EXPECT_TRUE(png.ok()) << png.error().message;
  return png.ok() ? png.value() : std::vector<std::uint8_t>{};
}

Point mirror_point(int index, const std::string& scene, int workers, int frac_bits) {
  Point p;
  p.index = index;
  p.config.scene = scene;
  p.config.preset = "board-2023";
  p.config.workers = workers;
  p.config.frac_bits = frac_bits;
  p.config.sqrt_iterations = 8;
  p.config.bounces = 1;
  p.config.spi_hz = 10'000'000;
  p.config.transfer_bytes = 64;
  p.config.wire = "v1";
  p.m.late_lines = workers >= 8 ? 0 : 400 / workers;
  p.m.late_pixels = p.m.late_lines * 300;
  p.m.line_load = 8.0 / workers;
  p.m.fps = workers >= 8 ? 60 : 60.0 * workers / 8;
  p.m.pixels = 307'200;
  p.m.differing = static_cast<std::uint64_t>(30'000 >> (frac_bits - 8));
  p.m.max_levels = 2;
  p.m.dsp = 12 * workers + 4;
  p.m.dsp_per_worker = 12;
  p.m.dsp_shared = 4;
  p.m.bram_kbit = 1200;
  return p;
}

Point path_point(int index, const std::string& scene, int workers, int spp) {
  Point p;
  p.index = index;
  p.config.scene = scene;
  p.config.preset = "path";
  p.config.workers = workers;
  p.config.frac_bits = 12;
  p.config.sqrt_iterations = 10;
  p.config.spp = spp;
  p.config.depth = 3;
  p.config.frames = 4;
  p.config.spi_hz = 20'000'000;
  p.config.transfer_bytes = 256;
  p.config.frame_memory = "external";
  p.config.wire = "v2";
  p.m.late_lines = 480;
  p.m.fps = 40.0 * workers / spp;
  p.m.relmse = 0.5 / spp;
  p.m.bias = 0.01;
  p.m.reference_spp = 1024;
  p.m.dsp = 20 * workers + 6;
  p.m.bram_kbit = 3000;
  p.m.random_draws = 12.5 * spp;
  return p;
}

Report sample_report() {
  Report r;
  int i = 0;
  for (const int w : {1, 4, 8}) r.points.push_back(mirror_point(i++, "cluster", w, 10));
  r.points.push_back(mirror_point(i++, "cluster", 8, 14));
  for (const int spp : {1, 4}) r.points.push_back(path_point(i++, "demo", 8, spp));
  r.points[1].thumbnail_png = thumbnail(1);
  r.points[4].thumbnail_png = thumbnail(2);
  r.summary = Json::parse(R"({
    "cheapest_on_time": [{"scene": "cluster", "preset": "board-2023", "point": 2},
                         {"scene": "demo", "preset": "path", "point": null}],
    "sixty_hz": [{"scene": "cluster", "point": 2}],
    "thumbnails": [{"point": 1, "caption": "cluster, board-2023, 4 workers: 100 late lines"},
                   {"point": 4, "caption": "demo, path, 1 spp"},
                   {"point": 3, "caption": "no thumbnail kept"},
                   {"point": 99, "caption": "no such point"}]})");
  r.sweep = Json::parse(R"({"command": "tripsitter explore --scene cluster --scene demo --sweep workers=1,4,8",
    "scenes": ["cluster", "demo"], "sweeps": ["workers=1,4,8", "frac_bits=10,14", "spp=1,4"],
    "points_planned": 8, "points_done": 6, "interrupted": true, "seconds": 12.5})");
  return r;
}

// The text of the page's data element, parsed.
Json page_data(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"report-data\">";
  const std::size_t begin = page.find(open);
  EXPECT_NE(begin, std::string::npos);
  if (begin == std::string::npos) return Json();
  const std::size_t end = page.find("</script>", begin);
  EXPECT_NE(end, std::string::npos);
  return Json::parse(page.substr(begin + open.size(), end - begin - open.size()));
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

class ReportTest : public test::ScratchDirTest {
 protected:
  std::vector<std::string> entries(const fs::path& dir) const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
};

TEST_F(ReportTest, Base64IsRfc4648) {
  const auto b64 = [](const std::string& s) { return base64(std::vector<std::uint8_t>(s.begin(), s.end())); };
  EXPECT_EQ(b64(""), "");
  EXPECT_EQ(b64("f"), "Zg==");
  EXPECT_EQ(b64("fo"), "Zm8=");
  EXPECT_EQ(b64("foo"), "Zm9v");
  EXPECT_EQ(b64("foob"), "Zm9vYg==");
  EXPECT_EQ(b64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(b64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64({0xff, 0xfe, 0x00, 0x3e, 0x3f}), "//4APj8=");
}

TEST_F(ReportTest, WritesTheThreeFilesIntoANewDirectory) {
  const Report report = sample_report();
  const fs::path dir = dir_ / "out" / "report";
  const auto written = write_report(dir, report);
  ASSERT_TRUE(written.ok()) << written.error().message;
  EXPECT_EQ(entries(dir), (std::vector<std::string>{"index.html", "points.csv", "points.json"}))
      << "no temporary file stays behind";

  // points.csv: the header, then one row per point whose fields read back.
  const std::vector<std::string> csv = lines_of(test::slurp(dir / "points.csv"));
  ASSERT_EQ(csv.size(), report.points.size() + 1);
  EXPECT_EQ(csv[0], csv_header());
  const std::vector<std::string> header = csv_fields(csv[0]);
  const auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  for (std::size_t i = 0; i < report.points.size(); ++i) {
    const Point& p = report.points[i];
    const std::vector<std::string> f = csv_fields(csv[i + 1]);
    ASSERT_EQ(f.size(), header.size()) << csv[i + 1];
    EXPECT_EQ(f[column("index")], std::to_string(p.index));
    EXPECT_EQ(f[column("scene")], p.config.scene);
    EXPECT_EQ(f[column("preset")], p.config.preset);
    EXPECT_EQ(std::stoi(f[column("workers")]), p.config.workers);
    EXPECT_EQ(std::stoi(f[column("late_lines")]), p.m.late_lines);
    EXPECT_EQ(std::stoi(f[column("dsp")]), p.m.dsp);
    EXPECT_EQ(f[column("on_time")], p.on_time() ? "true" : "false");
    EXPECT_EQ(f[column("spp")], p.config.path() ? std::to_string(p.config.spp) : "");
  }

  // points.json: sweep, summary, columns and points as given.
  const Json doc = Json::parse(test::slurp(dir / "points.json"));
  EXPECT_EQ(doc["sweep"], report.sweep);
  EXPECT_EQ(doc["summary"], report.summary);
  ASSERT_EQ(doc["columns"].size(), columns().size());
  EXPECT_EQ(doc["columns"][0]["name"], columns()[0].name);
  EXPECT_TRUE(doc["columns"][0].contains("unit"));
  EXPECT_TRUE(doc["columns"][0].contains("description"));
  // The configuration's columns are marked (the page groups series by them): exactly Configuration's fields.
  std::vector<std::string> marked;
  for (const Json& c : doc["columns"])
    if (c["configuration"] == true) marked.push_back(c["name"]);
  EXPECT_EQ(marked, (std::vector<std::string>{"scene", "preset", "workers", "frac_bits", "sqrt_iterations", "bounces",
                                              "capacity", "spp", "depth", "frames", "spi_mhz", "transfer_bytes",
                                              "frame_memory", "wire"}));
  ASSERT_EQ(doc["points"].size(), report.points.size());
  for (std::size_t i = 0; i < report.points.size(); ++i) EXPECT_EQ(doc["points"][i], to_json(report.points[i]));

  // index.html: Chart.js verbatim (its license comment included), the points, the thumbnails.
  const std::string page = test::slurp(dir / "index.html");
  EXPECT_EQ(page, report_page(report));
  const std::string chart = embedded::chart_js();
  ASSERT_GT(chart.size(), 100'000u);
  EXPECT_NE(page.find(chart), std::string::npos) << "Chart.js inlined verbatim";
  EXPECT_NE(page.find("Released under the MIT License"), std::string::npos);
  const Json data = page_data(page);
  ASSERT_EQ(data["rows"].size(), report.points.size());
  ASSERT_EQ(data["columns"].size(), columns().size());
  for (std::size_t i = 0; i < report.points.size(); ++i) {
    std::size_t c = 0;
    const Json object = to_json(report.points[i]);
    for (const auto& [key, value] : object.items()) {
      EXPECT_EQ(data["columns"][c]["name"], key);
      EXPECT_EQ(data["rows"][i][c], value) << "point " << i << ", " << key;
      ++c;
    }
  }
  EXPECT_EQ(data["summary"], report.summary);
  EXPECT_EQ(data["sweep"], report.sweep);
  // Thumbnails: the two points that kept one, not the point without one nor the missing point.
  ASSERT_EQ(data["thumbnails"].size(), 2u);
  EXPECT_EQ(data["thumbnails"][0]["point"], 1);
  EXPECT_EQ(data["thumbnails"][1]["caption"], "demo, path, 1 spp");
  for (const int i : {1, 4}) {
    EXPECT_NE(page.find("data:image/png;base64," + base64(report.points[static_cast<std::size_t>(i)].thumbnail_png)),
              std::string::npos)
        << "thumbnail of point " << i;
  }
  EXPECT_EQ(count(page, "data:image/png;base64,"), 2u);
}

// Nothing the browser would load from elsewhere: outside the scripts every src= and href= is a data: URL or an
// #anchor (browser_test.cpp checks the elements the script makes, in the browser's DOM), no url() or @import in
// the style, and outside Chart.js (whose license comment names its home page) no address at all.
TEST_F(ReportTest, ThePageLoadsNothingFromElsewhere) {
  const std::string page = report_page(sample_report());
  const std::string chart = embedded::chart_js();
  std::string without_chart = page;
  without_chart.erase(without_chart.find(chart), chart.size());

  // The markup alone: each script's text removed.
  std::string markup;
  for (std::size_t at = 0;;) {
    const std::size_t open = test::lowered(page).find("<script", at);
    markup += page.substr(at, open == std::string::npos ? std::string::npos : open - at);
    if (open == std::string::npos) break;
    const std::size_t close = test::lowered(page).find("</script>", open);
    ASSERT_NE(close, std::string::npos);
    at = close + 9;
  }
  int links = 0;
  for (const test::Attribute& a : test::link_attributes(markup)) {
    EXPECT_TRUE(a.value.rfind("data:", 0) == 0 || a.value.rfind("#", 0) == 0) << a.text;
    ++links;
  }
  EXPECT_GE(links, 5) << "the navigation's #anchors";

  const std::string text = test::lowered(without_chart);
  EXPECT_FALSE(test::has_css_url(text)) << "no url() in the style";
  EXPECT_EQ(text.find("@import"), std::string::npos);
  for (const char* scheme : {"http:", "https:", "ftp:", "file:", "ws:", "wss:"}) {
    EXPECT_EQ(text.find(scheme), std::string::npos) << scheme;
  }
  // Chart.js mentions addresses only in comments: its own home page and its colour library's.
  for (std::size_t at = chart.find("http"); at != std::string::npos; at = chart.find("http", at + 1)) {
    const std::string around = chart.substr(at, 40);
    EXPECT_TRUE(around.rfind("https://www.chartjs.org", 0) == 0 || around.rfind("https://github.com/kurkle/color", 0) == 0)
        << around;
  }
}

// A scene file's name is text to the page, whatever it holds: it cannot end the data's <script> element.
TEST_F(ReportTest, ASceneNamedLikeMarkupStaysInsideTheData) {
  Report report = sample_report();
  const std::string nasty = "scenes/</script><script>alert(1)</script><!--<b>&amp;\".json";
  report.points[0].config.scene = nasty;
  report.summary["thumbnails"][0]["caption"] = "caption </SCRIPT> too";
  const auto written = write_report(dir_, report);
  ASSERT_TRUE(written.ok()) << written.error().message;
  const std::string page = test::slurp(dir_ / "index.html");

  // Three script elements (Chart.js, the data, the page's script) and nothing else closes or opens one.
  EXPECT_EQ(count(test::lowered(page), "<script"), 3u);
  EXPECT_EQ(count(test::lowered(page), "</script"), 3u);
  EXPECT_EQ(page.find("<!--<b>"), std::string::npos);
  const Json data = page_data(page);
  EXPECT_EQ(data["rows"][0][1], nasty);
  EXPECT_EQ(data["thumbnails"][0]["caption"], "caption </SCRIPT> too");

  // Scripts get the name as it is.
  EXPECT_EQ(Json::parse(test::slurp(dir_ / "points.json"))["points"][0]["scene"], nasty);
  const std::vector<std::string> csv = lines_of(test::slurp(dir_ / "points.csv"));
  EXPECT_EQ(csv_fields(csv[1])[1], nasty);
}

// The summary and sweep may be missing: the page still has its data, and no thumbnail.
TEST_F(ReportTest, WritesWithoutSummaryOrSweepAndWithNoPoints) {
  Report report = sample_report();
  report.summary = nullptr;
  report.sweep = nullptr;
  ASSERT_TRUE(write_report(dir_ / "a", report).ok());
  const Json data = page_data(test::slurp(dir_ / "a" / "index.html"));
  EXPECT_EQ(data["rows"].size(), report.points.size());
  EXPECT_TRUE(data["thumbnails"].empty());
  EXPECT_TRUE(data["summary"].is_object());

  ASSERT_TRUE(write_report(dir_ / "b", Report{}).ok());
  EXPECT_EQ(lines_of(test::slurp(dir_ / "b" / "points.csv")).size(), 1u);
  EXPECT_TRUE(page_data(test::slurp(dir_ / "b" / "index.html"))["rows"].empty());
}

TEST_F(ReportTest, RewritingReplacesTheFiles) {
  Report report = sample_report();
  ASSERT_TRUE(write_report(dir_, report).ok());
  report.points.resize(2);
  ASSERT_TRUE(write_report(dir_, report).ok());
  EXPECT_EQ(lines_of(test::slurp(dir_ / "points.csv")).size(), 3u);
  EXPECT_EQ(entries(dir_), (std::vector<std::string>{"index.html", "points.csv", "points.json"}));
}

// DIR is a regular file: an error naming it, and nothing written or changed.
TEST_F(ReportTest, ADirectoryThatIsAFileIsAnErrorAndLeavesNothing) {
  const fs::path file = dir_ / "taken";
  std::ofstream(file) << "not a directory";
  for (const fs::path& dir : {file, file / "below"}) {
    SCOPED_TRACE(dir.string());
    const auto written = write_report(dir, sample_report());
    ASSERT_FALSE(written.ok());
    EXPECT_NE(written.error().message.find(dir.string()), std::string::npos) << written.error().message;
    EXPECT_EQ(entries(dir_), std::vector<std::string>{"taken"});
    EXPECT_EQ(test::slurp(file), "not a directory");
  }
}

}  // namespace
}  // namespace tripsitter::explore

#include <tripsitter/explore/summary.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <set>
#include <tuple>

#include <tripsitter/device/preset.h>
#include <tripsitter/device/resources.h>
#include <tripsitter/explore/evaluate.h>
#include <tripsitter/explore/sweep.h>

namespace tripsitter::explore {
namespace {

constexpr std::size_t kMaxThumbnails = 12;

// Whether the point draws complete frames at the monitor's rate.
bool at_refresh_rate(const Point& p) { return p.m.fps >= refresh_hz() * (1 - 1e-9); }

std::string configuration_text(const Point& p) {
  const Configuration& c = p.config;
  // The artix preset's parallel parts are sphere units shared by a line's pixels, not per-pixel workers.
  const std::optional<device::DevicePreset> preset = device::preset_by_name(c.preset);
  const char* parts = preset && preset->units ? "sphere units" : "workers";
  char buf[256];
  if (c.path())
    std::snprintf(buf, sizeof buf, "%s, %d %s, %d spp, depth %d, %d %s", c.preset.c_str(), c.workers, parts, c.spp,
                  c.depth, c.frames, c.frames == 1 ? "frame" : "frames accumulated");
  else
    std::snprintf(buf, sizeof buf, "%s, %d %s, %d fractional bits, %d sqrt iterations, %d bounces", c.preset.c_str(),
                  c.workers, parts, c.frac_bits, c.sqrt_iterations, c.bounces);
  return buf;
}

std::string cost_text(const Point& p) {
  char luts[96] = "";
  if (p.m.luts > 0)
    std::snprintf(luts, sizeof luts, ", %d LUTs (%s the XC7A100T's %d)", p.m.luts, p.lut_fits() ? "fits" : "more than",
                  device::kBoardLuts);
  char buf[320];
  std::snprintf(buf, sizeof buf, "%d DSP48E1 (%s the XC7A100T's %d)%s, %.0f Kbit of block RAM%s", p.m.dsp,
                p.dsp_fits() ? "fits" : "more than", device::kBoardDsp, luts, p.m.bram_kbit,
                p.bram_fits() ? "" : " (more than the XC7A100T's 4,860)");
  return buf;
}

std::string error_text(const Point& p) {
  char buf[128];
  if (p.config.path())
    std::snprintf(buf, sizeof buf, "relMSE %.4g against the float path tracer", p.m.relmse);
  else
    std::snprintf(buf, sizeof buf, "%.3f%% of pixels differ from the float reference", p.error());
  return buf;
}

}  // namespace

Summary summarise(const std::vector<Point>& points) {
  Summary s;
  // Scenes and (scene, preset) pairs in the order first met.
  std::vector<std::string> scenes;
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const Point& p : points) {
    if (std::find(scenes.begin(), scenes.end(), p.config.scene) == scenes.end()) scenes.push_back(p.config.scene);
    const std::pair<std::string, std::string> pair{p.config.scene, p.config.preset};
    if (std::find(pairs.begin(), pairs.end(), pair) == pairs.end()) pairs.push_back(pair);
  }
  for (const auto& [scene, preset] : pairs) {
    Finding f{scene, preset, std::nullopt};
    for (const Point& p : points) {
      if (p.config.scene != scene || p.config.preset != preset || !p.on_time() || !p.fits()) continue;
      const auto rank = [](const Point& q) { return std::make_tuple(q.m.dsp, q.config.workers, q.error(), q.index); };
      if (!f.point || rank(p) < rank(points[static_cast<std::size_t>(*f.point)])) f.point = p.index;
    }
    s.cheapest_on_time.push_back(f);
  }
  for (const std::string& scene : scenes) {
    bool has_path = false;
    Finding f{scene, "path", std::nullopt};
    for (const Point& p : points) {
      if (p.config.scene != scene || !p.config.path()) continue;
      has_path = true;
      if (!at_refresh_rate(p) || !p.fits()) continue;
      const auto rank = [](const Point& q) {
        return std::make_tuple(-q.config.spp * q.config.depth, q.m.dsp, q.index);
      };
      if (!f.point || rank(p) < rank(points[static_cast<std::size_t>(*f.point)])) f.point = p.index;
    }
    if (has_path) s.sixty_hz.push_back(f);
  }

  // Thumbnails, scene by scene.
  std::set<int> chosen;
  const auto add = [&](int index, const std::string& why) {
    if (s.thumbnails.size() == kMaxThumbnails || !chosen.insert(index).second) return;
    const Point& p = points[static_cast<std::size_t>(index)];
    char buf[512];
    std::snprintf(buf, sizeof buf, "%s, %s: %s; %d late lines", p.config.scene.c_str(), why.c_str(),
                  configuration_text(p).c_str(), p.m.late_lines);
    s.thumbnails.push_back({index, buf});
  };
  for (const std::string& scene : scenes) {
    const Configuration board = preset_configuration(scene, "board-2023");
    for (const Point& p : points)
      if (p.config == board) add(p.index, "the board as it shipped");
    for (const Finding& f : s.cheapest_on_time)
      if (f.scene == scene && f.point) add(*f.point, "cheapest that fits and is on time");
    for (const Finding& f : s.sixty_hz)
      if (f.scene == scene && f.point) add(*f.point, "best path picture at 60 Hz");
    std::optional<int> most;
    for (const Point& p : points)
      if (p.config.scene == scene && p.config.path() &&
          (!most || p.config.spp * p.config.frames > points[static_cast<std::size_t>(*most)].config.spp *
                                                         points[static_cast<std::size_t>(*most)].config.frames))
        most = p.index;
    if (most) add(*most, "most samples per pixel");
  }
  return s;
}

nlohmann::ordered_json to_json(const Summary& summary) {
  const auto findings = [](const std::vector<Finding>& list, bool with_preset) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const Finding& f : list) {
      nlohmann::ordered_json e = {{"scene", f.scene}};
      if (with_preset) e["preset"] = f.preset;
      e["point"] = f.point ? nlohmann::ordered_json(*f.point) : nlohmann::ordered_json(nullptr);
      out.push_back(std::move(e));
    }
    return out;
  };
  nlohmann::ordered_json doc;
  doc["cheapest_on_time"] = findings(summary.cheapest_on_time, true);
  doc["sixty_hz"] = findings(summary.sixty_hz, false);
  doc["thumbnails"] = nlohmann::ordered_json::array();
  for (const Thumbnail& t : summary.thumbnails) doc["thumbnails"].push_back({{"point", t.point}, {"caption", t.caption}});
  return doc;
}

std::vector<std::string> describe(const Summary& summary, const std::vector<Point>& points) {
  std::vector<std::string> lines;
  for (const Finding& f : summary.cheapest_on_time) {
    if (!f.point) {
      lines.push_back(f.scene + ", " + f.preset +
                      ": no point of the sweep fits the XC7A100T and draws every line on time");
      continue;
    }
    const Point& p = points[static_cast<std::size_t>(*f.point)];
    lines.push_back(f.scene + ": cheapest that fits and is on time: " + configuration_text(p) + ": " + cost_text(p) + "; " +
                    error_text(p));
  }
  for (const Finding& f : summary.sixty_hz) {
    if (!f.point) {
      lines.push_back(f.scene + ", path: no point of the sweep draws complete frames at 60 Hz and fits the XC7A100T");
      continue;
    }
    const Point& p = points[static_cast<std::size_t>(*f.point)];
    char fps[64];
    std::snprintf(fps, sizeof fps, "%.1f frames/s", p.m.fps);
    lines.push_back(f.scene + ": path at " + fps + " with the most samples per frame that fits: " +
                    configuration_text(p) + ": " + cost_text(p) + "; " + error_text(p));
  }
  return lines;
}

}  // namespace tripsitter::explore

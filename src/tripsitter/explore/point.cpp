#include <tripsitter/explore/point.h>

#include <cmath>
#include <cstdio>
#include <functional>

#include <nlohmann/json.hpp>

#include <tripsitter/device/resources.h>

namespace tripsitter::explore {
namespace {

using Value = nlohmann::ordered_json;

struct Field {
  Column column;
  std::function<Value(const Point&)> value;
};

// A column of the point's Configuration.
Field configuration(Column column, std::function<Value(const Point&)> value) {
  column.configuration = true;
  return {std::move(column), std::move(value)};
}

// Null unless the point is of the path preset (path == true) or of a mirror preset (path == false).
template <class F>
std::function<Value(const Point&)> only(bool path, F f) {
  return [path, f](const Point& p) { return p.config.path() == path ? Value(f(p)) : Value(nullptr); };
}

const std::vector<Field>& fields() {
  static const std::vector<Field> all = {
      {{"index", "", "the point's place in the sweep"}, [](const Point& p) { return p.index; }},
      configuration({"scene", "", "built-in scene or scene file"}, [](const Point& p) { return p.config.scene; }),
      configuration({"preset", "", "device preset the point starts from"}, [](const Point& p) { return p.config.preset; }),
      configuration({"workers", "", "ray-tracing workers"}, [](const Point& p) { return p.config.workers; }),
      configuration({"frac_bits", "bits", "fractional bits of x, y, z and radius"}, [](const Point& p) { return p.config.frac_bits; }),
      configuration({"sqrt_iterations", "", "square-root unit iterations"}, [](const Point& p) { return p.config.sqrt_iterations; }),
      configuration({"bounces", "", "mirror bounces"}, only(false, [](const Point& p) { return p.config.bounces; })),
      configuration({"capacity", "spheres", "scene memory capacity"}, [](const Point& p) { return p.config.capacity; }),
      configuration({"spp", "", "samples per pixel per frame"}, only(true, [](const Point& p) { return p.config.spp; })),
      configuration({"depth", "", "rays per path"}, only(true, [](const Point& p) { return p.config.depth; })),
      configuration({"frames", "", "frames of the still world drawn"}, [](const Point& p) { return p.config.frames; }),
      configuration({"spi_mhz", "MHz", "SPI clock"}, [](const Point& p) { return static_cast<double>(p.config.spi_hz) / 1e6; }),
      configuration({"transfer_bytes", "bytes", "largest SPI transfer"}, [](const Point& p) { return p.config.transfer_bytes; }),
      configuration({"frame_memory", "", "where frame memory lives"}, only(true, [](const Point& p) { return p.config.frame_memory; })),
      configuration({"wire", "", "link wire format"}, [](const Point& p) { return p.config.wire; }),
      {{"late_pixels", "", "pixels late in the last frame"}, [](const Point& p) { return p.m.late_pixels; }},
      {{"late_lines", "", "lines with a late pixel in the last frame"}, [](const Point& p) { return p.m.late_lines; }},
      {{"on_time", "", "every line meets its deadline"}, [](const Point& p) { return p.on_time(); }},
      {{"line_load", "", "slowest line's cycles / lead time"}, [](const Point& p) { return p.m.line_load; }},
      {{"fps", "frames/s", "complete new worlds per second the monitor could show"}, [](const Point& p) { return p.m.fps; }},
      {{"link_bits", "bits", "one world on the wire"}, [](const Point& p) { return p.m.link_bits; }},
      {{"link_ms", "ms", "one world at the SPI clock"}, [](const Point& p) { return p.m.link_ms; }},
      {{"link_transfers", "", "SPI transfers of one world"}, [](const Point& p) { return p.m.link_transfers; }},
      {{"saturations", "", "values the host clamped to the formats"}, [](const Point& p) { return p.m.saturations; }},
      {{"spheres", "", "spheres sent"}, [](const Point& p) { return p.m.spheres; }},
      {{"spheres_dropped", "", "spheres beyond scene memory"}, [](const Point& p) { return p.m.spheres_dropped; }},
      {{"pixels", "", "pixels compared"}, [](const Point& p) { return p.m.pixels; }},
      {{"differing", "", "pixels differing from the float reference"}, only(false, [](const Point& p) { return p.m.differing; })},
      {{"differing_percent", "%", "percent of pixels differing from the float reference"},
       only(false, [](const Point& p) { return p.error(); })},
      {{"over_one_level", "", "pixels differing by more than one level"}, only(false, [](const Point& p) { return p.m.over_one_level; })},
      {{"max_levels", "levels", "largest difference from the float reference"}, only(false, [](const Point& p) { return p.m.max_levels; })},
      {{"relmse", "", "relative MSE against the float path tracer"}, only(true, [](const Point& p) { return p.m.relmse; })},
      {{"bias", "", "mean relative bias against the float path tracer"}, only(true, [](const Point& p) { return p.m.bias; })},
      {{"reference_spp", "", "samples per pixel of the float path tracer"}, only(true, [](const Point& p) { return p.m.reference_spp; })},
      {{"multiplies", "per pixel", "multiplies per pixel"}, [](const Point& p) { return p.m.multiplies; }},
      {{"additions", "per pixel", "additions per pixel"}, [](const Point& p) { return p.m.additions; }},
      {{"square_roots", "per pixel", "square roots per pixel"}, [](const Point& p) { return p.m.square_roots; }},
      {{"divisions", "per pixel", "divisions per pixel"}, [](const Point& p) { return p.m.divisions; }},
      {{"random_draws", "per pixel", "random numbers per pixel"}, only(true, [](const Point& p) { return p.m.random_draws; })},
      {{"dsp", "slices", "DSP48E1 slices"}, [](const Point& p) { return p.m.dsp; }},
      {{"dsp_per_worker", "slices", "DSP48E1 slices per worker"}, [](const Point& p) { return p.m.dsp_per_worker; }},
      {{"dsp_shared", "slices", "DSP48E1 slices shared by the workers"}, [](const Point& p) { return p.m.dsp_shared; }},
      {{"luts", "LUTs", "LUTs as logic and memory (0: not counted)"}, [](const Point& p) { return p.m.luts; }},
      {{"bram_kbit", "Kbit", "block RAM needed"}, [](const Point& p) { return p.m.bram_kbit; }},
      {{"sram_bits_per_cycle", "bits/cycle", "external frame memory traffic"},
       only(true, [](const Point& p) { return p.m.sram_bits_per_cycle; })},
      {{"fits", "", "fits the XC7A100T's DSPs, LUTs and block RAM"}, [](const Point& p) { return p.fits(); }},
  };
  return all;
}

std::string csv_text(const Value& v) {
  if (v.is_null()) return "";
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_string()) {
    const std::string s = v.get<std::string>();
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string quoted = "\"";
    for (char c : s) {
      if (c == '"') quoted += '"';
      quoted += c;
    }
    return quoted + "\"";
  }
  if (v.is_number_float()) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", v.get<double>());
    return buf;
  }
  return v.dump();
}

}  // namespace

bool Point::dsp_fits() const { return m.dsp <= device::kBoardDsp; }
bool Point::lut_fits() const { return m.luts <= device::kBoardLuts; }
bool Point::bram_fits() const { return m.bram_kbit * 1024 <= static_cast<double>(device::kBoardBramBits); }

double Point::error() const {
  if (config.path()) return m.relmse;
  return m.pixels == 0 ? 0.0 : 100.0 * static_cast<double>(m.differing) / static_cast<double>(m.pixels);
}

const std::vector<Column>& columns() {
  static const std::vector<Column> all = [] {
    std::vector<Column> c;
    for (const auto& f : fields()) c.push_back(f.column);
    return c;
  }();
  return all;
}

nlohmann::ordered_json columns_json() {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const Column& c : columns())
    out.push_back({{"name", c.name}, {"unit", c.unit}, {"description", c.description}, {"configuration", c.configuration}});
  return out;
}

nlohmann::ordered_json to_json(const Point& point) {
  nlohmann::ordered_json doc = nlohmann::ordered_json::object();
  for (const auto& f : fields()) {
    Value v = f.value(point);
    if (v.is_number_float() && !std::isfinite(v.get<double>())) v = nullptr;
    doc[f.column.name] = std::move(v);
  }
  return doc;
}

std::string csv_header() {
  std::string line;
  for (const auto& f : fields()) line += (line.empty() ? "" : ",") + f.column.name;
  return line;
}

std::string csv_row(const Point& point) {
  std::string line;
  bool first = true;
  for (const auto& f : fields()) {
    if (!first) line += ',';
    first = false;
    line += csv_text(f.value(point));
  }
  return line;
}

}  // namespace tripsitter::explore

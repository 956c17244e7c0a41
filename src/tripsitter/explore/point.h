// One point of a design-space sweep (`tripsitter explore`, docs/explore.md): a device configuration, a scene, and
// what the bit-exact device model measured for them. points.csv, points.json and index.html are written from
// these; every figure has one column, in the order of columns().
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace tripsitter::explore {

// The configuration of a point: the parameters `--sweep` names (sweep.h), with the preset's own values where the
// sweep leaves one alone.
struct Configuration {
  std::string scene;      // a built-in name or a scene file, as given to --scene
  std::string preset;     // wide, board-2023 or path
  int workers = 0;
  int frac_bits = 0;      // of x, y, z and radius; each format keeps its integer bits
  int sqrt_iterations = 0;
  int bounces = 0;        // mirror bounces (wide and board-2023)
  int capacity = 0;       // scene memory, in spheres
  int spp = 0;            // path preset only (0 otherwise): samples per pixel per frame
  int depth = 0;          // path preset only: rays per path
  int frames = 1;         // frames of the still world drawn; a path preset accumulates them in frame memory
  std::int64_t spi_hz = 0;
  std::int64_t transfer_bytes = 0;
  std::string frame_memory;  // path preset only: "external" (the board's DDR3L) or "bram"; empty otherwise
  std::string wire;          // v1 or v2

  bool path() const { return spp > 0; }
  bool operator==(const Configuration&) const = default;
};

// What the model measured for a configuration.
struct Measurement {
  // Time. fps: the frames per second at which the device could show complete new worlds: the monitor's
  // refresh rate, divided by the slowest line's load when it is above 1, and at most the worlds per second the
  // link carries.
  int late_pixels = 0;
  int late_lines = 0;
  double line_load = 0;   // the slowest line's cycles (its busiest worker's, to the last colour) / the lead time
  double fps = 0;
  std::uint64_t link_bits = 0;   // one world on the wire
  double link_ms = 0;            // its bits at the SPI clock (the link model has no gaps between transfers)
  std::uint64_t link_transfers = 0;  // SPI transfers (chip-select assertions) the host's driver makes of it
  // The host's conversion.
  std::uint64_t saturations = 0;
  std::uint64_t spheres = 0;           // sent
  std::uint64_t spheres_dropped = 0;   // beyond scene memory
  // Error against the float renderer of the same world. Mirror presets: pixels of the 12-bit picture that
  // differ from the float reference's, how many by more than one level, the largest difference in levels.
  // Path preset: relMSE and mean relative bias of frame memory's linear mean against the float path tracer of
  // the device's rays at reference_spp samples per pixel (modes/device_compare.h).
  std::uint64_t pixels = 0;
  std::uint64_t differing = 0;
  std::uint64_t over_one_level = 0;
  int max_levels = 0;
  double relmse = 0;
  double bias = 0;
  int reference_spp = 0;
  // Operations per pixel of the last frame (device/resources.h), every pixel traced counted.
  double multiplies = 0, additions = 0, square_roots = 0, divisions = 0, random_draws = 0;
  // On the XC7A100T (device/resources.h).
  int dsp = 0;                // dsp_per_worker * workers + dsp_shared
  int dsp_per_worker = 0;
  int dsp_shared = 0;
  int luts = 0;               // LUTs as logic and as memory: the ledger's RTL blocks (0 for a preset without)
  double bram_kbit = 0;       // block RAM the design needs, in whole 18-Kbit halves
  double sram_bits_per_cycle = 0;  // frame memory's traffic when it is external (0 otherwise)
};

struct Point {
  int index = 0;  // in the sweep's order
  Configuration config;
  Measurement m;
  std::vector<std::uint8_t> thumbnail_png;  // the monitor's frame, scaled down (empty: not kept)

  bool on_time() const { return m.late_lines == 0; }
  bool dsp_fits() const;
  bool lut_fits() const;  // true when the LUTs are not counted (luts 0)
  bool bram_fits() const;
  bool fits() const { return dsp_fits() && lut_fits() && bram_fits(); }
  // The error in one number for charts: percent of pixels differing (mirror presets) or relMSE (path).
  double error() const;
};

// A column of points.csv and a key of points.json: its name and unit (for the page's axes).
struct Column {
  std::string name;
  std::string unit;
  std::string description;
  bool configuration = false;  // one of the point's Configuration (what was swept), not a measurement
};
const std::vector<Column>& columns();
// The columns as points.json and the report's page carry them: [{name, unit, description, configuration}, ...].
nlohmann::ordered_json columns_json();

// The point's value in each column, in columns()'s order: numbers, text and booleans; null where a column does
// not apply (relmse on a mirror preset, differing on a path one, spp and frame_memory off the path preset).
nlohmann::ordered_json to_json(const Point& point);
std::string csv_header();
std::string csv_row(const Point& point);

}  // namespace tripsitter::explore

// The points of a design-space sweep (docs/explore.md, "Sweeps"): `--sweep` specifications parsed, checked and
// expanded over the scenes into device configurations.
//
// A specification is a comma-separated list of parameters, each `name=values`; a parameter's values run on
// after further commas until the next `name=`: `preset=board-2023,workers=1..16,fracbits=3,4,8`. A value is a
// number, a range `a..b` (every integer from a to b) or `a..b:s` (a, a + s, ... up to b), or a word. The sweep
// is every combination of its parameters' values; a parameter it does not name keeps the preset's value.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <tripsitter/device/preset.h>
#include <tripsitter/explore/point.h>
#include <tripsitter/link/spi.h>

namespace tripsitter::explore {

// A specification the sweep cannot run: what is wrong, and where (a byte offset into the specification).
class SweepError : public std::invalid_argument {
 public:
  SweepError(std::string spec, std::size_t offset, const std::string& what);
  const std::string& spec() const { return spec_; }
  std::size_t offset() const { return offset_; }
  // The message, the specification and a caret under the offending part, on three lines.
  std::string pointed() const;

 private:
  std::string spec_;
  std::size_t offset_;
};

// The parameters a specification may name, with what each means, for --help and errors.
struct ParameterInfo {
  std::string name;
  std::string values;  // what it takes
  std::string meaning;
};
const std::vector<ParameterInfo>& parameters();

// One parsed specification: each named parameter and its values as text (numbers already checked), in order.
struct Sweep {
  std::string spec;
  struct Parameter {
    std::string name;
    std::size_t offset = 0;            // of the name in spec
    std::vector<std::string> values;   // expanded (ranges become their numbers)
    std::vector<std::size_t> offsets;  // of each value's text in spec (a range's numbers share its offset)
  };
  std::vector<Parameter> parameters;
};

// Throws SweepError for a specification that is not the syntax above, names an unknown or repeated parameter,
// gives a value out of the parameter's range, or expands to more than kMaxPoints combinations.
Sweep parse_sweep(const std::string& spec);

inline constexpr std::size_t kMaxPoints = 10'000;

// The specifications `tripsitter explore` runs without --sweep, and the scenes without --scene.
std::vector<std::string> default_sweeps();
std::vector<std::string> default_scenes();

// The configuration of a preset as it is, over `scene`: the point a sweep starts each combination from.
// REQUIRES preset to name a preset (device::preset_by_name).
Configuration preset_configuration(const std::string& scene, const std::string& preset);

// A point's configuration made into the device preset and link settings it runs with.
struct DeviceSetup {
  device::DevicePreset preset;
  link::SpiConfig spi;
  std::string wire;
};

// The configurations of `sweeps` over `scenes`, scene by scene, each sweep's combinations in order (the last
// parameter varying fastest); a configuration met twice runs once. Throws SweepError when a combination is not a
// device the model can run (a path parameter with a mirror preset, formats wider than the preset allows, ...),
// pointing at the value that made it so.
std::vector<Configuration> expand(const std::vector<Sweep>& sweeps, const std::vector<std::string>& scenes);

// The device preset, SPI settings and wire of a configuration that expand() returned.
DeviceSetup setup_of(const Configuration& config);

}  // namespace tripsitter::explore

#include <tripsitter/explore/sweep.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <functional>
#include <set>
#include <cstdio>
#include <tuple>

#include <tripsitter/device/frame_memory.h>
#include <tripsitter/device/sqrt_unit.h>

namespace tripsitter::explore {
namespace {

// Which presets a parameter applies to.
enum class Applies { kAny, kMirror, kPath };

struct ParameterRule {
  ParameterInfo info;
  Applies applies = Applies::kAny;
  // Numbers: the range allowed, and whether decimals are; words: the words allowed (numbers not).
  double lo = 0, hi = 0;
  bool decimal = false;
  std::vector<std::string> words;
  // Sets the parameter's value in a configuration.
  std::function<void(Configuration&, const std::string&)> set;
};

int to_int(const std::string& s) { return std::stoi(s); }

const std::vector<ParameterRule>& rules() {
  static const std::vector<ParameterRule> all = [] {
    std::vector<ParameterRule> r;
    const auto number = [&r](std::string name, std::string meaning, Applies applies, double lo, double hi,
                             std::function<void(Configuration&, const std::string&)> set, bool decimal = false) {
      ParameterRule rule;
      char range[64];
      std::snprintf(range, sizeof range, decimal ? "%g to %g" : "%.0f to %.0f", lo, hi);
      rule.info = {std::move(name), range, std::move(meaning)};
      rule.applies = applies;
      rule.lo = lo;
      rule.hi = hi;
      rule.decimal = decimal;
      rule.set = std::move(set);
      r.push_back(std::move(rule));
    };
    const auto word = [&r](std::string name, std::string meaning, Applies applies, std::vector<std::string> words,
                           std::function<void(Configuration&, const std::string&)> set) {
      ParameterRule rule;
      std::string list;
      for (const auto& w : words) list += (list.empty() ? "" : ", ") + w;
      rule.info = {std::move(name), list, std::move(meaning)};
      rule.applies = applies;
      rule.words = std::move(words);
      rule.set = std::move(set);
      r.push_back(std::move(rule));
    };
    word("preset", "the device preset a point starts from (docs/device.md)", Applies::kAny, device::preset_names(),
         [](Configuration& c, const std::string& v) { c.preset = v; });
    number("workers", "ray-tracing workers", Applies::kAny, 1, device::kLineWidth,
           [](Configuration& c, const std::string& v) { c.workers = to_int(v); });
    number("fracbits", "fractional bits of x, y, z and radius (each format keeps its integer bits)", Applies::kAny, 0,
           30, [](Configuration& c, const std::string& v) { c.frac_bits = to_int(v); });
    number("sqrt", "iterations of the square-root unit", Applies::kAny, 1, device::kMaxSqrtIterations,
           [](Configuration& c, const std::string& v) { c.sqrt_iterations = to_int(v); });
    number("bounces", "mirror bounces (wide, board-2023)", Applies::kMirror, 0, core::kMaxBounces,
           [](Configuration& c, const std::string& v) { c.bounces = to_int(v); });
    number("capacity", "scene memory, in spheres", Applies::kAny, 1, 1'000'000,
           [](Configuration& c, const std::string& v) { c.capacity = to_int(v); });
    number("spp", "samples per pixel per frame (path)", Applies::kPath, 1, device::kMaxSamples,
           [](Configuration& c, const std::string& v) { c.spp = to_int(v); });
    number("depth", "rays per path (path)", Applies::kPath, 1, device::kMaxPathDepth,
           [](Configuration& c, const std::string& v) { c.depth = to_int(v); });
    number("frames", "frames of the still world drawn (path: accumulated in frame memory)", Applies::kAny, 1, 64,
           [](Configuration& c, const std::string& v) { c.frames = to_int(v); });
    number("spi", "SPI clock in MHz", Applies::kAny, 0.001, 1000,
           [](Configuration& c, const std::string& v) { c.spi_hz = std::llround(std::stod(v) * 1e6); }, true);
    number("transfer", "largest SPI transfer, in bytes", Applies::kAny, 1, 1 << 20,
           [](Configuration& c, const std::string& v) { c.transfer_bytes = to_int(v); });
    word("memory", "where frame memory lives (path)", Applies::kPath, {"external", "bram"},
         [](Configuration& c, const std::string& v) { c.frame_memory = v; });
    word("wire", "the link's wire format (v1 words carry no material: normal-shaded)", Applies::kAny, {"v1", "v2", "v3"},
         [](Configuration& c, const std::string& v) { c.wire = v; });
    return r;
  }();
  return all;
}

const ParameterRule* rule_named(std::string_view name) {
  for (const auto& r : rules())
    if (r.info.name == name) return &r;
  return nullptr;
}

std::string known_names() {
  std::string list;
  for (const auto& r : rules()) list += (list.empty() ? "" : ", ") + r.info.name;
  return list;
}

std::optional<long long> parse_integer(std::string_view s) {
  long long v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

std::optional<double> parse_decimal(std::string_view s) {
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string format_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Adds `text` (at `offset` in spec), one value of `rule`, to `parameter`: a word, a number, or a range.
void add_values(const std::string& spec, const ParameterRule& rule, std::string_view text, std::size_t offset,
                Sweep::Parameter& parameter) {
  const auto add = [&](std::string value) {
    if (std::find(parameter.values.begin(), parameter.values.end(), value) != parameter.values.end())
      throw SweepError(spec, offset, parameter.name + "=" + value + " is listed twice");
    parameter.values.push_back(std::move(value));
    parameter.offsets.push_back(offset);
  };
  if (text.empty()) throw SweepError(spec, offset, parameter.name + " has an empty value");
  if (!rule.words.empty()) {
    if (std::find(rule.words.begin(), rule.words.end(), text) == rule.words.end())
      throw SweepError(spec, offset, "'" + std::string(text) + "' is not a value of " + parameter.name + " (" +
                                         rule.info.values + ")");
    add(std::string(text));
    return;
  }
  const auto in_range = [&](double v, std::size_t at) {
    if (v < rule.lo || v > rule.hi)
      throw SweepError(spec, at, parameter.name + " must be " + rule.info.values + ", not " + format_number(v));
  };
  const std::size_t dots = text.find("..");
  if (dots == std::string_view::npos) {
    std::optional<double> v = parse_decimal(text);
    if (!rule.decimal) {
      const auto i = parse_integer(text);
      v = i ? std::optional<double>(static_cast<double>(*i)) : std::nullopt;
    }
    if (!v)
      throw SweepError(spec, offset, "'" + std::string(text) + "' is not " + (rule.decimal ? "a number" : "an integer") +
                                         " (" + parameter.name + " takes " + rule.info.values + ")");
    in_range(*v, offset);
    add(format_number(*v));
    return;
  }
  // a..b or a..b:s, integers only
  const std::string_view first = text.substr(0, dots);
  std::string_view rest = text.substr(dots + 2);
  std::string_view step_text = "1";
  std::size_t step_at = 0;
  if (const std::size_t colon = rest.find(':'); colon != std::string_view::npos) {
    step_text = rest.substr(colon + 1);
    step_at = offset + dots + 2 + colon + 1;
    rest = rest.substr(0, colon);
  }
  const auto a = parse_integer(first);
  const auto b = parse_integer(rest);
  const auto s = parse_integer(step_text);
  if (!a) throw SweepError(spec, offset, "'" + std::string(first) + "' does not start a range of integers (a..b or a..b:step)");
  if (!b) throw SweepError(spec, offset + dots + 2, "'" + std::string(rest) + "' does not end a range of integers (a..b or a..b:step)");
  if (!s || *s < 1) throw SweepError(spec, step_at, "a range's step must be a positive integer, not '" + std::string(step_text) + "'");
  if (*b < *a) throw SweepError(spec, offset, "the range " + std::string(text) + " is empty: it must go up");
  in_range(static_cast<double>(*a), offset);
  in_range(static_cast<double>(*b), offset + dots + 2);
  if ((*b - *a) / *s + 1 > static_cast<long long>(kMaxPoints))
    throw SweepError(spec, offset, "the range " + std::string(text) + " has more than " + std::to_string(kMaxPoints) + " values");
  for (long long v = *a; v <= *b; v += *s) add(std::to_string(v));
}

}  // namespace

Configuration preset_configuration(const std::string& scene, const std::string& preset_name) {
  const auto preset = device::preset_by_name(preset_name);
  const link::SpiConfig spi;
  Configuration c;
  c.scene = scene;
  c.preset = preset_name;
  c.workers = preset->workers;
  c.frac_bits = preset->frac_bits();
  c.sqrt_iterations = preset->sqrt_iterations;
  c.bounces = preset->path ? 0 : preset->max_bounces;
  c.capacity = static_cast<int>(preset->max_spheres);
  c.spp = preset->path ? preset->path->spp : 0;
  c.depth = preset->path ? preset->path->depth : 0;
  c.frames = 1;
  c.spi_hz = spi.clock_hz;
  c.transfer_bytes = static_cast<std::int64_t>(spi.max_transfer_bytes);
  c.frame_memory = preset->path ? "external" : "";
  c.wire = "v3";
  return c;
}

namespace {

auto key_of(const Configuration& c) {
  return std::make_tuple(c.scene, c.preset, c.workers, c.frac_bits, c.sqrt_iterations, c.bounces, c.capacity, c.spp, c.depth,
                  c.frames, c.spi_hz, c.transfer_bytes, c.frame_memory, c.wire);
}

}  // namespace

SweepError::SweepError(std::string spec, std::size_t offset, const std::string& what)
    : std::invalid_argument(what), spec_(std::move(spec)), offset_(offset) {}

std::string SweepError::pointed() const {
  return std::string(what()) + "\n  " + spec_ + "\n  " + std::string(std::min(offset_, spec_.size()), ' ') + "^";
}

const std::vector<ParameterInfo>& parameters() {
  static const std::vector<ParameterInfo> all = [] {
    std::vector<ParameterInfo> p;
    for (const auto& r : rules()) p.push_back(r.info);
    return p;
  }();
  return all;
}

Sweep parse_sweep(const std::string& spec) {
  Sweep sweep;
  sweep.spec = spec;
  if (spec.empty()) throw SweepError(spec, 0, "the sweep is empty: it needs name=values (" + known_names() + ")");
  std::size_t at = 0;
  while (at <= spec.size()) {
    const std::size_t comma = std::min(spec.find(',', at), spec.size());
    const std::string_view item(spec.data() + at, comma - at);
    if (const std::size_t eq = item.find('='); eq != std::string_view::npos) {
      const std::string name(item.substr(0, eq));
      const ParameterRule* rule = rule_named(name);
      if (rule == nullptr)
        throw SweepError(spec, at, name.empty() ? "a parameter has no name before '='"
                                                : "unknown parameter '" + name + "' (known: " + known_names() + ")");
      for (const auto& p : sweep.parameters)
        if (p.name == name) throw SweepError(spec, at, name + " is named twice in one sweep");
      sweep.parameters.push_back({name, at, {}, {}});
      add_values(spec, *rule, item.substr(eq + 1), at + eq + 1, sweep.parameters.back());
    } else {
      if (sweep.parameters.empty())
        throw SweepError(spec, at, "'" + std::string(item) + "' has no parameter: write name=values (" + known_names() + ")");
      add_values(spec, *rule_named(sweep.parameters.back().name), item, at, sweep.parameters.back());
    }
    at = comma + 1;
  }
  std::size_t combinations = 1;
  for (const auto& p : sweep.parameters) {
    combinations *= p.values.size();
    if (combinations > kMaxPoints)
      throw SweepError(spec, p.offset, "the sweep has more than " + std::to_string(kMaxPoints) +
                                           " combinations from here on; split it or use range steps (a..b:step)");
  }
  return sweep;
}

std::vector<std::string> default_sweeps() {
  return {
      // The board's formats and cycle costs: how many workers draw each line in time.
      "preset=board-2023,workers=1..96,112,128,160,192,256,320,640",
      // Pipelined workers with the wide formats.
      "preset=wide,workers=1..16",
      // What the formats' fractional bits and the square-root unit's iterations cost in error, with workers enough
      // to be on time.
      "preset=board-2023,workers=96,fracbits=0..8",
      "preset=wide,fracbits=0..12",
      "preset=board-2023,workers=96,sqrt=2..16",
      "preset=wide,sqrt=2..16",
      // Mirrors: reflections cost passes over the spheres.
      "preset=wide,bounces=0..3,workers=2,4,10",
      // The path preset: samples per pixel and depth against frames per second, the workers each needs, and
      // where frame memory lives.
      "preset=path,spp=1,2,4,8,16,depth=1,2,4,8",
      "preset=path,workers=1..16,32,64",
      "preset=path,fracbits=0..4",
      "preset=path,workers=3,8,spp=1,frames=1,4,16",
      "preset=path,memory=external,bram",
      // The link: SPI clock and transfer size, for both wires, with workers enough that the link alone limits.
      "preset=board-2023,workers=96,spi=0.01,0.02,0.05,0.1,0.2,0.5,1,10,transfer=64,1024,wire=v1,v2,v3",
  };
}

std::vector<std::string> default_scenes() { return {"demo", "cluster"}; }

DeviceSetup setup_of(const Configuration& c) {
  auto preset = device::preset_by_name(c.preset);
  if (!preset) throw std::invalid_argument("unknown preset " + c.preset);
  DeviceSetup s{*preset, {}, c.wire};
  device::DevicePreset& p = s.preset;
  p.workers = c.workers;
  for (core::FixedFormat* f : {&p.x, &p.y, &p.z, &p.radius}) {
    f->total_bits += c.frac_bits - f->frac_bits;
    f->frac_bits = c.frac_bits;
  }
  p.sqrt_iterations = c.sqrt_iterations;
  if (!p.path) p.max_bounces = c.bounces;
  p.max_spheres = static_cast<std::uint32_t>(c.capacity);
  if (p.path) {
    p.path->spp = c.spp;
    p.path->depth = c.depth;
    p.path->frame_memory = c.frame_memory == "bram" ? device::FrameMemoryPlace::kBlockRam : device::FrameMemoryPlace::kExternal;
  }
  p.trace_late_pixels = true;  // the slowest line's load, exactly (line_load, fps)
  s.spi.clock_hz = c.spi_hz;
  s.spi.max_transfer_bytes = static_cast<std::size_t>(c.transfer_bytes);
  return s;
}

namespace {

// The preset parameter of a sweep, or null: a sweep that names none runs wide.
const Sweep::Parameter* preset_parameter(const Sweep& sweep) {
  for (const auto& p : sweep.parameters)
    if (p.name == "preset") return &p;
  return nullptr;
}

// Throws SweepError at a parameter of the path preset in a sweep of a mirror preset, or the other way round.
void check_kinds(const Sweep& sweep) {
  const Sweep::Parameter* preset = preset_parameter(sweep);
  const std::vector<std::string> presets = preset != nullptr ? preset->values : std::vector<std::string>{"wide"};
  for (const auto& p : sweep.parameters) {
    const Applies applies = rule_named(p.name)->applies;
    if (applies == Applies::kAny) continue;
    for (const std::string& name : presets) {
      const bool path = device::preset_by_name(name)->path.has_value();
      if (path != (applies == Applies::kPath))
        throw SweepError(sweep.spec, p.offset,
                         p.name + " is a parameter of " + (path ? "the mirror presets" : "the path preset") +
                             ", and this sweep runs preset " + name);
    }
  }
}

}  // namespace

std::vector<Configuration> expand(const std::vector<Sweep>& sweeps, const std::vector<std::string>& scenes) {
  for (const Sweep& sweep : sweeps) check_kinds(sweep);
  std::vector<Configuration> out;
  std::set<decltype(key_of(std::declval<const Configuration&>()))> seen;
  for (const auto& scene : scenes) {
    for (const Sweep& sweep : sweeps) {
      // The preset of each combination first: it sets the values the other parameters change.
      const Sweep::Parameter* preset = preset_parameter(sweep);
      const std::size_t preset_k = preset != nullptr ? static_cast<std::size_t>(preset - sweep.parameters.data()) : 0;
      std::vector<std::size_t> choice(sweep.parameters.size(), 0);
      for (bool more = true; more;) {
        Configuration c = preset_configuration(scene, preset != nullptr ? preset->values[choice[preset_k]] : "wide");
        for (std::size_t k = 0; k < sweep.parameters.size(); ++k)
          rule_named(sweep.parameters[k].name)->set(c, sweep.parameters[k].values[choice[k]]);
        if (auto why = setup_of(c).preset.validate()) {
          // Point at the value that alone makes the preset fail, if one does.
          std::size_t at = 0;
          for (std::size_t k = 0; k < sweep.parameters.size() && at == 0; ++k) {
            Configuration alone = preset_configuration(scene, c.preset);
            rule_named(sweep.parameters[k].name)->set(alone, sweep.parameters[k].values[choice[k]]);
            if (setup_of(alone).preset.validate()) at = sweep.parameters[k].offsets[choice[k]];
          }
          throw SweepError(sweep.spec, at, "preset " + c.preset + " cannot run this combination: " + *why);
        }
        if (seen.insert(key_of(c)).second) {
          if (out.size() == kMaxPoints)
            throw SweepError(sweep.spec, 0, "the sweeps over " + std::to_string(scenes.size()) +
                                                " scenes make more than " + std::to_string(kMaxPoints) + " points");
          out.push_back(c);
        }
        // The next combination, the last parameter fastest.
        more = false;
        for (std::size_t k = sweep.parameters.size(); k-- > 0;) {
          if (++choice[k] < sweep.parameters[k].values.size()) {
            more = true;
            break;
          }
          choice[k] = 0;
        }
      }
    }
  }
  return out;
}

}  // namespace tripsitter::explore

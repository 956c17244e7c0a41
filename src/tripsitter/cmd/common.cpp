#include "common.h"

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <iterator>

#include <tripsitter/scene/scene_json.h>

namespace tripsitter::cmd {

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

MpirunPlace mpirun_place() {
  const auto number = [](const char* name) {
    const char* value = std::getenv(name);
    return value != nullptr ? std::atoi(value) : 0;
  };
  return {number("OMPI_COMM_WORLD_RANK"), number("OMPI_COMM_WORLD_SIZE")};
}

scene::Scene load_scene(const std::string& name_or_path) {
  auto result = scene::resolve_scene(name_or_path);
  if (!result) throw InputError(result.error().to_string());
  return std::move(result).value();
}

device::DevicePreset load_preset(const std::string& name, int workers, int bounces, int spp, int depth) {
  auto preset = device::preset_by_name(name);
  if (!preset) throw InputError("unknown preset '" + name + "' (known: " + join(device::preset_names()) + ")");
  if (workers != 0) preset->workers = workers;
  if (bounces >= 0) preset->max_bounces = bounces;
  if ((spp != 0 || depth != 0) && !preset->path)
    throw InputError("--spp and --depth in hw mode need a path-tracing preset (--preset path or artix-path); preset " + name +
                     " traces one ray per pixel");
  if (spp != 0) preset->path->spp = spp;
  if (depth != 0) preset->path->depth = depth;
  if (auto why = preset->validate()) throw InputError("preset " + name + ": " + *why);
  return *preset;
}

std::vector<std::uint8_t> read_bytes(const std::string& path) {
  if (path == "-") {
    std::cin >> std::noskipws;
    return {std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>()};
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace tripsitter::cmd

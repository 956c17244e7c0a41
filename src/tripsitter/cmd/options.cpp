#include "options.h"

#include <utility>
#include <vector>

#include <tripsitter/device/preset.h>
#include <tripsitter/scene/builtin.h>

#include "common.h"

namespace tripsitter::cmd {
namespace {

std::string with_note(std::string help, std::string_view note) {
  if (!note.empty()) help += "; " + std::string(note);
  return help;
}

// `flag` takes one of `choices` by name and stores its enum as the command line is read; an unknown name is a
// usage error that names the choices. The help shows the value's name as the default.
template <class E>
CLI::Option* add_choice_option(CLI::App& cmd, const std::string& flag, const std::string& noun, E& value,
                               const std::vector<std::pair<std::string, E>>& choices, const std::string& help) {
  std::vector<std::string> names;
  std::string default_name;
  for (const auto& [name, choice] : choices) {
    names.push_back(name);
    if (choice == value) default_name = name;
  }
  const auto parse = [&value, flag, noun, choices, known = join(names)](const std::string& given) {
    for (const auto& [name, choice] : choices) {
      if (name == given) {
        value = choice;
        return;
      }
    }
    throw CLI::ValidationError(flag, "unknown " + noun + " '" + given + "' (known: " + known + ")");
  };
  return cmd.add_option_function<std::string>(flag, parse, help)->default_str(default_name);
}

}  // namespace

CLI::Option* add_scene_option(CLI::App& cmd, std::string& scene, std::string_view note) {
  return cmd
      .add_option("--scene", scene,
                  with_note("Built-in scene name (" + join(scene::builtin_names()) + ", random-N) or JSON scene file",
                            note))
      ->capture_default_str();
}

CLI::Option* add_preset_option(CLI::App& cmd, std::string& preset, std::string_view note) {
  return cmd.add_option("--preset", preset, with_note("Device preset (" + join(device::preset_names()) + ")", note))
      ->capture_default_str();
}

CLI::Option* add_wire_option(CLI::App& cmd, link::WireVersion& wire, std::string_view note) {
  std::vector<std::pair<std::string, link::WireVersion>> choices;
  for (link::WireVersion w : {link::WireVersion::kV1, link::WireVersion::kV2, link::WireVersion::kV3})
    choices.emplace_back(link::wire_name(w), w);
  return add_choice_option(cmd, "--wire", "wire", wire, choices,
                           with_note("Link protocol: v1 (the board's 8-byte sphere word), v2 (framed worlds) or v3 "
                                     "(framed worlds with a header check and sessions)",
                                     note));
}

CLI::Option* add_mode_option(CLI::App& cmd, modes::Mode& mode, std::string_view note) {
  std::vector<std::pair<std::string, modes::Mode>> choices;
  for (modes::Mode m : {modes::Mode::kHw, modes::Mode::kNormal, modes::Mode::kPath})
    choices.emplace_back(modes::mode_name(m), m);
  return add_choice_option(cmd, "--mode", "mode", mode, choices, with_note("How the picture is made", note));
}

CLI::Option* add_sampler_option(CLI::App& cmd, render::SamplerKind& sampler, std::string_view note) {
  return add_choice_option(cmd, "--sampler", "sampler", sampler,
                           {{"sobol", render::SamplerKind::kSobol}, {"independent", render::SamplerKind::kIndependent}},
                           with_note("Where the path tracer's samples come from: sobol (Owen-scrambled Sobol points, "
                                     "less noise at equal spp) or independent (a random stream per pixel)",
                                     note));
}

CLI::Option* add_exr_pixel_option(CLI::App& cmd, display::ExrPixel& pixel, std::string_view note) {
  return add_choice_option(cmd, "--exr-pixel", "pixel type", pixel,
                           {{"half", display::ExrPixel::kHalf}, {"float", display::ExrPixel::kFloat}},
                           with_note("OpenEXR channels: half or float (depth is always float)", note));
}

}  // namespace tripsitter::cmd

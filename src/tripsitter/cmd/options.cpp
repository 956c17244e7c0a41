#include "options.h"

#include <tripsitter/device/preset.h>
#include <tripsitter/scene/builtin.h>

#include "common.h"

namespace tripsitter::cmd {
namespace {

std::string with_note(std::string help, std::string_view note) {
  if (!note.empty()) help += "; " + std::string(note);
  return help;
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
  return cmd
      .add_option_function<std::string>(
          "--wire",
          [&wire](const std::string& name) {
            const auto parsed = link::wire_by_name(name);
            if (!parsed) throw CLI::ValidationError("--wire", "unknown wire '" + name + "' (known: v1, v2, v3)");
            wire = *parsed;
          },
          with_note("Link protocol: v1 (the board's 8-byte sphere word), v2 (framed worlds) or v3 (framed worlds "
                    "with a header check and sessions)",
                    note))
      ->default_str(std::string(link::wire_name(wire)));
}

}  // namespace tripsitter::cmd

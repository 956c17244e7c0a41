// The options several subcommands share, each declared once here with one help text: --scene, --preset and
// --wire. A subcommand adds what the option means for it as a note (appended to the help after "; "). --wire is
// parsed to link::WireVersion as the command line is read, so the subcommands hold the enum, never the name.
#pragma once

#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include <tripsitter/link/wire.h>

namespace tripsitter::cmd {

// --scene: a built-in scene's name (random-N included) or a JSON scene file (load_scene reads either).
CLI::Option* add_scene_option(CLI::App& cmd, std::string& scene, std::string_view note = {});

// --preset: a device preset's name (checked where the preset is loaded: load_preset).
CLI::Option* add_preset_option(CLI::App& cmd, std::string& preset, std::string_view note = {});

// --wire: v1, v2 or v3; an unknown name is a usage error (exit 2) naming the wires there are.
CLI::Option* add_wire_option(CLI::App& cmd, link::WireVersion& wire, std::string_view note = {});

}  // namespace tripsitter::cmd

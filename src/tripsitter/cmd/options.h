// The options several subcommands share, each declared once here with one help text: --scene, --preset, --wire
// and --mode, and render's choices --sampler and --exr-pixel. A subcommand adds what the option means for it as a
// note (appended to the help after "; "). The choices are parsed to their enums as the command line is read, so
// the subcommands hold the enum, never the name, and an unknown name is a usage error (exit 2) naming the
// choices there are.
#pragma once

#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include <tripsitter/display/io.h>
#include <tripsitter/link/wire.h>
#include <tripsitter/modes/mode.h>
#include <tripsitter/render/sampler.h>

namespace tripsitter::cmd {

// --scene: a built-in scene's name (random-N included) or a JSON scene file (load_scene reads either).
CLI::Option* add_scene_option(CLI::App& cmd, std::string& scene, std::string_view note = {});

// --preset: a device preset's name (checked where the preset is loaded: load_preset).
CLI::Option* add_preset_option(CLI::App& cmd, std::string& preset, std::string_view note = {});

// --wire: v1, v2 or v3; an unknown name is a usage error (exit 2) naming the wires there are.
CLI::Option* add_wire_option(CLI::App& cmd, link::WireVersion& wire, std::string_view note = {});

// --mode: hw, normal or path; the note says what each mode does in the subcommand.
CLI::Option* add_mode_option(CLI::App& cmd, modes::Mode& mode, std::string_view note);

// --sampler: sobol or independent (render::SamplerKind).
CLI::Option* add_sampler_option(CLI::App& cmd, render::SamplerKind& sampler, std::string_view note = {});

// --exr-pixel: half or float channels of an OpenEXR file.
CLI::Option* add_exr_pixel_option(CLI::App& cmd, display::ExrPixel& pixel, std::string_view note = {});

}  // namespace tripsitter::cmd

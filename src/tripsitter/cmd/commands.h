// The subcommands of tripsitter. Each adds itself to the app and, when chosen, sets `run`.
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace tripsitter::cmd {

using Action = std::function<int()>;

void add_render_command(CLI::App& app, Action& run);
void add_link_command(CLI::App& app, Action& run);
void add_bench_command(CLI::App& app, Action& run);
void add_host_command(CLI::App& app, Action& run);
void add_device_command(CLI::App& app, Action& run);
void add_run_command(CLI::App& app, Action& run);
void add_approx_command(CLI::App& app, Action& run);
void add_explore_command(CLI::App& app, Action& run);
void add_rom_command(CLI::App& app, Action& run);

}  // namespace tripsitter::cmd

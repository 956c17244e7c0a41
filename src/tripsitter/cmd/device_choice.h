// --device: which back-end plays the device (device/backend.h) in render, run and the device program: the C++ model
// or, in builds with Verilator, the Verilated RTL (rtl/device/rtl_device.h).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include <tripsitter/device/backend.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/link/wire.h>

namespace tripsitter::cmd {

struct DeviceChoice {
  std::string name = "model";  // model or rtl
  // rtl only: SCLK, and a VCD of the simulation (its pins; with vcd_worker >= 0 every signal of that worker too),
  // from reset to `vcd_lines` lines into the first frame drawn.
  std::int64_t spi_hz = 10'000'000;
  std::string vcd;
  int vcd_worker = -1;
  int vcd_lines = 525;
};

// Adds --device (and says which RTL builds this program has) to a subcommand.
void add_device_option(CLI::App& cmd, DeviceChoice& choice);

// Whether --device names the RTL; throws InputError for a name that is neither model nor rtl.
bool wants_rtl(const DeviceChoice& choice);

// The back-end's maker for a board (board::BoardConfig::make_device): empty for the model; for the RTL the device,
// made now so that a preset, worker count or wire the program has no build of fails before any work (InputError,
// naming the builds there are).
std::function<std::unique_ptr<device::Backend>()> device_maker(const DeviceChoice& choice,
                                                               const device::DevicePreset& preset,
                                                               link::WireVersion wire);

}  // namespace tripsitter::cmd

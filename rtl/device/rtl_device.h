// The Verilated RTL of the whole device (ts_device.sv) as a device back-end (device/backend.h): the board, `render`'s
// device alone and the device program run it in place of the C++ model with `--device rtl`. It takes the link's bytes
// through its SPI pins (mode 0, SCLK from the link's clock against the device's 100 MHz) and gives the samples of its
// VGA pins, one per pixel clock; a transfer takes the clock cycles it takes on a board, during which the VGA signal
// goes on unwatched.
//
// The RTL's parameters are fixed when Verilator generates its C++, so only the builds listed by rtl_builds() exist in
// a program: the presets' hardware (formats, square-root iterations, cycle costs, bounces, scene memory) and wire, with
// a few worker counts.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <tripsitter/core/result.h>
#include <tripsitter/device/backend.h>
#include <tripsitter/device/preset.h>
#include <tripsitter/link/wire.h>

namespace tripsitter::rtl {

// The device's clock, which the RTL is designed for (docs/rtl.md).
inline constexpr std::int64_t kClockHz = 100'000'000;

struct RtlOptions {
  std::int64_t spi_hz = 10'000'000;  // SCLK; at most kMaxSpiHz
  // A VCD file of the simulation (GTKWave reads it), empty for none: the top's pins and simulation outputs, and every
  // signal inside worker `vcd_worker` when it is >= 0; every clock of reset, of each transfer (chip select falling to
  // the receiver settling) and of the first frame drawn up to `vcd_lines` lines into it, where the file is closed. The
  // clocks that pass unwatched on the way to a frame's start are left out: time jumps over them.
  std::string vcd;
  int vcd_worker = -1;
  int vcd_lines = 525;
};

// SCLK is sampled by the device's clock through a two-flop synchroniser: each half period lasts at least 4 clocks
// (receiver_rtl_test runs the receiver there, and at 5).
inline constexpr std::int64_t kMaxSpiHz = kClockHz / 8;

// The builds in this program, for people: "board-2023 with 10 or 1 workers on wire v2, ...".
std::string rtl_builds();

// The RTL device for `preset` and `wire`, reset and at the start of vertical blanking. The error says why there is
// none: no build of those parameters (and which there are), an SPI clock out of range, a VCD file that cannot be
// written, a worker that does not exist.
core::Result<std::unique_ptr<device::Backend>, std::string> make_rtl_device(const device::DevicePreset& preset,
                                                                            link::WireVersion wire,
                                                                            const RtlOptions& options = {});

}  // namespace tripsitter::rtl

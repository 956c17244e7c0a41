#include "rtl_device.h"

#include <fstream>
#include <vector>

#include "verilated_device.h"

// Verilator's headers are not warning-free under -Wextra.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include "Vts_artix_device_1.h"
#include "Vts_artix_device_5.h"
#include "Vts_artix_device_9.h"
#include "Vts_device_board.h"
#include "Vts_device_board_1.h"
#include "Vts_device_board_7.h"
#include "Vts_device_board_v1.h"
#include "Vts_device_wide.h"
#include "Vts_device_wide_1.h"
#include "Vts_device_wide_7.h"
#pragma GCC diagnostic pop

namespace tripsitter::rtl {
namespace {

// A back-end around a new instance of one Verilated top.
using Maker = std::unique_ptr<device::Backend> (*)(int half_bit, const RtlOptions& options,
                                                   const std::string& worker_scope);

template <class Top>
std::unique_ptr<device::Backend> make_top(int half_bit, const RtlOptions& options, const std::string& worker_scope) {
  return std::make_unique<RtlDevice<Top>>(half_bit, options, worker_scope);
}

// One Verilated build of ts_device: the preset and worker count its parameters were generated with (rtl/device/
// CMakeLists.txt), the wire its receiver speaks, and its top.
struct Build {
  device::DevicePreset preset;
  link::WireVersion wire;
  Maker make;
};

device::DevicePreset with_workers(device::DevicePreset p, int workers) {
  p.workers = workers;
  return p;
}

const std::vector<Build>& builds() {
  static const std::vector<Build> all = {
      {with_workers(device::board_2023_preset(), 10), link::WireVersion::kV2, make_top<Vts_device_board>},
      {with_workers(device::board_2023_preset(), 7), link::WireVersion::kV2, make_top<Vts_device_board_7>},
      {with_workers(device::board_2023_preset(), 1), link::WireVersion::kV2, make_top<Vts_device_board_1>},
      // The board as the report shipped it.
      {with_workers(device::board_2023_preset(), 10), link::WireVersion::kV1, make_top<Vts_device_board_v1>},
      {with_workers(device::wide_preset(), 10), link::WireVersion::kV3, make_top<Vts_device_wide>},
      {with_workers(device::wide_preset(), 7), link::WireVersion::kV3, make_top<Vts_device_wide_7>},
      {with_workers(device::wide_preset(), 1), link::WireVersion::kV3, make_top<Vts_device_wide_1>},
      {with_workers(device::artix_preset(), 9), link::WireVersion::kV3, make_top<Vts_artix_device_9>},
      {with_workers(device::artix_preset(), 5), link::WireVersion::kV3, make_top<Vts_artix_device_5>},
      {with_workers(device::artix_preset(), 1), link::WireVersion::kV3, make_top<Vts_artix_device_1>},
  };
  return all;
}

// The parameters the RTL is generated from; a preset's name, summary and measurement options are not hardware.
bool same_hardware(const device::DevicePreset& a, const device::DevicePreset& b) {
  const device::CycleCosts& p = a.costs;
  const device::CycleCosts& q = b.costs;
  return a.x == b.x && a.y == b.y && a.z == b.z && a.radius == b.radius && a.sqrt_iterations == b.sqrt_iterations &&
         a.max_bounces == b.max_bounces && a.workers == b.workers && a.lead_cycles == b.lead_cycles &&
         a.max_spheres == b.max_spheres && !a.path && !b.path && a.units == b.units && p.pipelined == q.pipelined &&
         p.pixel_setup == q.pixel_setup && p.sphere_test == q.sphere_test &&
         p.sqrt_cycles_per_iteration == q.sqrt_cycles_per_iteration && p.closest_update == q.closest_update &&
         p.shade == q.shade && p.reflect == q.reflect && p.issue_interval == q.issue_interval;
}

// "10 workers", or on the artix preset "9 sphere units".
std::string workers(const device::DevicePreset& p) {
  const char* part = p.units ? " sphere unit" : " worker";
  return std::to_string(p.workers) + part + (p.workers == 1 ? "" : "s");
}

}  // namespace

std::string rtl_builds() {
  std::string s;
  for (std::size_t i = 0; i < builds().size(); ++i) {
    const Build& b = builds()[i];
    s += (i == 0 ? "" : "; ") + b.preset.name + " with " + workers(b.preset) + " on wire " +
         std::string(link::wire_name(b.wire));
  }
  return s;
}

core::Result<std::unique_ptr<device::Backend>, std::string> make_rtl_device(const device::DevicePreset& preset,
                                                                            link::WireVersion wire,
                                                                            const RtlOptions& options) {
  const Build* build = nullptr;
  for (const Build& b : builds())
    if (same_hardware(b.preset, preset) && b.wire == wire) build = &b;
  if (build == nullptr)
    return std::string("the RTL is built for ") + rtl_builds() + ", not for " + preset.name + " with " +
           workers(preset) + " on wire " + std::string(link::wire_name(wire));
  if (options.spi_hz < 1 || options.spi_hz > kMaxSpiHz)
    return "the RTL's SPI clock must be 1 Hz to " + std::to_string(kMaxSpiHz) +
           " Hz (the device samples SCLK with its 100 MHz clock, at least 4 clocks a half period), not " +
           std::to_string(options.spi_hz);
  if (options.vcd_lines < 1) return std::string("the VCD needs at least one line");
  if (options.vcd_worker >= preset.workers)
    return "no worker " + std::to_string(options.vcd_worker) + " to trace: the device has " +
           std::to_string(preset.workers) + " (0 to " + std::to_string(preset.workers - 1) + ")";
  if (!options.vcd.empty() && !std::ofstream(options.vcd))
    return options.vcd + ": cannot write the VCD file";
  const int half_bit = static_cast<int>((kClockHz + 2 * options.spi_hz - 1) / (2 * options.spi_hz));  // rounded up
  // The traced worker: a worker of ts_device, or a sphere unit of ts_artix_device.
  const std::string worker =
      options.vcd_worker < 0 ? ""
      : preset.units         ? "TOP.ts_artix_device.g_unit[" + std::to_string(options.vcd_worker) + "].unit"
                             : "TOP.ts_device.g_worker[" + std::to_string(options.vcd_worker) + "].worker";
  return build->make(half_bit, options, worker);
}

}  // namespace tripsitter::rtl

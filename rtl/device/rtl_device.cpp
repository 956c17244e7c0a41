#include "rtl_device.h"

#include <fstream>
#include <vector>

#include "verilated_device.h"

// Verilator's headers are not warning-free under -Wextra.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include "Vts_device_board.h"
#include "Vts_device_board_1.h"
#include "Vts_device_board_7.h"
#include "Vts_device_wide.h"
#include "Vts_device_wide_1.h"
#include "Vts_device_wide_7.h"
#pragma GCC diagnostic pop

namespace tripsitter::rtl {
namespace {

// One Verilated build of ts_device: the preset and worker count its parameters were generated with (rtl/device/
// CMakeLists.txt), and the wire its receiver speaks.
struct Build {
  device::DevicePreset preset;
  link::WireVersion wire;
};

device::DevicePreset with_workers(device::DevicePreset p, int workers) {
  p.workers = workers;
  return p;
}

const std::vector<Build>& builds() {
  static const std::vector<Build> all = {
      {with_workers(device::board_2023_preset(), 10), link::WireVersion::kV2},
      {with_workers(device::board_2023_preset(), 7), link::WireVersion::kV2},
      {with_workers(device::board_2023_preset(), 1), link::WireVersion::kV2},
      {with_workers(device::wide_preset(), 10), link::WireVersion::kV3},
      {with_workers(device::wide_preset(), 7), link::WireVersion::kV3},
      {with_workers(device::wide_preset(), 1), link::WireVersion::kV3},
  };
  return all;
}

// The parameters the RTL is generated from; a preset's name, summary and measurement options are not hardware.
bool same_hardware(const device::DevicePreset& a, const device::DevicePreset& b) {
  const device::CycleCosts& p = a.costs;
  const device::CycleCosts& q = b.costs;
  return a.x == b.x && a.y == b.y && a.z == b.z && a.radius == b.radius && a.sqrt_iterations == b.sqrt_iterations &&
         a.max_bounces == b.max_bounces && a.workers == b.workers && a.lead_cycles == b.lead_cycles &&
         a.max_spheres == b.max_spheres && !a.path && !b.path && p.pipelined == q.pipelined &&
         p.pixel_setup == q.pixel_setup && p.sphere_test == q.sphere_test &&
         p.sqrt_cycles_per_iteration == q.sqrt_cycles_per_iteration && p.closest_update == q.closest_update &&
         p.shade == q.shade && p.reflect == q.reflect && p.issue_interval == q.issue_interval;
}

std::string wire_name(link::WireVersion w) {
  return w == link::WireVersion::kV1 ? "v1" : w == link::WireVersion::kV2 ? "v2" : "v3";
}

std::string workers(int n) { return std::to_string(n) + (n == 1 ? " worker" : " workers"); }

}  // namespace

std::string rtl_builds() {
  std::string s;
  for (std::size_t i = 0; i < builds().size(); ++i) {
    const Build& b = builds()[i];
    s += (i == 0 ? "" : "; ") + b.preset.name + " with " + workers(b.preset.workers) + " on wire " + wire_name(b.wire);
  }
  return s;
}

core::Result<std::unique_ptr<device::Backend>, std::string> make_rtl_device(const device::DevicePreset& preset,
                                                                            link::WireVersion wire,
                                                                            const RtlOptions& options) {
  std::size_t which = builds().size();
  for (std::size_t i = 0; i < builds().size(); ++i)
    if (same_hardware(builds()[i].preset, preset) && builds()[i].wire == wire) which = i;
  if (which == builds().size())
    return std::string("the RTL is built for ") + rtl_builds() + ", not for " + preset.name + " with " +
           workers(preset.workers) + " on wire " + wire_name(wire);
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
  const std::string worker =
      options.vcd_worker < 0 ? "" : "TOP.ts_device.g_worker[" + std::to_string(options.vcd_worker) + "].worker";
  // In the order of builds().
  const auto make = [&]<class Top>() -> std::unique_ptr<device::Backend> {
    return std::make_unique<RtlDevice<Top>>(half_bit, options, worker);
  };
  switch (which) {
    case 0: return make.operator()<Vts_device_board>();
    case 1: return make.operator()<Vts_device_board_7>();
    case 2: return make.operator()<Vts_device_board_1>();
    case 3: return make.operator()<Vts_device_wide>();
    case 4: return make.operator()<Vts_device_wide_7>();
    default: return make.operator()<Vts_device_wide_1>();
  }
}

}  // namespace tripsitter::rtl

// Device configurations: number formats, workers, square-root iterations, cycle costs and scene memory.
// docs/device.md explains each preset's numbers and where they come from.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <tripsitter/core/fixed.h>

namespace tripsitter::device {

inline constexpr int kDeviceClockHz = 100'000'000;
inline constexpr int kPixelClockHz = 25'000'000;
inline constexpr int kCyclesPerPixelClock = kDeviceClockHz / kPixelClockHz;  // 4
inline constexpr int kLineWidth = 640;
inline constexpr int kLineCycles = 800 * kCyclesPerPixelClock;               // 3200 device cycles per line

// What one worker spends, in device cycles. A pixel's ray is tested against every sphere in turn.
//   not pipelined: each pixel costs pixel_setup + spheres * (sphere_test + sqrt + closest_update) + shade,
//                  and a worker's pixels run back to back, so pixel k is done after (k + 1) such costs;
//   pipelined:     a new (pixel, sphere) pair enters every `issue_interval` cycles, and a pixel's colour is
//                  ready pixel_setup + sphere_test + sqrt + closest_update + shade cycles after its last
//                  sphere entered, so pixel k is done after (k + 1) * spheres * issue_interval + that latency.
// sqrt = sqrt_iterations * sqrt_cycles_per_iteration.
struct CycleCosts {
  bool pipelined = false;
  int pixel_setup = 2;
  int sphere_test = 12;
  int sqrt_cycles_per_iteration = 2;
  int closest_update = 1;
  int shade = 4;
  int issue_interval = 1;  // pipelined only
};

struct DevicePreset {
  std::string name;
  std::string summary;
  // Scene memory formats. The host rounds and saturates to these; the receiver rejects anything outside.
  core::FixedFormat x{16, 3, true};
  core::FixedFormat y{15, 3, true};
  core::FixedFormat z{15, 3, true};
  core::FixedFormat radius{12, 3, false};
  int sqrt_iterations = 16;
  int workers = 10;
  // The controller hands a line to the workers this many cycles before the line is shown (<= kLineCycles).
  int lead_cycles = 3000;
  CycleCosts costs;
  std::uint32_t max_spheres = 1;  // scene memory capacity

  int frac_bits() const { return x.frac_bits; }  // the same for x, y, z and radius
  // Cycles from the start of a line's work until a worker's k-th pixel (k = 0, 1, ...) has its colour,
  // with `spheres` spheres in scene memory. The schedule does not depend on the data.
  std::int64_t finish_cycle(std::int64_t k, std::int64_t spheres) const;
  // Why the preset cannot work, or nothing when it is consistent.
  std::optional<std::string> validate() const;
};

// "wide", the default: formats wide enough for multi-sphere scenes, pipelined workers.
DevicePreset wide_preset();
// "board-2023": the original board's formats, 10 workers and measured cycle costs.
DevicePreset board_2023_preset();

std::vector<std::string> preset_names();
std::optional<DevicePreset> preset_by_name(std::string_view name);

}  // namespace tripsitter::device

// Device configurations: number formats, workers, square-root iterations, cycle costs and scene memory.
// docs/device.md explains each preset's numbers and where they come from.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <tripsitter/core/fixed.h>
#include <tripsitter/core/screen.h>
#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/link/wire.h>

namespace tripsitter::device {

inline constexpr int kDeviceClockHz = 100'000'000;
inline constexpr int kPixelClockHz = 25'000'000;
inline constexpr int kCyclesPerPixelClock = kDeviceClockHz / kPixelClockHz;  // 4
inline constexpr int kLineWidth = core::kScreenWidth;
inline constexpr int kLineCycles = 800 * kCyclesPerPixelClock;               // 3200 device cycles per line
inline constexpr int kMaxPathDepth = 16;                                     // rays per path in the path preset

// What one worker spends, in device cycles. A pixel's ray is tested against every sphere in turn (a pass);
// a pixel that reflects off k metals makes k + 1 passes and k reflection steps (docs/device.md).
//   not pipelined: a pixel costs pixel_setup + (k + 1) * spheres * (sphere_test + sqrt + closest_update)
//                  + k * reflect + shade, and a worker's pixels run back to back;
//   pipelined:     a new (pixel, sphere) pair enters every `issue_interval` cycles, so a pass issues for
//                  spheres * issue_interval cycles; its closest hit is known pass_latency = pixel_setup +
//                  sphere_test + sqrt + closest_update cycles after its last pair entered, and a colour
//                  shade cycles later. A reflected pass can only start issuing once the previous pass's hit
//                  is known and reflected (pass_latency + reflect cycles of stall); the worker is in order,
//                  so its next pixel starts issuing when this pixel's last pass has issued.
// sqrt = sqrt_iterations * sqrt_cycles_per_iteration.
struct CycleCosts {
  bool pipelined = false;
  int pixel_setup = 2;
  int sphere_test = 12;
  int sqrt_cycles_per_iteration = 2;
  int closest_update = 1;
  int shade = 4;
  int reflect = 10;        // one reflection: hit point, normal, reflected direction, scaling
  int issue_interval = 1;  // pipelined only
  // The path preset (docs/device.md, "Cycle costs of the path preset"): a bounce from the closest hit known to
  // the next ray's direction, by material; and the frame-memory read-modify-write and display of a pixel.
  int scatter_lambertian = 42;
  int scatter_metal = 46;
  int scatter_dielectric = 69;
  int sky = 16;  // an escaping ray's direction normalised, the sky's blend, times the throughput
  int accumulate = 8;
};

// Where the path preset's frame memory lives (docs/device.md, "Frame memory"): it changes only what the design
// takes of the FPGA (resources.h), not what the device shows.
enum class FrameMemoryPlace {
  kExternal,  // external memory beside the FPGA: the development board's DDR3L (frame_dram.h)
  kBlockRam,  // the FPGA's block RAM
};

// The path preset's tracer (path_kernel.h): samples per pixel per frame, rays per path, ordered dithering, and
// where frame memory lives.
struct DevicePath {
  int spp = 1;
  int depth = 4;
  bool dither = true;
  FrameMemoryPlace frame_memory = FrameMemoryPlace::kExternal;
};

// The artix preset's sphere units (docs/device.md, "The artix preset"): DevicePreset::workers pipelined units, each
// taking one (ray, sphere) pair a cycle, shared by all the rays of a line. Unit u takes the columns u, u + N, ...;
// each of its pixels makes passes (the camera's ray, then one per reflection), a pass issuing one pair per cycle
// for every sphere it tests. A camera ray tests the spheres whose screen bounds meet its tile of the line; a
// reflected ray every sphere. A reflected ray waits in its unit's queue until it is known, and the unit takes a
// waiting reflected ray before its next camera ray, so the wait is filled with other pixels' pairs.
struct DeviceUnits {
  int tile_columns = 32;     // camera rays are culled per tile of this many columns (a divisor of 640)
  int min_pass = 3;          // cycles a pass takes at least (the shading block takes one channel a cycle)
  int hit_latency = 40;      // cycles from a pass's last pair issued to its closest hit known
  // The bounce stage: a pass's hit that reflects (or, artix-path, bounces or escapes to the sky) enters it, and
  // the next ray (or the sample's light) comes out reflect_latency cycles later.
  int reflect_latency = 20;  // from a hit entering the bounce stage to the reflected ray waiting in the unit's queue
  int shade_latency = 12;    // from the last hit known (or the light out of the bounce stage) to the colour in the
                             // line buffer; with pixel_port, from the last sample through the port to the entry final
  // Cycles a walk's later level (artix-path) holds the issue port before its first slot: the record of its first
  // node read (the walker keeps that node's index in a register).
  int walk_lead = 1;
  // Cycles from a walk level's hits known to its next level waiting in the unit's queue (artix-path: the walker's
  // count of the bounds entered is a register, written in the cycle of the level's last report).
  int walk_wait = 1;
  // The units share one bounce stage (artix-path: it is most of the DSP48E1), each entering it only in its own
  // cycles: unit u in the line's cycles c with c mod N = u (N units), one hit each, in the order its hits are known.
  // Otherwise (artix) each unit has its own and a hit enters it the cycle it is known.
  bool shared_bounce = false;
  // Paths a unit holds at once (artix-path; 0: no limit): a sample's path is the unit's from its camera ray's pass
  // to its end (its light out of the bounce stage, or the cycle after its cut hit), and the unit takes a camera ray
  // only while it holds fewer, so that its queues and stores of paths have that many places.
  int paths = 0;
  // Each unit's samples end into its pixels' bank through one port, a sample a cycle (artix-path: ts_path_pixels):
  // a light out of the bounce stage in its cycle, a cut path's end queued behind those in the order cut (a cut that
  // meets the stage's light in a cycle waits for the next free one). A column's entry is final shade_latency cycles
  // after its last sample went through the port (the bank's read-modify-write); a converged column's (it traces
  // nothing) is its frame-memory entry, final before the line's window. Otherwise a column's colour is in the line
  // buffer shade_latency after its last end.
  bool pixel_port = false;
  bool operator==(const DeviceUnits&) const = default;
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
  int max_bounces = 0;  // reflections traced per pixel off metals, 0..core::kMaxBounces (0: metals are normal-shaded)
  int workers = 10;
  // The controller hands a line to the workers this many cycles before the line is shown (<= kLineCycles).
  int lead_cycles = 3000;
  CycleCosts costs;
  std::uint32_t max_spheres = 1;  // scene memory capacity
  // Present: the workers path-trace v2 worlds (path_kernel.h) and accumulate them in frame memory; absent: the
  // mirror model. v1 words are normal-shaded either way (the board's wire carries no material).
  std::optional<DevicePath> path;
  // Present: the artix datapath (artix_kernel.h, artix_units.h), with `workers` sphere units; absent: per-pixel
  // workers.
  std::optional<DeviceUnits> units;
  // A measurement option of the model, not of the hardware: the workers trace their late pixels too, so that each
  // line's demand (LineResult::demand_cycles, FrameStats::worst_line_cycles) is exact. Late pixels stay black and
  // their colours never reach the line buffer or frame memory, so colours, late counts and frame memory are
  // bit-identical either way; the model pays for the late pixels' work (and PathCounters count it).
  bool trace_late_pixels = false;

  int frac_bits() const { return x.frac_bits; }  // the same for x, y, z and radius
  // Whether a line's demand (LineResult::demand_cycles) is exact when pixels are late: with trace_late_pixels, and
  // always on the sphere units, whose model traces every pixel for its schedule; otherwise a lower bound.
  bool demand_exact() const { return trace_late_pixels || units.has_value(); }
  // The sphere units path-tracing (artix-path): bounced rays walk the world's hierarchy of bounding spheres when
  // it carries one, so the host sends one (link::SceneFormats::hierarchy).
  bool walks_hierarchy() const { return units.has_value() && path.has_value(); }
  // Whether scene memory's formats hold a ball (a sphere, or a hierarchy's bound): its centre in x, y and z, its
  // radius in `radius`.
  bool holds_ball(std::int64_t cx, std::int64_t cy, std::int64_t cz, std::int64_t r) const {
    return x.contains(cx) && y.contains(cy) && z.contains(cz) && radius.contains(r);
  }
  // Cycles a pixel with `bounces` reflections keeps its worker from starting the next pixel, with
  // `spheres` spheres in scene memory.
  std::int64_t pixel_occupancy(std::int64_t spheres, int bounces) const;
  // Cycles from a worker moving on from a pixel until the pixel's colour is ready (0 when not pipelined).
  std::int64_t drain_cycles() const;
  // Cycles from the start of a line's work until a worker's k-th pixel (k = 0, 1, ...) has its colour,
  // when no pixel reflects: (k + 1) * pixel_occupancy(spheres, 0) + drain_cycles(). With reflections the
  // controller sums each pixel's own occupancy.
  std::int64_t finish_cycle(std::int64_t k, std::int64_t spheres) const;
  // The path preset's pixel: `rays` passes over `spheres` spheres, with `bounces` scatters between them (each
  // stalls the in-order worker until its direction is known).
  std::int64_t path_occupancy(std::int64_t spheres, std::int64_t rays, const std::array<std::int64_t, 3>& bounces) const;
  // Cycles from a path pixel's last pass issuing to its colour in the line buffer (pipelined; 0 otherwise).
  std::int64_t path_drain_cycles() const;
  // Why the preset cannot work, or nothing when it is consistent.
  std::optional<std::string> validate() const;
};

// "wide", the default: formats wide enough for multi-sphere scenes, pipelined workers.
DevicePreset wide_preset();
// "board-2023": the original board's formats, 10 workers and measured cycle costs.
DevicePreset board_2023_preset();
// "path": the wide preset's formats and pipelined workers, path-tracing with frame memory (the report's section 7).
DevicePreset path_preset();

// "artix": the XC7A100T's datapath: sphere units sized to the DSP48E1, shared by a line's rays, mirrors.
DevicePreset artix_preset();
// "artix-path": the artix datapath path-tracing with the path preset's materials (artix_path.h), in the model.
DevicePreset artix_path_preset();

// Whether the device path-traces with this preset on this wire: the path preset's frames on a framed wire (v2, v3);
// v1's words carry no materials, so every preset normal-shades them. The one home of that rule: the device, the
// frame sources, render, the window and explore ask it.
bool traces_paths(const DevicePreset& preset, link::WireVersion wire);

std::vector<std::string> preset_names();
std::optional<DevicePreset> preset_by_name(std::string_view name);

}  // namespace tripsitter::device

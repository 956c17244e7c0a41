// Helpers shared by the device tests.
#pragma once

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include <tripsitter/device/device.h>
#include <tripsitter/device/fast_tracer.h>
#include <tripsitter/link/wire_v2.h>

namespace tripsitter::device::testing {

// A v2 frame of spheres given in pixel units, in the preset's format (lambertian grey).
inline std::vector<std::uint8_t> frame_of(const DevicePreset& preset, std::uint32_t sequence,
                                          const std::vector<std::array<double, 4>>& xyzr) {
  link::World w;
  w.sequence = sequence;
  w.frac_bits = static_cast<std::uint8_t>(preset.frac_bits());
  for (const auto& s : xyzr) {
    link::WireSphere ws;
    ws.x = static_cast<std::int32_t>(preset.x.quantize(s[0]).raw);
    ws.y = static_cast<std::int32_t>(preset.y.quantize(s[1]).raw);
    ws.z = static_cast<std::int32_t>(preset.z.quantize(s[2]).raw);
    ws.radius = static_cast<std::uint32_t>(preset.radius.quantize(s[3]).raw);
    ws.albedo = {128, 128, 128};
    ws.ior = 6144;
    w.spheres.push_back(ws);
  }
  return link::encode_v2_frame(w);
}

// The visible pixels of one frame, read straight from the VGA samples by counting clocks from the start
// of vertical blanking (independent of the monitor model).
inline std::vector<core::Rgb444> visible_pixels(Device& device, FrameStats* stats = nullptr) {
  std::vector<core::Rgb444> pixels;
  int clock = 0;
  const FrameStats s = device.run_frame([&](const VgaSample& sample) {
    const int line = (480 + clock / 800) % 525;
    const int col = clock % 800;
    if (line < 480 && col < 640) pixels.push_back(sample.colour);
    ++clock;
  });
  if (stats) *stats = s;
  return pixels;  // rows 0..479 in order, 640 each
}

// Formats of 32 bits, the widest validate() allows: coordinates beyond FastTracer::kNarrowLimit are
// possible, so some worlds take the plain worker's path inside the fast model (FastTracer::kNarrowLimit).
inline DevicePreset wide_32_preset() {
  DevicePreset p = wide_preset();
  p.name = "wide-32";
  p.x = {32, 4, true};
  p.y = {32, 4, true};
  p.z = {32, 4, true};
  p.radius = {32, 4, false};
  return p;
}

// A random world in raw units of the preset: ordinary spheres in view, and the awkward ones — behind the
// camera, across its plane, around it, off screen, huge, tiny (a raw unit or a few), at the formats'
// limits, near the fast model's 64-bit limit; radii of at least one raw unit, as scene memory holds them;
// metals with random albedos, and sometimes no surfaces at all for the last spheres (as v1 words leave them).
inline SceneMemory random_world(const DevicePreset& p, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double scale = static_cast<double>(std::int64_t{1} << p.frac_bits());
  const auto clamp_to = [](const core::FixedFormat& f, double raw) {
    return std::clamp(static_cast<std::int64_t>(raw), f.min_raw(), f.max_raw());
  };
  // Scene memory never holds a radius of 0 (the receiver rejects it; the shading divides by r).
  const auto radius_of = [&](double raw) { return std::max<std::int64_t>(1, clamp_to(p.radius, raw)); };
  const auto pick = [&](const core::FixedFormat& f) {  // a raw value at or near one of the format's ends
    const std::int64_t edge = unit(rng) < 0.5 ? f.max_raw() : f.min_raw();
    return edge - (edge > 0 ? 1 : -1) * static_cast<std::int64_t>(rng() % 3);
  };
  SceneMemory m;
  m.valid = true;
  const int count = static_cast<int>(rng() % std::min<std::uint64_t>(p.max_spheres + 1, 41));
  for (int i = 0; i < count; ++i) {
    double x = 0, y = 0, z = 0, r = 0;  // pixel units
    const double kind = unit(rng);
    if (kind < 0.45) {  // in view
      z = 60 + 1500 * unit(rng);
      x = (unit(rng) * 2.4 - 1.2) * z;
      y = (unit(rng) * 1.8 - 0.9) * z;
      r = 2 + 150 * unit(rng) * unit(rng);
    } else if (kind < 0.55) {  // behind the camera, or across its plane
      z = -1500 * unit(rng);
      x = (unit(rng) * 2 - 1) * 800;
      y = (unit(rng) * 2 - 1) * 600;
      r = unit(rng) < 0.5 ? -z + (unit(rng) * 4 - 2) : 400 * unit(rng);
    } else if (kind < 0.62) {  // around the camera (it sees the inside)
      x = (unit(rng) * 2 - 1) * 50;
      y = (unit(rng) * 2 - 1) * 50;
      z = (unit(rng) * 2 - 1) * 50;
      r = 80 + 2000 * unit(rng);
    } else if (kind < 0.70) {  // off screen, beside the view frustum
      z = 100 + 800 * unit(rng);
      x = (unit(rng) < 0.5 ? -1 : 1) * (1.1 + unit(rng)) * z;
      y = (unit(rng) * 2 - 1) * z;
      r = 5 + 100 * unit(rng);
    } else if (kind < 0.78) {  // huge and far
      z = 3000 + 20000 * unit(rng);
      x = (unit(rng) * 2 - 1) * z;
      y = (unit(rng) * 2 - 1) * z;
      r = 1000 + 20000 * unit(rng);
    } else if (kind < 0.86) {  // tiny: 1..4 raw units
      z = 20 + 400 * unit(rng);
      x = (unit(rng) * 2 - 1) * z;
      y = (unit(rng) * 2 - 1) * z * 0.75;
      r = static_cast<double>(1 + rng() % 4) / scale;
    } else {  // at the formats' limits (and, in 32-bit formats, at the fast model's limit)
      std::int64_t raw[4] = {pick(p.x), pick(p.y), pick(p.z), unit(rng) < 0.5 ? p.radius.max_raw() : p.radius.max_raw() / 3};
      if (p.x.total_bits > 29 && unit(rng) < 0.5) {
        const std::int64_t lim = FastTracer::kNarrowLimit - 1;
        raw[0] = unit(rng) < 0.5 ? lim : -lim;
        raw[2] = unit(rng) < 0.5 ? lim : static_cast<std::int64_t>(unit(rng) * 4000 * scale);
        raw[3] = unit(rng) < 0.5 ? lim : static_cast<std::int64_t>(unit(rng) * 4000 * scale);
      }
      for (int k = 0; k < 3; ++k)
        if (unit(rng) < 0.5) raw[k] = static_cast<std::int64_t>((unit(rng) * 2 - 1) * 500 * scale);
      m.geometry.push_back({{clamp_to(p.x, static_cast<double>(raw[0])), clamp_to(p.y, static_cast<double>(raw[1])),
                             clamp_to(p.z, static_cast<double>(raw[2]))},
                            radius_of(static_cast<double>(raw[3]))});
      continue;
    }
    m.geometry.push_back({{clamp_to(p.x, x * scale), clamp_to(p.y, y * scale), clamp_to(p.z, z * scale)},
                          radius_of(r * scale)});
  }
  // Surfaces: a third metal, with albedos anywhere in 0..255; sometimes missing for the last spheres.
  const std::size_t with_surface = unit(rng) < 0.15 ? m.geometry.size() / 2 : m.geometry.size();
  for (std::size_t i = 0; i < with_surface; ++i) {
    SurfaceWord s;
    s.material = unit(rng) < 0.35 ? link::kMaterialMetal : link::kMaterialLambertian;
    s.albedo = {static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng())};
    m.surfaces.push_back(s);
  }
  return m;
}

}  // namespace tripsitter::device::testing

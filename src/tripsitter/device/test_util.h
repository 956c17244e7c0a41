// Helpers shared by the device tests.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/device.h>
#include <tripsitter/device/fast_tracer.h>
#include <tripsitter/device/receiver.h>
#include <tripsitter/host/hierarchy.h>
#include <tripsitter/link/frame.h>

namespace tripsitter::device::testing {

// A frame of spheres given in pixel units, in the preset's format (lambertian grey), on a framed wire.
inline std::vector<std::uint8_t> frame_on(link::WireVersion wire, const DevicePreset& preset, std::uint32_t session,
                                          std::uint32_t sequence, const std::vector<std::array<double, 4>>& xyzr) {
  link::World w;
  w.session = session;
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
  return link::encode_frame(wire, w);
}

// The same as a v2 frame.
inline std::vector<std::uint8_t> frame_of(const DevicePreset& preset, std::uint32_t sequence,
                                          const std::vector<std::array<double, 4>>& xyzr) {
  return frame_on(link::WireVersion::kV2, preset, 0, sequence, xyzr);
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

// The material codes of link/frame.h, as the tests write them.
inline constexpr std::uint8_t kLambertian = link::kMaterialLambertian, kMetal = link::kMaterialMetal,
                              kDielectric = link::kMaterialDielectric;

// The preset with another bounce cut-off (DevicePreset::max_bounces).
inline DevicePreset with_bounces(DevicePreset p, int bounces) {
  p.max_bounces = bounces;
  return p;
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

// The path preset's tests.

// A sphere with its surface, in pixel units, for the path preset's worlds.
struct PathBall {
  std::array<double, 4> xyzr{};
  std::uint8_t material = link::kMaterialLambertian;
  std::array<std::uint8_t, 3> albedo{128, 128, 128};
  std::uint16_t fuzz = 0;    // times 2^-16 on the device (the wire's fuzz * 65535)
  std::uint16_t ior = 6144;  // u4.12: 1.5
};

// A v2 frame of `balls` in the preset's formats.
inline std::vector<std::uint8_t> path_frame_of(const DevicePreset& preset, std::uint32_t sequence,
                                               const std::vector<PathBall>& balls) {
  link::World w;
  w.sequence = sequence;
  w.frac_bits = static_cast<std::uint8_t>(preset.frac_bits());
  for (const PathBall& b : balls) {
    link::WireSphere ws;
    ws.x = static_cast<std::int32_t>(preset.x.quantize(b.xyzr[0]).raw);
    ws.y = static_cast<std::int32_t>(preset.y.quantize(b.xyzr[1]).raw);
    ws.z = static_cast<std::int32_t>(preset.z.quantize(b.xyzr[2]).raw);
    ws.radius = static_cast<std::uint32_t>(std::max<std::int64_t>(1, preset.radius.quantize(b.xyzr[3]).raw));
    ws.material = b.material;
    ws.albedo = b.albedo;
    ws.fuzz = b.fuzz;
    ws.ior = b.ior;
    w.spheres.push_back(ws);
  }
  return link::encode_frame(link::WireVersion::kV2, w);
}

// The scene's spheres as wire records.
inline std::vector<link::WireSphere> wire_spheres(const SceneMemory& scene) {
  std::vector<link::WireSphere> out;
  for (std::size_t i = 0; i < scene.geometry.size(); ++i) {
    const auto& g = scene.geometry[i];
    const SurfaceWord& s = scene.surfaces.at(i);
    out.push_back({static_cast<std::int32_t>(g.center.x), static_cast<std::int32_t>(g.center.y),
                   static_cast<std::int32_t>(g.center.z), static_cast<std::uint32_t>(g.radius), s.material, s.albedo,
                   s.fuzz, s.ior});
  }
  return out;
}

// The frame (v2 unless `wire` says otherwise; v3 in host session `session`) that puts exactly `scene` (raw geometry
// and surface words, one surface per sphere, and its hierarchy: v3 only) into scene memory.
inline std::vector<std::uint8_t> frame_of_scene(const DevicePreset& preset, std::uint32_t sequence,
                                                const SceneMemory& scene,
                                                link::WireVersion wire = link::WireVersion::kV2,
                                                std::uint32_t session = 0) {
  link::World w;
  w.session = session;
  w.sequence = sequence;
  w.frac_bits = static_cast<std::uint8_t>(preset.frac_bits());
  w.spheres = wire_spheres(scene);
  for (const HierarchyNode& v : scene.hierarchy) w.nodes.push_back(wire_node(v));
  return link::encode_frame(wire, w);
}

// The scene as the host of a preset that walks a hierarchy sends it (host/hierarchy.h): its spheres in the
// hierarchy's order and the hierarchy's nodes (none for a world of 8 spheres or fewer).
inline SceneMemory with_hierarchy(const DevicePreset& preset, const SceneMemory& scene) {
  link::SceneFormats formats{preset.x, preset.y, preset.z, preset.radius, preset.max_spheres};
  formats.hierarchy = true;
  const host::Hierarchy h = host::build_hierarchy(wire_spheres(scene), formats);
  if (h.nodes.empty()) return scene;
  SceneMemory out = scene;
  for (std::size_t i = 0; i < h.order.size(); ++i) {
    out.geometry[i] = scene.geometry[h.order[i]];
    out.surfaces[i] = scene.surfaces[h.order[i]];
  }
  for (const link::WireNode& v : h.nodes) out.hierarchy.push_back(hierarchy_node(v));
  return out;
}

// A random surface of any material: albedos anywhere in 0..255 (often 255, the exact 1), metals with and
// without fuzz (up to the wire's largest), dielectrics with indices anywhere in the path preset's 0.25..8 (often
// near 1.5, sometimes exactly 1: straight through, and at both ends of the range).
inline SurfaceWord random_path_surface(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SurfaceWord s;
  const double kind = unit(rng);
  s.material = kind < 0.4 ? link::kMaterialLambertian : kind < 0.7 ? link::kMaterialMetal : link::kMaterialDielectric;
  for (auto& a : s.albedo) a = unit(rng) < 0.25 ? 255 : static_cast<std::uint8_t>(rng());
  s.fuzz = unit(rng) < 0.3 ? 0 : unit(rng) < 0.2 ? 65535 : static_cast<std::uint16_t>(rng());
  const double ior = unit(rng);
  s.ior = ior < 0.1   ? 4096
          : ior < 0.15 ? kPathIorMin
          : ior < 0.2  ? kPathIorMax
          : ior < 0.6  ? static_cast<std::uint16_t>(5000 + rng() % 3000)
                       : static_cast<std::uint16_t>(kPathIorMin + rng() % (kPathIorMax - kPathIorMin + 1));
  return s;
}

// A random world for the path preset: random_world's geometry (in view, behind the camera, around it, tiny,
// huge, at the formats' limits), at most `max_random` of it, then 2 to 5 spheres well in view (so that paths
// bounce), now and then a sphere around the camera and a pair of overlapping spheres in view; a random surface
// for every sphere (random_path_surface).
inline SceneMemory random_path_world(const DevicePreset& p, std::mt19937_64& rng, std::size_t max_random) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SceneMemory m = random_world(p, rng);
  if (m.geometry.size() > max_random) m.geometry.resize(max_random);
  const double scale = static_cast<double>(std::int64_t{1} << p.frac_bits());
  const auto raw = [&](double v) { return static_cast<std::int64_t>(std::llround(v * scale)); };
  for (int i = 2 + static_cast<int>(rng() % 4); i > 0; --i) {
    const double z = 150 + 1000 * unit(rng);
    m.geometry.push_back({{raw((unit(rng) * 1.6 - 0.8) * z), raw((unit(rng) * 1.2 - 0.6) * z), raw(z)},
                          raw(20 + z / 2 * unit(rng))});
  }
  if (unit(rng) < 0.3)  // around the camera
    m.geometry.push_back({{0, 0, raw(40 * unit(rng))}, raw(300 + 3000 * unit(rng))});
  if (unit(rng) < 0.4) {  // two overlapping spheres in view
    const double z = 300 + 600 * unit(rng), x = (unit(rng) - 0.5) * z, y = (unit(rng) - 0.5) * z * 0.6;
    const double r = 40 + 100 * unit(rng);
    m.geometry.push_back({{raw(x), raw(y), raw(z)}, raw(r)});
    m.geometry.push_back({{raw(x + r * unit(rng)), raw(y + r * (unit(rng) - 0.5)), raw(z - r * unit(rng))},
                          raw(r * (0.5 + unit(rng)))});
  }
  m.surfaces.clear();
  for (std::size_t i = 0; i < m.geometry.size(); ++i) m.surfaces.push_back(random_path_surface(rng));
  return m;
}

// A point on sphere s's surface (a bounce's origin) in a random direction, in the artix formats.
inline artix::Vec3i point_on(const artix::UnitSphere& s, std::mt19937_64& rng) {
  std::uniform_int_distribution<std::int64_t> component(-30000, 30000);
  const artix::Vec3i n = artix::unit_direction({component(rng), component(rng), component(rng)});
  artix::Vec3i o{};
  for (std::size_t c = 0; c < 3; ++c)
    o[c] = std::clamp(s.c[c] + ((n[c] * s.r) >> artix::kDirectionFrac), -(std::int64_t{1} << 22), std::int64_t{1} << 22);
  return o;
}

}  // namespace tripsitter::device::testing

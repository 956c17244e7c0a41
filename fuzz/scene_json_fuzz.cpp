// The scene loader (scene/scene_json.h), and the host and device behind it.
//
// Input: the text of a scene file.
//
// Checks:
//   - a failure has a place inside the text (1-based line and column; the line exists) and a message;
//   - a scene that loads keeps every limit and range of docs/scene_format.md and scene.h: image size, spp,
//     depth, sphere count, finite numbers, radius > 0, albedo and fuzz in [0, 1], ior > 0, a usable camera;
//   - such a scene goes through the host to the device without harm: on v3 (wide preset) and v2 (board-2023),
//     the host's world, numbered as the link numbers it, is one frame that the receiver accepts whole (the host saturates to the preset's formats, so
//     nothing it sends may be rejected), holding the scene's spheres up to the scene memory; on v1, every
//     word the host sends is accepted or rejected, none lost; and a worker draws a few pixels of what the
//     device holds (trace_pixels.h). JSON numbers are the easy way to put spheres at the formats' extremes.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <tripsitter/device/preset.h>
#include <tripsitter/device/receiver.h>
#include <tripsitter/host/host.h>
#include <tripsitter/link/sequence.h>
#include <tripsitter/scene/scene.h>
#include <tripsitter/scene/scene_json.h>

#include "check.h"
#include "trace_pixels.h"

namespace {

namespace device = tripsitter::device;
namespace host = tripsitter::host;
namespace link = tripsitter::link;
namespace scene = tripsitter::scene;

bool finite(const scene::Vec3d& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool unit(double v) { return v >= 0 && v <= 1; }
bool unit(const scene::Vec3d& v) { return unit(v.x) && unit(v.y) && unit(v.z); }

void check_scene(const scene::Scene& s) {
  const scene::RenderSettings& r = s.render;
  FUZZ_CHECK(r.width >= 1 && r.width <= scene::kMaxImageSide, "width out of 1..16384");
  FUZZ_CHECK(r.height >= 1 && r.height <= scene::kMaxImageSide, "height out of 1..16384");
  FUZZ_CHECK(r.spp >= 1 && r.spp <= scene::kMaxSpp, "spp out of 1..65536");
  FUZZ_CHECK(r.max_depth >= 1 && r.max_depth <= scene::kMaxDepth, "max_depth out of 1..1024");
  FUZZ_CHECK(s.spheres.size() <= scene::kMaxSpheres, "more spheres than the limit");
  FUZZ_CHECK(std::isfinite(s.units_per_world) && s.units_per_world >= 0, "units_per_world not finite or negative");

  const scene::CameraSettings& c = s.camera;
  FUZZ_CHECK(finite(c.lookfrom) && finite(c.lookat) && finite(c.vup), "a camera vector is not finite");
  FUZZ_CHECK(c.vfov > 0 && c.vfov < 180, "vfov out of (0, 180)");
  FUZZ_CHECK(c.defocus_angle >= 0 && c.defocus_angle < 180, "defocus_angle out of [0, 180)");
  FUZZ_CHECK(std::isfinite(c.focus_dist) && c.focus_dist > 0, "focus_dist not finite or not above 0");
  const scene::Vec3d d = c.lookat - c.lookfrom;
  FUZZ_CHECK(finite(d), "lookat - lookfrom is not finite");
  FUZZ_CHECK(d.x != 0 || d.y != 0 || d.z != 0, "lookfrom equals lookat");
  FUZZ_CHECK(c.vup.x != 0 || c.vup.y != 0 || c.vup.z != 0, "vup is zero");

  for (const scene::Sphere& sp : s.spheres) {
    FUZZ_CHECK(finite(sp.center), "a sphere centre is not finite");
    FUZZ_CHECK(std::isfinite(sp.radius) && sp.radius > 0, "a radius not finite or not above 0");
    const scene::Material& m = sp.material;
    FUZZ_CHECK(m.type == scene::MaterialType::kLambertian || m.type == scene::MaterialType::kMetal ||
                   m.type == scene::MaterialType::kDielectric,
               "an unknown material type");
    FUZZ_CHECK(unit(m.albedo), "an albedo component out of [0, 1]");
    FUZZ_CHECK(unit(m.fuzz), "fuzz out of [0, 1]");
    FUZZ_CHECK(std::isfinite(m.ior) && m.ior > 0, "ior not finite or not above 0");
  }
}

link::SceneFormats formats_of(const device::DevicePreset& p) { return {p.x, p.y, p.z, p.radius, p.max_spheres}; }

// The scene through the host, its bytes into a receiver of the same preset.
void check_host_to_device(const scene::Scene& s, const device::DevicePreset& preset, link::WireVersion wire) {
  host::Host h(s, formats_of(preset), wire);
  const host::ReadyWorld& world = h.update();
  std::vector<std::uint8_t> bytes = world.bytes;
  link::Numbering numbering(wire, 1);
  numbering.stamp(bytes);
  device::Receiver receiver(preset, wire);
  receiver.receive(bytes);
  receiver.end_of_stream();
  const device::ReceiverStats& stats = receiver.stats();
  FUZZ_CHECK(stats.garbage_runs == 0, "the host's bytes contain garbage for the device");
  if (wire != link::WireVersion::kV1) {
    FUZZ_CHECK(stats.worlds_accepted == 1 && stats.frames_rejected == 0 && stats.bytes_dropped == 0,
               "the device rejected the host's world (the host must saturate to the device's formats)");
    const std::size_t expected = std::min<std::size_t>(s.spheres.size(), preset.max_spheres);
    FUZZ_CHECK(world.spheres_dropped == s.spheres.size() - expected, "spheres_dropped miscounted");
    device::SceneMemory front;
    FUZZ_CHECK(receiver.swap_if_pending(front), "no world to swap in after an accepted one");
    FUZZ_CHECK(front.geometry.size() == expected, "the device holds other than the scene's spheres");
    tripsitter::fuzz::trace_some_pixels(front, preset);
  } else {
    FUZZ_CHECK(world.bytes.size() == s.spheres.size() * link::kV1WordBytes, "not one v1 word per sphere");
    FUZZ_CHECK(stats.worlds_accepted + stats.frames_rejected == s.spheres.size(),
               "v1 words neither accepted nor rejected");
    FUZZ_CHECK(stats.bytes_dropped == stats.frames_rejected * link::kV1WordBytes, "v1 bytes dropped miscounted");
    device::SceneMemory front;
    if (receiver.swap_if_pending(front)) tripsitter::fuzz::trace_some_pixels(front, preset);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const scene::SceneResult result = scene::parse_scene_json(text, "<fuzz>");
  if (!result.ok()) {
    const scene::SceneError& e = result.error();
    FUZZ_CHECK(e.source == "<fuzz>", "the error names another source");
    FUZZ_CHECK(!e.message.empty(), "an error without a message");
    const auto lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
    FUZZ_CHECK(e.line >= 1 && static_cast<std::size_t>(e.line) <= lines, "an error on a line the text does not have");
    FUZZ_CHECK(e.column >= 1, "an error without a column");
    FUZZ_CHECK(e.to_string().starts_with("<fuzz>:" + std::to_string(e.line) + ":" + std::to_string(e.column) + ": "),
               "to_string() is not source:line:column: message");
    return 0;
  }
  const scene::Scene& s = result.value();
  check_scene(s);
  // Keep each input cheap: the host's cost grows with the sphere count, the parser's checks do not.
  if (s.spheres.size() > 10'000) return 0;
  check_host_to_device(s, device::wide_preset(), link::WireVersion::kV3);
  check_host_to_device(s, device::board_2023_preset(), link::WireVersion::kV2);
  check_host_to_device(s, device::board_2023_preset(), link::WireVersion::kV1);
  return 0;
}

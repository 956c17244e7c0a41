#include <tripsitter/host/host.h>

#include <algorithm>
#include <cmath>

#include <tripsitter/core/albedo.h>
#include <tripsitter/host/hierarchy.h>

namespace tripsitter::host {
namespace {

// The albedo byte the device mixes reflections with (core/albedo.h).
constexpr auto& unit_to_byte = core::albedo_byte;

std::uint16_t to_u16(double v, double scale) {
  return static_cast<std::uint16_t>(std::lround(std::clamp(v * scale, 0.0, 65535.0)));
}

std::int32_t quantize(const core::FixedFormat& f, double v, std::uint64_t& saturations) {
  const core::Quantized q = f.quantize(v);
  if (q.saturated) ++saturations;
  return static_cast<std::int32_t>(q.raw);
}

}  // namespace

link::V1Sphere to_v1(const scene::Sphere& s, Saturations& sat) {
  link::V1Sphere w;
  w.x_raw = quantize(link::kV1X, s.center.x, sat.coordinates);
  w.y_raw = quantize(link::kV1Y, s.center.y, sat.coordinates);
  w.z_raw = quantize(link::kV1Z, s.center.z, sat.coordinates);
  // The radius is a power of two: the nearest one in log scale.
  const double log2r = std::round(std::log2(s.radius));
  if (!(log2r >= 0.0 && log2r <= link::kV1RadiusLog2Max)) ++sat.radii;
  w.radius_log2 = static_cast<std::uint8_t>(std::clamp(std::isnan(log2r) ? 0.0 : log2r, 0.0, double{link::kV1RadiusLog2Max}));
  const auto channel = [](double v) { return static_cast<int>(std::lround(std::clamp(v, 0.0, 1.0) * 15.0)); };
  w.colour = static_cast<std::uint16_t>((channel(s.material.albedo.x) << 8) | (channel(s.material.albedo.y) << 4) |
                                        channel(s.material.albedo.z));
  return w;
}

link::WireSphere to_wire(const scene::Sphere& s, const link::SceneFormats& formats, Saturations& sat) {
  link::WireSphere w;
  w.x = quantize(formats.x, s.center.x, sat.coordinates);
  w.y = quantize(formats.y, s.center.y, sat.coordinates);
  w.z = quantize(formats.z, s.center.z, sat.coordinates);
  const core::Quantized r = formats.radius.quantize(s.radius);
  // A radius that rounds to zero would be no sphere at all: the smallest step stands in for it.
  w.radius = static_cast<std::uint32_t>(std::max<std::int64_t>(r.raw, 1));
  if (r.saturated || r.raw < 1) ++sat.radii;
  w.material = static_cast<std::uint8_t>(s.material.type);
  w.albedo = {unit_to_byte(s.material.albedo.x), unit_to_byte(s.material.albedo.y), unit_to_byte(s.material.albedo.z)};
  w.fuzz = to_u16(s.material.fuzz, link::kFuzzScale);
  w.ior = std::max<std::uint16_t>(to_u16(s.material.ior, link::kIorScale), 1);
  if (w.material == link::kMaterialDielectric && (w.ior < formats.ior_min || w.ior > formats.ior_max)) {
    w.ior = std::clamp(w.ior, formats.ior_min, formats.ior_max);
    ++sat.iors;
  }
  return w;
}

Host::Host(scene::Scene scene, link::SceneFormats formats, link::WireVersion wire)
    : initial_(std::move(scene)),
      world_(initial_.spheres),
      camera_(initial_.camera.lookfrom, initial_.camera.lookat, initial_.camera.vup),
      units_per_world_(host::units_per_world(initial_)),
      formats_(formats),
      wire_(wire) {}

void Host::reset() {
  world_ = initial_.spheres;
  camera_ = Camera(initial_.camera.lookfrom, initial_.camera.lookat, initial_.camera.vup);
}

std::vector<scene::Sphere> Host::view() const {
  const std::size_t count = spheres_carried(world_.size(), formats_, wire_);
  return view_spheres(std::span(world_).first(count), camera_, units_per_world_);
}

const ReadyWorld& Host::update() {
  ReadyWorld next;
  const std::vector<scene::Sphere> view = this->view();
  next.spheres = view.size();
  next.spheres_dropped = world_.size() - view.size();
  if (wire_ == link::WireVersion::kV1) {
    // The board's stream: one word per sphere; the device keeps the latest.
    for (const auto& v : view) link::append_v1_bytes(link::encode_v1_word(to_v1(v, next.saturations)), next.bytes);
  } else {
    // Session and sequence number are the link's to give, as the world goes out (link/sequence.h).
    link::World world;
    world.frac_bits = static_cast<std::uint8_t>(formats_.x.frac_bits);
    world.spheres.reserve(view.size());
    for (const auto& v : view) world.spheres.push_back(to_wire(v, formats_, next.saturations));
    if (formats_.hierarchy && wire_ == link::WireVersion::kV3)
      attach_hierarchy(world, build_hierarchy(world.spheres, formats_));
    next.bytes = link::encode_frame(wire_, world);
  }
  total_saturations_ += next.saturations;
  ready_ = std::move(next);
  return ready_;
}

}  // namespace tripsitter::host

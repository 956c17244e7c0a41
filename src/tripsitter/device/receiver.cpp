#include <tripsitter/device/receiver.h>

#include <array>
#include <string>
#include <utility>

#include <tripsitter/core/crc32.h>
#include <tripsitter/device/path_kernel.h>

namespace tripsitter::device {
namespace {

// The CRC-32 of every sphere's geometry and surface, then of every node of the hierarchy, little-endian field by
// field, as the bytes are written.
std::uint32_t content_of(const SceneMemory& scene) {
  std::uint32_t crc = 0;
  for (std::size_t i = 0; i < scene.geometry.size(); ++i) {
    const auto& g = scene.geometry[i];
    const SurfaceWord& w = scene.surfaces[i];
    std::array<std::uint8_t, 4 * 4 + 1 + 3 + 2 + 2> bytes{};
    std::size_t at = 0;
    for (const std::int64_t v : {g.center.x, g.center.y, g.center.z, g.radius})
      for (int b = 0; b < 4; ++b) bytes[at++] = static_cast<std::uint8_t>(static_cast<std::uint64_t>(v) >> (8 * b));
    bytes[at++] = w.material;
    for (const std::uint8_t a : w.albedo) bytes[at++] = a;
    for (const std::uint16_t v : {w.fuzz, w.ior})
      for (int b = 0; b < 2; ++b) bytes[at++] = static_cast<std::uint8_t>(v >> (8 * b));
    crc = core::crc32(bytes, crc);
  }
  for (const HierarchyNode& v : scene.hierarchy) {
    std::array<std::uint8_t, 8 * 4> bytes{};
    std::size_t at = 0;
    for (const std::int64_t f : {v.bound.center.x, v.bound.center.y, v.bound.center.z, v.bound.radius,
                                 std::int64_t{v.first_child}, std::int64_t{v.children}, std::int64_t{v.first_sphere},
                                 std::int64_t{v.spheres}})
      for (int b = 0; b < 4; ++b) bytes[at++] = static_cast<std::uint8_t>(static_cast<std::uint64_t>(f) >> (8 * b));
    crc = core::crc32(bytes, crc);
  }
  return crc;
}

}  // namespace

HierarchyNode hierarchy_node(const link::WireNode& v) {
  return {{{v.x, v.y, v.z}, v.radius}, v.first_child, v.children, static_cast<int>(v.first_sphere), v.sphere_count};
}

link::WireNode wire_node(const HierarchyNode& v) {
  return {static_cast<std::int32_t>(v.bound.center.x), static_cast<std::int32_t>(v.bound.center.y),
          static_cast<std::int32_t>(v.bound.center.z), static_cast<std::uint32_t>(v.bound.radius),
          static_cast<std::uint16_t>(v.first_child), static_cast<std::uint8_t>(v.children),
          static_cast<std::uint8_t>(v.spheres), static_cast<std::uint32_t>(v.first_sphere)};
}

Receiver::Receiver(const DevicePreset& preset, link::WireVersion wire)
    : preset_(preset),
      wire_(wire),
      v1_([this](const link::V1Sphere& word) { accept_v1(word); }),
      // A v1 receiver has no frames; its frame decoder and rules are never fed.
      frames_(wire == link::WireVersion::kV1 ? link::WireVersion::kV3 : wire, preset.max_spheres,
              {.on_frame = [this](link::World&& world) { accept_frame(std::move(world)); },
               .on_error =
                   [this](const link::FrameFailure& failure, std::size_t bytes) {
                     if (!failure.intact || admit(failure.intact->session, failure.intact->sequence, bytes)) {
                       report(link::to_string(failure.error), failure.detail, bytes, failure.offset);
                     }
                   }},
              preset.walks_hierarchy()),
      sequence_(wire == link::WireVersion::kV1 ? link::WireVersion::kV3 : wire) {}

void Receiver::receive(std::span<const std::uint8_t> bytes) {
  if (wire_ == link::WireVersion::kV1) {
    v1_.push(bytes);
  } else {
    frames_.push(bytes);
  }
}

void Receiver::end_of_stream() {
  if (wire_ == link::WireVersion::kV1) {
    if (v1_.pending_bytes() > 0) report("truncated", "the stream ended inside a v1 word", v1_.pending_bytes(), {});
    v1_.reset();
  } else {
    frames_.end_of_stream();
  }
}

ReceiverEvent Receiver::event(ReceiverEvent::Kind kind, std::size_t bytes, std::string error, std::string detail) {
  ReceiverEvent e;
  e.kind = kind;
  e.bytes = bytes;
  e.error = std::move(error);
  e.detail = std::move(detail);
  return e;
}

void Receiver::emit(const ReceiverEvent& event) const {
  if (listener_) listener_(event);
}

void Receiver::reject(const std::string& why, std::size_t bytes) {
  ++stats_.frames_rejected;
  stats_.bytes_dropped += bytes;
  stats_.last_error = why;
  if (listener_) emit(event(ReceiverEvent::Kind::kRejected, bytes, "rejected", why));
}

void Receiver::report(const std::string& error, const std::string& detail, std::size_t bytes,
                      std::optional<std::size_t> found_at) {
  stats_.bytes_dropped += bytes;
  const bool garbage = error == link::to_string(link::FrameError::kBadMagic);
  if (garbage) {
    ++stats_.garbage_runs;
  } else {
    ++stats_.frames_rejected;
    stats_.last_error = error + ": " + detail;
  }
  if (!listener_) return;
  ReceiverEvent e = event(garbage ? ReceiverEvent::Kind::kGarbage : ReceiverEvent::Kind::kRejected, bytes, error, detail);
  e.found_at = found_at;
  emit(e);
}

void Receiver::accept_v1(const link::V1Sphere& word) {
  // A v1 word is in 3 fractional bits with a power-of-two radius; scene memory uses the preset's format.
  const int f = preset_.frac_bits();
  const std::int64_t x = core::rescale_raw(word.x_raw, 3, f);
  const std::int64_t y = core::rescale_raw(word.y_raw, 3, f);
  const std::int64_t z = core::rescale_raw(word.z_raw, 3, f);
  const int radius_shift = word.radius_log2 + f;
  if (radius_shift > 62 || !preset_.radius.contains(std::int64_t{1} << radius_shift) || !preset_.x.contains(x) ||
      !preset_.y.contains(y) || !preset_.z.contains(z)) {
    reject("v1 word out of the device's range (radius 2^" + std::to_string(word.radius_log2) + ")", link::kV1WordBytes);
    return;
  }
  back_.geometry.assign(1, {{x, y, z}, std::int64_t{1} << radius_shift});
  const std::uint8_t r = static_cast<std::uint8_t>(((word.colour >> 8) & 0xF) * 17);
  const std::uint8_t g = static_cast<std::uint8_t>(((word.colour >> 4) & 0xF) * 17);
  const std::uint8_t b = static_cast<std::uint8_t>((word.colour & 0xF) * 17);
  // A v1 word carries no ior: scene memory holds a scene material's default, 1.5, in the v2 wire's u4.12.
  constexpr auto kIor = static_cast<std::uint16_t>(1.5 * link::kIorScale);
  back_.surfaces.assign(1, SurfaceWord{link::kMaterialLambertian, {r, g, b}, 0, kIor});
  back_.hierarchy.clear();
  back_.content = content_of(back_);
  back_.sequence = ++v1_words_;
  back_.valid = true;
  if (pending_) ++stats_.worlds_replaced;
  pending_ = true;
  ++stats_.worlds_accepted;
  if (!listener_) return;
  ReceiverEvent e = event(ReceiverEvent::Kind::kAccepted, link::kV1WordBytes, "", "");
  e.word = &word;
  emit(e);
}

std::optional<link::SequenceCheck> Receiver::admit(std::uint32_t session, std::uint32_t sequence,
                                                   std::size_t bytes) {
  const link::SequenceCheck c = sequence_.check(session, sequence);
  if (c.verdict == link::SequenceVerdict::kReplay) {
    ++stats_.worlds_replayed;
    stats_.bytes_dropped += bytes;
    if (listener_) {
      emit(event(ReceiverEvent::Kind::kReplayed, bytes, "replay",
                 "world " + std::to_string(sequence) + " of session " + std::to_string(session) +
                     (c.ended_session ? " belongs to a session that has ended"
                                      : " is not newer than the last one of its session")));
    }
    return std::nullopt;
  }
  stats_.worlds_missing += c.missing;
  if (c.new_session) ++stats_.sessions;
  return c;
}

void Receiver::accept_frame(link::World&& world) {
  const std::size_t bytes = link::frame_bytes(wire_, world.spheres.size(), world.nodes.size());
  const std::optional<link::SequenceCheck> check = admit(world.session, world.sequence, bytes);
  if (!check) return;
  if (world.frac_bits != preset_.frac_bits()) {
    reject("format mismatch: frame has " + std::to_string(world.frac_bits) + " fractional bits, the device " +
               std::to_string(preset_.frac_bits()),
           bytes);
    return;
  }
  for (std::size_t i = 0; i < world.spheres.size(); ++i) {
    const auto& s = world.spheres[i];
    if (!preset_.holds_ball(s.x, s.y, s.z, s.radius)) {
      reject("sphere " + std::to_string(i) + " lies outside the device's number formats", bytes);
      return;
    }
    if (preset_.path && s.material == link::kMaterialDielectric && (s.ior < kPathIorMin || s.ior > kPathIorMax)) {
      reject("sphere " + std::to_string(i) + " has an index of refraction of " + std::to_string(s.ior / 4096.0) +
                 ", outside the path preset's 0.25 to 8",
             bytes);
      return;
    }
  }
  // The hierarchy's bounds are read by the same sphere units: the root's carries nothing and is never tested.
  for (std::size_t i = 1; i < world.nodes.size(); ++i) {
    const auto& v = world.nodes[i];
    if (!preset_.holds_ball(v.x, v.y, v.z, v.radius)) {
      reject("the bound of node " + std::to_string(i) + " lies outside the device's number formats", bytes);
      return;
    }
  }
  back_.geometry.resize(world.spheres.size());
  back_.surfaces.resize(world.spheres.size());
  for (std::size_t i = 0; i < world.spheres.size(); ++i) {
    const auto& s = world.spheres[i];
    back_.geometry[i] = {{s.x, s.y, s.z}, s.radius};
    back_.surfaces[i] = {s.material, s.albedo, s.fuzz, s.ior};
  }
  back_.hierarchy.clear();
  for (const link::WireNode& v : world.nodes) back_.hierarchy.push_back(hierarchy_node(v));
  back_.content = content_of(back_);
  back_.sequence = world.sequence;
  back_.valid = true;
  if (pending_) ++stats_.worlds_replaced;
  pending_ = true;
  ++stats_.worlds_accepted;
  if (!listener_) return;
  ReceiverEvent e = event(ReceiverEvent::Kind::kAccepted, bytes, "", "");
  e.world = &world;
  e.check = *check;
  emit(e);
}

bool Receiver::swap_if_pending(SceneMemory& front) {
  if (!pending_) return false;
  std::swap(front, back_);
  pending_ = false;
  return true;
}

}  // namespace tripsitter::device

// tripsitter link encode|decode: the host's bytes for a scene, and what a device makes of bytes.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <span>
#include <sstream>

#include <nlohmann/json.hpp>

#include <tripsitter/board/board.h>
#include <tripsitter/device/receiver.h>
#include <tripsitter/host/host.h>
#include <tripsitter/host/camera_path.h>
#include <tripsitter/link/frame.h>
#include <tripsitter/link/sequence.h>
#include <tripsitter/link/wire_v1.h>

#include "commands.h"
#include "common.h"
#include "options.h"

namespace tripsitter::cmd {
namespace {

struct LinkOptions {
  std::string scene = "demo";
  link::WireVersion wire = link::WireVersion::kV3;
  std::string preset = "wide";
  std::string input = "-";
  int worlds = 1;
  double orbit = 360;
  std::uint64_t session = 0;  // 0: not given, a random one
  bool json = false;
};

int run_encode(const LinkOptions& o) {
  const link::WireVersion wire = o.wire;
  if (o.session != 0 && wire != link::WireVersion::kV3)
    throw InputError("--session is for --wire v3: " + std::string(link::wire_name(o.wire)) + " carries no session");
  const device::DevicePreset preset = load_preset(o.preset, 0);
  scene::Scene scene = load_scene(o.scene);
  if (isatty(STDOUT_FILENO)) throw InputError("link encode writes binary: redirect standard output to a file");
  host::Host host(std::move(scene), board::formats_of(preset), wire);
  const std::uint32_t session = wire != link::WireVersion::kV3 ? 0
                                : o.session != 0              ? static_cast<std::uint32_t>(o.session)
                                                              : link::random_session();
  link::Numbering numbering(wire, session);
  std::size_t bytes = 0;
  for (int i = 0; i < o.worlds; ++i) {
    if (i > 0) host::step_camera(host.camera(), {host::CameraPath::Kind::kOrbit, o.orbit}, o.worlds);
    std::vector<std::uint8_t> world = host.update().bytes;
    numbering.stamp(world);
    std::fwrite(world.data(), 1, world.size(), stdout);
    bytes += world.size();
  }
  if (std::fflush(stdout) != 0) throw std::runtime_error("writing standard output failed");
  std::cerr << "encoded " << o.worlds << (o.worlds == 1 ? " world of " : " worlds of ") << host.ready().spheres
            << " spheres as " << bytes << " bytes (" << link::wire_name(o.wire);
  if (wire == link::WireVersion::kV3) std::cerr << ", session " << session;
  if (wire != link::WireVersion::kV1) {
    std::cerr << ", numbered 1";
    if (o.worlds > 1) std::cerr << " to " << numbering.last_sequence();
  }
  std::cerr << ", " << host.total_saturations().total() << " saturated values)\n";
  return kExitOk;
}

const char* wire_description(link::WireVersion wire) {
  switch (wire) {
    case link::WireVersion::kV1: return "v1 (the board's sphere words, no numbers)";
    case link::WireVersion::kV2: return "v2 (TripSitter's earlier framed wire, still decoded)";
    case link::WireVersion::kV3: return "v3 (framed worlds numbered in host sessions)";
  }
  return "";
}

void print_sphere(std::size_t i, double x, double y, double z, double r, const std::string& extra) {
  std::cout << "  sphere " << i << ": centre (" << x << ", " << y << ", " << z << ") radius " << r << extra << "\n";
}

void print_world(link::WireVersion wire, const link::World& w, const link::SequenceCheck& c, std::size_t shown) {
  const core::FixedFormat f{32, w.frac_bits, true};
  std::cout << "world " << shown << ": sequence " << w.sequence;
  if (wire == link::WireVersion::kV3) std::cout << ", session " << w.session;
  std::cout << ", " << int(w.frac_bits) << " fractional bits, " << w.spheres.size() << " spheres";
  if (c.new_session) std::cout << ", a new session";
  if (c.missing > 0) std::cout << ", " << c.missing << " missing before it";
  std::cout << "\n";
  for (std::size_t i = 0; i < w.spheres.size(); ++i) {
    const auto& s = w.spheres[i];
    std::ostringstream extra;
    extra << ", " << scene::material_name(static_cast<scene::MaterialType>(s.material)) << " albedo ("
          << int(s.albedo[0]) << ", " << int(s.albedo[1]) << ", " << int(s.albedo[2]) << ")/255, fuzz "
          << s.fuzz / link::kFuzzScale << ", ior " << s.ior / link::kIorScale;
    print_sphere(i, f.to_double(s.x), f.to_double(s.y), f.to_double(s.z), f.to_double(s.radius), extra.str());
  }
  if (!w.nodes.empty()) std::cout << "  hierarchy of " << w.nodes.size() << " nodes (node 0 the root):\n";
  for (std::size_t i = 0; i < w.nodes.size(); ++i) {
    const auto& v = w.nodes[i];
    const auto range = [](std::uint64_t first, std::uint64_t n) {
      return n == 0 ? std::string("none") : n == 1 ? std::to_string(first)
                                                     : std::to_string(first) + ".." + std::to_string(first + n - 1);
    };
    std::cout << "  node " << i << ": ";
    if (i > 0)
      std::cout << "bound centre (" << f.to_double(v.x) << ", " << f.to_double(v.y) << ", " << f.to_double(v.z)
                << ") radius " << f.to_double(v.radius) << ", ";
    std::cout << "children " << range(v.first_child, v.children) << ", spheres " << range(v.first_sphere, v.sphere_count)
              << "\n";
  }
}

void print_word(const link::V1Sphere& s, std::size_t place) {
  std::cout << "word " << place << ":\n";
  std::ostringstream extra;
  extra << " (2^" << int(s.radius_log2) << "), colour 0x" << std::hex << std::setw(3) << std::setfill('0') << s.colour;
  print_sphere(0, link::kV1X.to_double(s.x_raw), link::kV1Y.to_double(s.y_raw), link::kV1Z.to_double(s.z_raw),
               std::ldexp(1.0, s.radius_log2), extra.str());
}

// What the device makes of a stream: a device::Receiver of the preset and wire, whose events say world by
// world what it showed and why it refused the rest, and whose counts are the device's own.
int run_decode(const LinkOptions& o) {
  const link::WireVersion wire = o.wire;
  const device::DevicePreset preset = load_preset(o.preset, 0);
  const std::vector<std::uint8_t> bytes = read_bytes(o.input);
  const std::string source = o.input == "-" ? "<stdin>" : o.input;
  if (!o.json) std::cout << "wire: " << wire_description(wire) << "\n";

  std::vector<std::uint32_t> accepted;  // sequence numbers of the worlds shown (v1: places of the words, from 1)
  nlohmann::json problems = nlohmann::json::array();
  std::size_t at = 0;  // where the piece of the next event begins
  device::Receiver receiver(preset, wire);
  receiver.set_listener([&](const device::ReceiverEvent& e) {
    using Kind = device::ReceiverEvent::Kind;
    if (e.kind == Kind::kAccepted) {
      accepted.push_back(e.world ? e.world->sequence : static_cast<std::uint32_t>(at / link::kV1WordBytes + 1));
      if (!o.json && e.world) print_world(wire, *e.world, e.check, accepted.size());
      if (!o.json && e.word) print_word(*e.word, accepted.back());
    } else {
      const std::size_t offset = e.found_at.value_or(at);
      std::cerr << source << ": byte " << offset << ": " << e.error << ": " << e.detail << " (" << e.bytes
                << (e.bytes == 1 ? " byte " : " bytes ")
                << (e.kind == Kind::kReplayed ? "dropped, not shown" : "dropped") << ")\n";
      problems.push_back({{"offset", offset}, {"error", e.error}, {"detail", e.detail}, {"bytes", e.bytes}});
    }
    at += e.bytes;
  });
  receiver.receive(bytes);
  receiver.end_of_stream();
  const device::ReceiverStats& rx = receiver.stats();

  if (bytes.empty()) std::cerr << source << ": no " << link::wire_name(o.wire) << " data: the input is empty\n";
  if (o.json) {
    const nlohmann::json doc = {{"wire", link::wire_name(o.wire)},
                                {"bytes", bytes.size()},
                                {"accepted", accepted},
                                {"rejected", rx.frames_rejected},
                                {"replayed", rx.worlds_replayed},
                                {"missing", rx.worlds_missing},
                                {"sessions", rx.sessions},
                                {"garbage_runs", rx.garbage_runs},
                                {"bytes_dropped", rx.bytes_dropped},
                                {"problems", problems}};
    std::cout << doc.dump(2) << "\n";
  } else {
    std::cout << "shown " << accepted.size() << ", rejected " << rx.frames_rejected << ", replayed "
              << rx.worlds_replayed << ", missing " << rx.worlds_missing << ", garbage runs " << rx.garbage_runs
              << ", bytes dropped " << rx.bytes_dropped << "\n";
  }
  const bool all_shown = !bytes.empty() && rx.frames_rejected == 0 && rx.worlds_replayed == 0 && rx.garbage_runs == 0;
  return all_shown ? kExitOk : kExitBadInput;
}

}  // namespace

void add_link_command(CLI::App& app, Action& run) {
  auto o = std::make_shared<LinkOptions>();
  CLI::App* cmd = app.add_subcommand("link", "Encode a scene as link bytes, or decode link bytes");
  cmd->require_subcommand(1);
  CLI::App* enc = cmd->add_subcommand(
      "encode",
      "Write the host's encoded worlds of a scene to standard output, one after another, numbered as the link "
      "numbers them; a summary goes to standard error");
  add_scene_option(*enc, o->scene);
  add_wire_option(*enc, o->wire, "v2 numbers the worlds 1 to N, v3 numbers them 1 to N in a session");
  add_preset_option(*enc, o->preset, "the host rounds to its number formats");
  enc->add_option("--worlds", o->worlds, "Worlds to write (N), the camera orbiting its target between them")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  enc->add_option("--orbit", o->orbit,
                  "Degrees the camera circles its target over the N worlds: each world is DEG/N further on than "
                  "the one before, the first as the scene has it (as render --frames N --orbit DEG)")
      ->capture_default_str()
      ->check(CLI::Range(-36000.0, 36000.0));
  enc->add_option("--session", o->session,
                  "v3: the session the worlds carry, 1 to 4294967295 (default: a random one, as a host that "
                  "starts chooses)")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{UINT32_MAX}));
  enc->callback([o, &run] { run = [o] { return run_encode(*o); }; });
  CLI::App* dec = cmd->add_subcommand(
      "decode",
      "Print what a device makes of a stream of link bytes under its rules: each world it shows (stdout), and each "
      "problem (stderr: FILE: byte N: error: detail (K bytes dropped)), including worlds it does not show because "
      "they are replays (v3: not newer than the last of their session, or of a session that has ended). Exit 0 "
      "when every byte was in a world the device shows (numbers missing between them do not change that); 2 when anything was rejected, dropped or replayed, or the "
      "input is empty");
  add_wire_option(*dec, o->wire);
  add_preset_option(*dec, o->preset, "its scene memory limits the sphere count, its number formats the content");
  dec->add_option("--in", o->input, "Input file ('-' is standard input)")->capture_default_str();
  dec->add_flag("--json", o->json,
                "Print one JSON object on stdout instead of the worlds (printed on exit 2 too): accepted (the "
                "sequence numbers of the worlds shown, in order; v1: the words' places in the stream, from 1), "
                "rejected (damaged or refused frames), replayed, missing (numbers skipped: worlds lost), sessions, "
                "garbage_runs, bytes_dropped, bytes, wire and problems (offset, error, detail, bytes)");
  dec->callback([o, &run] { run = [o] { return run_decode(*o); }; });
}

}  // namespace tripsitter::cmd

// tripsitter link encode|decode: the host's bytes for a scene, and what a device makes of bytes.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include <tripsitter/board/board.h>
#include <tripsitter/host/host.h>
#include <tripsitter/link/wire_v1.h>
#include <tripsitter/link/wire_v2.h>

#include "commands.h"
#include "common.h"

namespace tripsitter::cmd {
namespace {

struct LinkOptions {
  std::string scene = "demo";
  std::string wire = "v2";
  std::string preset = "wide";
  std::string input = "-";
};

int run_encode(const LinkOptions& o) {
  const link::WireVersion wire = parse_wire(o.wire);
  const device::DevicePreset preset = load_preset(o.preset, 0);
  scene::Scene scene = load_scene(o.scene);
  if (isatty(STDOUT_FILENO)) throw InputError("link encode writes binary: redirect standard output to a file");
  host::Host host(std::move(scene), board::formats_of(preset), wire);
  const auto& world = host.update();
  std::fwrite(world.bytes.data(), 1, world.bytes.size(), stdout);
  if (std::fflush(stdout) != 0) throw std::runtime_error("writing standard output failed");
  std::cerr << "encoded " << world.spheres << " spheres as " << world.bytes.size() << " bytes ("
            << o.wire << ", " << world.saturations.total() << " saturated values)\n";
  return kExitOk;
}

void print_sphere(std::size_t i, double x, double y, double z, double r, const std::string& extra) {
  std::cout << "  sphere " << i << ": centre (" << x << ", " << y << ", " << z << ") radius " << r << extra << "\n";
}

int run_decode(const LinkOptions& o) {
  const link::WireVersion wire = parse_wire(o.wire);
  const device::DevicePreset preset = load_preset(o.preset, 0);
  const std::vector<std::uint8_t> bytes = read_bytes(o.input);
  const std::string source = o.input == "-" ? "<stdin>" : o.input;
  std::size_t errors = 0;
  std::size_t decoded = 0;
  if (wire == link::WireVersion::kV1) {
    link::V1StreamDecoder decoder([&](const link::V1Sphere& s) {
      std::cout << "word " << decoded << ":\n";
      std::ostringstream extra;
      extra << " (2^" << int(s.radius_log2) << "), colour 0x" << std::hex << std::setw(3) << std::setfill('0')
            << s.colour;
      print_sphere(0, link::kV1X.to_double(s.x_raw), link::kV1Y.to_double(s.y_raw), link::kV1Z.to_double(s.z_raw),
                   std::ldexp(1.0, s.radius_log2), extra.str());
      ++decoded;
    });
    decoder.push(bytes);
    if (decoder.pending_bytes() > 0) {
      std::cerr << source << ": byte " << bytes.size() - decoder.pending_bytes() << ": truncated: "
                << decoder.pending_bytes() << " bytes of an incomplete word at the end\n";
      ++errors;
    }
  } else {
    link::V2StreamDecoder decoder(
        preset.max_spheres,
        {.on_frame =
             [&](link::World&& w) {
               const core::FixedFormat f{32, w.frac_bits, true};
               std::cout << "frame " << decoded << ": sequence " << w.sequence << ", " << int(w.frac_bits)
                         << " fractional bits, " << w.spheres.size() << " spheres\n";
               for (std::size_t i = 0; i < w.spheres.size(); ++i) {
                 const auto& s = w.spheres[i];
                 std::ostringstream extra;
                 extra << ", " << scene::material_name(static_cast<scene::MaterialType>(s.material)) << " albedo (" << int(s.albedo[0]) << ", " << int(s.albedo[1])
                       << ", " << int(s.albedo[2]) << ")/255, fuzz " << s.fuzz / link::kV2FuzzScale << ", ior "
                       << s.ior / link::kV2IorScale;
                 print_sphere(i, f.to_double(s.x), f.to_double(s.y), f.to_double(s.z), f.to_double(s.radius),
                              extra.str());
               }
               ++decoded;
             },
         .on_error =
             [&](const link::V2Failure& failure, std::size_t dropped) {
               std::cerr << source << ": byte " << failure.offset << ": " << link::to_string(failure.error) << ": "
                         << failure.detail << " (" << dropped << " bytes dropped)\n";
               ++errors;
             }});
    decoder.push(bytes);
    decoder.end_of_stream();
  }
  if (decoded == 0 && errors == 0) {
    std::cerr << source << ": no " << o.wire << " data in " << bytes.size() << " bytes\n";
    return kExitBadInput;
  }
  return errors == 0 ? kExitOk : kExitBadInput;
}

}  // namespace

void add_link_command(CLI::App& app, Action& run) {
  auto o = std::make_shared<LinkOptions>();
  CLI::App* cmd = app.add_subcommand("link", "Encode a scene as link bytes, or decode link bytes");
  cmd->require_subcommand(1);
  CLI::App* enc = cmd->add_subcommand("encode", "Write the host's encoded world for a scene to standard output");
  enc->add_option("--scene", o->scene, "Built-in scene name or JSON scene file")->capture_default_str();
  enc->add_option("--wire", o->wire, "v1 (one 8-byte word per sphere) or v2 (one framed world)")->capture_default_str();
  enc->add_option("--preset", o->preset, "Device preset whose number formats the host rounds to")->capture_default_str();
  enc->callback([o, &run] { run = [o] { return run_encode(*o); }; });
  CLI::App* dec = cmd->add_subcommand(
      "decode", "Print what the device decodes from link bytes; exit 2 with the reason if it rejects any");
  dec->add_option("--wire", o->wire, "v1 or v2")->capture_default_str();
  dec->add_option("--preset", o->preset, "Device preset (its scene memory limits the sphere count)")->capture_default_str();
  dec->add_option("--in", o->input, "Input file ('-' is standard input)")->capture_default_str();
  dec->callback([o, &run] { run = [o] { return run_decode(*o); }; });
}

}  // namespace tripsitter::cmd

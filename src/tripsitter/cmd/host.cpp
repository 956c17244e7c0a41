// tripsitter host: the microcontroller and its keyboard as a program, sending worlds to a device over TCP.
#include <csignal>
#include <chrono>
#include <iostream>
#include <memory>
#include <string>

#include <tripsitter/board/board.h>
#include <tripsitter/host/host.h>
#include <tripsitter/host/key_script.h>
#include <tripsitter/scene/builtin.h>
#include <tripsitter/transport/stream.h>

#include "commands.h"
#include "common.h"

namespace tripsitter::cmd {
namespace {

struct HostOptions {
  std::string connect;
  std::string scene = "demo";
  std::string keys;
  std::string wire = "v2";
  std::string preset = "wide";
  std::size_t transfer_bytes = link::SpiConfig{}.max_transfer_bytes;
  bool fast = false;
  double timeout_s = 10;
};

std::vector<host::KeyAction> load_script(const std::string& path) {
  if (path.empty()) return {};
  const std::vector<std::uint8_t> bytes = read_bytes(path);
  const std::string source = path == "-" ? "<stdin>" : path;
  auto script = host::parse_key_script(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  if (!script) throw InputError(script.error().to_string(source));
  return std::move(script).value();
}

// A failure once connected: the message on stderr, exit 1.
int lost(const transport::StreamError& e) {
  std::cerr << "tripsitter: " << e.message << "\n";
  return kExitInternal;
}

int run_host(const HostOptions& o) {
  const link::WireVersion wire = parse_wire(o.wire);
  const device::DevicePreset preset = load_preset(o.preset, 0);
  scene::Scene scene = load_scene(o.scene);
  std::vector<host::KeyAction> actions = load_script(o.keys);
  auto address = transport::parse_stream_address(o.connect);
  if (!address) throw InputError("--connect: " + address.error().message);
  const auto timeout = std::chrono::milliseconds(static_cast<std::int64_t>(o.timeout_s * 1000));

  std::signal(SIGPIPE, SIG_IGN);
  auto socket = transport::connect_stream(address.value(), timeout);
  if (!socket)
    throw InputError(socket.error().message + " (is `tripsitter device --listen " + address.value().to_string() +
                     "` running?)");
  const std::string peer = address.value().to_string();
  transport::StreamSender sender(std::move(socket).value(), peer, o.transfer_bytes, timeout);

  const std::int64_t ticks = host::total_ticks(actions);
  std::cerr << "host: connected to " << peer << "; " << actions.size() << " key actions, " << ticks << " ticks ("
            << static_cast<double>(ticks) / host::kScriptTicksPerSecond << " s of script time"
            << (o.fast ? ", played as fast as the device takes worlds" : "") << ")\n";

  host::Host h(std::move(scene), board::formats_of(preset), wire);
  host::KeyScriptPlayer player(std::move(actions));
  using Clock = transport::StreamClock;
  const auto tick = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / host::kScriptTicksPerSecond));
  const auto start = Clock::now();
  // Tick 0 is the scene as loaded; every tick of the script makes a newer world.
  const auto submit = [&] { sender.submit(h.update().bytes); };
  // The world of tick t is made at start + t/60 s and may go out until the next tick's is made.
  for (std::int64_t t = 0; t == 0 || player.step(h); ++t) {
    submit();
    if (auto r = sender.pump_until(o.fast ? Clock::time_point{} : start + (t + 1) * tick); !r) return lost(r.error());
  }
  const host::ReadyWorld& last = h.ready();
  auto answer = sender.finish(Clock::now() + timeout);
  if (!answer) return lost(answer.error());
  sender.close();

  const auto& s = sender.stats();
  std::cerr << "host: " << s.worlds_submitted << " worlds made, " << s.worlds_sent << " sent, " << s.worlds_replaced
            << " replaced before the device was ready; " << s.bytes_sent << " bytes in " << s.transfers
            << " transfers of at most " << o.transfer_bytes << "; the last world has " << last.saturations.total()
            << " saturated values\n";
  if (last.spheres_dropped > 0)
    std::cerr << "host: " << last.spheres_dropped << " spheres beyond the device's scene memory were not sent\n";
  if (s.worlds_rejected > 0) std::cerr << "host: the device rejected " << s.worlds_rejected << " worlds\n";
  if (answer.value() == transport::WorldAnswer::kRejected) {
    std::cerr << "tripsitter: the device at " << peer << " rejected the last world (sequence " << last.sequence
              << "); do --wire and --preset match the device's?\n";
    return kExitInternal;
  }
  std::cerr << "host: the device took the last world (sequence " << last.sequence << ")\n";
  return kExitOk;
}

}  // namespace

void add_host_command(CLI::App& app, Action& run) {
  auto o = std::make_shared<HostOptions>();
  CLI::App* cmd = app.add_subcommand("host", "The host (microcontroller) and its keyboard as a program, sending worlds over TCP");
  cmd->footer(
      "Plays a key script on the scene's camera in ticks of 1/60 s, makes a world every tick and sends it to\n"
      "`tripsitter device` whenever the device is ready (a newer world replaces one not yet sent). Exits once\n"
      "the device has taken the last world. Exit 2: bad input, or no device at the address; exit 1: the\n"
      "connection was lost, the device was busy or did not answer, or it rejected the last world.");
  cmd->add_option("--connect", o->connect, "Address of the device, HOST:PORT")->required();
  cmd->add_option("--scene", o->scene, "Built-in scene name (" + join(scene::builtin_names()) + ") or JSON scene file")
      ->capture_default_str();
  cmd->add_option("--keys", o->keys,
                  "Key script ('-' for stdin; docs/key_script.md): lines like 'W 500ms', 'J 0.25s', 'R', 'wait 1s'. "
                  "Without one, the host sends the scene as loaded and exits");
  cmd->add_option("--wire", o->wire, "v1 (one 8-byte word per sphere) or v2 (framed worlds)")->capture_default_str();
  cmd->add_option("--preset", o->preset, "Device preset whose number formats the host rounds to (as the device's)")
      ->capture_default_str();
  cmd->add_option("--transfer-bytes", o->transfer_bytes, "Largest SPI transfer in bytes")
      ->capture_default_str()->check(CLI::Range(std::size_t{1}, std::size_t{1} << 30));
  cmd->add_flag("--fast", o->fast,
                "Do not wait 1/60 s of real time per tick: play the script at once (the last world is the same)");
  cmd->add_option("--timeout", o->timeout_s, "Seconds to wait for the device to connect, read or answer")
      ->capture_default_str()->check(CLI::Range(0.1, 3600.0));
  cmd->callback([o, &run] { run = [o] { return run_host(*o); }; });
}

}  // namespace tripsitter::cmd

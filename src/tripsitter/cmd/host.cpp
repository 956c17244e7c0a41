// tripsitter host: the microcontroller and its keyboard as a program, sending worlds to a device over TCP.
#include <csignal>
#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include <tripsitter/board/board.h>
#include <tripsitter/host/host.h>
#include <tripsitter/host/key_script.h>
#include <tripsitter/scene/builtin.h>
#include <tripsitter/transport/stream.h>

#include "commands.h"
#include "common.h"
#include "options.h"

namespace tripsitter::cmd {
namespace {

struct HostOptions {
  std::string connect;
  std::string scene = "demo";
  std::string keys;
  link::WireVersion wire = link::WireVersion::kV3;
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

using Clock = transport::StreamClock;

// The host's end of the link over TCP, one StreamSender per connection. When the device goes away (it was
// killed, or restarted), the link reconnects with backoff, under a new session (link/sequence.h), and sends
// the latest world again; it gives up once the device has answered no world for the timeout.
class ReconnectingLink {
 public:
  ReconnectingLink(transport::StreamAddress address, link::WireVersion wire, std::size_t transfer_bytes,
                   std::chrono::milliseconds timeout)
      : address_(std::move(address)), peer_(address_.to_string()), wire_(wire), transfer_bytes_(transfer_bytes),
        timeout_(timeout) {}

  // The first connection; nothing there is bad input (exit 2).
  void connect() {
    auto socket = transport::connect_stream(address_, timeout_);
    if (!socket)
      throw InputError(socket.error().message + " (is `tripsitter device --listen " + peer_ + "` running?)");
    open(std::move(socket).value());
  }

  void submit(std::vector<std::uint8_t> bytes) {
    latest_ = bytes;
    sender_->submit(std::move(bytes));
  }

  core::Result<bool, transport::StreamError> pump_until(Clock::time_point until) {
    for (;;) {
      auto r = sender_->pump_until(until);
      if (r) return r;
      transport::StreamError e = r.error();
      if (!recover(e)) return e;
    }
  }

  core::Result<transport::WorldAnswer, transport::StreamError> finish() {
    for (;;) {
      auto r = sender_->finish(Clock::now() + timeout_);
      if (r) return r;
      transport::StreamError e = r.error();
      if (!recover(e)) return e;
    }
  }

  void close() {
    sender_->close();
    totals_ += sender_->stats();
  }

  const transport::StreamSenderStats& totals() const { return totals_; }
  std::uint32_t last_sequence() const { return sender_->numbering()->last_sequence(); }
  std::uint32_t session() const { return sender_->numbering()->session(); }
  const std::string& peer() const { return peer_; }

 private:
  void open(transport::StreamSocket socket) {
    if (!sender_) last_answer_at_ = Clock::now();  // the first connection starts the clock
    sender_.emplace(std::move(socket), peer_, transfer_bytes_, timeout_, link::Numbering(wire_, link::random_session()));
  }

  // Reconnects after a lost connection, retrying with a backoff that doubles from 100 ms to 2 s, until the
  // device has answered no world for the timeout. False: the error stands (with why, added to it).
  bool recover(transport::StreamError& e) {
    if (e.kind != transport::StreamError::Kind::kLost) return false;
    const transport::StreamSenderStats& s = sender_->stats();
    const auto lost_at = Clock::now();
    if (s.worlds_taken + s.worlds_rejected > 0) last_answer_at_ = lost_at;
    totals_ += sender_->stats();
    // A device that answers no world for the timeout, across reconnections, is given up: it may run another
    // wire, and drop every connection of this host for sending no world it can read.
    const auto give_up_at = last_answer_at_ + timeout_;
    const auto hint = [this] { return totals_.worlds_taken + totals_.worlds_rejected == 0 ? " (does it run the same --wire?)" : ""; };
    if (lost_at >= give_up_at) {
      e.message += std::string("; no world answered for ") + std::to_string(timeout_.count()) + " ms" + hint();
      return false;
    }
    std::cerr << "host: " << e.message << "; reconnecting\n";
    auto backoff = std::chrono::milliseconds(100);
    for (int attempt = 1;; ++attempt) {
      if (Clock::now() + backoff > give_up_at) {
        e.message += "; gave up reconnecting after " + std::to_string(attempt - 1) + " attempts" + hint();
        return false;
      }
      std::this_thread::sleep_for(backoff);
      backoff = std::min(backoff * 2, std::chrono::milliseconds(2000));
      auto socket = transport::connect_stream(address_, timeout_);
      if (!socket) continue;
      open(std::move(socket).value());
      std::cerr << "host: reconnected to " << peer_ << " at attempt " << attempt << ", "
                << std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - lost_at).count()
                << " ms after the loss; new session " << session() << "\n";
      if (!latest_.empty()) sender_->submit(latest_);
      return true;
    }
  }

  transport::StreamAddress address_;
  std::string peer_;
  link::WireVersion wire_;
  std::size_t transfer_bytes_;
  std::chrono::milliseconds timeout_;
  std::optional<transport::StreamSender> sender_;
  std::vector<std::uint8_t> latest_;  // the newest world, sent again after a reconnection
  transport::StreamSenderStats totals_;  // of the connections closed so far
  Clock::time_point last_answer_at_;     // when a connection that had answered a world was lost, or connected
};

int run_host(const HostOptions& o) {
  const link::WireVersion wire = o.wire;
  const device::DevicePreset preset = load_preset(o.preset, 0);
  scene::Scene scene = load_scene(o.scene);
  std::vector<host::KeyAction> actions = load_script(o.keys);
  auto address = transport::parse_stream_address(o.connect);
  if (!address) throw InputError("--connect: " + address.error().message);
  const auto timeout = std::chrono::milliseconds(static_cast<std::int64_t>(o.timeout_s * 1000));

  std::signal(SIGPIPE, SIG_IGN);
  ReconnectingLink link(address.value(), wire, o.transfer_bytes, timeout);
  link.connect();
  const std::string& peer = link.peer();

  const std::int64_t ticks = host::total_ticks(actions);
  std::cerr << "host: connected to " << peer << "; " << actions.size() << " key actions, " << ticks << " ticks ("
            << static_cast<double>(ticks) / host::kScriptTicksPerSecond << " s of script time"
            << (o.fast ? ", played as fast as the device takes worlds" : "") << ")\n";

  host::Host h(std::move(scene), board::formats_of(preset), wire);
  host::KeyScriptPlayer player(std::move(actions));
  const auto tick = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / host::kScriptTicksPerSecond));
  const auto start = Clock::now();
  // Tick 0 is the scene as loaded; every tick of the script makes a newer world.
  // The world of tick t is made at start + t/60 s and may go out until the next tick's is made.
  std::uint64_t made = 0;
  for (std::int64_t t = 0; t == 0 || player.step(h); ++t) {
    link.submit(h.update().bytes);
    ++made;
    if (auto r = link.pump_until(o.fast ? Clock::time_point{} : start + (t + 1) * tick); !r) return lost(r.error());
  }
  const host::ReadyWorld& last = h.ready();
  auto answer = link.finish();
  if (!answer) return lost(answer.error());
  link.close();

  const auto& s = link.totals();
  std::cerr << "host: " << made << " worlds made, " << s.worlds_sent << " sent, " << s.worlds_replaced
            << " replaced before the device was ready; " << s.bytes_sent << " bytes in " << s.transfers
            << " transfers of at most " << o.transfer_bytes << "; the last world has " << last.saturations.total()
            << " saturated values\n";
  if (last.spheres_dropped > 0)
    std::cerr << "host: " << last.spheres_dropped << " spheres beyond the device's scene memory were not sent\n";
  if (s.worlds_rejected > 0) std::cerr << "host: the device rejected " << s.worlds_rejected << " worlds\n";
  if (answer.value() == transport::WorldAnswer::kRejected) {
    std::cerr << "tripsitter: the device at " << peer << " rejected the last world (sequence " << link.last_sequence()
              << "); do --wire and --preset match the device's?\n";
    return kExitInternal;
  }
  std::cerr << "host: the device took the last world (sequence " << link.last_sequence() << " of session "
            << link.session() << ")\n";
  return kExitOk;
}

}  // namespace

void add_host_command(CLI::App& app, Action& run) {
  auto o = std::make_shared<HostOptions>();
  CLI::App* cmd = app.add_subcommand("host", "The host (microcontroller) and its keyboard as a program, sending worlds over TCP");
  cmd->footer(
      "Plays a key script on the scene's camera in ticks of 1/60 s, makes a world every tick and sends it to\n"
      "`tripsitter device` whenever the device is ready (a newer world replaces one not yet sent). Exits once\n"
      "the device has taken the last world. If the device goes away (it was restarted), the host reconnects\n"
      "with backoff and goes on, until the device has answered no world for --timeout seconds. Exit 2: bad\n"
      "input, or no device at the address; exit 1: the connection was lost for good, the device was busy or\n"
      "did not answer, or it rejected the last world.");
  cmd->add_option("--connect", o->connect, "Address of the device, HOST:PORT")->required();
  add_scene_option(*cmd, o->scene);
  cmd->add_option("--keys", o->keys,
                  "Key script ('-' for stdin; docs/key_script.md): lines like 'W 500ms', 'J 0.25s', 'R', 'wait 1s'. "
                  "Without one, the host sends the scene as loaded and exits");
  add_wire_option(*cmd, o->wire);
  add_preset_option(*cmd, o->preset, "the host rounds to its number formats, as the device's");
  cmd->add_option("--transfer-bytes", o->transfer_bytes, "Largest SPI transfer in bytes")
      ->capture_default_str()->check(CLI::Range(std::size_t{1}, std::size_t{1} << 30));
  cmd->add_flag("--fast", o->fast,
                "Do not wait 1/60 s of real time per tick: play the script at once (the last world is the same)");
  cmd->add_option("--timeout", o->timeout_s, "Seconds to wait for the device to connect, read or answer")
      ->capture_default_str()->check(CLI::Range(0.1, 3600.0));
  cmd->callback([o, &run] { run = [o] { return run_host(*o); }; });
}

}  // namespace tripsitter::cmd

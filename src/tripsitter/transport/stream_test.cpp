#include <tripsitter/transport/stream.h>

#include <sys/socket.h>

#include <atomic>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>

#include <tripsitter/link/frame.h>

namespace tripsitter::transport {
namespace {

using namespace std::chrono_literals;
using link::encode_frame;
using link::FrameError;
using link::FrameFailure;
using link::FrameStreamDecoder;
using link::World;

// ---------------------------------------------------------------------------------------------------------
// Addresses

TEST(StreamAddress, GoodAddresses) {
  struct Case {
    const char* text;
    const char* host;
    std::uint16_t port;
    const char* printed;
  };
  const Case cases[] = {
      {"127.0.0.1:7000", "127.0.0.1", 7000, "127.0.0.1:7000"},
      {"127.0.0.1:0", "127.0.0.1", 0, "127.0.0.1:0"},
      {"localhost:65535", "localhost", 65535, "localhost:65535"},
      {"board-7.lan:00080", "board-7.lan", 80, "board-7.lan:80"},
      {"[::1]:7000", "::1", 7000, "[::1]:7000"},
      {"[::ffff:127.0.0.1]:1", "::ffff:127.0.0.1", 1, "[::ffff:127.0.0.1]:1"},
  };
  for (const Case& c : cases) {
    auto a = parse_stream_address(c.text);
    ASSERT_TRUE(a.ok()) << c.text << ": " << a.error().message;
    EXPECT_EQ(a.value().host, c.host);
    EXPECT_EQ(a.value().port, c.port);
    EXPECT_EQ(a.value().to_string(), c.printed);
  }
}

TEST(StreamAddress, BadAddressesAreNamedWithTheReason) {
  struct Case {
    const char* text;
    const char* why;
  };
  const Case cases[] = {
      {"", "empty"},
      {"127.0.0.1", "missing ':PORT'"},
      {"127.0.0.1:", "missing port"},
      {":7000", "missing host"},
      {"127.0.0.1:70000", "port 70000 is above 65535"},
      {"127.0.0.1:123456", "bad port '123456'"},
      {"127.0.0.1:-1", "bad port '-1'"},
      {"127.0.0.1:7x", "bad port '7x'"},
      {"127.0.0.1: 7000", "bad port ' 7000'"},
      {"::1:7000", "brackets"},
      {"[::1]7000", "missing ':PORT' after ']'"},
      {"[::1:7000", "'[' without ']'"},
      {"[]:7000", "bad IPv6 address ''"},
      {"[::g]:7000", "bad IPv6 address '::g'"},
      {"my host:7000", "bad host 'my host'"},
  };
  for (const Case& c : cases) {
    auto a = parse_stream_address(c.text);
    ASSERT_FALSE(a.ok()) << c.text;
    EXPECT_NE(a.error().message.find("address '" + std::string(c.text) + "'"), std::string::npos) << a.error().message;
    EXPECT_NE(a.error().message.find(c.why), std::string::npos) << c.text << " -> " << a.error().message;
  }
}

// ---------------------------------------------------------------------------------------------------------
// Sockets

StreamAddress loopback(std::uint16_t port) { return {"127.0.0.1", port}; }

TEST(StreamSockets, ListeningOnPortZeroReportsThePortChosen) {
  auto port = StreamPort::listen(loopback(0));
  ASSERT_TRUE(port.ok()) << port.error().message;
  EXPECT_NE(port.value().address().port, 0);
  EXPECT_EQ(port.value().address().host, "127.0.0.1");
  auto s = connect_stream(port.value().address());
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s.value().peer_name(), port.value().address().to_string());
}

TEST(StreamSockets, ConnectErrorsNameTheAddress) {
  auto zero = connect_stream(loopback(0));
  ASSERT_FALSE(zero.ok());
  EXPECT_NE(zero.error().message.find("127.0.0.1:0"), std::string::npos) << zero.error().message;

  // A port that was just free: nothing listens there.
  std::uint16_t free_port = 0;
  {
    auto p = StreamPort::listen(loopback(0));
    ASSERT_TRUE(p.ok());
    free_port = p.value().address().port;
  }
  auto refused = connect_stream(loopback(free_port));
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("cannot connect to 127.0.0.1:" + std::to_string(free_port)), std::string::npos)
      << refused.error().message;
  EXPECT_NE(refused.error().message.find("refused"), std::string::npos) << refused.error().message;

  auto unresolved = connect_stream({"no-such-host.invalid", 7000});
  ASSERT_FALSE(unresolved.ok());
  EXPECT_NE(unresolved.error().message.find("no-such-host.invalid:7000"), std::string::npos);
}

TEST(StreamSockets, ListeningTwiceOnOnePortFails) {
  auto a = StreamPort::listen(loopback(0));
  ASSERT_TRUE(a.ok());
  auto b = StreamPort::listen(a.value().address());
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().message.find("cannot listen on " + a.value().address().to_string()), std::string::npos)
      << b.error().message;
}

// ---------------------------------------------------------------------------------------------------------
// The protocol, in one thread: the test plays the device's frames by calling service() and vblank().

// A receiver like the device's: v2 frames, a back copy that waits for vertical blanking (ready low meanwhile),
// damaged frames counted and dropped.
struct FakeReceiver : link::StreamEndpoint {
  FrameStreamDecoder decoder{link::WireVersion::kV2, 16,
                          {.on_frame =
                               [this](World&& w) {
                                 frames.push_back(std::move(w));
                                 pending = true;
                                 ++accepted;
                               },
                           .on_error =
                               [this](const FrameFailure& f, std::size_t bytes) {
                                 dropped += bytes;
                                 if (f.error != FrameError::kBadMagic) {
                                   ++rejected;
                                   errors.push_back(f.error);
                                 }
                               }}};
  bool pending = false;
  std::vector<World> frames;
  std::vector<FrameError> errors;
  std::uint64_t accepted = 0, rejected = 0, dropped = 0, eos = 0;
  std::vector<std::size_t> transfer_sizes;

  bool ready() const override { return !pending; }
  void transfer(std::span<const std::uint8_t> bytes) override {
    transfer_sizes.push_back(bytes.size());
    decoder.push(bytes);
  }
  void end_of_stream() override {
    ++eos;
    decoder.end_of_stream();
  }
  std::uint64_t worlds_accepted() const override { return accepted; }
  std::uint64_t worlds_rejected() const override { return rejected; }
  void vblank() { pending = false; }  // the waiting world becomes scene memory
};

std::vector<std::uint8_t> frame(std::uint32_t sequence, std::size_t spheres = 1) {
  World w;
  w.sequence = sequence;
  w.frac_bits = 4;
  for (std::size_t i = 0; i < spheres; ++i) w.spheres.push_back({0, 0, 6400, 1024, 0, {1, 2, 3}, 0, 6144});
  return encode_frame(link::WireVersion::kV2, w);
}

// A past instant: pump_until makes one pass and does not wait.
StreamClock::time_point now() { return StreamClock::time_point{}; }

struct Rig {
  Rig() {
    auto p = StreamPort::listen(loopback(0), [this](const StreamPortEvent& e) { events.push_back(e); });
    if (!p.ok()) throw std::runtime_error(p.error().message);
    port.emplace(std::move(p).value());
  }
  StreamSender connect(std::size_t transfer_bytes = 1024) {
    auto s = connect_stream(port->address());
    if (!s.ok()) throw std::runtime_error(s.error().message);
    return StreamSender(std::move(s).value(), port->address().to_string(), transfer_bytes, 5s);
  }
  // Lets bytes cross the loopback in both directions until `done` or a generous time has passed.
  template <class Done>
  bool settle(StreamSender& host, Done done) {
    const auto give_up = StreamClock::now() + 10s;
    while (StreamClock::now() < give_up) {
      port->service(device);
      if (auto r = host.pump_until(now()); !r.ok()) {
        last_error = r.error().message;
        return done();
      }
      if (done()) return true;
      std::this_thread::sleep_for(1ms);
    }
    return false;
  }

  std::optional<StreamPort> port;
  FakeReceiver device;
  std::vector<StreamPortEvent> events;
  std::string last_error;
};

TEST(StreamProtocol, TheDeviceGrantsACreditOnConnectAndOneWorldGoesPerCredit) {
  Rig rig;
  StreamSender host = rig.connect();
  ASSERT_TRUE(rig.settle(host, [&] { return host.stats().credits == 1; }));
  ASSERT_EQ(rig.events.size(), 1u);
  EXPECT_EQ(rig.events[0].kind, StreamPortEvent::Kind::kConnected);
  EXPECT_EQ(rig.port->stats().hosts_served, 1u);

  host.submit(frame(1));
  ASSERT_TRUE(rig.settle(host, [&] { return rig.device.frames.size() == 1; }));
  EXPECT_TRUE(host.awaiting_answer());
  EXPECT_FALSE(rig.device.ready());

  // While world 1 waits for vertical blanking, worlds 2 and 3 are made; 3 replaces 2, neither goes out.
  host.submit(frame(2));
  host.submit(frame(3));
  for (int i = 0; i < 20; ++i) {
    rig.port->service(rig.device);
    ASSERT_TRUE(host.pump_until(now()).ok());
  }
  EXPECT_EQ(rig.device.frames.size(), 1u);
  EXPECT_EQ(host.stats().worlds_sent, 1u);
  EXPECT_EQ(host.stats().worlds_replaced, 1u);
  EXPECT_EQ(rig.port->stats().credits_sent, 1u);

  // Vertical blanking: world 1 is taken, the credit goes back, and the newest world (3) follows.
  rig.device.vblank();
  ASSERT_TRUE(rig.settle(host, [&] { return rig.device.frames.size() == 2; }));
  EXPECT_EQ(rig.device.frames[1].sequence, 3u);
  EXPECT_EQ(host.stats().worlds_taken, 1u);
  EXPECT_EQ(host.stats().worlds_sent, 2u);
  EXPECT_EQ(host.stats().worlds_submitted, 3u);

  rig.device.vblank();
  ASSERT_TRUE(rig.settle(host, [&] { return !host.awaiting_answer(); }));
  EXPECT_EQ(host.last_answer(), WorldAnswer::kTaken);
  EXPECT_EQ(host.stats().worlds_taken, 2u);
  EXPECT_EQ(rig.device.rejected, 0u);
}

TEST(StreamProtocol, WorldsGoOutInTransfersOfAtMostTheLimit) {
  Rig rig;
  StreamSender host = rig.connect(7);
  const std::vector<std::uint8_t> bytes = frame(1, 3);  // 96 bytes: 13 transfers of at most 7
  host.submit(bytes);
  ASSERT_TRUE(rig.settle(host, [&] { return rig.device.frames.size() == 1; }));
  EXPECT_EQ(host.stats().transfers, 14u);
  EXPECT_EQ(host.stats().bytes_sent, bytes.size());
  EXPECT_EQ(rig.device.frames[0].spheres.size(), 3u);
}

TEST(StreamProtocol, ARejectedWorldIsAnsweredAtOnceWithX) {
  Rig rig;
  StreamSender host = rig.connect();
  std::vector<std::uint8_t> bad = frame(1);
  bad[30] ^= 0x01;  // a payload bit: the CRC fails
  host.submit(bad);
  ASSERT_TRUE(rig.settle(host, [&] { return host.stats().worlds_sent == 1 && !host.awaiting_answer(); }));
  EXPECT_EQ(host.last_answer(), WorldAnswer::kRejected);
  EXPECT_EQ(rig.device.rejected, 1u);
  ASSERT_EQ(rig.device.errors.size(), 1u);
  EXPECT_EQ(rig.device.errors[0], FrameError::kBadCrc);

  // The device is still ready, so the next world goes at once and is taken.
  host.submit(frame(2));
  ASSERT_TRUE(rig.settle(host, [&] { return rig.device.frames.size() == 1; }));
  EXPECT_EQ(rig.device.frames[0].sequence, 2u);
  rig.device.vblank();
  ASSERT_TRUE(rig.settle(host, [&] { return !host.awaiting_answer(); }));
  EXPECT_EQ(host.last_answer(), WorldAnswer::kTaken);
}

TEST(StreamProtocol, ADeviceNotReadyAtConnectGrantsNoCreditUntilBlanking) {
  Rig rig;
  rig.device.pending = true;  // a world from an earlier host waits for the swap
  StreamSender host = rig.connect();
  host.submit(frame(1));
  for (int i = 0; i < 20; ++i) {
    rig.port->service(rig.device);
    ASSERT_TRUE(host.pump_until(now()).ok());
    std::this_thread::sleep_for(1ms);
  }
  EXPECT_EQ(host.stats().credits, 0u);
  EXPECT_EQ(host.stats().worlds_sent, 0u);
  rig.device.vblank();
  ASSERT_TRUE(rig.settle(host, [&] { return rig.device.frames.size() == 1; }));
}

TEST(StreamProtocol, AHostGoneMidFrameIsCountedByTheReceiverAndTheNextHostIsServed) {
  Rig rig;
  {
    auto raw = connect_stream(rig.port->address());
    ASSERT_TRUE(raw.ok());
    rig.port->service(rig.device);  // accepted; credit sent
    const std::vector<std::uint8_t> bytes = frame(1, 2);
    ASSERT_EQ(::send(raw.value().fd(), bytes.data(), 30, MSG_NOSIGNAL), 30);
  }  // the host vanishes 30 bytes into a 72-byte frame
  const auto give_up = StreamClock::now() + 10s;
  while (rig.port->connected() && StreamClock::now() < give_up) {
    rig.port->service(rig.device);
    std::this_thread::sleep_for(1ms);
  }
  ASSERT_FALSE(rig.port->connected());
  EXPECT_EQ(rig.device.eos, 1u);
  ASSERT_EQ(rig.device.errors.size(), 1u);
  EXPECT_EQ(rig.device.errors[0], FrameError::kTruncated);
  EXPECT_EQ(rig.device.dropped, 30u);
  ASSERT_EQ(rig.events.size(), 2u);
  EXPECT_EQ(rig.events[1].kind, StreamPortEvent::Kind::kDisconnected);
  EXPECT_EQ(rig.events[1].bytes, 30u);

  // A new host is served from a clean start: a credit at once, and its world goes through.
  StreamSender host = rig.connect();
  host.submit(frame(7));
  ASSERT_TRUE(rig.settle(host, [&] { return rig.device.frames.size() == 1; }));
  EXPECT_EQ(rig.device.frames[0].sequence, 7u);
  EXPECT_EQ(rig.port->stats().hosts_served, 2u);
}

TEST(StreamProtocol, ASecondHostIsRefusedAsBusy) {
  Rig rig;
  StreamSender first = rig.connect();
  ASSERT_TRUE(rig.settle(first, [&] { return first.stats().credits == 1; }));
  StreamSender second = rig.connect();
  ASSERT_TRUE(rig.settle(second, [&] { return !rig.last_error.empty(); }));
  EXPECT_NE(rig.last_error.find("busy with another host"), std::string::npos) << rig.last_error;
  EXPECT_NE(rig.last_error.find(rig.port->address().to_string()), std::string::npos) << rig.last_error;
  EXPECT_EQ(rig.port->stats().hosts_refused, 1u);
  EXPECT_EQ(rig.events.back().kind, StreamPortEvent::Kind::kRefused);
  // The first host is still served.
  first.submit(frame(1));
  ASSERT_TRUE(rig.settle(first, [&] { return rig.device.frames.size() == 1; }));
}

TEST(StreamProtocol, TheHostSeesTheDeviceGo) {
  Rig rig;
  StreamSender host = rig.connect();
  ASSERT_TRUE(rig.settle(host, [&] { return host.stats().credits == 1; }));
  rig.port.reset();  // the device process ends
  std::string error;
  const auto give_up = StreamClock::now() + 10s;
  while (error.empty() && StreamClock::now() < give_up) {
    auto r = host.pump_until(StreamClock::now() + 10ms);
    if (!r.ok()) error = r.error().message;
  }
  EXPECT_NE(error.find("closed the connection"), std::string::npos) << error;
}

TEST(StreamProtocol, AByteThatIsNotInTheProtocolIsAnError) {
  int fds[2];  // the device's end is played by hand
  ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK, 0, fds), 0);
  StreamSocket device_end(fds[1]);
  StreamSender host(StreamSocket{fds[0]}, "pair", 64, 1s);
  const std::uint8_t junk = 'Z';
  ASSERT_EQ(::send(device_end.fd(), &junk, 1, MSG_NOSIGNAL), 1);
  auto r = host.pump_until(now());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("byte 0x5A"), std::string::npos) << r.error().message;
}

// ---------------------------------------------------------------------------------------------------------
// The protocol with the device in its own thread, as in the two programs: finish() returns once the last
// world has been taken, and close() ends the connection without a reset.

TEST(StreamProtocol, FinishWaitsUntilTheLastWorldIsTaken) {
  Rig rig;
  std::atomic<bool> stop{false};
  std::mutex m;
  std::vector<std::uint32_t> shown;  // sequence of each world swapped in
  std::thread device([&] {
    std::size_t swapped = 0;
    while (!stop) {
      rig.port->service(rig.device);
      if (rig.device.pending) {  // vertical blanking
        rig.device.vblank();
        std::lock_guard<std::mutex> lock(m);
        shown.push_back(rig.device.frames[swapped++].sequence);
      }
      rig.port->wait(StreamClock::now() + 2ms);
    }
  });
  StreamSender host = rig.connect(16);
  for (std::uint32_t seq = 1; seq <= 50; ++seq) {
    host.submit(frame(seq, 2));
    ASSERT_TRUE(host.pump_until(now()).ok());
  }
  auto answer = host.finish(StreamClock::now() + 10s);
  ASSERT_TRUE(answer.ok()) << answer.error().message;
  EXPECT_EQ(answer.value(), WorldAnswer::kTaken);
  {
    std::lock_guard<std::mutex> lock(m);
    ASSERT_FALSE(shown.empty());
    EXPECT_EQ(shown.back(), 50u);  // the final world was shown
  }
  const auto& s = host.stats();
  EXPECT_EQ(s.worlds_submitted, 50u);
  EXPECT_EQ(s.worlds_sent + s.worlds_replaced, 50u);
  EXPECT_EQ(s.worlds_taken, s.worlds_sent);
  host.close(10s);  // returns once the device has closed its side
  stop = true;
  device.join();
  ASSERT_FALSE(rig.port->connected());
  EXPECT_EQ(rig.events.back().kind, StreamPortEvent::Kind::kDisconnected);
  EXPECT_EQ(rig.events.back().detail, "closed the connection");
  EXPECT_EQ(rig.device.rejected, 0u);
  EXPECT_EQ(rig.device.dropped, 0u);
}

}  // namespace
}  // namespace tripsitter::transport

// The link over TCP: host and device as two programs joined by a stream socket (docs/link_format.md, "Over
// a byte stream"). What the bytes mean (the credit bytes, the credit rule, the device's endpoint) is
// link/stream_protocol.h; this library moves them: addresses, sockets, the host's sender and the device's
// port. Plain POSIX sockets; every write uses MSG_NOSIGNAL, so a vanished peer is an error value, never
// SIGPIPE.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <tripsitter/core/result.h>
#include <tripsitter/link/sequence.h>
#include <tripsitter/link/stream_protocol.h>

namespace tripsitter::transport {

using StreamClock = std::chrono::steady_clock;

struct StreamError {
  enum class Kind {
    kOther,  // could not connect, a byte not in the protocol, a timeout
    kLost,   // the connection ended or broke: the other side went away
    kBusy,   // the device serves another host
  };
  std::string message;  // names the address and what went wrong
  Kind kind = Kind::kOther;
};

// "HOST:PORT": an IPv4 address, a host name, or an IPv6 address in brackets ("[::1]:7000"); the port is
// 0..65535, and 0 asks the system to choose one when listening.
struct StreamAddress {
  std::string host;
  std::uint16_t port = 0;
  std::string to_string() const;
};

core::Result<StreamAddress, StreamError> parse_stream_address(std::string_view text);

// A connected stream socket, non-blocking. Owns its descriptor; move-only.
class StreamSocket {
 public:
  StreamSocket() = default;
  explicit StreamSocket(int fd) : fd_(fd) {}
  StreamSocket(StreamSocket&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  StreamSocket& operator=(StreamSocket&& other) noexcept;
  StreamSocket(const StreamSocket&) = delete;
  StreamSocket& operator=(const StreamSocket&) = delete;
  ~StreamSocket() { close(); }

  int fd() const { return fd_; }
  bool is_open() const { return fd_ >= 0; }
  void close();
  // "address:port" of the other end, for messages.
  std::string peer_name() const;

 private:
  int fd_ = -1;
};

// Connects to a listening device; fails if nothing answers within `timeout`.
// REQUIRES address.port != 0 (checked: an error value).
core::Result<StreamSocket, StreamError> connect_stream(const StreamAddress& address,
                                                       std::chrono::milliseconds timeout = std::chrono::seconds(10));

// ---------------------------------------------------------------------------------------------------------
// Host side: the host's SPI driver, over a stream.

// What became of the last world the host sent.
enum class WorldAnswer { kNone, kTaken, kRejected };

struct StreamSenderStats {
  std::uint64_t worlds_submitted = 0;
  std::uint64_t worlds_sent = 0;
  std::uint64_t worlds_replaced = 0;  // submitted, then replaced by a newer world before a credit came
  std::uint64_t worlds_taken = 0;     // answered 'R': swapped into the device's scene memory
  std::uint64_t worlds_rejected = 0;  // answered 'X'
  std::uint64_t transfers = 0;
  std::uint64_t bytes_sent = 0;
  std::uint64_t credits = 0;          // credit bytes received

  StreamSenderStats& operator+=(const StreamSenderStats& o) {
    worlds_submitted += o.worlds_submitted;
    worlds_sent += o.worlds_sent;
    worlds_replaced += o.worlds_replaced;
    worlds_taken += o.worlds_taken;
    worlds_rejected += o.worlds_rejected;
    transfers += o.transfers;
    bytes_sent += o.bytes_sent;
    credits += o.credits;
    return *this;
  }
};

class StreamSender {
 public:
  // `peer` names the device in messages. `io_timeout` bounds how long one transfer may wait for the device
  // to read. REQUIRES max_transfer_bytes >= 1.
  // With `numbering`, each world gets its sequence number (and session) as it starts to go out
  // (link/sequence.h); without, the bytes go out as submitted.
  StreamSender(StreamSocket socket, std::string peer, std::size_t max_transfer_bytes,
               std::chrono::milliseconds io_timeout = std::chrono::seconds(10),
               std::optional<link::Numbering> numbering = std::nullopt);

  // A complete encoded world to send; a world not yet sent is replaced.
  void submit(std::vector<std::uint8_t> world_bytes);
  bool has_pending() const { return pending_; }
  // A world has been sent and its answer has not arrived.
  bool awaiting_answer() const { return awaiting_answer_; }
  WorldAnswer last_answer() const { return last_answer_; }

  // Reads the device's bytes and sends the pending world whenever a credit is held, until `until` (a time
  // in the past makes one pass that does not wait). Errors: the device closed the connection, refused it
  // as busy, sent a byte that is not in the protocol, or stopped reading for io_timeout.
  core::Result<bool, StreamError> pump_until(StreamClock::time_point until);

  // Sends what is pending and waits for the device's answer to the last world sent (taken or rejected),
  // until `deadline`. Returns that answer (kNone if no world was ever submitted).
  core::Result<WorldAnswer, StreamError> finish(StreamClock::time_point deadline);

  // Ends the connection cleanly: no more bytes from this side, then reads until the device closes its side
  // (or `linger` passes), so that nothing the device sent is left unread (which would reset the connection).
  void close(std::chrono::milliseconds linger = std::chrono::seconds(1));

  const StreamSenderStats& stats() const { return stats_; }
  const std::optional<link::Numbering>& numbering() const { return numbering_; }

 private:
  core::Result<bool, StreamError> read_answers();
  core::Result<bool, StreamError> send_pending();
  core::Result<bool, StreamError> write_all(std::span<const std::uint8_t> bytes);

  StreamSocket socket_;
  std::string peer_;
  std::size_t max_transfer_bytes_;
  std::chrono::milliseconds io_timeout_;
  std::optional<link::Numbering> numbering_;
  std::vector<std::uint8_t> pending_bytes_;
  bool pending_ = false;
  std::uint64_t credits_ = 0;  // held, not yet used
  bool awaiting_answer_ = false;
  WorldAnswer last_answer_ = WorldAnswer::kNone;
  StreamSenderStats stats_;
};

// ---------------------------------------------------------------------------------------------------------
// Device side: the device's end of the link, serving one host at a time.

struct StreamPortEvent {
  enum class Kind {
    kConnected,     // a host connected and is now served
    kDisconnected,  // the host went away (detail: why); bytes: what it sent
    kRefused,       // a second host was refused while one is served
    kError,         // a socket error that did not stop the port (detail)
  };
  Kind kind;
  std::string peer;
  std::uint64_t bytes = 0;
  std::string detail;
};

struct StreamPortStats {
  std::uint64_t hosts_served = 0;
  std::uint64_t hosts_refused = 0;
  std::uint64_t bytes_received = 0;
  std::uint64_t credits_sent = 0;
};

class StreamPort {
 public:
  // Listens on `address` (port 0: the system chooses; address() then holds the real port). A host that has
  // sent bytes and completed no world (accepted or rejected) for `stall_timeout` is dropped, so that a host
  // sending one byte a second, or bytes that are no world at all, cannot hold the device.
  static core::Result<StreamPort, StreamError> listen(const StreamAddress& address,
                                                      std::function<void(const StreamPortEvent&)> on_event = {},
                                                      std::chrono::milliseconds stall_timeout = kDefaultStallTimeout);
  static constexpr std::chrono::milliseconds kDefaultStallTimeout{5000};

  const StreamAddress& address() const { return address_; }
  bool connected() const { return host_.is_open(); }

  // Never blocks. Moves every byte the host has sent so far into `device` (at most a few megabytes per
  // call), notices a host that went away (device.end_of_stream()), accepts a waiting host if none is served
  // and refuses the others, and sends the credit byte when the rule says so.
  void service(link::StreamEndpoint& device);

  // Sleeps until a host connects or sends bytes, or until `until`; returns early when a signal arrives.
  void wait(StreamClock::time_point until) const;

  const StreamPortStats& stats() const { return stats_; }

 private:
  StreamPort(StreamSocket listener, StreamAddress address, std::function<void(const StreamPortEvent&)> on_event,
             std::chrono::milliseconds stall_timeout)
      : listener_(std::move(listener)), address_(std::move(address)), on_event_(std::move(on_event)),
        stall_timeout_(stall_timeout) {}
  void read_from_host(link::StreamEndpoint& device);
  void accept_hosts(const link::StreamEndpoint& device);
  void grant_credit(link::StreamEndpoint& device);
  void drop_host(link::StreamEndpoint& device, std::string why);
  void emit(StreamPortEvent::Kind kind, std::string peer, std::uint64_t bytes, std::string detail);

  StreamSocket listener_;
  StreamAddress address_;
  std::function<void(const StreamPortEvent&)> on_event_;
  std::chrono::milliseconds stall_timeout_;
  StreamSocket host_;
  std::string host_name_;
  std::uint64_t host_bytes_ = 0;
  // The stall rule: bytes since the receiver last completed a world, and when that was.
  std::uint64_t bytes_since_world_ = 0;
  std::uint64_t worlds_seen_ = 0;
  StreamClock::time_point last_world_at_{};
  // The credit rule: one credit outstanding at most, and with it the receiver's totals when it was granted.
  bool credit_out_ = false;
  bool last_rejected_ = false;
  std::uint64_t accepted_at_credit_ = 0;
  std::uint64_t rejected_at_credit_ = 0;
  StreamPortStats stats_;
};

}  // namespace tripsitter::transport

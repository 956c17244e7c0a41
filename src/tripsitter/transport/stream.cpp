#include <tripsitter/transport/stream.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace tripsitter::transport {
namespace {

constexpr std::size_t kReadChunk = 64 * 1024;
constexpr std::size_t kMaxReadPerService = 4 * 1024 * 1024;  // then the device draws a frame and comes back
// Hosts that connect at once wait here until the device accepts them (to refuse all but one).
constexpr int kListenBacklog = 128;

std::string errno_text(int err) { return std::strerror(err); }

std::string quoted(std::string_view s) {
  std::string out = "'";
  out += s;
  out += '\'';
  return out;
}

// An IPv6 address goes in brackets before ":port".
std::string with_port(const std::string& host, std::string_view port) {
  std::string out;
  if (host.find(':') != std::string::npos) {
    out += '[';
    out += host;
    out += ']';
  } else {
    out += host;
  }
  out += ':';
  out += port;
  return out;
}

bool valid_host_name(std::string_view h) {
  return !h.empty() && std::all_of(h.begin(), h.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '-' ||
           c == '_';
  });
}

bool valid_ipv6_literal(std::string_view h) {
  return !h.empty() && std::all_of(h.begin(), h.end(), [](char c) {
    return (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F') || (c >= '0' && c <= '9') || c == ':' || c == '.';
  });
}

int set_nonblocking(int fd) {
  const int flags = ::fcntl(fd, F_GETFL, 0);
  if (flags < 0) return -1;
  return ::fcntl(fd, F_SETFL, flags | O_NONBLOCK);
}

void set_nodelay(int fd) {
  // Transfers and credit bytes are small and each one matters now: no Nagle delay.
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

std::string name_of(const sockaddr* sa) {
  char host[NI_MAXHOST], port[NI_MAXSERV];
  const socklen_t len = sa->sa_family == AF_INET6 ? sizeof(sockaddr_in6) : sizeof(sockaddr_in);
  if (::getnameinfo(sa, len, host, sizeof host, port, sizeof port, NI_NUMERICHOST | NI_NUMERICSERV) != 0)
    return "?";
  return with_port(host, port);
}

// getaddrinfo for a stream socket; `passive` for listening.
struct AddrInfo {
  addrinfo* list = nullptr;
  AddrInfo() = default;
  AddrInfo(const AddrInfo&) = delete;
  AddrInfo& operator=(const AddrInfo&) = delete;
  ~AddrInfo() {
    if (list != nullptr) ::freeaddrinfo(list);
  }
};

std::optional<StreamError> resolve(const StreamAddress& a, bool passive, AddrInfo& out) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_NUMERICSERV | (passive ? AI_PASSIVE : 0);
  const std::string port = std::to_string(a.port);
  const int rc = ::getaddrinfo(a.host.c_str(), port.c_str(), &hints, &out.list);
  if (rc != 0) return StreamError{"address " + a.to_string() + ": cannot resolve " + quoted(a.host) + ": " + ::gai_strerror(rc)};
  return std::nullopt;
}

int ms_until(StreamClock::time_point until) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - StreamClock::now()).count();
  if (left <= 0) return 0;
  return static_cast<int>(std::min<long long>(left + 1, 60'000));  // +1: never wake a hair early
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// Addresses and sockets

std::string StreamAddress::to_string() const {
  return with_port(host, std::to_string(port));
}

core::Result<StreamAddress, StreamError> parse_stream_address(std::string_view text) {
  const auto fail = [&](const std::string& why) {
    return StreamError{"address " + quoted(text) + ": " + why + " (expected HOST:PORT, like 127.0.0.1:7000)"};
  };
  if (text.empty()) return fail("empty");
  std::string_view host, port;
  if (text.front() == '[') {
    const std::size_t close = text.find(']');
    if (close == std::string_view::npos) return fail("'[' without ']'");
    host = text.substr(1, close - 1);
    if (close + 1 >= text.size() || text[close + 1] != ':') return fail("missing ':PORT' after ']'");
    port = text.substr(close + 2);
    if (!valid_ipv6_literal(host)) return fail("bad IPv6 address " + quoted(host));
  } else {
    const std::size_t colon = text.rfind(':');
    if (colon == std::string_view::npos) return fail("missing ':PORT'");
    host = text.substr(0, colon);
    port = text.substr(colon + 1);
    if (host.find(':') != std::string_view::npos) return fail("an IPv6 address goes in brackets, like [::1]:7000");
    if (host.empty()) return fail("missing host (127.0.0.1 is this machine)");
    if (!valid_host_name(host)) return fail("bad host " + quoted(host));
  }
  if (port.empty()) return fail("missing port");
  if (port.size() > 5 || !std::all_of(port.begin(), port.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return fail("bad port " + quoted(port));
  const int value = std::stoi(std::string(port));
  if (value > 65535) return fail("port " + std::string(port) + " is above 65535");
  return StreamAddress{std::string(host), static_cast<std::uint16_t>(value)};
}

StreamSocket& StreamSocket::operator=(StreamSocket&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

void StreamSocket::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

std::string StreamSocket::peer_name() const {
  sockaddr_storage ss{};
  socklen_t len = sizeof ss;
  if (fd_ < 0 || ::getpeername(fd_, reinterpret_cast<sockaddr*>(&ss), &len) != 0) return "?";
  return name_of(reinterpret_cast<const sockaddr*>(&ss));
}

core::Result<StreamSocket, StreamError> connect_stream(const StreamAddress& address,
                                                       std::chrono::milliseconds timeout) {
  if (address.port == 0)
    return StreamError{"address " + address.to_string() + ": port 0 only means 'choose one' when listening"};
  AddrInfo ai;
  if (auto err = resolve(address, false, ai)) return *err;
  std::string why = "no address";
  const auto deadline = StreamClock::now() + timeout;
  for (const addrinfo* p = ai.list; p != nullptr; p = p->ai_next) {
    StreamSocket s(::socket(p->ai_family, p->ai_socktype | SOCK_CLOEXEC, p->ai_protocol));
    if (!s.is_open()) {
      why = errno_text(errno);
      continue;
    }
    if (set_nonblocking(s.fd()) != 0) {
      why = errno_text(errno);
      continue;
    }
    if (::connect(s.fd(), p->ai_addr, p->ai_addrlen) != 0) {
      if (errno != EINPROGRESS) {
        why = errno_text(errno);
        continue;
      }
      pollfd pfd{s.fd(), POLLOUT, 0};
      int rc;
      do {
        rc = ::poll(&pfd, 1, ms_until(deadline));
      } while (rc < 0 && errno == EINTR);
      if (rc == 0) {
        why = "no answer within " + std::to_string(timeout.count()) + " ms";
        continue;
      }
      int err = 0;
      socklen_t len = sizeof err;
      if (rc < 0 || ::getsockopt(s.fd(), SOL_SOCKET, SO_ERROR, &err, &len) != 0) err = errno;
      if (err != 0) {
        why = errno_text(err);
        continue;
      }
    }
    set_nodelay(s.fd());
    return s;
  }
  return StreamError{"cannot connect to " + address.to_string() + ": " + why};
}

// ---------------------------------------------------------------------------------------------------------
// Host side

StreamSender::StreamSender(StreamSocket socket, std::string peer, std::size_t max_transfer_bytes,
                           std::chrono::milliseconds io_timeout, std::optional<link::Numbering> numbering)
    : socket_(std::move(socket)), peer_(std::move(peer)), max_transfer_bytes_(max_transfer_bytes),
      io_timeout_(io_timeout), numbering_(std::move(numbering)) {
  if (max_transfer_bytes_ == 0) throw std::invalid_argument("transfer size must be at least 1 byte");
  set_nonblocking(socket_.fd());  // waits go through poll(), with their deadlines
}

void StreamSender::submit(std::vector<std::uint8_t> world_bytes) {
  ++stats_.worlds_submitted;
  if (pending_) ++stats_.worlds_replaced;
  pending_bytes_ = std::move(world_bytes);
  pending_ = true;
}

core::Result<bool, StreamError> StreamSender::read_answers() {
  std::uint8_t buf[256];
  for (;;) {
    const ssize_t n = ::recv(socket_.fd(), buf, sizeof buf, 0);
    if (n == 0) return StreamError{"the device at " + peer_ + " closed the connection", StreamError::Kind::kLost};
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) return true;
      return StreamError{"lost the connection to the device at " + peer_ + ": " + errno_text(errno),
                         StreamError::Kind::kLost};
    }
    for (ssize_t i = 0; i < n; ++i) {
      const std::uint8_t b = buf[i];
      if (b == link::kStreamBusy)
        return StreamError{"the device at " + peer_ + " is busy with another host", StreamError::Kind::kBusy};
      if (b != link::kStreamReady && b != link::kStreamRejected) {
        char hex[8];
        std::snprintf(hex, sizeof hex, "0x%02X", b);
        return StreamError{"the device at " + peer_ + " sent byte " + hex +
                           ", which is not in the protocol (is it a tripsitter device?)"};
      }
      ++credits_;
      ++stats_.credits;
      if (awaiting_answer_) {
        awaiting_answer_ = false;
        last_answer_ = b == link::kStreamReady ? WorldAnswer::kTaken : WorldAnswer::kRejected;
        ++(b == link::kStreamReady ? stats_.worlds_taken : stats_.worlds_rejected);
      }
    }
  }
}

core::Result<bool, StreamError> StreamSender::write_all(std::span<const std::uint8_t> bytes) {
  auto last_progress = StreamClock::now();
  while (!bytes.empty()) {
    const ssize_t n = ::send(socket_.fd(), bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (n > 0) {
      bytes = bytes.subspan(static_cast<std::size_t>(n));
      last_progress = StreamClock::now();
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)
      return StreamError{"lost the connection to the device at " + peer_ + ": " + errno_text(errno),
                         StreamError::Kind::kLost};
    // The device has not read what it was sent so far: wait for room, within the timeout.
    pollfd pfd{socket_.fd(), POLLOUT, 0};
    const int rc = ::poll(&pfd, 1, ms_until(last_progress + io_timeout_));
    if (rc == 0)
      return StreamError{"the device at " + peer_ + " stopped reading (nothing went out for " +
                         std::to_string(io_timeout_.count()) + " ms)"};
  }
  return true;
}

core::Result<bool, StreamError> StreamSender::send_pending() {
  if (!pending_ || credits_ == 0) return false;
  if (numbering_) numbering_->stamp(pending_bytes_);
  const std::span<const std::uint8_t> all(pending_bytes_);
  for (std::size_t at = 0; at < all.size(); at += max_transfer_bytes_) {
    auto wrote = write_all(all.subspan(at, std::min(max_transfer_bytes_, all.size() - at)));
    if (!wrote) return wrote.error();
    ++stats_.transfers;
  }
  --credits_;
  stats_.bytes_sent += all.size();
  ++stats_.worlds_sent;
  pending_ = false;
  pending_bytes_.clear();
  awaiting_answer_ = true;
  return true;
}

core::Result<bool, StreamError> StreamSender::pump_until(StreamClock::time_point until) {
  for (;;) {
    if (auto r = read_answers(); !r) return r.error();
    if (auto s = send_pending(); !s) return s.error();
    const int wait_ms = ms_until(until);
    if (wait_ms == 0) return true;
    pollfd pfd{socket_.fd(), POLLIN, 0};
    ::poll(&pfd, 1, wait_ms);  // EINTR: go round again
  }
}

core::Result<WorldAnswer, StreamError> StreamSender::finish(StreamClock::time_point deadline) {
  for (;;) {
    if (auto r = read_answers(); !r) return r.error();
    if (auto s = send_pending(); !s) return s.error();
    if (!pending_ && !awaiting_answer_) return last_answer_;
    const int wait_ms = ms_until(deadline);
    if (wait_ms == 0)
      return StreamError{std::string("the device at ") + peer_ +
                         (pending_ ? " did not become ready for the last world" : " did not answer the last world") +
                         " in time (does it run the same --wire?)"};
    pollfd pfd{socket_.fd(), POLLIN, 0};
    ::poll(&pfd, 1, wait_ms);
  }
}

void StreamSender::close(std::chrono::milliseconds linger) {
  if (!socket_.is_open()) return;
  ::shutdown(socket_.fd(), SHUT_WR);
  const auto deadline = StreamClock::now() + linger;
  std::uint8_t buf[256];
  for (;;) {
    const ssize_t n = ::recv(socket_.fd(), buf, sizeof buf, 0);
    if (n == 0) break;  // the device closed its side
    if (n < 0 && errno != EINTR && errno != EAGAIN && errno != EWOULDBLOCK) break;
    const int wait_ms = ms_until(deadline);
    if (wait_ms == 0) break;
    if (n < 0 && errno != EINTR) {
      pollfd pfd{socket_.fd(), POLLIN, 0};
      ::poll(&pfd, 1, wait_ms);
    }
  }
  socket_.close();
}

// ---------------------------------------------------------------------------------------------------------
// Device side

core::Result<StreamPort, StreamError> StreamPort::listen(const StreamAddress& address,
                                                         std::function<void(const StreamPortEvent&)> on_event,
                                                         std::chrono::milliseconds stall_timeout) {
  AddrInfo ai;
  if (auto err = resolve(address, true, ai)) return *err;
  std::string why = "no address";
  for (const addrinfo* p = ai.list; p != nullptr; p = p->ai_next) {
    StreamSocket s(::socket(p->ai_family, p->ai_socktype | SOCK_CLOEXEC, p->ai_protocol));
    if (!s.is_open()) {
      why = errno_text(errno);
      continue;
    }
    const int one = 1;
    ::setsockopt(s.fd(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (::bind(s.fd(), p->ai_addr, p->ai_addrlen) != 0 || ::listen(s.fd(), kListenBacklog) != 0 || set_nonblocking(s.fd()) != 0) {
      why = errno_text(errno);
      continue;
    }
    sockaddr_storage ss{};
    socklen_t len = sizeof ss;
    StreamAddress bound = address;
    if (::getsockname(s.fd(), reinterpret_cast<sockaddr*>(&ss), &len) == 0) {
      const auto* sa = reinterpret_cast<const sockaddr*>(&ss);
      bound.port = ntohs(sa->sa_family == AF_INET6 ? reinterpret_cast<const sockaddr_in6*>(sa)->sin6_port
                                                   : reinterpret_cast<const sockaddr_in*>(sa)->sin_port);
    }
    return StreamPort(std::move(s), std::move(bound), std::move(on_event), stall_timeout);
  }
  return StreamError{"cannot listen on " + address.to_string() + ": " + why};
}

void StreamPort::emit(StreamPortEvent::Kind kind, std::string peer, std::uint64_t bytes, std::string detail) {
  if (on_event_) on_event_({kind, std::move(peer), bytes, std::move(detail)});
}

void StreamPort::drop_host(link::StreamEndpoint& device, std::string why) {
  device.end_of_stream();
  host_.close();
  credit_out_ = false;
  emit(StreamPortEvent::Kind::kDisconnected, host_name_, host_bytes_, std::move(why));
}

void StreamPort::read_from_host(link::StreamEndpoint& device) {
  // The stall clock starts with the first byte after the last world the receiver completed.
  if (bytes_since_world_ == 0) last_world_at_ = StreamClock::now();
  std::uint8_t buf[kReadChunk];
  std::size_t total = 0;
  while (total < kMaxReadPerService) {
    const ssize_t n = ::recv(host_.fd(), buf, sizeof buf, 0);
    if (n > 0) {
      device.transfer(std::span<const std::uint8_t>(buf, static_cast<std::size_t>(n)));
      total += static_cast<std::size_t>(n);
      host_bytes_ += static_cast<std::uint64_t>(n);
      bytes_since_world_ += static_cast<std::uint64_t>(n);
      stats_.bytes_received += static_cast<std::uint64_t>(n);
      continue;
    }
    if (n == 0) return drop_host(device, "closed the connection");
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) break;
    return drop_host(device, errno_text(errno));
  }
  // The world granted by the last credit has ended once the receiver has accepted or rejected something.
  if (credit_out_) {
    const bool accepted = device.worlds_accepted() != accepted_at_credit_;
    const bool rejected = device.worlds_rejected() != rejected_at_credit_;
    if (accepted || rejected) {
      credit_out_ = false;
      last_rejected_ = !accepted;
    }
  }
  // A host that sends bytes but no world (too slowly, or bytes that are no world at all) holds the device
  // for nobody: it is dropped once it has taken stall_timeout without completing one.
  const std::uint64_t worlds = device.worlds_accepted() + device.worlds_rejected();
  const auto now = StreamClock::now();
  if (worlds != worlds_seen_) {
    worlds_seen_ = worlds;
    bytes_since_world_ = 0;
  } else if (bytes_since_world_ > 0 && now - last_world_at_ > stall_timeout_) {
    drop_host(device, "sent " + std::to_string(bytes_since_world_) + " bytes in " +
                          std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(now - last_world_at_).count()) +
                          " ms without completing a world (the limit is " + std::to_string(stall_timeout_.count()) +
                          " ms); dropped");
  }
}

void StreamPort::accept_hosts(const link::StreamEndpoint& device) {
  for (;;) {
    sockaddr_storage ss{};
    socklen_t len = sizeof ss;
    StreamSocket s(::accept4(listener_.fd(), reinterpret_cast<sockaddr*>(&ss), &len, SOCK_NONBLOCK | SOCK_CLOEXEC));
    if (!s.is_open()) {
      if (errno == EINTR || errno == ECONNABORTED) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) emit(StreamPortEvent::Kind::kError, "", 0, "accept: " + errno_text(errno));
      return;
    }
    const std::string name = name_of(reinterpret_cast<const sockaddr*>(&ss));
    set_nodelay(s.fd());
    if (host_.is_open()) {
      // One host at a time: tell this one why, and close.
      ::send(s.fd(), &link::kStreamBusy, 1, MSG_NOSIGNAL);
      ++stats_.hosts_refused;
      emit(StreamPortEvent::Kind::kRefused, name, 0, "busy with " + host_name_);
      continue;
    }
    host_ = std::move(s);
    host_name_ = name;
    host_bytes_ = 0;
    bytes_since_world_ = 0;
    worlds_seen_ = device.worlds_accepted() + device.worlds_rejected();
    credit_out_ = false;
    last_rejected_ = false;
    ++stats_.hosts_served;
    emit(StreamPortEvent::Kind::kConnected, name, 0, "");
  }
}

void StreamPort::grant_credit(link::StreamEndpoint& device) {
  if (credit_out_ || !device.ready()) return;
  const std::uint8_t byte = last_rejected_ ? link::kStreamRejected : link::kStreamReady;
  const ssize_t n = ::send(host_.fd(), &byte, 1, MSG_NOSIGNAL);
  if (n == 1) {
    credit_out_ = true;
    accepted_at_credit_ = device.worlds_accepted();
    rejected_at_credit_ = device.worlds_rejected();
    ++stats_.credits_sent;
    return;
  }
  if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;  // try again next time
  drop_host(device, errno_text(errno));
}

void StreamPort::service(link::StreamEndpoint& device) {
  if (host_.is_open()) read_from_host(device);
  accept_hosts(device);
  if (host_.is_open()) grant_credit(device);
}

void StreamPort::wait(StreamClock::time_point until) const {
  pollfd fds[2] = {{listener_.fd(), POLLIN, 0}, {host_.fd(), POLLIN, 0}};  // a closed host (-1) is ignored
  ::poll(fds, 2, ms_until(until));
}

}  // namespace tripsitter::transport

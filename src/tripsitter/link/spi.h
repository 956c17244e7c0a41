// The SPI bus between host and device (SPEC.md section A.2): transfers of at most a configured number of
// bytes, the device's ready line, and a bit count that turns bytes into time at the SPI clock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <tripsitter/link/sequence.h>

namespace tripsitter::link {

// The device side of the bus, as the host's SPI driver sees it.
class Endpoint {
 public:
  virtual ~Endpoint() = default;
  // The ready line: high when the device can take a new world.
  virtual bool ready() const = 0;
  // One transfer (chip select low, bytes, chip select high).
  virtual void transfer(std::span<const std::uint8_t> bytes) = 0;
};

struct SpiConfig {
  std::size_t max_transfer_bytes = 1024;  // the host's SPI driver moves at most this many bytes per transfer
  std::int64_t clock_hz = 10'000'000;     // SPI clock, one bit per clock (mode 0, MSB first)
};

struct SpiStats {
  std::uint64_t worlds_sent = 0;
  std::uint64_t worlds_replaced = 0;  // submitted, then replaced by a newer world before the device was ready
  std::uint64_t transfers = 0;
  std::uint64_t bytes_sent = 0;
  std::size_t last_world_bytes = 0;
};

class SpiLink {
 public:
  // With `numbering`, each world gets its sequence number (and session) as it starts to go out, so the host
  // numbers only the worlds it sends; without, the bytes go out as submitted (tests that number by hand).
  explicit SpiLink(SpiConfig config = {}, std::optional<Numbering> numbering = std::nullopt);

  // Host side: a complete encoded world to send. A world that has not started to go out is replaced.
  void submit(std::vector<std::uint8_t> world_bytes);
  bool has_pending() const { return pending_; }

  // Sends the pending world if the device is ready, as consecutive transfers. Returns whether it sent.
  bool pump(Endpoint& device);

  // Time the bus needs for `bytes` bytes at the configured clock.
  double seconds_for(std::size_t bytes) const;
  const SpiConfig& config() const { return config_; }
  const SpiStats& stats() const { return stats_; }
  const std::optional<Numbering>& numbering() const { return numbering_; }

 private:
  SpiConfig config_;
  std::optional<Numbering> numbering_;
  std::vector<std::uint8_t> pending_bytes_;
  bool pending_ = false;
  SpiStats stats_;
};

}  // namespace tripsitter::link

#include <tripsitter/link/spi.h>

#include <algorithm>
#include <stdexcept>

namespace tripsitter::link {

SpiLink::SpiLink(SpiConfig config, std::optional<Numbering> numbering)
    : config_(config), numbering_(std::move(numbering)) {
  if (config_.max_transfer_bytes == 0) throw std::invalid_argument("SPI transfer size must be at least 1 byte");
  if (config_.clock_hz <= 0) throw std::invalid_argument("SPI clock must be positive");
}

void SpiLink::submit(std::vector<std::uint8_t> world_bytes) {
  if (pending_) ++stats_.worlds_replaced;
  pending_bytes_ = std::move(world_bytes);
  pending_ = true;
}

bool SpiLink::pump(Endpoint& device) {
  if (!pending_ || !device.ready()) return false;
  if (numbering_) numbering_->stamp(pending_bytes_);
  const std::span<const std::uint8_t> all(pending_bytes_);
  for (std::size_t at = 0; at < all.size(); at += config_.max_transfer_bytes) {
    device.transfer(all.subspan(at, std::min(config_.max_transfer_bytes, all.size() - at)));
    ++stats_.transfers;
  }
  stats_.bytes_sent += all.size();
  stats_.last_world_bytes = all.size();
  ++stats_.worlds_sent;
  pending_ = false;
  pending_bytes_.clear();
  return true;
}

double SpiLink::seconds_for(std::size_t bytes) const {
  return static_cast<double>(bytes) * 8.0 / static_cast<double>(config_.clock_hz);
}

}  // namespace tripsitter::link

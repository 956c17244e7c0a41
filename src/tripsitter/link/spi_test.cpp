#include <tripsitter/link/spi.h>

#include <gtest/gtest.h>

namespace tripsitter::link {
namespace {

struct FakeDevice : Endpoint {
  bool is_ready = true;
  std::vector<std::vector<std::uint8_t>> transfers;
  bool ready() const override { return is_ready; }
  void transfer(std::span<const std::uint8_t> bytes) override { transfers.emplace_back(bytes.begin(), bytes.end()); }
};

TEST(SpiLink, SplitsAWorldIntoTransfersOfAtMostTheLimit) {
  SpiLink link({.max_transfer_bytes = 5, .clock_hz = 1'000'000});
  FakeDevice dev;
  std::vector<std::uint8_t> world(23);
  for (std::size_t i = 0; i < world.size(); ++i) world[i] = static_cast<std::uint8_t>(i);
  link.submit(world);
  EXPECT_TRUE(link.pump(dev));
  ASSERT_EQ(dev.transfers.size(), 5u);
  std::vector<std::uint8_t> joined;
  for (const auto& t : dev.transfers) {
    EXPECT_LE(t.size(), 5u);
    joined.insert(joined.end(), t.begin(), t.end());
  }
  EXPECT_EQ(joined, world);
  EXPECT_EQ(link.stats().bytes_sent, 23u);
  EXPECT_FALSE(link.has_pending());
}

TEST(SpiLink, WaitsForReadyAndANewerWorldReplacesAnUnsentOne) {
  SpiLink link;
  FakeDevice dev;
  dev.is_ready = false;
  link.submit({1, 2, 3});
  EXPECT_FALSE(link.pump(dev));
  link.submit({4, 5});
  EXPECT_EQ(link.stats().worlds_replaced, 1u);
  EXPECT_FALSE(link.pump(dev));
  EXPECT_TRUE(dev.transfers.empty());
  dev.is_ready = true;
  EXPECT_TRUE(link.pump(dev));
  ASSERT_EQ(dev.transfers.size(), 1u);
  EXPECT_EQ(dev.transfers[0], (std::vector<std::uint8_t>{4, 5}));
  EXPECT_FALSE(link.pump(dev));  // nothing left to send
}

TEST(SpiLink, CountsBitsIntoTime) {
  SpiLink link({.max_transfer_bytes = 64, .clock_hz = 8'000'000});
  EXPECT_DOUBLE_EQ(link.seconds_for(1000), 1e-3);
}

TEST(SpiLink, RejectsAZeroTransferSize) { EXPECT_THROW(SpiLink({.max_transfer_bytes = 0}), std::invalid_argument); }

}  // namespace
}  // namespace tripsitter::link
